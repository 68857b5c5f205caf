#include "quadcage/bench/child_process.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "quadcage/core/errors.h"

namespace quadcage::bench {
namespace {

constexpr off_t kStderrKept = 64 * 1024;

int open_or_throw(const std::string& path, int flags, const char* what) {
    const int fd = ::open(path.empty() ? "/dev/null" : path.c_str(), flags | O_CLOEXEC, 0644);
    if (fd < 0) throw InvalidInput(path + ": cannot open the " + what + " file (" + std::strerror(errno) + ")");
    return fd;
}

// The bytes of `path` from `offset` on (at most the last kStderrKept of them).
std::string read_from(const std::string& path, off_t offset) {
    if (path.empty()) return {};
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return {};
    struct stat st {};
    std::string out;
    if (::fstat(fd, &st) == 0 && st.st_size > offset) {
        const off_t start = std::max(offset, st.st_size - kStderrKept);
        out.resize(static_cast<size_t>(st.st_size - start));
        const ssize_t n = ::pread(fd, out.data(), out.size(), start);
        out.resize(n > 0 ? static_cast<size_t>(n) : 0);
    }
    ::close(fd);
    return out;
}

}  // namespace

std::string ChildResult::last_stderr_line() const {
    size_t end = stderr_text.size();
    while (end > 0) {
        size_t start = stderr_text.rfind('\n', end - 1);
        start = start == std::string::npos ? 0 : start + 1;
        std::string line = stderr_text.substr(start, end - start);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
        if (!line.empty()) return line;
        end = start == 0 ? 0 : start - 1;
    }
    return {};
}

ChildResult run_child(const std::vector<std::string>& argv, const ChildOptions& o) {
    if (argv.empty() || argv[0].empty()) throw InvalidInput("run_child: no command given");
    ChildResult r;
    const int in_fd = open_or_throw("", O_RDONLY, "input");
    const int out_fd = open_or_throw(o.stdout_path, O_WRONLY | O_CREAT | O_TRUNC, "output");
    int err_fd = -1;
    try {
        err_fd = open_or_throw(o.stderr_path, O_WRONLY | O_CREAT | O_APPEND, "log");
    } catch (...) {
        ::close(in_fd);
        ::close(out_fd);
        throw;
    }
    struct stat st {};
    const off_t err_start = (!o.stderr_path.empty() && ::fstat(err_fd, &st) == 0) ? st.st_size : 0;

    // Everything the child needs is prepared before fork(): after it, only async-signal-safe calls
    // (hence the PATH lookup here and execv() below, not execvp()).
    const std::string program = find_on_path(argv[0]);
    if (program.empty()) {
        r.error = "cannot run '" + argv[0] + "': " +
                  (argv[0].find('/') == std::string::npos ? "not found on PATH" : "No such file or not executable");
        ::close(in_fd), ::close(out_fd), ::close(err_fd);
        return r;
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    int report[2];
    if (::pipe2(report, O_CLOEXEC) != 0) {
        r.error = std::string("pipe: ") + std::strerror(errno);
        ::close(in_fd), ::close(out_fd), ::close(err_fd);
        return r;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::setpgid(0, 0);
        ::dup2(in_fd, 0);
        ::dup2(out_fd, 1);
        ::dup2(err_fd, 2);
        ::execv(program.c_str(), args.data());
        const int e = errno;
        ssize_t ignored = ::write(report[1], &e, sizeof e);
        (void)ignored;
        ::_exit(127);
    }
    ::close(report[1]);
    ::close(in_fd);
    ::close(out_fd);
    ::close(err_fd);
    if (pid < 0) {
        r.error = std::string("fork: ") + std::strerror(errno);
        ::close(report[0]);
        return r;
    }
    ::setpgid(pid, pid);  // also here: no window in which a timeout kill could miss the group
    int exec_errno = 0;
    const bool exec_failed = ::read(report[0], &exec_errno, sizeof exec_errno) == static_cast<ssize_t>(sizeof exec_errno);
    ::close(report[0]);

    int status = 0;
    rusage usage{};
    bool timed_out = false;
    auto sleep_for = std::chrono::milliseconds(1);
    for (;;) {
        const pid_t w = ::wait4(pid, &status, WNOHANG, &usage);
        if (w == pid) break;
        if (w < 0 && errno != EINTR) break;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.timeout_seconds > 0 && elapsed >= o.timeout_seconds && !timed_out) {
            ::kill(-pid, SIGKILL);
            timed_out = true;
            while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
            }
            break;
        }
        std::this_thread::sleep_for(sleep_for);
        sleep_for = std::min(sleep_for * 2, std::chrono::milliseconds(20));
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.peak_memory_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: KiB
    r.stderr_text = read_from(o.stderr_path, err_start);
    if (exec_failed) {
        r.end = ChildResult::End::not_started;
        r.error = "cannot run '" + argv[0] + "': " + std::strerror(exec_errno);
    } else if (timed_out) {
        r.end = ChildResult::End::timed_out;
        r.signal = SIGKILL;
    } else if (WIFSIGNALED(status)) {
        r.end = ChildResult::End::signalled;
        r.signal = WTERMSIG(status);
    } else {
        r.end = ChildResult::End::exited;
        r.exit_code = WEXITSTATUS(status);
    }
    return r;
}

std::string self_executable() {
    char buf[4096];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return {};
    return std::string(buf, static_cast<size_t>(n));
}

std::string find_on_path(const std::string& name) {
    if (name.empty()) return {};
    if (name.find('/') != std::string::npos) return ::access(name.c_str(), X_OK) == 0 ? name : std::string();
    const char* path = std::getenv("PATH");
    std::string all = path ? path : "/usr/local/bin:/usr/bin:/bin";
    size_t start = 0;
    while (start <= all.size()) {
        size_t end = all.find(':', start);
        if (end == std::string::npos) end = all.size();
        const std::string dir = end > start ? all.substr(start, end - start) : ".";
        const std::string candidate = dir + "/" + name;
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
            return candidate;
        start = end + 1;
    }
    return {};
}

}  // namespace quadcage::bench

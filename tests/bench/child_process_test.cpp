// run_child(): exit codes, signals, timeouts (whole process group), stderr capture, missing programs.

#include "quadcage/bench/child_process.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace {

namespace fs = std::filesystem;
using quadcage::bench::ChildOptions;
using quadcage::bench::ChildResult;
using quadcage::bench::run_child;

fs::path scratch() {
    const fs::path d = fs::temp_directory_path() / ("quadcage_child_test_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

TEST(RunChild, ExitCodeStdoutAndStderr) {
    ChildOptions o;
    o.stdout_path = (scratch() / "out.txt").string();
    o.stderr_path = (scratch() / "err.txt").string();
    std::ofstream(o.stderr_path) << "earlier stage\n";
    const ChildResult r =
        run_child({"/bin/sh", "-c", "echo hello; echo first >&2; echo 'last line' >&2; exit 7"}, o);
    EXPECT_EQ(r.end, ChildResult::End::exited);
    EXPECT_EQ(r.exit_code, 7);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.stderr_text, "first\nlast line\n");  // only this child's part of the log
    EXPECT_EQ(r.last_stderr_line(), "last line");
    std::ifstream in(o.stdout_path);
    std::string s;
    std::getline(in, s);
    EXPECT_EQ(s, "hello");
    std::ifstream log(o.stderr_path);
    std::stringstream all;
    all << log.rdbuf();
    EXPECT_EQ(all.str(), "earlier stage\nfirst\nlast line\n");  // appended
}

TEST(RunChild, SignalIsReported) {
    const ChildResult r = run_child({"/bin/sh", "-c", "kill -SEGV $$"});
    EXPECT_EQ(r.end, ChildResult::End::signalled);
    EXPECT_EQ(r.signal, SIGSEGV);
}

TEST(RunChild, TimeoutKillsTheProcessGroup) {
    const fs::path pid_file = scratch() / "grandchild.pid";
    ChildOptions o;
    o.timeout_seconds = 0.5;
    // The shell starts a background sleeper (a grandchild) and waits.
    const ChildResult r =
        run_child({"/bin/sh", "-c", "sleep 30 & echo $! > '" + pid_file.string() + "'; wait"}, o);
    EXPECT_EQ(r.end, ChildResult::End::timed_out);
    EXPECT_GE(r.seconds, 0.5);
    EXPECT_LT(r.seconds, 10.0);
    std::ifstream in(pid_file);
    int pid = 0;
    ASSERT_TRUE(in >> pid);
    // Killed with its group: gone, or a zombie waiting for init. SIGKILL is delivered
    // asynchronously, so give the kernel up to 5 s to finish it before looking.
    std::string text;
    for (int i = 0; i < 100; ++i) {
        std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
        text.clear();
        std::getline(stat, text);
        if (text.empty() || text.find(") Z") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!text.empty()) {
        EXPECT_NE(text.find(") Z"), std::string::npos) << text;
    }
}

TEST(RunChild, MissingProgramIsNotStarted) {
    const ChildResult r = run_child({"/nonexistent/quadcage-tool", "x"});
    EXPECT_EQ(r.end, ChildResult::End::not_started);
    EXPECT_NE(r.error.find("No such file"), std::string::npos) << r.error;
}

TEST(RunChild, PathLookupAndPeakMemory) {
    const ChildResult r = run_child({"true"});
    EXPECT_TRUE(r.ok());
    EXPECT_GT(r.peak_memory_mib, 0.0);
    EXPECT_FALSE(quadcage::bench::find_on_path("sh").empty());
    EXPECT_TRUE(quadcage::bench::find_on_path("no-such-program-quadcage").empty());
    EXPECT_FALSE(quadcage::bench::self_executable().empty());
}

}  // namespace

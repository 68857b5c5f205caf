#include "quadcage/core/output_dir.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <sys/stat.h>
#include <unistd.h>

#include "quadcage/core/errors.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;

// Absolute and normalised, without a trailing separator ("out/" -> "/cwd/out").
fs::path absolute_dir(const std::string& dir) {
    fs::path p = fs::absolute(dir).lexically_normal();
    if (p.filename().empty() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
    return p;
}

bool exists_no_follow(const fs::path& p) {
    std::error_code ec;
    return fs::exists(fs::symlink_status(p, ec));
}

bool is_dir(const fs::path& p) {
    std::error_code ec;
    return fs::is_directory(p, ec);
}

std::string error_text(int err) { return std::strerror(err); }

// A relative output name that stays inside the directory.
fs::path checked_relative(const std::string& relative) {
    const fs::path r = fs::path(relative).lexically_normal();
    if (r.is_absolute() || (!r.empty() && *r.begin() == ".."))
        throw InvalidInput("output name '" + relative + "' must be relative to the output directory and stay inside it");
    return r;
}

// Makes a fresh directory `<where>/.quadcage-staging-<name>-XXXXXX`; empty on failure (errno set).
std::string make_staging(const fs::path& where, const std::string& name) {
    std::string pattern = (where / (".quadcage-staging-" + name + "-XXXXXX")).string();
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data())) return {};
    return std::string(buf.data());
}

dev_t device_of(const fs::path& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 ? st.st_dev : static_cast<dev_t>(-1);
}

}  // namespace

OutputDir::OutputDir(const std::string& dir, OutputDirOptions options) : dir_(dir), options_(std::move(options)) {
    if (dir.empty()) throw InvalidInput("the output directory name is empty");
    const fs::path target = absolute_dir(dir);
    target_ = target.string();
    std::error_code ec;
    const fs::file_status st = fs::status(target, ec);
    std::vector<fs::path> candidates;  // where the staging directory may go, best first
    if (fs::exists(st)) {
        if (!fs::is_directory(st))
            throw InvalidInput(dir + ": exists and is not a directory; give a directory (or a new name) after -o");
        if (::access(target.c_str(), W_OK | X_OK) != 0)
            throw InvalidInput(dir + ": the output directory is not writable (" + error_text(errno) + ")");
        // Beside the directory when on the same file system (renames must not cross one), else inside.
        if (target.has_parent_path() && device_of(target.parent_path()) == device_of(target))
            candidates.push_back(target.parent_path());
        candidates.push_back(target);
    } else {
        // The directory will be created: its nearest existing ancestor must be a writable directory.
        fs::path up = target.parent_path();
        while (!up.empty() && !exists_no_follow(up) && up != up.parent_path()) up = up.parent_path();
        if (!is_dir(up))
            throw InvalidInput(dir + ": cannot create the output directory: " + up.string() + " is not a directory");
        if (::access(up.c_str(), W_OK | X_OK) != 0)
            throw InvalidInput(dir + ": cannot create the output directory in " + up.string() + " (" + error_text(errno) + ")");
        candidates.push_back(up);
    }
    int err = 0;
    for (const fs::path& where : candidates) {
        staging_ = make_staging(where, target.filename().string());
        if (!staging_.empty()) break;
        err = errno;
    }
    if (staging_.empty())
        throw InvalidInput(dir + ": cannot write beside or into the output directory (" + error_text(err) + ")");
}

OutputDir::~OutputDir() {
    std::error_code ec;
    if (!staging_.empty()) fs::remove_all(staging_, ec);  // after commit() only the emptied folders are left
}

void OutputDir::expect(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
    for (const std::string& in : inputs) inputs_.push_back(in);
    const fs::path target(target_);
    for (const std::string& rel : outputs) {
        const fs::path r = checked_relative(rel);
        const fs::path out = target / r;
        // Every folder on the way must be a directory (or not exist yet).
        fs::path at = target;
        for (const fs::path& part : r.parent_path()) {
            at /= part;
            if (exists_no_follow(at) && !is_dir(at))
                throw InvalidInput((fs::path(dir_) / r.parent_path()).string() + ": exists and is not a directory, so " +
                                   (fs::path(dir_) / r).string() + " cannot be written; remove it or choose another -o");
        }
        if (is_dir(out))
            throw InvalidInput((fs::path(dir_) / r).string() + ": is a directory, so the output file of that name cannot "
                               "replace it; remove it or choose another -o");
        std::error_code ec;
        for (const std::string& in : inputs_)
            if (fs::exists(out, ec) && fs::equivalent(out, in, ec))
                throw OutputConflict((fs::path(dir_) / r).string() + ": this output would replace the input " + in +
                                     "; choose another output directory (-o) or move the input");
    }
}

std::string OutputDir::path(const std::string& relative) {
    const fs::path p = fs::path(staging_) / checked_relative(relative);
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec) throw InvalidInput(dir_ + ": cannot stage " + relative + " (" + ec.message() + ")");
    return p.string();
}

std::string OutputDir::folder(const std::string& relative) {
    const fs::path p = fs::path(staging_) / checked_relative(relative);
    std::error_code ec;
    fs::create_directories(p, ec);
    if (ec) throw InvalidInput(dir_ + ": cannot stage " + relative + " (" + ec.message() + ")");
    return p.lexically_normal().string();
}

void OutputDir::commit() {
    if (committed_) throw InvalidInput(dir_ + ": the outputs were committed already");
    const fs::path staging(staging_), target(target_);
    // Every staged file, by its name relative to the directory (the backup folder is ours).
    const std::string backup_name = ".quadcage-replaced";
    std::vector<fs::path> files;
    for (auto it = fs::recursive_directory_iterator(staging); it != fs::recursive_directory_iterator(); ++it) {
        const fs::path rel = it->path().lexically_relative(staging);
        if (it.depth() == 0 && rel == backup_name) {
            it.disable_recursion_pending();
            continue;
        }
        if (!it->is_directory()) files.push_back(rel);
    }
    std::sort(files.begin(), files.end());
    // All checks first, against the directory as it is now.
    std::vector<std::string> names;
    for (const fs::path& f : files) names.push_back(f.string());
    expect(names);

    auto do_rename = [this](const fs::path& from, const fs::path& to) {
        return options_.rename ? options_.rename(from.string(), to.string()) : std::rename(from.c_str(), to.c_str());
    };
    std::vector<fs::path> created_dirs;                   // in creation order
    std::vector<std::pair<fs::path, fs::path>> replaced;  // (target, backup)
    std::vector<fs::path> placed;                         // targets that now hold a new file
    auto undo = [&] {
        std::error_code ec;
        for (auto it = placed.rbegin(); it != placed.rend(); ++it) fs::remove(*it, ec);
        for (auto it = replaced.rbegin(); it != replaced.rend(); ++it) std::rename(it->second.c_str(), it->first.c_str());
        for (auto it = created_dirs.rbegin(); it != created_dirs.rend(); ++it) fs::remove(*it, ec);  // only if empty
    };
    auto fail = [&](const fs::path& what, const std::string& why) {
        undo();
        throw InvalidInput((fs::path(dir_) / what).string() + ": " + why + "; the output directory was left as it was");
    };
    auto make_dir = [&](const fs::path& d, const fs::path& rel) {
        if (exists_no_follow(d)) return;
        if (::mkdir(d.c_str(), 0777) != 0) fail(rel, "cannot create the directory (" + error_text(errno) + ")");
        created_dirs.push_back(d);
    };
    // The directory and its parents.
    {
        std::vector<fs::path> chain;
        for (fs::path d = target; !d.empty() && !exists_no_follow(d) && d != d.parent_path(); d = d.parent_path())
            chain.push_back(d);
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) make_dir(*it, "");
    }
    const fs::path backups = staging / backup_name;
    for (const fs::path& rel : files) {
        fs::path at = target;
        fs::path so_far;
        for (const fs::path& part : rel.parent_path()) {
            at /= part;
            so_far /= part;
            make_dir(at, so_far);
        }
        const fs::path to = target / rel;
        if (exists_no_follow(to)) {
            const fs::path keep = backups / rel;
            std::error_code ec;
            fs::create_directories(keep.parent_path(), ec);
            if (ec) fail(rel, "cannot set the old file aside (" + ec.message() + ")");
            if (do_rename(to, keep) != 0) fail(rel, "cannot set the old file aside (" + error_text(errno) + ")");
            replaced.push_back({to, keep});
        }
        if (do_rename(staging / rel, to) != 0) fail(rel, "cannot move the new file in (" + error_text(errno) + ")");
        placed.push_back(to);
    }
    committed_ = true;
}

}  // namespace quadcage

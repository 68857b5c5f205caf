#pragma once
// Running one stage of a benchmark in its own process: isolated from crashes, bounded in time.

#include <string>
#include <vector>

namespace quadcage::bench {

/// Options for run_child().
struct ChildOptions {
    double timeout_seconds = 0;  ///< Wall-clock limit (> 0); 0 = none. On expiry the whole process group is killed.
    std::string stdout_path;     ///< File that receives the child's stdout (truncated); empty: /dev/null.
    std::string stderr_path;     ///< File the child's stderr is appended to; empty: /dev/null.
};

/// How a child ended.
struct ChildResult {
    enum class End { exited, signalled, timed_out, not_started };
    End end = End::not_started;
    int exit_code = -1;            ///< When exited.
    int signal = 0;                ///< When signalled (or the signal that ended a timed-out child).
    double seconds = 0;            ///< Wall-clock time.
    double peak_memory_mib = 0;    ///< Peak resident memory of the child (and its reaped descendants).
    std::string stderr_text;       ///< What this child wrote to stderr (its last 64 KiB).
    std::string error;             ///< Why it did not start (not_started).

    bool ok() const { return end == End::exited && exit_code == 0; }  ///< Exited with status 0.
    /// Last non-empty line of stderr_text ("" if none).
    std::string last_stderr_line() const;
};

/// Runs argv[0] (a path, or a name looked up on PATH) with arguments argv[1..] in a new process
/// group, stdin from /dev/null, and waits for it (or kills the group at the timeout). Safe to call
/// from several threads at once. Never throws for a child that fails: the result says what happened.
/// \throw InvalidInput if argv is empty or an output file cannot be opened.
ChildResult run_child(const std::vector<std::string>& argv, const ChildOptions& options = {});

/// Absolute path of the running executable (/proc/self/exe); empty if unknown.
std::string self_executable();

/// Full path of `name` found on $PATH as an executable file; empty if not found.
std::string find_on_path(const std::string& name);

}  // namespace quadcage::bench

#pragma once
// All-or-nothing output directories: every command's files are staged beside the directory and moved
// in together, so a failed run leaves the directory as it was and never replaces an input.

#include <functional>
#include <string>
#include <vector>

namespace quadcage {

/// Options for OutputDir.
struct OutputDirOptions {
    /// The rename(2) used by commit() (returns 0 or -1 with errno set). Tests replace it to make a
    /// given move fail; empty: ::rename.
    std::function<int(const std::string& from, const std::string& to)> rename;
};

/// The files of one run, written into a directory all at once.
///
/// Usage: construct (checks that the directory is usable and makes a staging directory beside it),
/// expect() the outputs and name the inputs (checked before the work starts), write each file at
/// path() (or into folder()), then commit(). Destroying an OutputDir without commit() removes what
/// was staged; the directory itself is never touched before commit().
///
/// A successful commit() replaces the outputs it moves in and leaves every other file in the
/// directory alone. Files are moved by rename within one file system; when one move fails, the moves
/// already made are undone (replaced files come back), so the directory is as it was.
class OutputDir {
public:
    /// \param dir the output directory; created at commit() if missing (with its parents).
    /// \throw InvalidInput (naming dir) if dir is a file, or cannot be created or written (its nearest
    ///        existing ancestor is not a writable directory), or no staging directory can be made.
    explicit OutputDir(const std::string& dir, OutputDirOptions options = {});
    ~OutputDir();
    OutputDir(const OutputDir&) = delete;
    OutputDir& operator=(const OutputDir&) = delete;

    /// Checks, before the work starts, the outputs the run will write (paths relative to the
    /// directory, e.g. "component_1/cage.obj") against the directory as it is now, and remembers the
    /// inputs for commit() to check again.
    /// \throw InvalidInput (naming the path) if an output's name is taken by a directory or a folder on
    ///        its way is a file; OutputConflict if an output is (the same file as) one of `inputs`.
    void expect(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs = {});

    /// Where to write output `relative` now (in the staging directory, whose folders are created).
    /// \throw InvalidInput if `relative` is absolute or leaves the directory ("..").
    std::string path(const std::string& relative);

    /// A staging folder for a writer that puts several files into one directory (e.g. "component_0"
    /// or "" for the directory itself). Every file written there is an output.
    std::string folder(const std::string& relative);

    /// Moves every staged file into the directory (created if missing), replacing files of the same
    /// name; all or nothing.
    /// \throw InvalidInput (naming the file) if a move fails or a name is taken by a directory, and
    ///        OutputConflict if an output would replace an input; the directory is then as it was.
    void commit();

    /// The output directory as given.
    const std::string& dir() const { return dir_; }

private:
    std::string dir_;          // as given (for messages)
    std::string target_;       // absolute, normalised
    std::string staging_;      // absolute staging directory
    std::vector<std::string> inputs_;
    OutputDirOptions options_;
    bool committed_ = false;
};

}  // namespace quadcage

#pragma once
// Helpers shared by the tests: the shared real meshes, scratch directories, shell commands and the
// independent Python checkers in ../shared/tools.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/validate.h"
#include "support/names.h"

namespace quadcage::test {

namespace fs = std::filesystem;

inline fs::path shared_meshes_dir() {
    return fs::path(QUADCAGE_SHARED_DIR) / "data" / "meshes";
}
inline bool have_shared_meshes() {
    return fs::is_directory(shared_meshes_dir());
}
inline fs::path shared_tool(const std::string& name) {
    return fs::path(QUADCAGE_SHARED_DIR) / "tools" / name;
}

/// A shared real mesh made ready for the pipeline (its single component).
inline Mesh load_shared(const std::string& file) {
    const std::string path = (shared_meshes_dir() / file).string();
    const PreparedMesh prepared = prepare_for_quadding(read_mesh(path), path);
    QC_CHECK(prepared.components.size() == 1, path + " has more than one component");
    return prepared.components[0];
}

/// Genus of a mesh that must be one closed, manifold, consistently oriented component; -1 if not.
inline int closed_genus(const Mesh& mesh) {
    const ValidationReport r = validate(mesh);
    if (!r.quaddable() || r.components.size() != 1 || !r.components[0].consistently_oriented) return -1;
    return r.components[0].genus;
}

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs a shell command; returns its exit status (128 + signal if killed).
inline int run_shell(const std::string& command) {
    const int status = std::system(command.c_str());
    if (status == -1) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

inline std::string shell_quoted(const fs::path& p) {
    return "'" + p.string() + "'";
}

/// A fresh scratch directory for the running test (the caller removes it).
inline fs::path scratch_dir(const std::string& prefix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = identifier(std::string(info->test_suite_name()) + "_" + info->name());
    const fs::path dir = fs::temp_directory_path() / (prefix + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

/// Why the Python checkers cannot run here, or "" if they can.
inline std::string python_unavailable() {
    if (!fs::exists("/usr/bin/python3")) return "/usr/bin/python3 is missing";
    if (run_shell("/usr/bin/python3 -c 'import numpy, scipy' >/dev/null 2>&1") != 0)
        return "/usr/bin/python3 cannot import numpy and scipy";
    return "";
}

/// Runs `command` with its output into `log_file`; returns the exit status and the output.
inline int run_logged(const std::string& command, const fs::path& log_file, std::string* log) {
    const int code = run_shell(command + " >" + shell_quoted(log_file) + " 2>&1 </dev/null");
    *log = slurp(log_file);
    return code;
}

/// report.json without the lines of its measurements of the run itself (wall-clock time, memory),
/// which legitimately differ between two runs; everything else must be identical.
inline std::string report_without_measurements(const fs::path& report) {
    std::istringstream in(slurp(report));
    std::string line, out;
    bool in_seconds = false;
    while (std::getline(in, line)) {
        if (line.find("\"seconds\":") != std::string::npos) {
            in_seconds = line.find('{') != std::string::npos && line.find('}') == std::string::npos;
            continue;
        }
        if (in_seconds) {
            if (line.find('}') != std::string::npos) in_seconds = false;
            continue;
        }
        if (line.find("\"peak_memory_mib\":") == std::string::npos) out += line + "\n";
    }
    return out;
}

}  // namespace quadcage::test

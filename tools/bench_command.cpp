// `quadcage bench`: many meshes, every stage in a child process, tables and pictures (issue #6).

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "quadcage/bench/bench_runner.h"
#include "quadcage/bench/child_process.h"
#include "quadcage/bench/inputs.h"
#include "quadcage/bench/tables.h"
#include "quadcage/core/errors.h"

namespace quadcage::cli {
namespace {

// "0,1,2,3" -> {0, 1, 2, 3}; "" or "none" -> {}.
std::vector<int> parse_levels(const std::string& text) {
    std::vector<int> levels;
    if (text.empty() || text == "none") return levels;
    std::stringstream s(text);
    for (std::string item; std::getline(s, item, ',');) {
        size_t used = 0;
        int v = -1;
        try {
            v = std::stoi(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size())
            throw InvalidInput("--levels '" + text + "': '" + item + "' is not a whole number (e.g. --levels 0,1,2,3)");
        levels.push_back(v);
    }
    return levels;
}

// The QuadriFlow script: PREFIX/share/quadcage/quadriflow.py beside an installed executable, else
// the source tree's tools/bench/quadriflow.py (a build tree). If neither exists, the installed path:
// the peer column then says "peer script not found (<path>)" and the bench goes on.
std::string default_peer_script(const std::string& executable) {
    std::error_code ec;
    const std::filesystem::path installed =
        std::filesystem::path(executable).parent_path() / QUADCAGE_PEER_SCRIPT_FROM_BIN;
    if (!executable.empty() && std::filesystem::exists(installed, ec))
        return installed.lexically_normal().string();
    if (std::filesystem::exists(QUADCAGE_PEER_SCRIPT, ec)) return QUADCAGE_PEER_SCRIPT;
    return executable.empty() ? std::string(QUADCAGE_PEER_SCRIPT) : installed.lexically_normal().string();
}

}  // namespace

int run_bench(const BenchCommandOptions& o) {
    bench::BenchOptions b;
    b.output_dir = o.output_dir;
    b.levels = parse_levels(o.levels);
    b.tolerance = o.tolerance;
    b.fit_rounds = o.rounds;
    b.turned_over_weight = o.turned_over_weight;
    b.jobs = o.jobs;
    b.timeout_seconds = o.timeout_seconds;
    b.peer = !o.no_peer;
    b.pictures = !o.no_pictures;
    b.blender = o.blender;
    b.executable = bench::self_executable();
    b.peer_script = o.peer_script.empty() ? default_peer_script(b.executable) : o.peer_script;
    b.layout_flags = embedding_arguments(o.embedding);
    if (b.executable.empty()) throw InternalError("cannot find the quadcage executable (/proc/self/exe)");
    if (const std::string e = b.validate(); !e.empty()) throw InvalidInput("bench: " + e);
    b.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

    const std::vector<bench::BenchInput> inputs = bench::expand_inputs(o.paths);
    std::fprintf(stderr, "bench: %zu mesh%s, levels %s, %d job%s, timeout %g s per stage, peer %s\n", inputs.size(),
                 inputs.size() == 1 ? "" : "es", o.levels.c_str(), o.jobs, o.jobs == 1 ? "" : "s", o.timeout_seconds,
                 !b.peer ? "disabled" : bench::find_on_path(b.blender).empty() ? "not installed" : "QuadriFlow (Blender)");
    const bench::BenchResult result = bench::run_bench(inputs, b);
    bench::write_bench_tables(o.output_dir, result);
    std::printf("%s\n", bench::summary_line(result).c_str());
    const std::filesystem::path d(o.output_dir);
    std::printf("wrote %s, %s, %s\n", (d / "bench.csv").c_str(), (d / "bench.json").c_str(), (d / "bench.md").c_str());
    return kOk;
}

}  // namespace quadcage::cli

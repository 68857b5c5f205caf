#pragma once
// `quadcage bench`: run info, layout and fit (and pictures, and the QuadriFlow peer) on many meshes,
// each stage in its own child process, and collect the results. Issue #6.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "quadcage/bench/inputs.h"
#include "quadcage/bench/results.h"

namespace quadcage::bench {

/// The command line of each stage, as argv templates. Placeholders, replaced in every argument:
/// {exe} the quadcage executable, {mesh} the input mesh, {dir} the stage's output folder,
/// {level} the subdivision level, {input} the render input, {png} the picture, {kind} the picture
/// kind, {title} its title, {blender} the Blender executable, {script} the peer script,
/// {out} the peer's output OBJ, {faces} the peer's target face count, {seed} QuadriFlow's seed,
/// {cage} the peer's remesh to fit.
struct StageCommands {
    std::vector<std::string> info = {"{exe}", "info", "{mesh}", "--json"};
    std::vector<std::string> layout = {"{exe}", "layout", "{mesh}", "-o", "{dir}"};
    std::vector<std::string> fit = {"{exe}", "fit", "{mesh}", "-o", "{dir}", "--level", "{level}"};
    std::vector<std::string> render = {"{exe}", "render", "{input}", "-o", "{png}", "--kind", "{kind}",
                                       "--title", "{title}", "-q"};
    std::vector<std::string> peer = {"{blender}", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
                                     "--python", "{script}",
                                     "--", "{mesh}", "{out}", "{faces}", "{seed}"};
    /// Our fitter on the peer's remesh, its own vertices as the unknowns.
    std::vector<std::string> peer_fit = {"{exe}", "fit", "{mesh}", "--cage", "{cage}", "--level", "0", "-o", "{dir}"};
};

/// Options for run_bench().
struct BenchOptions {
    std::string output_dir;          ///< Receives bench.csv/json/md, plot.png and meshes/<name>/ (created).
    std::vector<int> levels = {0, 1, 2, 3};  ///< Fit levels, each 0..8; may be empty (no fits).
    double tolerance = 0;            ///< If > 0, `--tolerance T` is appended to every fit command.
    /// If > 0, `--rounds N` is appended to every fit command, ours and the peer's alike, so the
    /// equal-control-point comparison runs one fitter on both cages (fit's default: 16).
    int fit_rounds = 0;
    /// If set, `--turned-over-weight W` is appended to every fit command, ours and the peer's alike
    /// (unset: fit's default), so both surfaces are kept from pleating alike, or (0) neither is.
    std::optional<double> turned_over_weight;
    int jobs = 1;                    ///< Meshes processed at the same time (1..64).
    double timeout_seconds = 1800;   ///< Wall-clock limit of every child process (> 0).
    bool pictures = true;            ///< Run the render stage after layout and after each fit.
    bool peer = true;                ///< Run the QuadriFlow peer when Blender is found.
    int peer_attempts = 4;           ///< QuadriFlow calls per mesh and level at most (1..16).
    std::string executable;          ///< {exe}: the quadcage executable (required).
    std::string blender = "blender"; ///< {blender}: path or name on PATH; not found -> peer "not installed".
    std::string peer_script;         ///< {script}: tools/bench/quadriflow.py; required when the peer runs.
    StageCommands commands;          ///< Stage command lines (tests substitute fake children).
    /// Appended to the layout command and to every fit of our layout, not to the peer's fit: e.g.
    /// `--embedding-iterations 30 --embedding-extract`, to compare the embedding stage with the peer.
    std::vector<std::string> layout_flags;
    /// Progress lines ("bench [i/n] name: stage (t s)"); called from worker threads, one call at a time.
    std::function<void(const std::string&)> progress;
    std::string validate() const;    ///< Empty if valid, else what is wrong.
};

/// Runs every stage of every input (see the issue): info (exit 3 -> "rejected"), layout, the
/// layout picture, fit at each level with its deviation picture, and the peer at each level; a
/// crash, timeout or error of one child is recorded and the run goes on. A failed layout skips that
/// mesh's fits.
///
/// The peer at level K (issue #19): QuadriFlow remeshes the input at T = quads * 4^K faces, our
/// level-K control-face count. A closed quad mesh has V = F + 2 - 2g vertices, so T is also our
/// level-K control points + 2g - 2: the remesh's vertices, the unknowns of its level-0 fit, then
/// match our control points (at level 0 too: 10g-10 quads, 8g-8 corners). A remesh that is a closed,
/// manifold, consistently oriented quad mesh of the input's genus (peer_cage_problem()) with a vertex
/// count within 10% of our control points is fitted by the `peer_fit` command. Otherwise QuadriFlow
/// runs again, at most `peer_attempts` times in all: after a remesh whose count is off, at the
/// target scaled by ours / its vertices; after an invalid one (or one the fit rejects), with seeds 1
/// and 2, then at T +5%, -5%, +10%, -10% (seed 0). Every attempt is recorded with its reason. If no
/// attempt matched the count, the valid remesh with the closest count is fitted (its ratios then do
/// not count).
/// Writes each child's stderr to DIR/meshes/<name>/log.txt, info's JSON to .../info.json; writes
/// the plot (DIR/plot.png) but not the tables (see write_bench_tables()).
/// \throw InvalidInput if the options are invalid or the output folder cannot be created.
BenchResult run_bench(const std::vector<BenchInput>& inputs, const BenchOptions& options);

}  // namespace quadcage::bench

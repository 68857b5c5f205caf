#pragma once
// What a benchmark run found, per mesh, per subdivision level and per peer remesh. Every measured
// value is optional: a stage that did not run or did not report it leaves it empty ("-" in tables).

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "quadcage/bench/inputs.h"

namespace quadcage::bench {

/// One Catmull-Clark fit of a mesh at one level (`quadcage fit --level K`).
struct LevelResult {
    int level = 0;
    std::string status = "-";             ///< "ok", "rejected", "failed: ...", "skipped" or "-" (not run).
    std::string reason;                   ///< For rejected: the stage's error line.
    std::optional<int> control_points;
    std::optional<double> relative_rms;   ///< RMS distance over the bounding-box diagonal.
    std::optional<double> relative_hausdorff;
    std::optional<double> fit_seconds;    ///< As reported by the fit ("seconds.total").
    std::optional<double> peak_memory_mib;  ///< Of the fit process.
    std::string deviation_png;            ///< Relative to the run's output folder; empty if none.
};

/// QuadriFlow's remesh of the mesh at one target face count.
struct PeerResult {
    std::string target;                   ///< "minimal" (our minimal quad count) or "level2" (16 times it).
    std::optional<int> target_faces;
    std::string status = "-";             ///< "ok", "empty", "not installed", "disabled", "not run (...)", "failed: ...".
    std::optional<int> faces, quads, genus, irregular_vertices;
    std::optional<double> seconds;        ///< QuadriFlow alone, as timed inside Blender.
};

/// Everything measured for one mesh.
struct MeshResult {
    BenchInput input;
    std::string status = "-";             ///< "ok", "rejected" or "failed: ..." (the first failure).
    std::string stage;                    ///< Stage of that failure ("info", "layout", "fit", ...); "" if ok.
    std::string reason;                   ///< For rejected: the error line of the stage.
    // info
    std::optional<int> triangles, components, minimal_quads;
    std::string genus;                    ///< "2", or per component "2+0"; "" if unknown.
    // layout
    std::optional<int> quads, corners, edges;
    std::map<int, int> corner_degrees;    ///< Degree -> number of corners.
    std::optional<bool> verified;         ///< The layout verifier's verdict.
    std::optional<double> layout_seconds;
    std::optional<double> peak_memory_mib;  ///< Of the layout process (rusage; else its report).
    std::string layout_png;               ///< Relative to the run's output folder; empty if none.
    std::vector<LevelResult> levels;
    std::vector<PeerResult> peers;
    double wall_seconds = 0;              ///< All stages of this mesh.
    std::vector<std::string> notes;       ///< Things worth knowing that are not failures (a picture not drawn).
};

/// A whole run.
struct BenchResult {
    std::vector<MeshResult> meshes;       ///< In input order.
    std::vector<int> levels;              ///< Levels requested.
    double wall_seconds = 0;
    std::string plot_png;                 ///< RMS against control points; relative path, empty if none.
};

/// Totals for the summary line.
struct BenchSummary {
    int meshes = 0, ok = 0, rejected = 0, failed = 0;
    long long triangles = 0;
    double layout_seconds = 0, fit_seconds = 0, wall_seconds = 0;
};

/// Counts and totals of `result`.
BenchSummary summarize(const BenchResult& result);

/// "bench: 5 meshes: 3 ok, 1 rejected, 1 failed; 123456 triangles; layout 12.3 s, fit 45.6 s,
/// wall 70.1 s".
std::string summary_line(const BenchResult& result);

}  // namespace quadcage::bench

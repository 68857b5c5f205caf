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

/// One QuadriFlow call of a peer fit.
struct PeerAttempt {
    int target_faces = 0;
    int seed = 0;
    /// "ok" (used, or kept as the closest count), or why not: "empty output (no faces)", "wrong genus
    /// 1 (input 2)", "open (8 boundary edges)", "not all quads (...)", "control points 620 not within
    /// 10% of ours 1276", "failed: timeout after 1800 s", "fit rejected: ...", ...
    std::string outcome;
    std::optional<int> faces, quads, vertices, genus;
    std::optional<double> seconds;        ///< QuadriFlow alone, as timed inside Blender.
};

/// The peer at one level K: QuadriFlow's remesh at our level-K control-face count, fitted by our own
/// fitter at level 0 (`quadcage fit MESH --cage qf.obj --level 0`), so that both surfaces have about
/// the same number of control points as unknowns.
struct PeerResult {
    int level = 0;
    std::optional<int> target_faces;      ///< Our level-K control faces: quads * 4^K (= control points + 2g - 2).
    /// "ok" (fitted), "not installed", "disabled", "not run (...)", "failed: <the last attempt's reason>",
    /// "fit failed: ..." (a valid remesh our fitter did not fit).
    std::string status = "-";
    std::vector<PeerAttempt> attempts;    ///< Every QuadriFlow call, in order.
    std::string cage;                     ///< The remesh fitted, relative to the run's output folder.
    std::optional<int> faces, quads, irregular_vertices;  ///< Of that remesh.
    std::optional<int> control_points;    ///< Of the fit (the remesh's vertices).
    std::optional<double> relative_rms;   ///< Of the fit, over the bounding-box diagonal.
    std::optional<double> relative_hausdorff;
    std::optional<double> fit_seconds;    ///< As the fit reports it ("seconds.total").
    std::optional<double> quadriflow_seconds;  ///< QuadriFlow's own time for the remesh fitted.
};

/// Our fit against the peer's at one level: ratios ours / peer (below 1: ours is more accurate).
struct PeerComparison {
    std::optional<double> rms_ratio, hausdorff_ratio;  ///< Set only when the ratio counts.
    /// Why there is no ratio: "n/a (1200 vs 980 control points)", "n/a (peer: failed: ...)", ...; ""
    /// when the ratios count.
    std::string note;
    bool counted() const { return rms_ratio.has_value(); }
};

/// Largest ratio of two control-point counts for which the ratios count (10%: max/min <= 1.1).
constexpr double kPeerCountTolerance = 1.1;

/// Compares our level `ours` with the peer at the same level. The ratios count when both fits
/// reported control points and errors, and the counts are within 10% of each other (max/min <= 1.1).
PeerComparison compare_with_peer(const LevelResult& ours, const PeerResult* peer);

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
    std::vector<PeerResult> peers;        ///< One per level of the run (none without levels).
    double wall_seconds = 0;              ///< All stages of this mesh.
    std::vector<std::string> notes;       ///< Things worth knowing that are not failures (a picture not drawn).
};

/// A whole run.
struct BenchResult {
    std::vector<MeshResult> meshes;       ///< In input order.
    std::vector<int> levels;              ///< Levels requested.
    std::vector<std::string> layout_flags;  ///< BenchOptions::layout_flags: how our layouts were made.
    int fit_rounds = 0;                   ///< BenchOptions::fit_rounds (0: fit's default).
    std::optional<double> turned_over_weight;  ///< BenchOptions::turned_over_weight (unset: fit's default).
    double wall_seconds = 0;
    std::string plot_png;                 ///< RMS against control points; relative path, empty if none.
};

/// Totals for the summary line.
struct BenchSummary {
    int meshes = 0, ok = 0, rejected = 0, failed = 0;
    long long triangles = 0;
    double layout_seconds = 0, fit_seconds = 0, wall_seconds = 0;
    int peer_rows = 0;                    ///< Rows (mesh x level) whose ratios ours / peer count.
    std::optional<double> rms_ratio_worst, rms_ratio_median;  ///< Over those rows; worst = largest.
    std::optional<double> hausdorff_ratio_worst, hausdorff_ratio_median;
};

/// Counts and totals of `result`.
BenchSummary summarize(const BenchResult& result);

/// "bench: 5 meshes: 3 ok, 1 rejected, 1 failed; 123456 triangles; layout 12.3 s, fit 45.6 s,
/// wall 70.1 s; ours / QuadriFlow over 4 rows: RMS worst 1.52 median 1.10, Hausdorff worst 4.1
/// median 2.2" (the last part "...: no row at equal control points" when none counts; absent when
/// no peer ran).
std::string summary_line(const BenchResult& result);

}  // namespace quadcage::bench

#pragma once
// The CLI's commands: each parses nothing itself; quadcage.cpp fills the options and calls one.

#include <optional>
#include <string>
#include <vector>

#include "quadcage/fit/fit.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::cli {

/// Exit codes of every command.
enum ExitCode { kOk = 0, kInternalError = 1, kUsage = 2, kInvalidInput = 3 };

struct InfoOptions {
    std::string mesh;
    bool json = false;
};
int run_info(const InfoOptions& options);

int run_version();

struct CyclesOptions {
    std::string mesh;
    std::string output_dir;
    bool quiet = false;  ///< No progress on stderr.
};
int run_cycles(const CyclesOptions& options);

/// The experimental embedding stage's flags (issue #20), shared by `layout` and `fit`; each is the
/// layout::QuadLayoutOptions field of the same name with the embedding_ prefix.
struct EmbeddingFlags {
    int iterations = 0;
    bool extract = false;
    double area_weight = 0;
    double conformal_weight = 0;
    double cone_conformal_weight = 0;
    int cone_sweeps = 0;
    bool staircase_edges = false;  ///< --staircase-edges: the layout edges not smoothed
    bool no_necks = false;         ///< --no-necks: the S-cycles from the handle loops, not the necks
    bool no_long_edge_splits = false;  ///< --no-long-edge-splits: the input's long edges not split first
    bool choose_by_shape = false;  ///< --choose-s-cycles shape: by patch areas and angles, not a level-1 fit
    /// --edge-embedding N: Newton iterations of the global edge embedding (0: off)
    int edge_embedding = quadcage::layout::QuadLayoutOptions{}.edge_embedding_iterations;
    /// --edge-embedding-max-vertices N: above this many layout-mesh vertices it is skipped
    int edge_embedding_max_vertices = quadcage::layout::QuadLayoutOptions{}.edge_embedding_max_vertices;
    /// --edge-embedding-cone-charts S: the edge embedding's pull towards the corners' cone charts
    double edge_embedding_cone_charts = quadcage::layout::QuadLayoutOptions{}.edge_embedding_cone_charts;
    /// --edge-embedding-area-weight W: the weight of an area term in the edge embedding's energy
    double edge_embedding_area_weight = quadcage::layout::QuadLayoutOptions{}.edge_embedding_area_weight;
    /// --proxy-vertices N: build the layout on a copy decimated to N vertices (0: never)
    int proxy_vertices = quadcage::layout::QuadLayoutOptions{}.proxy_vertices;
    /// --proxy-above M: only for inputs of more than M vertices
    long long proxy_above = quadcage::layout::QuadLayoutOptions{}.proxy_above;
};

/// The flags as `layout`/`fit` arguments: only those that differ from the defaults.
std::vector<std::string> embedding_arguments(const EmbeddingFlags& flags);

struct LayoutOptions {
    std::string mesh;
    std::string output_dir;
    bool quiet = false;  ///< No progress on stderr.
    EmbeddingFlags embedding;
};
int run_layout(const LayoutOptions& options);

struct FitCommandOptions {
    std::string mesh;
    std::string output_dir;
    int level = 3;            ///< --level K (used unless a tolerance is given).
    double tolerance = 0;     ///< --tolerance T: fit levels 0, 1, ... until the relative RMS <= T.
    int max_level = 5;        ///< --max-level with --tolerance.
    std::string cage;         ///< --cage CAGE: fit this control mesh instead of building a layout.
    std::string solver = "direct";  ///< --solver: direct or ceres (fit::FitSolver).
    int rounds = fit::FitOptions{}.outer_iterations;  ///< --rounds N: solve / correspondence rounds a level.
    int extra_rounds = fit::FitOptions{}.extra_rounds;  ///< --extra-rounds N: fit::FitOptions::extra_rounds.
    double tangential_weight = fit::FitOptions{}.tangential_weight;  ///< --tangential-weight W: fit::FitOptions::tangential_weight.
    double turned_over_weight = fit::FitOptions{}.turned_over_weight;  ///< --turned-over-weight W: fit::FitOptions::turned_over_weight.
    double limit_max_error = 0;     ///< --limit-max-error R: limit.ply within R of the diagonal everywhere measured.
    bool plane_feet_only = false;   ///< --plane-feet-only: fit::FitOptions::surface_feature_feet off.
    std::string step;         ///< --step FILE: also export the fitted surface as a STEP solid.
    std::string iges;         ///< --iges FILE: ... and/or as IGES.
    double cad_tolerance = 1e-5;  ///< --cad-tolerance T (relative to the diagonal).
    bool json = false;        ///< Print report.json instead of the summary.
    bool quiet = false;       ///< No progress on stderr.
    EmbeddingFlags embedding;  ///< For the layout (not with --cage).
};
int run_fit(const FitCommandOptions& options);

/// `export DIR`: the fit in DIR as a B-rep solid (STEP and/or IGES; issue 22).
struct ExportOptions {
    std::string dir;              ///< Written by `fit`.
    std::string step;             ///< --step FILE (default DIR/surface.step when neither is given).
    std::string iges;             ///< --iges FILE.
    double cad_tolerance = 1e-5;  ///< --cad-tolerance T, relative to the fit's diagonal, >= 1e-9.
    bool json = false;
    bool quiet = false;
};
int run_export(const ExportOptions& options);

struct GenerateOptions {
    std::string shape;   ///< "sphere", "torus", "plate", "limbs", "handles" or "wheel".
    int genus = 2;       ///< plate, handles, wheel (at least 1: the axle).
    int resolution = 2;  ///< plate: grid cells per unit; sphere, limbs: subdivisions; torus: segments / 8;
                         ///< handles, wheel: voxels per cell.
    bool in_a_row = false;  ///< handles only: side by side along one edge.
    int limbs = 4;       ///< limbs only: protrusions.
    unsigned seed = 1;   ///< limbs: which figure; handles: where the bumps and fins go.
    int bumps = 0;       ///< handles only: bumps and dents on the body.
    int fins = 0;        ///< limbs, handles: thin, flat protrusions.
    int ribs = 0;        ///< wheel only: radial ribs round the hub.
    bool cad = false;    ///< wheel only: flat faces as fans of long, thin triangles (a CAD export's).
    std::string output;
};
int run_generate(const GenerateOptions& options);

struct SubdivideOptions {
    std::string mesh;
    int times = 1;
    std::string output;
};
int run_subdivide(const SubdivideOptions& options);

struct RenderCommandOptions {
    std::string input;          ///< A mesh file, or a directory written by `layout` / `fit`.
    std::string output;         ///< PNG file.
    std::string kind = "auto";  ///< "layout", "deviation", "plain" or "auto" (from the input).
    std::string size = "1200x600";
    std::string title;          ///< Empty: the input's file name.
    bool quiet = false;
};
int run_render(const RenderCommandOptions& options);

struct BenchCommandOptions {
    std::vector<std::string> paths;  ///< Meshes, folders of meshes, manifests (.txt).
    std::string output_dir;
    std::string levels = "0,1,2,3";
    double tolerance = 0;            ///< > 0: passed to fit as --tolerance.
    int rounds = 0;                  ///< > 0: passed to every fit (ours and the peer's) as --rounds.
    /// Given: passed to every fit (ours and the peer's) as --turned-over-weight.
    std::optional<double> turned_over_weight;
    int jobs = 1;
    double timeout_seconds = 1800;   ///< Per child process.
    bool no_peer = false;
    bool no_pictures = false;
    std::string blender = "blender";
    std::string peer_script;         ///< Empty: the repository's tools/bench/quadriflow.py.
    EmbeddingFlags embedding;        ///< Passed to our layout and fits (bench::BenchOptions::layout_flags).
};
int run_bench(const BenchCommandOptions& options);

/// A single output file's extension in lower case (".ply"); InvalidInput naming the file unless it
/// is one of `allowed`, before any work: a command writes one format by name and must not put it
/// under another's.
std::string output_extension(const std::string& path, const std::vector<std::string>& allowed);

}  // namespace quadcage::cli

#pragma once
// The files of `quadcage fit`: fitted_cage.obj, limit.ply, deviation.ply, report.json (issue #5).
// Every writer is atomic (temporary file + rename) and independent of the CLI.

#include <optional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit {

/// Options for the limit-surface tessellation written to limit.ply.
struct LimitPlyOptions {
    double error_fraction = 0.1;          ///< Tessellation RMS error must be below this fraction of the
                                          ///< fit's absolute symmetric RMS, in (0, 1].
    double max_error_relative = 0;        ///< If > 0: the largest measured |tessellation - limit| must
                                          ///< also be below this fraction of the bounding-box diagonal
                                          ///< (for checks of points on the limit surface against limit.ply).
    long long max_triangles = 20000000;   ///< Upper bound on the tessellation size, >= 2 * faces.
    int min_segments = 2;                 ///< Fewest segments per face side, >= 1.
    int estimate_faces = 512;             ///< Faces (evenly spread) on which the error is estimated, >= 1.
    int estimate_points_per_face = 32;    ///< Random points per such face, >= 1.
    unsigned seed = 11;
    int threads = 0;                      ///< 0 = all cores.
    std::string validate() const;         ///< Empty if valid, else what is wrong.
};

/// A tessellation density and its measured error.
struct TessellationChoice {
    int segments = 0;          ///< Segments per face side (each face becomes 2 * segments^2 triangles).
    long long triangles = 0;
    double rms_error = 0;      ///< RMS of |tessellation - limit| at the same (u, v), random points (absolute).
    double max_error = 0;      ///< Largest such distance seen.
    double target = 0;         ///< The RMS it had to stay below (absolute).
    bool met = false;          ///< rms_error <= target (false if max_triangles stopped the refinement).
    /// Set by write_fit_files() (else -1): folded_area_fraction() of the tessellation written, the
    /// share of the fitted surface on the creases where it folds back on itself (pleats a fit can
    /// leave close to the input, where its distances do not see them) ...
    double folded_area_fraction = -1;
    double input_folded_area_fraction = -1;  ///< ... and of the input mesh, whose own sharp creases count too.
    /// Set by write_fit_files() (else -1): the share of the tessellation's area turned over against
    /// the input: triangles whose normal points against the normal of the input's triangle at the
    /// closest input point of each of their three vertices (a pleat's middle sheet, whole).
    double inverted_area_fraction = -1;
};

/// The error of a tessellation with `segments` per side: distance between the flat triangles and
/// the limit surface at the same parameter, at random points of evenly spread faces (an upper bound
/// on the distance from the triangles to the surface).
/// \throw InvalidInput if segments < 1, options are invalid or the surface is empty.
TessellationChoice tessellation_error(const FittedSurface& surface, int segments, const LimitPlyOptions& options = {});

/// The coarsest uniform tessellation (error ~ 1/segments^2, refined until measured) whose RMS error
/// is at most options.error_fraction * fit_rms and, with options.max_error_relative > 0, whose
/// measured max error is at most options.max_error_relative * diagonal, within options.max_triangles.
/// \throw InvalidInput if fit_rms is not positive and finite, options are invalid, the surface is
///        empty, or max_error_relative > 0 without a positive diagonal.
TessellationChoice choose_tessellation(const FittedSurface& surface, double fit_rms, const LimitPlyOptions& options = {},
                                       double diagonal = 0);

/// Writes a quad mesh as OBJ (`v` with 17 significant digits, `f` with 4 one-based indices).
/// \throw InvalidInput (naming path) if the file cannot be written.
void write_quad_obj(const std::string& path, const subdiv::QuadMesh& mesh);

/// Writes a polygon mesh as OBJ (as write_quad_obj()).
/// \throw InvalidInput (naming path) if the file cannot be written.
void write_polygon_obj(const std::string& path, const PolygonMesh& mesh);

/// Writes the tessellation of `choice.segments` of the surface as binary PLY with the per-vertex
/// `float distance` to `input` (exact closest point); returns `choice` with folded_area_fraction,
/// input_folded_area_fraction and inverted_area_fraction set.
/// \throw InvalidInput if the file cannot be written or the input mesh is invalid.
TessellationChoice write_limit_ply(const std::string& path, const Mesh& input, const FittedSurface& surface,
                     const TessellationChoice& choice, int threads = 0);

/// Writes `input` as binary PLY with the per-vertex `float distance` to the fitted limit surface.
/// \throw InvalidInput if the file cannot be written.
void write_deviation_ply(const std::string& path, const Mesh& input, const FittedSurface& surface, int threads = 0);

/// The report of a fit (report.json of write_fit_outputs(); `quadcage fit` adds its run fields
/// beside these, see fit/mesh_fit.h). Distances in LevelReport as there: absolute in the mesh's
/// units, relative to the bounding-box diagonal.
struct FitReport {
    FitMode mode = FitMode::Level;   ///< FitOptions::mode.
    int requested_level = 0;         ///< FitOptions::level (Level mode).
    int max_level = 0;               ///< FitOptions::max_level (Tolerance mode).
    double tolerance = 0;            ///< FitOptions::tolerance.
    bool tolerance_met = false;      ///< FitResult::tolerance_met.
    int level = -1;                  ///< The last level fitted; -1 if none.
    std::string message;             ///< FitResult::message.
    double diagonal = 0;             ///< Bounding-box diagonal of the mesh (0 if no level was fitted).
    std::vector<LevelReport> levels; ///< FitResult::levels.
    std::optional<LevelReport> rejected_level;  ///< FitResult::rejected_level.
    /// Size of the fitted control mesh (FittedSurface::control_mesh()); unset if the surface is empty.
    struct ControlMesh {
        int vertices = 0;
        int quads = 0;
        int level0_faces = 0;  ///< FittedSurface::cage_faces(): faces of the level-0 cage.
    };
    std::optional<ControlMesh> fitted_cage;
    int irregular_level = 0;  ///< FitOptions::irregular_level (the export evaluates with it).
    /// The weights of the fit's terms, so a report says which settings made its surface (their
    /// defaults change: the turned-over term was off until stop 63).
    struct Weights {
        double surface_to_input = 0;  ///< FitOptions::surface_to_input_weight.
        double tangential = 0;        ///< FitOptions::tangential_weight.
        double turned_over = 0;       ///< FitOptions::turned_over_weight.
    };
    Weights weights;
    std::optional<TessellationChoice> limit_tessellation;  ///< The tessellation of limit.ply, once written.

    /// The report as pretty-printed JSON (2-space indent, keys in this order, a final newline):
    /// mode, requested_level (Level mode) or max_level, tolerance, tolerance_met, level, message,
    /// diagonal, levels [{level, control_points, absolute: {input_to_surface: {rms, mean, max},
    /// surface_to_input: {...}, rms, hausdorff}, relative: {same}, within_tolerance, iterations,
    /// solver_iterations, stop_reason, seconds: {parameterization, evaluation, closest_points,
    /// solve, total}, unfitted_relative: {rms, hausdorff} when measured}], rejected_level (same
    /// shape) if set, fitted_cage {vertices, quads, level0_faces} if set, irregular_level,
    /// weights {surface_to_input, tangential, turned_over}, limit_tessellation {segments_per_face,
    /// triangles, rms_error, max_error, target, met} if set. Deterministic: equal reports give
    /// equal text.
    /// \throw InternalError if a number is not finite (it would be written as null).
    std::string to_json() const;
};

/// The report of `result`, fitted with `options`; `tessellation` (may be null) is limit.ply's.
FitReport fit_report(const FitResult& result, const FitOptions& options, const TessellationChoice* tessellation = nullptr);

/// What write_fit_outputs() wrote.
struct FitOutputs {
    TessellationChoice tessellation;
    std::vector<std::string> files;  ///< Paths written, in order.
};

/// Writes fitted_cage.obj (result.fitted_cage if set, else the fitted control mesh), limit.ply
/// (choose_tessellation() for the last level's absolute RMS) and deviation.ply into `dir` (created
/// if missing): write_fit_outputs() without report.json, for callers that write their own report
/// (write_mesh_fit_outputs()).
/// `input` is the mesh the user gave (deviation.ply carries its vertices).
/// \throw InvalidInput if the directory or a file cannot be written, or the result is empty.
FitOutputs write_fit_files(const std::string& dir, const Mesh& input, const FitResult& result,
                           const LimitPlyOptions& ply_options = {});

/// Writes fitted_cage.obj (result.fitted_cage if set, else the fitted control mesh), limit.ply,
/// deviation.ply and report.json (fit_report() with the tessellation) into `dir` (created if missing).
/// `input` is the mesh the user gave (deviation.ply carries its vertices; the fit itself was done
/// on the layout's copy of the same surface).
/// \throw InvalidInput if the directory or a file cannot be written, or the result is empty.
FitOutputs write_fit_outputs(const std::string& dir, const Mesh& input, const FitResult& result,
                             const FitOptions& options, const LimitPlyOptions& ply_options = {});

}  // namespace quadcage::fit

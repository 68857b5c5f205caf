#pragma once
// Least-squares fit of a Catmull-Clark surface to a triangle mesh through its quad layout
// (design.md §5), and the one definition of fit error (design.md §6).

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/layout/quad_layout.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"
#include "quadcage/subdiv/limit_surface.h"

namespace quadcage::fit {

/// What fit_surface() aims for.
enum class FitMode {
    Level,      ///< Fit the control points of the cage refined exactly FitOptions::level times. The
                ///< levels from 1 up are fitted in turn, as in Tolerance mode: a level's fit is the
                ///< one from the parametric positions or, from level 2 on, when that one measures
                ///< worse than the level before (RMS or Hausdorff), the better of it and one from the
                ///< previous fit refined. Level 0 is fitted only when asked for.
    Tolerance,  ///< Fit levels 0, 1, 2, ... (as Level mode does) until the relative symmetric RMS
                ///< <= FitOptions::tolerance or FitOptions::max_level is reached; stops early when
                ///< a level's RMS is worse than the one before's (from level 2: from both starts).
};

/// How a round's linear least-squares problem (feet fixed) is solved. Both take the same damped
/// Gauss-Newton (Levenberg-Marquardt) step; they differ in rounding only.
enum class FitSolver {
    Direct,  ///< The normal equations factorised by CHOLMOD (supernodal), the symbolic analysis
             ///< done once per level and reused by every round. One step per round.
    Ceres,   ///< ceres::Solve on a new problem each round (FitOptions::solver_iterations steps),
             ///< preprocessing and analysis redone every round. The reference; several times slower.
};

/// Options for fit_surface(). Distances are relative to the bounding-box diagonal of the mesh.
struct FitOptions {
    FitMode mode = FitMode::Level;  ///< Level: fit `level`; Tolerance: fit until `tolerance` is met.
    int level = 3;             ///< Level mode: refinements of the cage (0 = the cage corners), 0..kMaxFitLevel.
    double tolerance = 1e-3;   ///< Tolerance mode: target relative symmetric RMS; both modes: threshold
                               ///< of LevelReport::within_tolerance. > 0.
    int max_level = 5;         ///< Tolerance mode: highest level tried, 0..kMaxFitLevel.
    int outer_iterations = 16;  ///< Solve / correspondence-update rounds per level, >= 1, over which the
                                ///< smoothness weight falls from smoothness_start to smoothness_end.
                                ///< At 8 the data RMS of a real layout's fit still fell 7% a round
                                ///< (botijo, level 3). 16 took botijo's level-3 fit from 4.46e-4 /
                                ///< 9.31e-3 to 3.18e-4 / 3.86e-3 (check_fit.py), its fit stage from
                                ///< 6.4-7.0 s to 10.7-11.7 s.
    int extra_rounds = 32;  ///< Rounds past outer_iterations at the final smoothness weight, at most,
                            ///< while each improves the data RMS by min_improvement or more; only at
                            ///< the level asked for (FitMode::Level) or at every level
                            ///< (FitMode::Tolerance), >= 0. At 16 rounds the fit had not converged:
                            ///< botijo decimated to 10k vertices fitted at level 3 to 5.29e-4 /
                            ///< 1.17e-2 (its surface slides slowly into a small knob), 3.07e-4 /
                            ///< 7.4e-3 with these (48 rounds); botijo 2.69e-4 -> 2.40e-4 (39).
    FitSolver solver = FitSolver::Direct;  ///< How each round is solved.
    int solver_iterations = 1;  ///< FitSolver::Ceres: Levenberg-Marquardt steps per solve, >= 1. With the feet fixed
                                ///< the residuals are linear in the control points (up to the Huber
                                ///< loss), so one step solves a round; the rounds re-linearise.
    double min_improvement = 2e-3;  ///< Stop a level when a round improves the data RMS by less than
                                    ///< this fraction, in [0, 1).
    double smoothness_start = 1e-3;  ///< Weight of the control-net Laplacian term relative to the data
                                     ///< term in the first round, >= 0 ...
    double smoothness_end = 1e-6;    ///< ... decreasing geometrically to this in the last round, >= 0.
    double tangential_weight = 0.002;  ///< Final weight (squared) of the tangential part of each data
                                       ///< residual, in [0, 1]: the part along the surface normal at the
                                       ///< foot counts fully, so the surface slides along itself
                                       ///< instead of being dragged to fixed feet (squared-distance
                                       ///< minimisation). Round r of every level uses max(this, 2^-r):
                                       ///< point-to-point first. At the closest feet the tangential
                                       ///< part is zero, so this sets how fast the rounds slide the
                                       ///< surface, not where they end: at 0.02 (before) botijo's
                                       ///< level 3 fitted to 2.41e-4 in 40 rounds, at 0.002 to
                                       ///< 2.29e-4 (check_fit.py). At 0 the surface folds where no
                                       ///< input point holds it (input_wheel: 8.4e-4 -> 2.1e-3).
    double surface_to_input_weight = 1.0;  ///< Weight of the surface-to-input (point-to-plane) term
                                            ///< relative to the input-to-surface term, >= 0.
    /// Weight of the turned-over term, >= 0 (0: none). At each surface sample s = (S_u x S_v) . n /
    /// (|S_u| |S_v|), the sine of the angle from S_u to S_v signed by the input's normal n at the
    /// sample's closest input point: negative where the surface is turned over against the input,
    /// the middle sheet of a pleat that lies on the input, where no distance sees it. There the
    /// residual weight * diagonal * s, linearised in the control points with |S_u| and |S_v| held
    /// and weighted as the sample's surface-to-input residual, pulls the sheet back. Without it the
    /// limit surfaces of level-3 fits had 19% more area than the input (botijo), 64% (boot), 97%
    /// (input_wheel), the pleats in plain sight on a rendering; with 0.01, 1.1%, 3.5% and 4.4%. It
    /// costs fit where the pleats helped: botijo's RMS +8%, boot's +14% (check_fit.py); skull's and
    /// input_wheel's fell. QuadriFlow cages fitted by the same fitter pleat less (botijo 0.05% of the
    /// surface turned over against ours 8.2%), so the term widens our gap to them (README, "Pleats in
    /// the fitted surface"); it is on by default all the same, since a pleated surface is not one a
    /// user can keep. 0 turns it off. The layout's S-cycle scores fit without it
    /// (kScoreTurnedOverWeight).
    double turned_over_weight = 0.01;
    /// How a surface sample's distance to the input is linearised where its closest input point
    /// lies on an edge or at a vertex of the input (a convex crease, a hole's rim, a thin part's
    /// edge): true, along the offset from that point, the direction in which the distance to the
    /// mesh grows there; false, along the normal of the triangle found, which lets the surface
    /// bulge past a crease unseen.
    bool surface_feature_feet = true;
    double huber_scale = 1e-1;   ///< Huber loss threshold (relative distance), > 0; residuals above it
                                 ///< count linearly: only gross outliers are down-weighted.
    int area_samples = 20000;    ///< Input points sampled uniformly by area for the data term (besides
                                 ///< the mesh vertices), >= 0.
    int max_data_points = 400000;  ///< Cap on data points (vertices + samples); vertices are subsampled
                                   ///< deterministically above it. >= 1.
    int data_points_per_face = 64;  ///< Cap on the data points of a level: this many per
                                    ///< limit-surface face (a fixed, evenly spread subset of all
                                    ///< of them: coarse levels need fewer), >= 0; 0 = no cap.
    int surface_samples_per_face = 64;  ///< Limit-surface samples per control face for the
                                        ///< surface-to-input term (a k x k grid, k = ceil(sqrt)), >= 1;
                                        ///< each weighted by the surface area it stands for. With 16,
                                        ///< a fold of the limit surface between two samples' rows
                                        ///< went unseen: skull's level-3 Hausdorff distance was
                                        ///< 1.10e-2 (check_fit.py), 9.9e-3 with 64.
    int error_samples = 100000;  ///< Area samples per side when measuring the error (design.md §6), >= 1.
    bool measure_unfitted = false;  ///< Also measure the error with the control points at their
                                    ///< parametric positions (LevelReport::unfitted_*).
    int irregular_level = 6;     ///< OpenSubdiv approximation level at extraordinary vertices (1..10).
    unsigned seed = 7;           ///< Seed of every random sample (results are deterministic).
    int threads = 0;             ///< Threads for Ceres, closest points and evaluation; 0 = all cores.
    std::function<void(const std::string&)> progress;  ///< Called with a short line per stage; may be empty.
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// Largest level fit_surface() accepts (4^5 * (40g-40) faces is plenty for scans).
constexpr int kMaxFitLevel = 7;

/// RMS, mean and maximum of a set of distances.
struct DistanceStats {
    double rms = 0;
    double mean = 0;
    double max = 0;
};

/// Fit error as defined in design.md §6, in one unit (absolute or relative to the diagonal).
struct FitError {
    DistanceStats input_to_surface;  ///< From area samples + vertices of the input to the surface.
    DistanceStats surface_to_input;  ///< From area samples + tessellation vertices of the surface to the input.
    double rms = 0;        ///< RMS over both sample sets together.
    double hausdorff = 0;  ///< The larger of the two maxima.
};

/// Wall-clock seconds by stage.
struct StageSeconds {
    double parameterization = 0;  ///< Inverse patch maps, initial control points, samples.
    double evaluation = 0;        ///< Limit stencils, evaluation and projection of correspondences.
    double closest_points = 0;    ///< Embree closest-point queries on the input.
    double solve = 0;             ///< Ceres (problem set-up and solve).
    double total = 0;             ///< The whole level, including error measurement.
};

/// What happened at one level.
struct LevelReport {
    int level = 0;                ///< Refinements of the cage (0 = its corners were fitted).
    int control_points = 0;       ///< Free control points (8g-8 cage corners at level 0).
    FitError absolute;            ///< In the units of the input mesh.
    FitError relative;            ///< absolute / diagonal.
    double diagonal = 0;          ///< Bounding-box diagonal of the mesh.
    double within_tolerance = 0;  ///< Share of input samples within FitOptions::tolerance (relative).
    int iterations = 0;           ///< Solve / correspondence rounds run.
    int solver_iterations = 0;    ///< Solver steps (accepted or not) summed over the rounds.
    std::string stop_reason;      ///< Why the rounds stopped.
    StageSeconds seconds;
    double unfitted_relative_rms = -1;        ///< With FitOptions::measure_unfitted, else -1.
    double unfitted_relative_hausdorff = -1;  ///< With FitOptions::measure_unfitted, else -1.
};

/// A fitted Catmull-Clark surface: the control mesh (level >= 1 as OpenSubdiv sees it) and its
/// limit. Cheap to copy (the evaluator is shared and immutable: copies share it through a
/// std::shared_ptr<const LimitSurface>, and it lives as long as the last copy). Every member
/// function is const and may be called from several threads at once. Coordinates are in the units
/// of the input mesh.
///
/// The level-0 cage is either the layout's 10g-10-quad cage (fit_surface()) or a user's control
/// mesh of any polygons (fit_control_mesh()); its first Catmull-Clark step has only quads, and
/// level L >= 1 has level1_quads * 4^(L-1) of them.
class FittedSurface {
public:
    FittedSurface() = default;
    /// A surface over a layout's quad cage.
    /// \param control_mesh simple closed quad mesh at cage level max(level, 1).
    /// \param level the fitted level (0 = the cage corners were the variables).
    /// \param cage_quads number of level-0 cage quads (control_mesh has cage_quads * 4^max(level,1) quads).
    /// \throw InvalidInput if the mesh is not a simple quad mesh or the counts disagree.
    FittedSurface(const subdiv::QuadMesh& control_mesh, int level, int cage_quads, int irregular_level = 6);
    /// Wraps an evaluator that nobody modifies any more (same counts as above).
    /// \throw InvalidInput if surface is null or the counts disagree.
    FittedSurface(std::shared_ptr<const subdiv::LimitSurface> surface, int level, int cage_quads);
    /// A surface over a user's control mesh of `cage_faces` polygons whose first refinement has
    /// `level1_quads` quads (4 * cage_faces when they are all quads).
    /// \throw InvalidInput if surface is null or the counts disagree.
    FittedSurface(std::shared_ptr<const subdiv::LimitSurface> surface, int level, int cage_faces, int level1_quads);

    bool empty() const { return !surface_; }  ///< Default-constructed: no surface to evaluate.
    int level() const { return level_; }      ///< The fitted level (0 = the cage corners or vertices).
    /// Faces of the level-0 cage (10g-10, 4 or 6 for a layout's cage).
    int cage_faces() const { return cage_faces_; }
    /// Quads of the level-0 cage: cage_faces() when every face is a quad, else 0.
    int cage_quads() const { return level1_quads_ == 4 * cage_faces_ ? cage_faces_ : 0; }
    /// The level at which a tessellation of `segments` per level-0 side is cut (see
    /// MeasureOptions::search_segments): level() for a layout cage; for a user's control mesh the
    /// level of a 40-quad cage with about as many faces, so a cage of thousands of faces is
    /// tessellated about as densely as a layout cage at the same face count.
    int search_level() const { return search_level_; }
    /// The control mesh whose limit is the fitted surface (simple, manifold quads).
    const subdiv::QuadMesh& control_mesh() const;
    /// Limit position, derivatives and normal at (face, u, v) of control_mesh().
    /// \throw InvalidInput if the face is out of range or the surface is empty.
    subdiv::LimitPoint evaluate(const subdiv::FacePoint& p) const;
    /// The same at (cage quad, u, v) of the level-0 cage (the layout's patch parameterisation).
    /// \throw InvalidInput if the quad is out of range or the cage has faces other than quads.
    subdiv::LimitPoint evaluate_on_cage(const subdiv::FacePoint& cage_point) const;
    /// The face point of control_mesh() for a point of the level-0 cage. \throw as evaluate_on_cage().
    subdiv::FacePoint from_cage(const subdiv::FacePoint& cage_point) const;
    /// The underlying evaluator (stencils, projection, tessellation). \throw InvalidInput if empty.
    const subdiv::LimitSurface& limit() const;

private:
    std::shared_ptr<const subdiv::LimitSurface> surface_;
    int level_ = 0;
    int cage_faces_ = 0;
    int level1_quads_ = 0;
    int search_level_ = 1;
};

/// The result of fit_surface().
struct FitResult {
    std::vector<LevelReport> levels;  ///< One per level fitted, in order.
    FittedSurface surface;            ///< The surface of the last level fitted.
    /// Level 0 only (levels.back().level == 0): the fitted level-0 control points, in the order of
    /// the layout cage's corners or of the control mesh's vertices (the cage with these points
    /// refines once to surface.control_mesh()). Empty otherwise.
    std::vector<Vec3> fitted_corners;
    /// fit_control_mesh() at level 0: the control mesh with its fitted points (its own faces).
    /// Empty otherwise.
    PolygonMesh fitted_cage;
    bool tolerance_met = false;       ///< Tolerance mode: the last level met the tolerance.
    /// Tolerance mode: a level that measured worse than the one before it (also when fitted from
    /// the previous fit), which ended the search; not in `levels`, and `surface` is the previous one.
    std::optional<LevelReport> rejected_level;
    std::string message;              ///< One line: which level, and why the fit stopped there.
};

/// Fits the control points of the layout's cage refined K times so that the Catmull-Clark limit
/// surface matches layout.mesh (design.md §5; Hoppe et al. 1994, Marinov & Kobbelt 2005): data
/// terms from area-uniform samples + vertices to the surface (correspondences from the patch
/// parameterisation, then re-projected onto the current surface between solves) and from limit
/// samples to the mesh (Embree closest points, point-to-plane), a control-net Laplacian that fades
/// out, Huber loss; Ceres (sparse normal Cholesky, analytic Jacobians from the limit stencils).
/// Initial control points sit at their parametric positions on the mesh. Errors per design.md §6.
/// Deterministic for fixed options (thread count included or not).
/// \pre layout passes layout::verify_quad_layout() (its cage is a closed 2-manifold, its triangles
///      carry patch coordinates in [0,1]^2).
/// \throw InvalidInput if options are invalid, or the layout is inconsistent (sizes, patch
///        indices, cage check, coordinates outside [0,1]).
FitResult fit_surface(const layout::QuadLayout& layout, const FitOptions& options = {});

/// Why a control mesh cannot be fitted to a mesh (fit_control_mesh(), `quadcage fit --cage`).
/// Empty if it can. Checks, in this order: check_polygon_cage() (closed, manifold, oriented, no
/// repeated or non-finite vertices), one connected component, the same genus as `mesh`, and a
/// limit surface within reach: its mean distance to `mesh` at most `max_mean_distance` of the
/// mesh's bounding-box diagonal.
/// \pre mesh is one closed, connected, orientable manifold component (core::prepare_for_quadding()).
std::string check_control_mesh(const Mesh& mesh, const PolygonMesh& cage, double max_mean_distance = 0.1);

/// Fits the control points of `cage` refined FitOptions::level times (level 0: the cage's own
/// vertices; Tolerance mode: levels 0, 1, ... in turn) so that its Catmull-Clark limit surface
/// matches `mesh`. The same fit as fit_surface() (terms, solver, errors, level sequencing), but
/// the start comes from where the cage's limit surface lies, not from patch maps: the control
/// points start at the cage (refined), and every data point's foot is its closest point on that
/// limit surface (a global search over a tessellation, then Newton steps). From level 2 on a level
/// starts from the previous fit refined. Deterministic for fixed options.
/// \pre mesh is one closed, connected, orientable manifold component (core::prepare_for_quadding()).
/// \throw InvalidInput if the options are invalid or check_control_mesh() reports a problem.
FitResult fit_control_mesh(const Mesh& mesh, const PolygonMesh& cage, const FitOptions& options = {});

/// The components of a control mesh matched to those of a mesh: result[i] is the component of
/// `cage` that overlaps `components[i]` most (by the volume shared by their bounding boxes),
/// with its vertices renumbered from 0 in their order in `cage`.
/// \throw InvalidInput if the component counts differ or the overlap does not pair them one to one.
std::vector<PolygonMesh> match_control_mesh(const std::vector<Mesh>& components, const PolygonMesh& cage);

/// Options for measure_fit_error().
struct MeasureOptions {
    int samples = 100000;      ///< Area samples per side (plus all vertices), >= 1.
    /// Tessellation that carries the surface samples and seeds the projections, in segments per side
    /// of a level-0 cage quad (so every level samples the same parameter points; each control face
    /// gets max(1, search_segments / 2^max(level,1))), >= 1. The input's projections are seeded
    /// from at least 4 segments per control face side (finer levels would get 2 or 1, and a walk
    /// from so coarse a seed can end on the wrong side of a bulge).
    int search_segments = 32;
    double tolerance = 1e-3;   ///< Relative threshold for within_tolerance, > 0.
    unsigned seed = 7;
    int threads = 0;           ///< 0 = all cores.
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// The error of a fitted surface against a mesh, with the share of input samples within tolerance.
struct ErrorMeasurement {
    FitError absolute;
    FitError relative;
    double diagonal = 0;
    double within_tolerance = 0;
};

/// Measures design.md §6 both ways: input samples (uniform by area + all used vertices) projected
/// onto the limit surface (seeded from a tessellation, refined by Newton steps on the exact
/// surface), and limit-surface samples (uniform by area of a tessellation, evaluated exactly, plus
/// its vertices) to their Embree closest points on the mesh.
/// \throw InvalidInput if options are invalid, the mesh has no triangles or the surface is empty.
ErrorMeasurement measure_fit_error(const Mesh& mesh, const FittedSurface& surface, const MeasureOptions& options = {});

/// Distance from each point to the limit surface (closest point as in measure_fit_error()).
/// \throw InvalidInput if the surface is empty or a point is not finite.
/// search_segments as in MeasureOptions.
std::vector<double> distances_to_surface(const FittedSurface& surface, const std::vector<Vec3>& points,
                                         int search_segments = 32, int threads = 0);

}  // namespace quadcage::fit

namespace quadcage::fit {

/// Layout and fit together: what a CAD exporter calls without the CLI.
struct CageFit {
    layout::QuadLayout layout;  ///< The minimal quad layout (its cage is the level-0 control cage).
    FitResult fit;              ///< The fitted surface (evaluate it with fit.surface) and its report.
    double layout_seconds = 0;  ///< Wall-clock seconds of build_quad_layout().
    double fit_seconds = 0;     ///< Wall-clock seconds of fit_surface().
};

/// The tangential weight level1_fit_score() fits with, whatever its options say: the default's
/// before it became 0.002, with which the score's choices were measured.
constexpr double kScoreTangentialWeight = 0.02;

/// The turned-over weight level1_fit_score() and level2_fit_score() fit with, whatever their options
/// say: none, as when their choices were measured. With FitOptions' default 0.01 the level-1 scores
/// of `generate wheel -g 11 -r 3`'s two constructions came within the 10% margin (0.00366 and
/// 0.00332), so a 28 s level-2 tie-break ran and kept the same layout (layout 11 s -> 40 s).
constexpr double kScoreTurnedOverWeight = 0;

/// The data points and limit-surface samples per limit face (FitOptions::data_points_per_face and
/// surface_samples_per_face, 64 by default) level1_fit_score() fits with, and the area samples a
/// side (FitOptions::error_samples, 100,000 by default) it measures its RMS with, whatever its
/// options say. With 64 and 100,000 the scores were nearly a third of botijo's layout (3.7 s); with
/// these they are 2.0 s, and the choices, and so the layouts, stayed the same on the 16 meshes of
/// the README's "The S-cycle scores at 16 points a face".
constexpr int kScorePointsPerFace = 16;
constexpr int kScoreErrorSamples = 20000;

/// A layout::QuadLayoutOptions::score that ranks candidate layouts by how their cages fit: the
/// relative symmetric RMS of fit_surface() at level 1 with `options` (its level, mode and progress
/// replaced, no extra rounds, the tangential weight kScoreTangentialWeight, the turned-over weight
/// kScoreTurnedOverWeight, kScorePointsPerFace
/// points and samples a face and kScoreErrorSamples error samples).
/// On 14 meshes, 23 of the 24 pairs of S-cycle constructions whose scores differed by
/// more than 10% (QuadLayoutOptions::score_margin) ranked as their level-3 fits did (the README's
/// "The S-cycles chosen by a level-1 fit", with 64 points a face and 100,000 samples). Costs 0.5-1.5 s a layout on botijo, boot and input_wheel.
/// Deterministic.
std::function<double(const layout::QuadLayout&)> level1_fit_score(FitOptions options = {});

/// A layout::QuadLayoutOptions::tie_score, for the choices the level-1 scores leave within their
/// margin: the relative symmetric RMS of fit_surface() at level 2 with `options` (its level, mode
/// and progress replaced, no extra rounds, the turned-over weight kScoreTurnedOverWeight), with the
/// fit's own points and samples, not the
/// level-1 score's fewer. About 5 times the cost of a level-1 score (a level-1 fit, then a level-2
/// one, at 4 times the points). Deterministic.
std::function<double(const layout::QuadLayout&)> level2_fit_score(FitOptions options = {});

/// How fit_cage() chooses among the layout's S-cycle constructions where
/// layout::QuadLayoutOptions::score is empty.
enum class SCycleChoice {
    Fit,   ///< By level1_fit_score(), ties by level2_fit_score() (default options).
    Shape  ///< By the layout's rule on patch area max/min and corner angles (no score).
};

/// Mesh in, layout + fitted cage + report out: build_quad_layout() then fit_surface(). Where
/// layout_options.score is empty and `choice` is SCycleChoice::Fit, the layout is chosen with
/// level1_fit_score() and its ties broken with level2_fit_score() (default options, as the CLI's
/// `layout` and `fit` do, so both build the same layout); with SCycleChoice::Shape by the rule, as
/// `--choose-s-cycles shape` asks. With default
/// options but for fit_options.level, this is what `quadcage fit MESH --level K` computes for each
/// component (fit::fit_mesh() in quadcage/fit/mesh_fit.h calls it on every component of a mesh;
/// fit::fit_report() and layout::layout_report() make its reports). Deterministic as both stages are. Coordinates and absolute errors are in the mesh's units.
/// \pre mesh is one closed, connected, orientable manifold component, oriented outward
///      (core::prepare_for_quadding() splits and orients a general mesh).
/// \throw InvalidInput if the mesh or the options are invalid.
CageFit fit_cage(const Mesh& mesh, const layout::QuadLayoutOptions& layout_options = {},
                 const FitOptions& fit_options = {}, SCycleChoice choice = SCycleChoice::Fit);

}  // namespace quadcage::fit

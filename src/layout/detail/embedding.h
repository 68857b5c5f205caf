#pragma once
// Global embedding optimisation of a quad layout (issue #20; Campen & Kobbelt, Quad Layout
// Embedding via Aligned Parameterization, CGF 2014; Khodakovsky, Litke & Schroder, Globally Smooth
// Parameterizations with Low Distortion, SIGGRAPH 2003). The layout's combinatorics stay fixed:
// every cage quad is a unit square, neighbouring squares are related by the transition their
// shared cage edge implies, the corners are the cones. One seamless map of the whole surface over
// that domain is optimised jointly; its integer iso-lines are the new layout edges.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

/// A transition between two charts: y = R^quarter_turns x + t, with R the counter-clockwise quarter
/// turn and t integer. Maps lattice points to lattice points and iso-lines u, v in Z to iso-lines.
struct Transition {
    int quarter_turns = 0;  ///< 0..3.
    std::array<int, 2> t{0, 0};

    UV apply(const UV& x) const;
    UV rotate(const UV& x) const;  ///< The linear part only (for directions).
    Transition then(const Transition& next) const;  ///< next(this(x)).
    Transition inverse() const;
};

/// The transition across side k of cage quad q: maps q's square chart to the chart of the quad on
/// the other side of that cage edge (stored in *neighbour), so that the two squares share the side
/// (q's side k runs from corner k to corner k+1, the neighbour's the other way) and lie on opposite
/// sides of it.
Transition side_transition(const subdiv::Cage& cage, int q, int k, int* neighbour);

/// A seamless map of the layout's mesh: per triangle the (u, v) of its corners in the chart of its
/// patch (layout.triangle_patch). Unlike QuadLayout::corner_uv, a triangle may leave [0,1]^2: it then
/// lies, through the transitions, in a neighbouring square.
struct SeamlessMap {
    std::vector<std::array<UV, 3>> uv;
    /// Per half-edge h: the transition from the chart of the triangle across h into the chart of
    /// h's triangle (identity inside a patch; side_transition() across a layout edge; a cone moved by
    /// relocate_cones() leaves a trail of edges whose transitions turn about its lattice point).
    std::vector<Transition> across;
    /// The mesh vertex of each cage corner: the cones, pinned at their lattice points.
    std::vector<int> cone_vertex;
};

/// Options for optimize_embedding().
struct EmbeddingOptions {
    int iterations = 30;         ///< Newton iterations at most, >= 0.
    double tolerance = 1e-4;     ///< Stop when an iteration lowers the energy by less than this fraction.
    /// Weight of an extra area term det J + 1/det J - 2 per triangle (0: symmetric Dirichlet
    /// alone), >= 0: trades angle distortion for area balance.
    double area_weight = 0;
    /// Weight of an extra conformal term |J|^2 / det J - 2 per triangle (MIPS; 0: none), >= 0: weighs
    /// angles against area.
    double conformal_weight = 0;
    /// Extra weight of that conformal term on the triangles near a cone: those whose centroid lies
    /// within cone_radius quad sides (sqrt(surface area / quads), straight-line distance) of a cone
    /// vertex, >= 0 (0: none). The energy over the whole surface is cheapest to lower by turning the
    /// layout edges about the corners, where little area is at stake: without it the extracted
    /// layouts' corner angles deviated by 50-73 deg on a body with two handles. Weight 300 keeps
    /// the map nearly conformal there and the corners' sectors near 360 deg / degree.
    double cone_conformal_weight = 0;
    double cone_radius = 0.2;  ///< See cone_conformal_weight; > 0.
    /// Weight of the |J^-1|^2 half of symmetric Dirichlet (1; 0: the Dirichlet energy |J|^2 alone,
    /// whose minimiser is the harmonic map, kept flip-free by the line search).
    double inverse_weight = 1;
    /// Order the Newton system by METIS's nested dissection as well as AMD and keep the one with
    /// less fill (worth it for the whole surface: half the flops on botijo); false: AMD alone
    /// (smooth_layout_edges()' band, where trying both took 0.68 s on botijo against 0.55 s).
    bool nested_dissection = true;
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// What optimize_embedding() did.
struct EmbeddingReport {
    int iterations = 0;
    int variables = 0;                 ///< Free (u, v) pairs: one per vertex that is no corner.
    double initial_energy = 0;         ///< Area-weighted mean symmetric Dirichlet energy (4 = isometric).
    double final_energy = 0;
    double transition_error = 0;       ///< Largest |T(uv_P) - uv_Q| over vertex copies of the result.
    int flipped_triangles = 0;         ///< Of the result (0 unless the start had flips).
    double seconds = 0;
    std::string message;               ///< Why it stopped.
};

/// Minimises the symmetric Dirichlet energy (Smith & Schaefer 2015) of the map from each triangle,
/// scaled so that every unit square targets area(mesh) / quads, to its chart, over all charts at
/// once. Unknowns: one (u, v) per vertex that is no corner; a vertex on a layout edge is stored in
/// the chart of the edge's first quad and seen by the second through side_transition(). Corners stay
/// at their square corners (cones). Projected Newton (per-triangle Hessians projected onto the
/// positive semidefinite cone; Teran et al. 2005) with a line search that never lets a triangle
/// flip, starting from the layout's corner_uv.
/// \pre verify_quad_layout(layout) is "" (so the start is flip-free and seamless).
EmbeddingReport optimize_embedding(const QuadLayout& layout, const EmbeddingOptions& options, SeamlessMap* map);

/// Cone relocation (issue #20): moves all cones at once down the gradient of the optimised energy
/// with respect to their places on the surface, while that lowers it. Per sweep:
/// - Each cone's configurational force: minus the derivative of the energy when the cone vertex
///   slides in its tangent plane with the map held (by the envelope theorem, that of the optimised
///   energy too), by central differences.
/// - Each cone walks the mesh edges towards the point its force points to, at a distance of
///   alpha * (a square's side on the surface) * |force| / (largest |force|), alpha = 1/2, 1/4, ...
///   Each step makes the edge v-w a cut whose transition turns about the lattice point (v becomes
///   regular, w the cone), rebuilds v in the cone's power chart (z - L)^(4/5) where the 450-degree
///   cone is flat, and untangles and relaxes the two rings around v and w (a step whose result flips
///   or winds a vertex the wrong number of times ends the walk).
/// - The moved map is untangled and optimised for `trial_iterations` Newton steps as a whole; it is
///   kept if it flips nothing, turns every vertex once (cones 5/4) and has a lower energy, else alpha
///   is halved (down to 1/32); a sweep that keeps nothing ends the relocation.
/// Then a full optimisation. Returns the number of cone walks kept.
int relocate_cones(const QuadLayout& layout, const EmbeddingOptions& options, int sweeps, int trial_iterations,
                   SeamlessMap* map, EmbeddingReport* report);

/// Where the surface falls in the quad domain under a seamless map.
struct AreaPotential {
    std::vector<double> patch_area;    ///< Surface area whose image lies in each unit square.
    double max_over_min = 0;           ///< Of patch_area (what extraction would give).
    double before_max_over_min = 0;    ///< Of the layout's own patches (triangle_patch).
    double unattributed_fraction = 0;  ///< Area whose square could not be told, over the total.
};

/// Clips every triangle's image against the lattice cells and attributes each piece to a square:
/// a triangle's square is found by walking from a neighbour's (starting from triangles whose
/// centroid lies in their own square) across the square sides the segment between their centroids
/// crosses; each piece of it by walking from its centroid within the triangle. Cones are never inside
/// a triangle of a locally injective map, so the walks are well defined; a walk that does not end
/// leaves its area unattributed.
AreaPotential measure_area_potential(const QuadLayout& layout, const SeamlessMap& map);

/// The layout the seamless map draws: its edges are the integer iso-lines u or v in Z between the
/// corners (Campen & Kobbelt 2014, §6). Mesh triangles are cut along the iso-lines (new vertices
/// only where an iso-line crosses a mesh edge, appended after the layout mesh's points; the pieces,
/// convex in the map, are triangulated without new points); every new triangle goes to the square
/// its image lies in; edge_paths follow the iso-lines from corner to corner; the cage, corners,
/// genus and input_vertices stay; orthogonal_system and s_cycles follow the split edges; corner_uv
/// is recomputed by parameterize_patches() (whose sides are by arc length, as verify_quad_layout()
/// requires). Returns "" and fills *out, or says why the map gives no layout (nothing is changed).
/// \pre map is seamless and flip-free over layout (optimize_embedding()'s result).
/// With slide_passes > 0, each new vertex that is the only crossing of its mesh edge then slides
/// along that edge, that many times, towards the middle of its two neighbours on its layout edge
/// (staying a tenth of the edge from its ends): a piecewise linear map's iso-lines kink at every
/// mesh edge they cross, and these kinks are smoothed out without changing which triangles the
/// curves cross.
std::string extract_layout(const QuadLayout& layout, const SeamlessMap& map, QuadLayout* out,
                           int slide_passes = 0);

/// What smooth_layout_edges() did.
struct SmoothingReport {
    int band_vertices = 0;  ///< Vertices freed round the layout edges.
    int iterations = 0;     ///< Newton steps.
    double seconds = 0;
};

/// The layout with its edges smoothed (issue #20: "no mesh-edge staircase"). A layout edge runs
/// along mesh edges, so it zigzags from triangle to triangle. The layout's own patch maps form a
/// seamless map (QuadLayout::corner_uv, tied across the layout edges by the cage's transitions);
/// in a band of vertices round the layout edges, less the corners' stars and each edge's first and
/// last 0.12 of its length (where the relaxation set the directions the edges leave the corners
/// in) with the ring round them, the map is
/// made harmonic (the Dirichlet energy, minimised by Newton steps that never flip a triangle; the
/// band's rim and the held vertices hold the map), and the mesh is cut along its integer
/// iso-lines (extract_layout(), whose crossings then slide along their mesh edges to take out the
/// kinks a piecewise linear map's iso-lines have at every edge). The new edges run across the
/// triangles (along mesh edges still near their ends), at most the band's width from the
/// old ones, through the same corners in the same places; new vertices lie only on the layout
/// mesh's edges. Returns "" and fills *out, or says
/// why there is no smoothed layout.
/// \pre verify_quad_layout(layout) is "".
std::string smooth_layout_edges(const QuadLayout& layout, QuadLayout* out, SmoothingReport* report);

/// Where embed_layout_edges() stops by default: a Newton step that lowers the energy by less than
/// this fraction of it is its last. On botijo the steps after it (14 to 30, at 1e-4) lowered the
/// energy by a further 1.7% in all, took 5-6.5 s of its 17-19 s layout, and changed its level-3 fit
/// by under 2% (RMS); tools/bench/fit_compare.sh on the shared and generated meshes: every RMS
/// within 2%, Hausdorff distances up on four (at most 18%) and down on four; on botijo and four
/// jittered copies, mean RMS 2% lower and mean Hausdorff 2% higher (README, "Global edge
/// embedding").
inline constexpr double kEdgeEmbeddingTolerance = 2e-3;

/// What embed_layout_edges() did.
struct EdgeEmbeddingReport {
    int variables = 0;          ///< Free (u, v) pairs.
    int iterations = 0;         ///< Newton steps.
    double initial_energy = 0;  ///< Area-weighted mean symmetric Dirichlet energy (4 = isometric).
    double final_energy = 0;
    std::string stopped;  ///< Why the Newton steps stopped.
    int pulled = 0;       ///< Vertices pulled towards the cone charts (with cone_charts > 0).
    double seconds = 0;
};

/// The layout with its edges where one map of the whole surface puts them (issue #20's global
/// embedding, with the corners held). The layout's own patch maps, tied into one seamless map as
/// in smooth_layout_edges(), minimise the symmetric Dirichlet energy at the scale area / quads
/// (optimize_embedding()'s energy) over every vertex but the corners' stars and each edge's first
/// and last tenth of its length with the ring round them, by flip-free Newton steps: at most
/// `iterations`, and none after a step that lowers the energy by less than `tolerance` of it.
/// Where the relaxation crowded the corners, this moves the edges between them so that the
/// surface spreads more evenly over the squares, while the corners and the directions
/// their edges leave them in (the corner angles check_layout.py measures) stay. The mesh is cut
/// along the map's integer iso-lines (extract_layout(), crossings slid as in
/// smooth_layout_edges()), so the edges run across the triangles. Returns "" and fills *out, or
/// says why there is no such layout.
/// With cone_charts > 0, nothing but the corners is held. Round each corner the map is instead pulled
/// towards its cone chart, with this strength: the conformal power map P + c z^(d/4) of the corner's
/// tangent plane (d its degree; c fitted to the layout's map), whose iso-lines leave the corner 360/d
/// degrees apart in that plane, where check_layout.py --quality measures the corner angles. The pull
/// covers a disk of 0.15 of the corner's longest edge (at most half its shortest), each vertex
/// weighted cone_charts * its area (at the scale area / quads) / the disk's radius in the map
/// squared; a corner whose tangent plane folds the disk (a crease) pulls its ring only, laid out
/// round it with its angles scaled to a full turn.
/// With area_weight > 0, the energy has EmbeddingOptions::area_weight's area term too, with this
/// weight: the squares' areas are evened out further, their shapes less kept.
/// \pre verify_quad_layout(layout) is "".
std::string embed_layout_edges(const QuadLayout& layout, int iterations, QuadLayout* out,
                               EdgeEmbeddingReport* report, double tolerance = kEdgeEmbeddingTolerance,
                               double cone_charts = 0, double area_weight = 0);

/// Where build_quad_layout() puts the layout edges (edges.cpp), on the relaxed layout: the edge
/// embedding (embed_layout_edges(), `options.edge_embedding_iterations` steps) where the layout mesh
/// has at most `options.edge_embedding_max_vertices` vertices, kept if it has a smaller patch area
/// max/min and, once the refinement no curve runs through is undone (undo_unused_refinement()),
/// adds at most `bound` vertices; else the smoothing (smooth_layout_edges()), kept unless it takes
/// the mesh past the bound; else the edges along mesh edges. Progress lines say which, and why.
/// With `options.smooth_edges` off, only the unused refinement is undone. Otherwise every undoing
/// is given `input`, so a layout still over the bound is traced again on the input's triangles.
/// \pre *layout is a verified layout of `input`, its quality measured.
void place_layout_edges(const Mesh& input, QuadLayout* layout, const QuadLayoutOptions& options,
                        long long bound, const std::function<void(const std::string&)>& say);

/// The embedding stage of build_quad_layout(): optimize_embedding(), relocate_cones() for
/// `cone_sweeps` passes (0: none), then measure_area_potential(); one progress line with the
/// figures. With `extract`, replaces *layout by extract_layout()'s result if that verifies and has a
/// smaller patch area max/min; progress lines give both layouts' balance figures and say which was
/// kept and why.
void embedding_stage(QuadLayout* layout, const EmbeddingOptions& options, int cone_sweeps, bool extract,
                     const std::function<void(const std::string&)>& say);

}  // namespace quadcage::layout::detail

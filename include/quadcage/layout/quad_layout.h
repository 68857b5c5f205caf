#pragma once
// Minimal quasi-regular quad layout (paper §3-4: Lemma 4, Corollary 2, Theorem 2, Algorithm 1) and
// its per-patch parameterization (design.md §2-5).

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/layout/orthogonal_system.h"
#include "quadcage/subdiv/cage.h"

namespace quadcage::layout {

/// (u, v) in the unit square of a patch.
using UV = std::array<double, 2>;

struct QuadLayout;

/// Options for build_quad_layout().
struct QuadLayoutOptions {
    OrthogonalSystemOptions cycles;  ///< For the orthogonal system the layout starts from (g >= 1).
    /// g >= 2: S-cycles from the handle loops (two parallel to each; the rest between T-shirts cut
    /// off the body one at a time, in an order that keeps holes close together on one side of every
    /// cut) instead of Algorithm 1's, which each cross the orthogonal system once and on a body with
    /// handles wind round it in stacks. Falls back to Algorithm 1's when a curve cannot be placed
    /// (plates of genus >= 9 do). Level-3 fits (issue #5, with the fit as it was at 1fc0e13):
    /// fertility RMS 1.9e-3 -> 2.4e-4, Hausdorff 2.6e-2 -> 4.0e-3; botijo RMS 1.55e-3 -> 1.43e-3 but
    /// Hausdorff 2.6e-2 -> 3.6e-2. The README has the current figures.
    bool s_cycles_from_handle_loops = true;
    /// With s_cycles_compare, genus 2..12: also build the layout with S-cycles round loops at the
    /// surface's necks (neck_s_cycles.cpp): a pants decomposition of short loops, taken shortest
    /// first, whose pairs of pants join into T-shirts along the perfect matching that drops the
    /// longest loops; an annulus round each loop kept. Kept, as Algorithm 1's are, if it is
    /// better than the layout kept so far (by `score`, else by the rule there) and within
    /// vertices_added_bound(). The handle loops' body cut winds long S-cycles round a
    /// ring of holes (a wheel's, input_wheel's); these stay short. The README has the figures.
    bool s_cycles_from_necks = true;
    /// Before the orthogonal system, split (at midpoints, repeatedly) every edge longer than 4 times
    /// the median edge length and than an eighth of a cage quad's side (sqrt(area / quads)): a CAD
    /// tessellation's flat faces are fans of long, thin triangles that the layout curves, routed
    /// along mesh edges, would follow into stacks of thin patches (input_wheel's back face). Only
    /// where the input's triangles with such an edge between two triangles within 1 degree of one
    /// plane cover a tenth of its surface or more (not a limb's stretched triangles). The splits no layout
    /// curve runs through are undone at the end, as the curves' own are; they do not count against the
    /// constructions' vertex budgets, but do against vertices_added_bound() at the end.
    bool split_long_edges = true;
    /// With s_cycles_from_handle_loops, where the handle loops gave the S-cycles: build the layout
    /// with Algorithm 1's S-cycles too (unless the first layout is past vertices_added_bound();
    /// abandoned once it refines past it) and keep it if both its patch area max/min and its
    /// corner angle deviation are smaller (or, with `score`, if it scores lower). Which fits better
    /// depends on the shape (big bodies with small handles: Algorithm 1's; fertility: the handle
    /// loops'; the README's Benchmarks). This about doubles the time of the layout curves.
    bool s_cycles_compare = true;
    /// Scores a candidate layout for the choice between S-cycle constructions above (lower is
    /// better), in place of the rule on patch area max/min and corner angles; empty: that rule.
    /// Called with each verified candidate before its edges are placed (smooth_edges), at most
    /// three times. fit::level1_fit_score() ranks by a level-1 fit (fit::fit_cage() and the CLI
    /// use it); if it throws InternalError, that choice falls back to the rule.
    std::function<double(const QuadLayout&)> score;
    /// Scores within this fraction of the kept layout's do not decide; the rule does, in [0, 1).
    /// Of 24 pairs of constructions whose level-1 fits differed by more than 10%, 23 ranked as
    /// their level-3 fits did; of 8 within 10%, 2 did (14 meshes: the README's "The S-cycles
    /// chosen by a level-1 fit").
    double score_margin = 0.1;
    /// Where `score` leaves the choice to the rule (the two scores within score_margin of each
    /// other), both layouts are scored again with this finer, costlier measure, and it decides
    /// where those scores differ by more than score_margin; empty, or failing (InternalError): the
    /// rule. fit::level2_fit_score() ranks by a level-2 fit (fit::fit_cage() and the CLI use it):
    /// on a jittered copy of botijo the level-1 scores of the handle loops' and the necks' layouts
    /// were 2% apart, the rule kept the handle loops', and its level-3 fit's Hausdorff distance was
    /// 2.3e-2 against the target of 1e-2 (README, "Ties broken at level 2").
    std::function<double(const QuadLayout&)> tie_score;
    int relax_sweeps = 3;  ///< Passes that move every layout edge to the middle of its two patches
                           ///< (0: keep the constructed routes), >= 0.
    int relax_corner_sweeps = 2;  ///< The first this many of those passes first move every corner
                                  ///< towards where it shares its patches' area evenly and reroute its
                                  ///< edges (0: the corners stay where the construction put them), >= 0.
    /// Smooth the layout edges: each runs along mesh edges as built (a staircase across the
    /// triangles); smoothed, it is an iso-line of the patch maps made harmonic in a band round the
    /// edges, cut into the mesh (new vertices on mesh edges), through the same corners. Kept if it
    /// verifies and, once the unused refinement is undone, stays within vertices_added_bound().
    bool smooth_edges = true;
    /// Newton iterations of the global edge embedding (0: skip it), >= 0; only with smooth_edges.
    /// One seamless map of the whole surface over the cage's unit squares, started from the patch
    /// maps, minimises symmetric Dirichlet at the scale area / quads with the corners and each
    /// edge's first and last tenth held; the layout edges become its iso-lines, cut into the mesh
    /// as smooth_edges cuts them. Kept, in place of the smoothing, if it verifies, has a smaller
    /// patch area max/min and stays within vertices_added_bound(). The corners stay where they
    /// are, and so do the corner angles.
    int edge_embedding_iterations = 30;
    /// The global edge embedding is skipped (the edges only smoothed) on a layout mesh with more
    /// vertices than this, >= 0. Its Newton steps factorise the whole map's Hessian: measured on one
    /// BLAS thread (two take about two thirds of the time), 0.37 s a step at 39k free vertices,
    /// 1.7 s at 158k, 8.4 s and 3.1 GiB peak at 648k.
    int edge_embedding_max_vertices = 200000;
    /// Strength of the edge embedding's cone charts (0: off, the default), >= 0. With it, the
    /// corners' stars and the edges' ends are not held; round each corner the map is pulled towards
    /// the conformal power map of the corner's tangent plane, whose iso-lines leave the corner
    /// 360/degree degrees apart there (where check_layout.py --quality measures the corner angles),
    /// and the embedded edges are kept if they have a smaller corner angle deviation (instead of a
    /// smaller patch area max/min). Measured with 1000 (the README's "Cone charts"): the mean corner
    /// angle deviation falls (botijo 23.1 -> 14.2 deg, skull 21.1 -> 8.3) but the level-3 fits'
    /// Hausdorff distances rise on eight of 15 meshes (skull 9.88e-3 -> 1.10e-2), so it is off by default.
    double edge_embedding_cone_charts = 0;
    /// Weight of an area term in the edge embedding's energy (0: symmetric Dirichlet alone, the
    /// default), >= 0: the embedding's area_weight (det J + 1/det J - 2 per triangle at the scale
    /// area / quads), which spreads the surface more evenly over the squares at the cost of their
    /// shapes. The corners and the edges' ends are held as without it. Measured (the README's "An
    /// area term in the edge embedding"): at 10, patch area max/min falls on every shared mesh of
    /// genus >= 2 (skull 7.92 -> 3.47, botijo 12.4 -> 8.41) with the level-3 RMS within 2% on all
    /// but skull, whose fit gets worse (RMS 7.76e-4 -> 9.32e-4, Hausdorff 9.65e-3 -> 1.24e-2), and
    /// boot's Hausdorff distance rises (1.01e-2 -> 1.44e-2), so it is off by default.
    double edge_embedding_area_weight = 0;
    /// Build the layout on a copy of the input decimated to this many vertices (decimated():
    /// shortest-edge collapses) and carry it onto the input (0: never), >= 0; only for inputs of
    /// more than proxy_above vertices and more than twice this many. Every stage above runs on the
    /// copy; the curves are then carried onto the input and followed across its triangles (the
    /// layout is on the input's own triangles, as without it). Where the copy loses the genus, its
    /// layout fails, or the curves cannot be carried over and verified, the layout is built on the
    /// input itself (the progress says why). The README's "A layout built on a decimated copy" and
    /// "The copy's normals, and the copy for large inputs" have what they measured: botijo split
    /// twice (658k vertices) in 22-25 s instead of 120-220 s.
    int proxy_vertices = 10000;
    /// Inputs of at most this many vertices are laid out on themselves (see proxy_vertices), >= 0.
    /// Below it, on the shared scans the copy's layouts fit with a larger Hausdorff distance
    /// (skull: 1.18e-2 against 9.46e-3), so the copy is kept for inputs where the layout on the
    /// input itself is slow.
    long long proxy_above = 100000;
    /// Newton iterations of the global embedding optimisation (issue #20; 0: skip it), >= 0. The
    /// stage optimises one seamless map of the whole surface over the cage's unit squares
    /// (symmetric Dirichlet, corners as cones) and reports how evenly it spreads the surface area
    /// over the squares.
    int embedding_iterations = 0;
    /// With embedding_iterations > 0: replace the layout by the optimised map's iso-lines when that
    /// layout verifies and is better balanced (patch area max/min), else keep it and say why.
    bool embedding_extract = false;
    /// Weight of the embedding's area term (det J + 1/det J - 2 per triangle, on top of symmetric
    /// Dirichlet), >= 0: higher evens out the squares' areas at the cost of angles at the corners,
    /// which stay where they are.
    double embedding_area_weight = 0;
    /// Weight of the embedding's conformal term (|J|^2 / det J - 2 per triangle, MIPS), >= 0: higher
    /// weighs angles against area. Its effect on the corner angles is small so far (eight, weight 5:
    /// mean deviation 34 -> 28 deg, against 17 for the layout without the stage).
    double embedding_conformal_weight = 0;
    /// Extra weight of that conformal term near the corners (the triangles within a fifth of a quad's
    /// side of one), >= 0 (0: none). Over the whole surface the energy is cheapest to lower by turning
    /// the layout edges about the corners, where little area is at stake; this keeps the map nearly
    /// conformal there. At 300, with embedding_area_weight 10, the extracted layouts' mean corner
    /// angle deviation on skull fell from 21.1 deg (the layout without the stage) to 8.8 and its
    /// patch area max/min from 7.92 to 3.61, but its level-3 fit got worse (README: "Corner angles
    /// held in the global embedding").
    double embedding_cone_conformal_weight = 0;
    /// Passes of the embedding's cone relocation (every corner moved along the surface, down the
    /// energy's gradient in its place, by up to half a square's side per pass, while that lowers the
    /// optimised energy; 0: the corners stay), >= 0. Experimental.
    int embedding_cone_sweeps = 0;
    std::function<void(const std::string&)>
        progress;                  ///< Called with a short message per stage; may be empty.
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// Quality figures of a layout (issue #4); all dimensionless.
struct LayoutQuality {
    double patch_area_max_over_min = 0;          ///< Largest over smallest patch area.
    double corner_angle_mean_deviation_deg = 0;  ///< Mean |sector angle - 360/degree| over corner sectors.
    double corner_angle_max_deviation_deg = 0;
    double distortion_mean = 0;  ///< Area-weighted geometric mean of the conformal distortion sigma1/sigma2
                                 ///< of the patch maps (1 = conformal).
    double distortion_max = 0;
    double edge_length_over_sqrt_area = 0;  ///< Total length of the layout edges / sqrt(surface area).
    int flipped_triangles = 0;              ///< Triangles whose (u, v) image has non-positive area.
};

/// A quad layout on a (possibly refined) copy of the input surface.
struct QuadLayout {
    Mesh mesh;  ///< The surface all curves and patches live on: the input's points first,
                ///< in order and unmoved, then new points on input edges.
    int input_vertices = 0;
    int genus = 0;
    subdiv::Cage cage;                ///< Level-0 cage: corners are mesh vertices (positions on the surface).
    std::vector<int> corner_vertex;   ///< Mesh vertex of each cage corner.
    std::vector<int> triangle_patch;  ///< Cage quad of each mesh triangle.
    /// (u, v) of each triangle's three corners in its patch's square (corner k of the cage quad at
    /// (0,0), (1,0), (1,1), (0,1) for k = 0..3). A vertex on a patch side has, in each of the two
    /// patches, coordinates on that side at the same arc-length fraction.
    std::vector<std::array<UV, 3>> corner_uv;
    /// Mesh-vertex paths of the layout edges, from edge.corners[0] to edge.corners[1].
    std::vector<std::vector<int>> edge_paths;
    /// The 2g cycles the layout was built from (empty for g = 0), as they were routed: the layout
    /// is relaxed after that, so its edges need not run along them. The 4g-4 cycles S_i of
    /// Algorithm 1 (empty for g <= 1) as they are in the layout: each is two layout edges, through
    /// two corners (the relaxed curves, unless relaxation is off or failed).
    std::vector<Cycle> orthogonal_system;
    std::vector<Cycle> s_cycles;
    /// Whether the layout edges were smoothed (QuadLayoutOptions::smooth_edges): they cross mesh
    /// triangles, with a new vertex wherever they cross a mesh edge.
    bool edges_smoothed = false;
    LayoutQuality quality;
    /// Wall-clock seconds by stage.
    struct Seconds {
        double cycles = 0;            ///< Orthogonal system (and refinement of small meshes).
        double curves = 0;            ///< S-cycles, rings and arcs (the layout curves).
        double parameterization = 0;  ///< Cage extraction and the patch maps.
        double verification = 0;      ///< verify_quad_layout() and quality figures.
    } seconds;
};

/// The minimal quad layout of a closed, connected, orientable manifold mesh: for genus g >= 2,
/// 10g-10 quads and 8g-8 corners of degree 5 (Algorithm 1: 4g-4 cycles S_i cut the surface into
/// 2g-2 handles of 2 quads and g-1 T-shirts of 6 quads); for g = 1, 4 quads with 4 corners of degree
/// 4 (Remark 1); for g = 0, a cube (6 quads, 8 corners of degree 3). Runs verify_quad_layout() on its
/// result. Deterministic. A mesh at least 64 times its extent from the origin along an axis is laid
/// out moved next to the origin and moved back, both exactly: the result lies where the mesh does,
/// its input points bit for bit, and is the layout the mesh gets at the origin.
/// \pre mesh is closed, connected, manifold, consistently oriented outward (core::prepare_for_quadding()).
/// \throw InvalidInput if the precondition fails or the genus exceeds options.cycles.max_genus.
QuadLayout build_quad_layout(const Mesh& mesh, const QuadLayoutOptions& options = {});

/// How many vertices a layout may add to its input (issue #20): a quarter of the input's vertices
/// plus 200 per layout corner (8g-8 for g >= 2, 4 for the torus, 8 for the cube). Routing the
/// curves splits edges for room; within this bound it makes room where curves must pass, beyond
/// it the refinement cascades (each new curve hugging the room made for the last). Reported as
/// LayoutReport::vertices_added_bound; build_quad_layout() says so in its progress when a layout
/// exceeds it (the layout is still valid and returned).
long long vertices_added_bound(int input_vertices, int corners);

/// Checks a layout: the cage is valid (subdiv::check_cage); counts and degrees are the minimum for
/// the genus; every patch is a connected disk whose boundary is a simple loop through its 4 corners
/// in the cage quad's order along the recorded edge paths (paper, rules i-iii); the maps into
/// [0,1]^2 put corners at the unit square's corners, agree on shared sides and flip no triangle.
/// Returns "" if all hold, else what fails.
std::string verify_quad_layout(const QuadLayout& layout);

}  // namespace quadcage::layout

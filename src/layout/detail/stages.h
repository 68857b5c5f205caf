#pragma once
// The stages of build_quad_layout() (paper, Algorithm 1; design.md §2 and §4) and what they share:
// the pieces of the cut surface (pieces.cpp), Algorithm 1's S-cycles (s_cycles.cpp), the S-cycles
// from the handle loops (handle_loop_s_cycles.cpp), T-shirts and handles (tshirts_and_handles.cpp),
// the torus and the cube (torus_and_cube.cpp), and the network from its curves to a verified
// layout (network.cpp). Private to src/layout.

#include <array>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "detail/curves.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

/// Progress lines.
using Say = std::function<void(const std::string&)>;
inline constexpr double kInf = std::numeric_limits<double>::infinity();
/// Extra cost (in edge lengths) of walking next to an existing curve; see Builder::cost_near().
inline constexpr double kAdjacency = 4.0;
/// How strongly a level-set curve keeps to its level: an edge costs its length times
/// 1 + kLevelStick * |u - level| (u in [0, 1]: an area quantile or a distance ratio; or a
/// distance over a width).
inline constexpr double kLevelStick = 20.0;
/// Times a search may open the walls around it (split_chords_around) before it gives up.
inline constexpr int kRoomAttempts = 24;
/// A T-shirt's rings that add at most this many vertices end the search over cyclic orders.
inline constexpr int kRingSplitsAccepted = 200;

/// The layout curves, as indices into a Builder's curves (which follow every split), plus the
/// corners they carry.
struct Network {
    std::vector<int> corners;                              // mesh vertices
    std::vector<std::pair<int, std::vector<int>>> closed;  // closed curve -> its corners (cut there)
    std::vector<int> arcs;                                 // open curves from a corner to a corner
    std::vector<int> s_cycles;                             // Algorithm 1's S_i (g >= 2)
    bool s_cycles_from_handle_loops = false;               // else Algorithm 1's (g >= 2)
};

/// One side of a closed curve that bounds a piece: the curve and which side faces the piece.
struct Hole {
    int curve = -1;
    int side = 0;
};

/// The pieces cut out by closed curves `ids`, and per piece the curves around it, facing it.
struct Cut {
    int count = 0;  // pieces
    std::vector<int> label;
    std::map<int, std::vector<Hole>> holes;
};

/// The pieces of Algorithm 1's cut, each with the S-cycles around it.
struct Pieces {
    std::vector<std::vector<Hole>> holes;  // per piece: the S-cycles around it, facing it
};

// ---- The cut surface: pieces, holes, helpers (pieces.cpp)

/// " (N triangles)": how far the surface has been refined, for progress messages.
std::string surface_size(const Builder& b);

/// Length of a vertex path along mesh edges.
double path_length(const Mesh& m, const std::vector<int>& p);

/// A vertex on both cycles (their crossing), or -1.
int common_vertex(const Cycle& a, const Cycle& b);

/// Position along a closed curve of the vertex at `fraction` of its length, walking from index i0.
int vertex_at_fraction(const Mesh& m, const Cycle& c, size_t i0, double fraction);

/// Triangle labels of the pieces cut out by the given closed curves.
int label_pieces(const Builder& b, const std::vector<int>& curve_ids, std::vector<int>* label);

/// Triangle on side `side` of closed curve c: side 0 has the half-edge c[0] -> c[1], side 1 its twin.
int triangle_beside(const Surface& s, const Cycle& c, int side);

/// The neighbours of x (on closed curve c) strictly inside the side of c whose triangles carry
/// `piece`, in rotation (counter-clockwise) order.
std::vector<int> side_toward(const Surface& s, const Cycle& c, int x, const std::vector<int>& label,
                             int piece);

/// Vertices that touch no triangle of `piece`.
std::vector<char> outside_piece(const Surface& s, const std::vector<int>& label, int piece);

/// The Euler characteristic V - E + F of piece `piece` (triangles labelled so), its boundary
/// included: 0 for an annulus, -2 for a four-holed sphere or a torus with two holes.
int piece_euler_characteristic(const Surface& s, const std::vector<int>& label, int piece);

/// The Euler characteristic V - E + F of the triangles listed (each once), `in(t)` telling whether
/// triangle t is one of them. On a closed manifold surface.
int euler_characteristic(const Surface& s, const std::vector<int>& triangles, const std::function<bool(int)>& in);

/// Elements [from, to) of v, clamped to its range.
std::vector<int> slice(const std::vector<int>& v, int from, int to);

/// Position of x in v, or -1.
int index_in(const std::vector<int>& v, int x);

/// Distances from `vertices` along mesh edges, entering no vertex marked in `block`.
std::vector<double> distances_from(const Surface& s, const std::vector<char>& block, const std::vector<int>& vertices);

/// The level below which `share` of the area of the triangles marked in `tri` lies under the vertex
/// function u (each triangle at the mean u of its corners; triangles with a corner at +inf left out).
double area_level(const Surface& s, const std::vector<double>& u, const std::vector<char>& tri, double share);

/// Each vertex's u as the share of the surface's area below it (triangles at the mean u of their
/// corners, those with a corner at +inf left out): a field with the level sets of u whose level is
/// the area it leaves on its lower side, in [0, 1] (+inf where u is).
std::vector<double> area_quantiles(const Surface& s, const std::vector<double>& u);

/// Where each vertex lies across the annulus that closed, non-separating curve c leaves when the
/// surface is cut along it: the harmonic function (clamped cotangent weights) that is 0 on c seen
/// from its sector 0 and 1 seen from its sector 1 (sectors()); +inf on c. It has no extremum inside
/// the annulus (maximum principle), so each of its level sets is one closed curve parallel to c,
/// and area_level() of 1/2 is the one that cuts the annulus in halves of equal area. (The distance
/// ratio d0 / (d0 + d1) it replaced has extrema beside a small handle's foot: a level set closed
/// round the foot there.)
std::vector<double> harmonic_across(const Surface& s, const Cycle& c);

/// The pieces cut out by the closed curves `ids`, with the holes of each.
Cut cut_by(const Builder& b, const std::vector<int>& ids);

/// The pieces cut out by the 4g-4 S-cycles; checks there are 2g-2 annuli and g-1 four-holed spheres.
Pieces find_pieces(const Builder& b, const std::vector<int>& s_ids, int g);

// ---- S-cycles (s_cycles.cpp, handle_loop_s_cycles.cpp)

/// Algorithm 1 (paper §4): 4g-4 cycles S_i, each crossing the orthogonal system once, on an arc of
/// a b-curve: one per arc of b1 and bg, two per arc of the middle b's. Returns their curve ids.
std::vector<int> place_s_cycles(Builder& b, int g, const Say& say);

/// S-cycles from the handle loops (an alternative to Algorithm 1 that gives the same pieces):
/// each handle loop a_i becomes a handle (annulus) between two parallel S-cycles; the rest, a
/// sphere with 2g holes, is cut into g-1 T-shirts by g-2 more annuli (cut_tshirt). They take the
/// holes as a tree (TshirtTree) where its greedy plan (tshirt_tree()) separates markedly fewer
/// close holes than the chain's (tshirt_plan()), else as the chain. Once no triple of the tree
/// cuts, or a cut of the chain's plan fails, each T-shirt takes the first of a few compact choices
/// (tshirt_choices(): holes near each other for the first, else the last annulus and two holes
/// near it) that cuts; should those fail after a tree, the chain is cut from the start. Areas aim
/// at an even share per quad (a handle 2, a T-shirt 6). Algorithm 1's S-cycles all cross the
/// orthogonal system once, so on a surface whose handles hang off one body they wind round the
/// body side by side in stacks.
/// Returns the S-cycles' curve ids, or nothing if some curve cannot be placed (b is then unchanged).
std::optional<std::vector<int>> tube_s_cycles(Builder& b, const std::vector<int>& loops, int g, const Say& say);
/// The annuli round closed curves `loops`: two S-cycles parallel to each, added to w and to *ids.
/// False if one does not fit. `unit`: one quad's share of the area (the annuli's width).
bool tube_loops(Builder& w, const std::vector<int>& loops, double unit, std::vector<int>* ids, const Say& say);
/// The loops to drop so that `pants` pairs of pants join in pairs into T-shirts: a perfect matching
/// of the pants graph (a node per pair of pants, an edge per loop: ends[e], a loop with both sides
/// on one pair of pants cannot be dropped) of the greatest total length, so that the loops kept are
/// the shortest possible. Per loop, 1 if dropped. Exact: a search over the sets of pants matched so
/// far, memoised (at most 64 pants). Empty if there is no perfect matching, or if the search meets
/// too many sets (then *too_many is set).
std::optional<std::vector<char>> pants_matching(const std::vector<std::array<int, 2>>& ends,
                                                const std::vector<double>& lengths, int pants,
                                                bool* too_many = nullptr);
/// The highest genus neck_s_cycles() tries: its 2g - 2 pairs of pants are matched by
/// pants_matching(), at most 64.
inline constexpr int kMaxNeckGenus = 33;
/// S-cycles round the 2g - 2 shortest loops of a pants decomposition that pair into T-shirts
/// (neck_s_cycles.cpp); b gets them. Empty (b unchanged) where none is found, and for g above
/// kMaxNeckGenus.
std::optional<std::vector<int>> neck_s_cycles(Builder& b, int g, const Say& say);

/// The chain of T-shirts over a body's holes (gap[i][j]: the distance in the body from hole i to
/// hole j; at most 64 holes): g-1 groups of holes, 3, 2, ..., 2, 3, in the order the T-shirts
/// take them, body annulus k separating the first k groups from the rest. *penalty: the sum of
/// the annuli's separation penalties (sum over a inside, b outside of 1 / gap(a, b)^2).
std::vector<std::vector<int>> tshirt_plan(const std::vector<std::vector<double>>& gap, double* penalty);

/// A tree of T-shirts over a body's holes (gap as for tshirt_plan()), cut one T-shirt at a time:
/// each cut merges three open nodes into one, the T-shirt whose body annulus separates the holes
/// under them from the rest. Nodes 0..n-1 are the holes, node n + k the outer S-cycle of merge k;
/// when four are open they bound the last T-shirt. The chain is the tree whose every merge takes
/// the one before: where the holes crowd into one region its annuli nest round the crowd, wrap the
/// body in thin bands and each squeezes past every hole, while a tree's annuli round separate
/// groups lie side by side.
class TshirtTree {
public:
    explicit TshirtTree(const std::vector<std::vector<double>>& gap);
    /// The open nodes.
    const std::vector<int>& open() const { return open_; }
    /// At most `count` triples of open nodes with the separation penalty of their annulus,
    /// cheapest first (ties in the order of the open nodes).
    std::vector<std::pair<double, std::array<int, 3>>> cheapest(size_t count) const;
    /// Merges three open nodes; returns the new node's id.
    int merge(const std::array<int, 3>& t);

private:
    std::vector<int> open_;
    std::vector<double> out_;                 // per node, the separation of an annulus round it
    std::vector<std::vector<double>> cross_;  // per pair of nodes, the weights from x's holes to y's
};

/// The greedy tree: g-2 merges, each of the cheapest triple. *penalty: the sum of their annuli's
/// separation penalties.
std::vector<std::array<int, 3>> tshirt_tree(const std::vector<std::vector<double>>& gap, double* penalty);

// ---- T-shirts and handles (tshirts_and_handles.cpp)

/// Routes a closed ring through corners x[0..3], corner j on hole j, inside the piece beside the
/// holes, one open curve per arc (added to b). With face_right the ring's face lies to the right of
/// x0 -> x1 -> x2 -> x3 at every corner, else to the left; at each corner the face sector (between
/// the arriving and the leaving arc) is kept clear of the hole: design.md §2, "Routing a ring".
/// Returns the new curve ids, or nothing if some arc cannot be routed or room for it would take the
/// surface beyond `max_vertices`.
std::optional<std::vector<int>> route_ring(Builder& b, const std::vector<int>& s_ids,
                                           const std::array<Hole, 4>& holes, const std::array<int, 4>& x,
                                           bool face_right, double* length,
                                           int max_vertices = std::numeric_limits<int>::max());

/// Thrown by network_of_handles_and_tshirts() when the S-cycles at the necks were asked for and
/// none were found: that layout is abandoned, not retried.
class NoNecks : public InternalError {
public:
    using InternalError::InternalError;
};

/// Genus >= 2: the S-cycles (with from_handle_loops: round the necks if `necks`, else from the
/// handle loops, Algorithm 1's where those fail; without it Algorithm 1's), then handles (2 quads)
/// and T-shirts (6 quads). \throw NoNecks where `necks` and none are found.
Network network_of_handles_and_tshirts(Builder& b, int g, const std::vector<int>& handle_loops,
                                        bool from_handle_loops, bool necks, const Say& say);

// ---- The network: from its curves to a verified layout (network.cpp)

/// Wall-clock seconds of the last finish_network(): the cage and the patch maps, and the check.
struct NetworkSeconds {
    double mapped = 0;
    double checked = 0;
};

/// The layout edges of a network: each closed curve cut at its two corners (from the first corner
/// to the second, then on round to the first), then the arcs.
std::vector<std::vector<int>> layout_edge_paths(const Builder& b, const Network& net);

/// Makes the network's curves the only obstacles (the orthogonal system is none any more) and takes
/// the hairpins out of them: where a curve comes back next to itself round a small disk that holds
/// nothing else, the detour is replaced by the shortcut. Shortest paths that must enter a corner's
/// sector from one side make such detours; left in place, the one-vertex-wide sliver between their
/// branches squeezes a patch map below rounding. S-cycles keep their single crossing with the
/// orthogonal system.
void tighten_layout_curves(Builder& b, const Network& net, int g);

/// The cage (extract_cage()), the patch maps and verify_quad_layout() of a network, into *L (whose
/// input_vertices and genus are set). Returns "" or what fails.
std::string finish_network(const Builder& b, const Network& net, QuadLayout* L, const Say& say,
                           NetworkSeconds* seconds);

/// Issue #20's balance targets: patch area max/min and mean corner angle deviation (degrees).
inline constexpr double kAreaRatioTarget = 4.0;
inline constexpr double kAngleDeviationTarget = 20.0;

/// How far a layout's balance is from those targets, as the larger of log(area max/min) /
/// log(kAreaRatioTarget) and the angle deviation / kAngleDeviationTarget: at most 1 when it meets
/// both. The area ratio counts on a log scale: a ratio of 16 is twice as far off as one of 4.
double balance_excess(const LayoutQuality& q);

/// Relaxes the network's corners and edges (relax_layout_corners(), relax_layout_edges(); the
/// options' sweeps) and builds the layout of the relaxed curves (finish_network()). Returns
/// whether *out now holds a built and verified layout: the relaxed one, or for genus 1 the
/// unrelaxed one where its balance_excess() is smaller; *b then holds its curves,
/// *s_cycle_ids its S-cycles, and *measured says whether out->quality was measured. Returns false,
/// with everything unchanged, if nothing moved or the relaxed layout fails a check.
bool relax_network(Builder* b, const Network& net, const QuadLayoutOptions& options, int g, const Say& say,
                   QuadLayout* out, std::vector<int>* s_cycle_ids, NetworkSeconds* seconds, bool* measured);

// ---- Genus 0 and 1 (torus_and_cube.cpp)

/// Genus 1 (Remark 1): two disjoint meridians (a1 and a parallel copy) and two disjoint longitudes
/// (b1 and a parallel copy); each meridian crosses each longitude once: 4 corners of degree 4.
Network network_of_torus(Builder& b, const Say& say);

/// Genus 0: a cube. Corners at the extremes of the 8 octant directions of the principal frame:
/// the bottom ring, then 4 vertical arcs into the other side, then the top ring through their ends.
Network network_of_cube(Builder& b, const Say& say);

}  // namespace quadcage::layout::detail

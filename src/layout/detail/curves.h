#pragma once
// Curves on a Surface: the rotation-order sectors of a vertex on a curve, and the state shared by
// every curve construction (orthogonal system, S-cycles, layout arcs): the surface being refined,
// the curves built so far, which of them block a search, chord splitting for room and a path cost
// that keeps new curves away from old ones (design.md §4).

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <unordered_set>
#include <utility>
#include <vector>

#include "detail/surface.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/validate.h"
#include "quadcage/layout/orthogonal_system.h"

namespace quadcage::layout::detail {

/// Sectors of vertex x on a curve through prev -> x -> next: the neighbours strictly between prev
/// and next in rotation order (sector 0) and strictly between next and prev (sector 1). Sector 0
/// starts next to triangle (x, prev, ...): the triangle of half-edge x -> prev lies in sector 0.
std::array<std::vector<int>, 2> sectors(const Surface& s, int x, int prev, int next);

/// The vertices before and after x on a closed curve.
std::pair<int, int> neighbours_on(const Cycle& c, int x);

/// A key for the undirected edge a-b.
std::uint64_t edge_key(int a, int b);

/// Which of a set of paths run through each vertex (a path's ends included; a corner is on
/// several): an edge whose two ends share a path without being part of it is a dividing chord, the
/// kind a convex-boundary Tutte map flattens (Builder::split_dividing_chords()).
class PathsThrough {
public:
    PathsThrough(int num_vertices, const std::vector<std::vector<int>>& paths);
    bool on_any(int v) const { return !on_[v].empty(); }
    bool share_a_path(int a, int b) const;

private:
    std::vector<std::vector<int>> on_;
};

/// Up to k vertices spread evenly along a curve, skipping those `skip` rejects.
std::vector<int> spread(const Cycle& c, int k, const std::function<bool(int)>& skip);

/// The path cost Builder::cost_near() returns: an edge's length, more near blocked vertices. A type
/// of its own so that dijkstra() can call it directly instead of through std::function.
struct NearCost {
    const Surface* s = nullptr;
    std::shared_ptr<const std::vector<double>> field;  ///< Distance to the nearest blocked vertex.
    std::shared_ptr<const std::vector<char>> beside;   ///< Neighbours of blocked vertices (or empty).
    double repulsion = 0, sigma = 1, adjacency = 0;
    /// Per half-edge, its cost once computed (NaN before), if memoised(): for a cost that many
    /// searches over the same region share. Copies share it: use them in one thread only, and
    /// (as the cost itself) only until the surface is split.
    std::shared_ptr<std::vector<double>> memo;

    double operator()(int h) const {
        if (!memo) return compute(h);
        double& c = (*memo)[h];
        if (std::isnan(c)) c = compute(h);
        return c;
    }
    double compute(int h) const {
        const double d = 0.5 * ((*field)[s->from(h)] + (*field)[s->to(h)]);
        double f = 1.0 + repulsion * std::exp(-d / sigma);
        if (!beside->empty()) f += 0.5 * adjacency * ((*beside)[s->from(h)] + (*beside)[s->to(h)]);
        return s->length(h) * f;
    }
};

/// `cost` (from Builder::cost_near()) remembering each half-edge's cost once computed; any other
/// cost unchanged. The same costs, computed once for searches that share them.
std::function<double(int)> memoised(const std::function<double(int)>& cost);

/// build_orthogonal_system() for a mesh whose validate() report is known.
OrthogonalSystem build_orthogonal_system_validated(const Mesh& mesh, const OrthogonalSystemOptions& options,
                                                   const ValidationReport& report);

/// Thrown when a Builder's splits pass its vertex budget (Builder::max_vertices_): the layout being
/// built is abandoned, not retried.
class OverBudget : public InternalError {
public:
    using InternalError::InternalError;
};

/// State of a curve construction: the surface, the curves, and which of them are obstacles now.
/// Copyable: trying alternatives on a copy is how constructions pick the shorter of two routes.
class Builder {
public:
    Builder(const Mesh& mesh, const OrthogonalSystemOptions& o);

    Surface s_;
    OrthogonalSystemOptions o_;
    double sigma_ = 1;
    std::vector<Cycle> curves_;   ///< Every curve built so far (open paths too, as vertex lists).
    std::vector<char> obstacle_;  ///< Per curve: does the current search avoid it.
    std::vector<char> closed_;    ///< Per curve: closed (a cycle) or an open path.
    int splits_ = 0;
    /// Vertices the surface may reach (0: no limit); a split past it throws OverBudget.
    long long max_vertices_ = 0;

    /// Adds a curve; returns its index.
    int add_curve(Cycle c, bool closed = true, bool obstacle = true);

    /// Vertices on obstacle curves.
    std::vector<char> blocked() const;

    /// Keys (edge_key) of the mesh edges that obstacle curves walk along.
    std::unordered_set<std::uint64_t> obstacle_edges() const;

    /// Splits every edge whose two ends are on obstacle curves (or `extra` curves) but which no
    /// such curve walks along, so that paths can pass between curves that run side by side
    /// (design.md §4, step 5). Curves get the midpoints of their own split edges (none: a curve
    /// edge is never a chord). Returns the number of edges split.
    int split_chords(const std::vector<Cycle>& extra = {});

    /// Splits the edges that no path walks along but whose two ends lie on one path (a vertex of
    /// a path includes its ends). With the paths the sides of quad patches, these are exactly
    /// the edges that join two points of one side: the ones a convex-boundary Tutte map flattens
    /// (Floater 2003, "dividing edges"). An edge between two different sides maps to a proper
    /// chord of the square and needs no split. Returns the number of edges split.
    int split_dividing_chords(const std::vector<std::vector<int>>& paths);

    /// Splits only the chords (as in split_chords()) on the rim of a failed search: chords of a
    /// triangle whose third vertex the search reached. Opens the walls that stopped that search
    /// without refining the rest of the surface. Returns the number of edges split.
    int split_chords_around(const std::vector<char>& reached);

    /// Room for the `attempt`-th retry of a failed search: split_chords_around(), or
    /// split_chords() everywhere if no chord borders the search or every 6th attempt (a long
    /// corridor would otherwise open a few edges per attempt).
    int open_room(const std::vector<char>& reached, int attempt) {
        const int n = attempt % 6 == 0 ? 0 : split_chords_around(reached);
        return n > 0 ? n : split_chords();
    }

    /// Room for a route that sector_path() did not find with the same arguments: a search in which
    /// a path may also pass through the midpoints of chords (split_chords()), at a cost far above
    /// any walk along free vertices, finds the route that needs the fewest and shortest chord
    /// crossings; exactly those chords are split. Splitting more (every chord round the failed
    /// search, or everywhere) makes corridors the next routes hug, which need splits again: the
    /// mesh grew several-fold that way. Returns the number of edges split (0: no route even
    /// through chords).
    int open_route(int x, const std::vector<int>& from_sector, int y, const std::vector<int>& to_sector,
                   const std::vector<char>& block, const std::function<double(int)>& cost);

    /// The chords open_route() would split (sorted), without splitting them: for a construction
    /// that searches on a trial copy and makes the room on the surface it started from. Edges in
    /// `walls` (edge_key) are never crossed, as if curves walked along them.
    std::vector<std::pair<int, int>> route_chords(
        int x, const std::vector<int>& from_sector, int y, const std::vector<int>& to_sector,
        const std::vector<char>& block, const std::function<double(int)>& cost,
        const std::unordered_set<std::uint64_t>* walls = nullptr) const;

    /// Splits the given edges at their midpoints and inserts the midpoints into every curve that
    /// walks along them.
    void split_curve_edges(const std::vector<std::pair<int, int>>& edges);

    /// Cost of walking half-edge h: its length, more near blocked vertices (avoids hugging them).
    /// With `outside`, the distance field neither starts from nor enters vertices marked there
    /// (a search confined to one region pays only for that region). `adjacency` adds that multiple
    /// of the length to each end of an edge that is a neighbour of a blocked vertex: a path that
    /// runs next to a curve makes chords, and splitting them makes room for the next path to hug.
    std::function<double(int)> cost_near(const std::vector<char>& block,
                                         const std::vector<char>* outside = nullptr,
                                         double adjacency = 0) const;

    /// cost_near(block, outside, adjacency) from `previous`, the cost_near() of `previous_block` with
    /// the same `outside` and adjacency, where `block` adds vertices to `previous_block` on the same
    /// surface (no split since): the same cost, its field lowered from the added vertices only
    /// (lower_distances()) instead of searched again from all.
    std::function<double(int)> grown_cost_near(const std::function<double(int)>& previous,
                                               const std::vector<char>& previous_block,
                                               const std::vector<char>& block,
                                               const std::vector<char>* outside) const;

    double edge_cost(const std::function<double(int)>& cost, int a, int b) const;

    /// Shortest path leaving x through `from_sector` and reaching y through `to_sector` (vertices
    /// of the sectors that are not blocked). Returns the interior vertices, or empty; then
    /// `reached` (if given) marks the vertices the search settled. A path whose search must settle
    /// a vertex farther than `bound` (so every path of cost above `bound`, some of cost `bound`) may
    /// be missed: a caller that only wants paths cheaper than `bound` gets the same answer sooner.
    /// The search runs from both ends (search::run_both_ways(): on botijo it cut the repulsion-cost
    /// searches' CPU samples by a third; README, Benchmarks). When it fails and `reached` is given,
    /// its forward half runs on to fill `reached`. Only a bounded search that must fill `reached`
    /// runs one way.
    std::vector<int> sector_path(int x, const std::vector<int>& from_sector, int y,
                                 const std::vector<int>& to_sector, const std::vector<char>& block,
                                 const std::function<double(int)>& cost, double* total,
                                 std::vector<char>* reached = nullptr,
                                 double bound = std::numeric_limits<double>::infinity()) const;
};

}  // namespace quadcage::layout::detail

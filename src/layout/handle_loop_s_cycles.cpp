// S-cycles from the handle loops: two S-cycles parallel to each handle loop, then T-shirts cut off
// the body one at a time (QuadLayoutOptions::s_cycles_from_handle_loops).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

namespace {

// How strongly a tree's path keeps away from the other tree: an edge within `reach` of it costs
// its length times 1 + kShun * (1 - distance / reach).
constexpr double kShun = 10.0;

// How many choices of holes for the next T-shirt the handle-loop S-cycles try when the plan
// fails, and up to how many holes the plan is made (one bit per hole).
constexpr size_t kTshirtChoices = 4;
constexpr int kMaxPlannedHoles = 62;

// The tree of T-shirts is cut when its separation penalty is below this fraction of the chain's.
// A tree that only takes the complement of a chain's sets costs the same (fertility: both
// 1.55e-3) and botijo's costs 0.98 of its chain's; both keep the chain, whose level-3 fits were
// the closer (botijo check_fit RMS 7.7e-4 against 9.3e-4). Boot's tree costs 0.53 of its chain's,
// input_wheel's 0.71, a plate of genus 10's 0.50: their chains nest every annulus round the
// cluster of holes and wrap the body in bands.
constexpr double kTreeGain = 0.9;

// How many times cut_tshirt() makes room for its loops before it gives up, and how many times it
// makes room for the outer loop beside one inner loop.
constexpr int kTshirtRoomAttempts = 8;
constexpr int kOuterRoomAttempts = 4;

// A closed curve near the level set {u = level}: it leaves x, the vertex of `cut` whose u is
// nearest the level, on one side of the cut and comes back on the other, so it crosses the cut
// once; it avoids `wall`, the rest of the cut and where |u - level| > band. Edges cost their length times
// 1 + kLevelStick * |u - level| / scale; x is cut[first] or later. Empty if there is no such curve;
// then, with `room`, the chords whose split would let one through (Builder::route_chords; the cut
// and the edges in `walls` are not crossed).
Cycle level_loop(const Builder& b, const std::vector<double>& u, double level, double scale, double band,
                 const std::vector<int>& cut, std::vector<char> wall, size_t first = 1,
                 std::vector<std::pair<int, int>>* room = nullptr,
                 const std::unordered_set<std::uint64_t>* walls = nullptr) {
    first = std::max<size_t>(first, 1);
    if (first + 1 >= cut.size()) return {};
    size_t at = first;
    for (size_t i = first; i + 1 < cut.size(); ++i)
        if (std::abs(u[cut[i]] - level) < std::abs(u[cut[at]] - level)) at = i;
    const int x = cut[at];
    for (int v : cut) wall[v] = 1;  // x too: the search leaves and enters it through its sectors
    for (size_t v = 0; v < wall.size(); ++v)
        if (!(std::abs(u[v] - level) <= band)) wall[v] = 1;  // +inf too
    const Surface& s = b.s_;
    const auto sec = sectors(s, x, cut[at - 1], cut[at + 1]);
    const auto cost = [&s, &u, level, scale](int h) {
        const double du = std::abs(u[s.from(h)] - level) + std::abs(u[s.to(h)] - level);
        return s.length(h) * (1 + kLevelStick * 0.5 * du / scale);
    };
    const std::vector<int> path = b.sector_path(x, sec[0], x, sec[1], wall, cost, nullptr);
    if (path.empty()) {
        if (room) {
            std::unordered_set<std::uint64_t> uncrossed;
            if (walls) uncrossed = *walls;
            for (size_t i = 0; i + 1 < cut.size(); ++i) uncrossed.insert(edge_key(cut[i], cut[i + 1]));
            *room = b.route_chords(x, sec[0], x, sec[1], wall, cost, &uncrossed);
        }
        return {};
    }
    Cycle loop{x};
    loop.insert(loop.end(), path.begin(), path.end());
    return loop;
}

// Splits the edges that join a vertex of handle loop m to another vertex of m or of a curve that
// tube_annulus() avoids (S-cycles, handle loops) without being an edge of those curves: where m
// touches them, an S-cycle beside m has no vertex to pass through. Returns the number split.
int split_chords_beside(Builder& b, int m, const std::vector<int>& loops) {
    const Surface& s = b.s_;
    std::vector<char> block = b.blocked(), on_m(s.num_vertices(), 0);
    std::unordered_set<std::uint64_t> curve_edges = b.obstacle_edges();
    for (int l : loops) {
        const Cycle& c = b.curves_[l];
        for (size_t i = 0; i < c.size(); ++i) {
            block[c[i]] = 1;
            curve_edges.insert(edge_key(c[i], c[(i + 1) % c.size()]));
        }
    }
    for (int v : b.curves_[m]) on_m[v] = 1;
    std::vector<std::pair<int, int>> chords;
    for (int v : b.curves_[m])
        for (int x : s.ring(v))
            if (block[x] && !curve_edges.count(edge_key(v, x)) && (!on_m[x] || v < x))
                chords.push_back({std::min(v, x), std::max(v, x)});
    std::sort(chords.begin(), chords.end());
    chords.erase(std::unique(chords.begin(), chords.end()), chords.end());
    b.split_curve_edges(chords);
    return static_cast<int>(chords.size());
}

// An S-cycle beside handle loop m on `side`, half an edge from it: the edges from m to its
// neighbours on that side are split and their midpoints, in order along m, joined (consecutive ones
// share a triangle). Call after split_chords_beside(): then no such edge ends on m or on another
// curve, and the loop touches no curve. Adds it to b; returns its id, or -1.
int offset_loop(Builder& b, int m, int side) {
    const Cycle c = b.curves_[m];
    std::vector<std::pair<int, int>> spokes;
    for (int v : c) {
        const auto [p, n] = neighbours_on(c, v);
        std::vector<int> sec = sectors(b.s_, v, p, n)[side];
        if (side == 1) std::reverse(sec.begin(), sec.end());  // sector 1 runs from next back to prev
        for (int w : sec) spokes.push_back({v, w});
    }
    const int n0 = b.s_.num_vertices();
    b.split_curve_edges(spokes);
    if (spokes.empty() || b.s_.num_vertices() != n0 + static_cast<int>(spokes.size())) return -1;
    Cycle loop;
    for (size_t i = 0; i < spokes.size(); ++i) loop.push_back(n0 + static_cast<int>(i));
    return b.add_curve(loop);
}

// Whether S-cycles made[0] and made[1] bound one piece that holds curve c, cut by s_ids, and that
// piece is an annulus: two holes alone do not say so, for a band round a handle loop can take in a
// whole small handle beside it (a torus with two holes; a jittered copy of boot.obj's laces did).
bool bounds_annulus(const Builder& b, const Cycle& c, const std::vector<int>& s_ids,
                    const std::array<int, 2>& made) {
    const Cut cut = cut_by(b, s_ids);
    const int piece = cut.label[triangle_beside(b.s_, c, 0)];
    const auto& around = cut.holes.at(piece);
    return around.size() == 2 && around[0].curve != around[1].curve &&
           std::all_of(around.begin(), around.end(),
                       [&](const Hole& h) { return h.curve == made[0] || h.curve == made[1]; }) &&
           piece_euler_characteristic(b.s_, cut.label, piece) == 0;
}

// The handle annulus round handle loop m: two S-cycles parallel to m, one on each side at distance
// about `width` (the distance from m on that side). Adds them to b and to s_ids; returns whether
// they bound an annulus round m. `loose` (a retry where that failed): an S-cycle may come as close
// to m as it needs (m's own vertices excepted), and may leave from a neighbour of m.
bool tube_annulus(Builder& b, int m, const std::vector<int>& loops, double width, std::vector<int>* s_ids,
                  std::array<int, 2>* made, bool loose = false) {
    const Surface& s = b.s_;
    const Cycle c = b.curves_[m];  // a copy: add_curve() below may move the curves
    for (int side = 0; side < 2; ++side) {
        std::vector<char> block = b.blocked();
        for (int l : loops)
            for (int v : b.curves_[l]) block[v] = 1;
        PathSearch q;
        q.blocked = &block;
        std::vector<int> beside(s.num_vertices(), -1);  // per source, the vertex of m it is next to
        for (int v : c) {
            const auto [p, n] = neighbours_on(c, v);
            const auto sec = sectors(s, v, p, n);  // named: a temporary's [side] would dangle
            for (int w : sec[side])
                if (!block[w]) {
                    q.sources.push_back({w, norm(s.point(w) - s.point(v))});
                    if (beside[w] < 0) beside[w] = v;
                }
        }
        q.max_distance = 4 * width;
        const PathResult r = detail::dijkstra(s, q);
        // The cut runs from m to 2 widths (loose: as far as the search went, so that a loop
        // round the cut's end alone leaves the band even on a coarse mesh).
        const double reach = loose ? 4 * width : 2 * width;
        int z = -1;
        for (int v = 0; v < s.num_vertices(); ++v)
            if (r.distance[v] < kInf &&
                (z < 0 || std::abs(r.distance[v] - reach) < std::abs(r.distance[z] - reach)))
                z = v;
        if (z < 0) return false;
        std::vector<int> cut = r.path_to(s, z);
        std::vector<double> u = r.distance;
        std::vector<char> wall = block;
        if (loose) {
            if (beside[cut[0]] >= 0) cut.insert(cut.begin(), beside[cut[0]]);
            for (double& d : u) d = std::max(d, 0.25 * width + 1e-9 * width);  // [0, width] in the band
            // Only m's side of the Voronoi diagram of m's two sides and the other curves: a loop
            // there is parallel to m, where a loop in a band round m can take in a close handle.
            PathSearch o;
            std::vector<char> on_m(s.num_vertices(), 0);
            for (int v : c) on_m[v] = 1;
            o.blocked = &on_m;
            for (int v = 0; v < s.num_vertices(); ++v)
                if (block[v] && !on_m[v]) o.sources.push_back({v, 0.0});
            for (int v : c) {
                const auto [p, n] = neighbours_on(c, v);
                const auto sec = sectors(s, v, p, n);
                for (int x : sec[1 - side])
                    if (!block[x]) o.sources.push_back({x, norm(s.point(x) - s.point(v))});
            }
            o.max_distance = 4 * width;
            const PathResult others = detail::dijkstra(s, o);
            for (int v = 0; v < s.num_vertices(); ++v)
                if (!(r.distance[v] <= others.distance[v])) wall[v] = 1;  // ties: chords' midpoints
        }
        const Cycle loop = level_loop(b, u, width, width, 0.75 * width, cut, wall);
        if (loop.empty()) return false;
        (*made)[side] = b.add_curve(loop);
        s_ids->push_back((*made)[side]);
    }
    // The two must bound one piece (the annulus) that holds m and no other curve.
    return bounds_annulus(b, c, *s_ids, *made);
}

// The body left after `ids`: the piece beside `last` (the outer S-cycle of the last body annulus)
// that is not that annulus, or, before any (last < 0), the one piece with 2g holes. -1: none.
int body_piece(const Cut& cut, int last, int g) {
    for (const auto& [p, hs] : cut.holes) {
        const bool has_last = std::any_of(hs.begin(), hs.end(), [last](const Hole& h) { return h.curve == last; });
        if ((last < 0 && hs.size() == static_cast<size_t>(2 * g)) || (last >= 0 && has_last && hs.size() > 2))
            return p;
    }
    return -1;
}

// One T-shirt cut off the body, and the annulus beyond it.
struct BodyCut {
    Builder b;
    std::vector<int> ids;  // every S-cycle so far
    int outer = -1;        // the annulus' S-cycle on the side of the body left
};

// Cuts a T-shirt holding holes C off the body (the piece beside `last`, or the first body), with
// an annulus separating it from holes D. `units` is the body's share of the area in quads (the
// T-shirt takes 6, the annulus 2), `unit` one quad's area. C's holes are joined into a tree by
// shortest paths, and D's likewise, each keeping away from the other: the body less the two trees
// is an annulus, so a loop in it that crosses a path from one tree to the other once separates C
// from D, whatever the level sets of d_C / (d_C + d_D) do round holes of D near C. When no loop
// fits, the chords its route must cross, else short cuts, else the chords between the trees are split
// for room (at most kTshirtRoomAttempts times). C's tree keeps off the rings of D's holes, unless
// `crowded`: where they wall a hole of C in, only D's holes are walls.
std::optional<BodyCut> cut_tshirt(Builder w, std::vector<int> ids, int last, const std::vector<int>& C,
                                  const std::vector<int>& D, int g, double units, double unit,
                                  bool crowded = false) {
    const Surface& s = w.s_;
    const double reach = std::sqrt(unit);  // how far a tree keeps off the other
    for (int room = 0; room <= kTshirtRoomAttempts; ++room) {
        const Cut cut = cut_by(w, ids);
        const int body = body_piece(cut, last, g);
        if (body < 0) return std::nullopt;
        const std::vector<char> block = outside_piece(s, cut.label, body);
        std::vector<char> tri(cut.label.size(), 0);
        for (size_t t = 0; t < cut.label.size(); ++t) tri[t] = cut.label[t] == body;
        auto distance_from = [&](const std::vector<int>& vertices) { return distances_from(s, block, vertices); };
        std::vector<Cycle> joins;  // the trees' paths: chords between them are split for room
        auto join = [&](const std::vector<int>& curves, const std::vector<char>& avoid,
                        const std::vector<double>& shun) -> std::optional<std::vector<int>> {
            std::vector<int> tree = w.curves_[curves[0]];
            for (size_t j = 1; j < curves.size(); ++j) {
                PathSearch q;
                q.blocked = &avoid;
                q.cost = [&s, &shun, reach](int h) {
                    const double d = 0.5 * (shun[s.from(h)] + shun[s.to(h)]);
                    return s.length(h) * (1 + kShun * std::max(0.0, 1 - d / reach));
                };
                for (int v : tree) q.sources.push_back({v, 0.0});
                for (int v : w.curves_[curves[j]]) q.targets.push_back({v, 0.0});
                const PathResult r = detail::dijkstra(s, q);
                if (r.target < 0) return std::nullopt;
                const std::vector<int> path = r.path_to(s, r.target);
                joins.push_back(path);
                tree.insert(tree.end(), path.begin(), path.end());
                tree.insert(tree.end(), w.curves_[curves[j]].begin(), w.curves_[curves[j]].end());
            }
            return tree;
        };
        // C's tree keeps a vertex off D's holes (crowded: only off the holes themselves) and shuns
        // them; D's keeps a vertex off C's tree and shuns it.
        std::vector<char> away = block;
        std::vector<int> d_holes;
        for (int c : D)
            for (int v : w.curves_[c]) {
                d_holes.push_back(v);
                away[v] = 1;
                if (!crowded)
                    for (int x : s.ring(v)) away[x] = 1;
            }
        for (int c : C)
            for (int v : w.curves_[c]) away[v] = block[v];
        const auto c_tree = join(C, away, distance_from(d_holes));
        if (!c_tree) {
            if (w.split_chords(joins) == 0) return std::nullopt;
            continue;
        }
        const std::vector<int>& core = *c_tree;
        const std::vector<double> d_c = distance_from(core);
        std::vector<char> off_c = block;
        for (int v : core) off_c[v] = 1;
        std::vector<char> near_c = off_c;
        for (int v : core)
            for (int x : s.ring(v)) near_c[x] = 1;
        for (int c : D)
            for (int v : w.curves_[c]) near_c[v] = 0;
        const size_t c_joins = joins.size();
        auto d_tree = join(D, near_c, d_c);
        if (!d_tree) {  // C's tree and its ring cut D's holes apart: only the tree itself is a wall
            joins.resize(c_joins);
            std::vector<char> on_c = off_c;
            for (int c : D)
                for (int v : w.curves_[c]) on_c[v] = 0;
            d_tree = join(D, on_c, d_c);
        }
        if (!d_tree) {
            // C's tree closes a pocket round a hole of D where it runs beside itself: split the
            // edges that join two of its vertices (the pocket's mouth) and try again.
            std::vector<char> on_core(s.num_vertices(), 0);
            for (int v : core) on_core[v] = 1;
            std::unordered_set<std::uint64_t> along = w.obstacle_edges();
            for (const Cycle& p : joins)
                for (size_t i = 0; i + 1 < p.size(); ++i) along.insert(edge_key(p[i], p[i + 1]));
            std::vector<std::pair<int, int>> mouths;
            for (int h = 0; h < s.num_half_edges(); ++h) {
                const int a = s.from(h), c = s.to(h);
                if (a < c && on_core[a] && on_core[c] && !block[a] && !along.count(edge_key(a, c)))
                    mouths.push_back({a, c});
            }
            if (!mouths.empty())
                w.split_curve_edges(mouths);
            else if (w.split_chords(joins) == 0)
                return std::nullopt;
            continue;
        }
        const std::vector<int>& d_vertices = *d_tree;
        const std::vector<double> d_d = distance_from(d_vertices);
        std::vector<double> u(s.num_vertices(), kInf);
        for (int v = 0; v < s.num_vertices(); ++v)
            if (!block[v] && d_c[v] < kInf && d_d[v] < kInf && d_c[v] + d_d[v] > 0) u[v] = d_c[v] / (d_c[v] + d_d[v]);
        const double lo0 = area_level(s, u, tri, 6 / units), hi0 = area_level(s, u, tri, 8 / units);
        PathSearch q;
        q.blocked = &block;
        for (int v : core) q.sources.push_back({v, 0.0});
        for (int v : d_vertices) q.targets.push_back({v, 0.0});
        const PathResult bridge = detail::dijkstra(s, q);
        if (bridge.target < 0) return std::nullopt;
        const std::vector<int> cut_path = bridge.path_to(s, bridge.target);
        // The trees' paths are walls the loops may not cross: room is made beside them, not
        // through them.
        std::unordered_set<std::uint64_t> tree_edges;
        for (const Cycle& p : joins)
            for (size_t i = 0; i + 1 < p.size(); ++i) tree_edges.insert(edge_key(p[i], p[i + 1]));
        std::vector<std::pair<int, int>> room_edges;  // the chords the first failed loop must cross
        // Lower levels if the loops take in holes of D that lie in C's region (islands).
        for (const double f : {1.0, 0.6, 0.35, 0.2}) {
            BodyCut out{w, ids};
            Builder& trial = out.b;
            std::vector<char> wall = trial.blocked();  // obstacle curves, C's tree and D's
            for (size_t v = 0; v < wall.size(); ++v) wall[v] = wall[v] || off_c[v];
            for (int v : d_vertices) wall[v] = 1;
            const Cycle inner = level_loop(trial, u, f * lo0, 1.0, kInf, cut_path, wall, 1,
                                           room_edges.empty() ? &room_edges : nullptr, &tree_edges);
            if (inner.empty()) continue;
            for (int v : inner) wall[v] = 1;
            size_t crossed = 0;  // where inner crosses the cut: outer crosses it farther on
            while (crossed < cut_path.size() && std::find(inner.begin(), inner.end(), cut_path[crossed]) == inner.end())
                ++crossed;
            // Outer passes between inner and D's tree, where inner may have left no vertex free:
            // the chords its route must cross are split on the trial, inner kept (made anew, it
            // would take the new room), up to kOuterRoomAttempts times.
            const int a = trial.add_curve(inner);
            std::vector<double> uf = u;
            Cycle outer;
            for (int open = 0;; ++open) {
                std::vector<std::pair<int, int>> edges;
                outer = level_loop(trial, uf, f * hi0, 1.0, kInf, cut_path, wall, crossed + 1,
                                   open < kOuterRoomAttempts ? &edges : nullptr, &tree_edges);
                if (!outer.empty() || edges.empty()) break;
                const size_t n0 = uf.size();
                trial.split_curve_edges(edges);  // new vertices n0, n0 + 1, ... in the order of `edges`
                uf.resize(trial.s_.num_vertices());
                for (size_t i = 0; i < edges.size(); ++i)
                    uf[n0 + i] = 0.5 * (uf[edges[i].first] + uf[edges[i].second]);
                wall.resize(uf.size(), 0);
            }
            if (outer.empty()) continue;
            out.outer = trial.add_curve(outer);
            out.ids.push_back(a);
            out.ids.push_back(out.outer);
            // The piece beside `inner` on C's side must have C and inner round it, the piece
            // between inner and outer no other hole.
            const Cut after = cut_by(trial, out.ids);
            int shirt = -1, ring = -1;
            for (int side = 0; side < 2; ++side) {
                const int p = after.label[triangle_beside(trial.s_, trial.curves_[a], side)];
                const auto& hs = after.holes.at(p);
                if (hs.size() == 4 && std::all_of(C.begin(), C.end(), [&](int c) {
                        return std::any_of(hs.begin(), hs.end(), [c](const Hole& h) { return h.curve == c; });
                    }))
                    shirt = p;
                else if (hs.size() == 2)
                    ring = p;
            }
            const auto& beside = trial.curves_[out.outer];
            const Surface& ts = trial.s_;
            const bool outer_on_ring = ring >= 0 && (after.label[triangle_beside(ts, beside, 0)] == ring ||
                                                     after.label[triangle_beside(ts, beside, 1)] == ring);
            if (shirt >= 0 && ring >= 0 && outer_on_ring) return out;
        }
        // No loop fits between the trees: split the chords the first failed loop must cross (a
        // few, where the trees or the inner loop pinch the body), else the edges of a short cut,
        // else every chord between the trees, and try again.
        if (!room_edges.empty()) {
            w.split_curve_edges(room_edges);
        } else if (cut_path.size() < 6) {
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i + 1 < cut_path.size(); ++i) edges.push_back({cut_path[i], cut_path[i + 1]});
            w.split_curve_edges(edges);
        } else if (w.split_chords(joins) == 0) {
            return std::nullopt;
        }
    }
    return std::nullopt;
}

// The penalty of a body annulus round the holes in `set` (one bit per hole, indices into `gap`,
// their distances in the body): the sum over a in the set and b not of 1 / gap(a, b)^2, large where
// the annulus must squeeze between holes close together. A set and its complement cost the same.
class Separation {
public:
    explicit Separation(const std::vector<std::vector<double>>& gap) : n_(static_cast<int>(gap.size())) {
        weight_.assign(n_, std::vector<double>(n_, 0));
        for (int i = 0; i < n_; ++i)
            for (int j = 0; j < n_; ++j)
                if (i != j) weight_[i][j] = 1 / std::max(gap[i][j] * gap[i][j], 1e-12);
    }
    double weight(int a, int b) const { return weight_[a][b]; }
    double operator()(std::uint64_t set) const {
        double p = 0;
        for (int a = 0; a < n_; ++a)
            if (set >> a & 1)
                for (int b = 0; b < n_; ++b)
                    if (!(set >> b & 1)) p += weight_[a][b];
        return p;
    }

private:
    int n_;
    std::vector<std::vector<double>> weight_;
};

}  // namespace

// The order in which T-shirts take the body's 2g holes (indices into `gap`, their distances in
// the body): g-1 groups of 3, 2, ..., 2, 3, so that body annulus k separates A_k, the holes of the
// first k groups, from the rest. Minimizes the sum over k of Separation(A_k): holes close together
// go to the same side of every body annulus, so that no annulus has to squeeze between them. Exact
// (over the subsets of holes) up to 16 holes, greedy beyond. *penalty: that sum.
std::vector<std::vector<int>> tshirt_plan(const std::vector<std::vector<double>>& gap, double* penalty) {
    const int n = static_cast<int>(gap.size());
    const Separation separation(gap);
    auto members = [n](std::uint64_t set) {
        std::vector<int> m;
        for (int a = 0; a < n; ++a)
            if (set >> a & 1) m.push_back(a);
        return m;
    };
    std::vector<std::uint64_t> chain;  // A_1, ..., A_{g-2}
    const int steps = n / 2 - 2;
    if (n <= 16) {
        const std::uint64_t all = (std::uint64_t{1} << n) - 1;
        std::vector<double> best(all + 1, kInf);
        std::vector<std::uint64_t> from(all + 1, 0);
        for (std::uint64_t set = 1; set <= all; ++set) {
            const int size = __builtin_popcountll(set);
            if (size < 3 || size % 2 == 0 || size > n - 3) continue;
            if (size == 3) {
                best[set] = separation(set);
                continue;
            }
            const std::vector<int> m = members(set);
            for (size_t i = 0; i < m.size(); ++i)
                for (size_t j = i + 1; j < m.size(); ++j) {
                    const std::uint64_t prev = set & ~(std::uint64_t{1} << m[i]) & ~(std::uint64_t{1} << m[j]);
                    if (best[prev] < best[set]) {
                        best[set] = best[prev];
                        from[set] = prev;
                    }
                }
            if (best[set] < kInf) best[set] += separation(set);
        }
        std::uint64_t end = 0;
        for (std::uint64_t set = 1; set <= all; ++set)
            if (__builtin_popcountll(set) == n - 3 && (end == 0 || best[set] < best[end])) end = set;
        for (std::uint64_t set = end; set != 0; set = from[set]) chain.insert(chain.begin(), set);
        *penalty = end != 0 ? best[end] : 0;
    } else {
        // Each step adds the triple (first) or pair of holes that adds the least penalty.
        std::uint64_t set = 0;
        *penalty = 0;
        for (int step = 0; step < steps; ++step) {
            std::uint64_t pick = 0;
            double least = kInf;
            auto consider = [&](std::uint64_t add) {
                if (set & add) return;
                const double p = separation(set | add);
                if (p < least) least = p, pick = set | add;
            };
            for (int a = 0; a < n; ++a)
                for (int b = a + 1; b < n; ++b) {
                    const std::uint64_t pair = (std::uint64_t{1} << a) | (std::uint64_t{1} << b);
                    if (step > 0)
                        consider(pair);
                    else
                        for (int c = b + 1; c < n; ++c) consider(pair | std::uint64_t{1} << c);
                }
            set = pick;
            chain.push_back(set);
            *penalty += least;
        }
    }
    std::vector<std::vector<int>> groups;
    std::uint64_t before = 0;
    for (std::uint64_t set : chain) {
        groups.push_back(members(set & ~before));
        before = set;
    }
    const std::uint64_t all = n >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
    groups.push_back(members(all & ~before));
    return groups;
}

TshirtTree::TshirtTree(const std::vector<std::vector<double>>& gap) {
    const int n = static_cast<int>(gap.size());
    const Separation separation(gap);
    cross_.assign(n, std::vector<double>(n, 0));
    for (int i = 0; i < n; ++i) {
        out_.push_back(separation(std::uint64_t{1} << i));
        open_.push_back(i);
        for (int j = 0; j < n; ++j)
            if (i != j) cross_[i][j] = separation.weight(i, j);
    }
}

std::vector<std::pair<double, std::array<int, 3>>> TshirtTree::cheapest(size_t count) const {
    std::vector<std::pair<double, std::array<int, 3>>> best;  // sorted, at most count
    const size_t n = open_.size();
    for (size_t a = 0; a < n; ++a)
        for (size_t b = a + 1; b < n; ++b)
            for (size_t c = b + 1; c < n; ++c) {
                const int x = open_[a], y = open_[b], z = open_[c];
                const double p = out_[x] + out_[y] + out_[z] - cross_[x][y] - cross_[y][x] - cross_[x][z] -
                                 cross_[z][x] - cross_[y][z] - cross_[z][y];
                if (best.size() == count && !(p < best.back().first)) continue;
                const std::pair<double, std::array<int, 3>> t{p, {x, y, z}};
                // After the ones no dearer: ties keep the order of enumeration.
                best.insert(std::upper_bound(best.begin(), best.end(), t,
                                             [](const auto& u, const auto& v) { return u.first < v.first; }),
                            t);
                if (best.size() > count) best.pop_back();
            }
    return best;
}

int TshirtTree::merge(const std::array<int, 3>& t) {
    const int m = static_cast<int>(out_.size());
    double p = 0;
    for (int x : t) {
        p += out_[x];
        for (int y : t)
            if (y != x) p -= cross_[x][y];
    }
    out_.push_back(p);
    for (auto& row : cross_) row.push_back(0);
    cross_.emplace_back(m + 1, 0.0);
    for (int r = 0; r < m; ++r)
        for (int x : t) {
            cross_[m][r] += cross_[x][r];
            cross_[r][m] += cross_[r][x];
        }
    open_.erase(std::remove_if(open_.begin(), open_.end(),
                               [&t](int x) { return x == t[0] || x == t[1] || x == t[2]; }),
                open_.end());
    open_.push_back(m);
    return m;
}

std::vector<std::array<int, 3>> tshirt_tree(const std::vector<std::vector<double>>& gap, double* penalty) {
    TshirtTree tree(gap);
    std::vector<std::array<int, 3>> merges;
    *penalty = 0;
    while (tree.open().size() > 4) {
        const auto [cost, t] = tree.cheapest(1).front();
        *penalty += cost;
        merges.push_back(t);
        tree.merge(t);
    }
    return merges;
}

namespace {

// The triples of holes a T-shirt may take next, most compact first: each hole with the hole
// nearest it and the hole nearest those two (the first body), or the last annulus' S-cycle with
// one of the holes nearest it and the hole nearest those two. `gap` holds distances in the body
// between holes; at most `count` triples.
std::vector<std::vector<int>> tshirt_choices(const std::vector<std::vector<double>>& gap, int last_index, size_t count) {
    const int n = static_cast<int>(gap.size());
    std::vector<std::pair<double, std::vector<int>>> found;
    for (int i = 0; i < n; ++i) {
        if (last_index >= 0 && i != last_index) continue;
        std::vector<int> order;
        for (int j = 0; j < n; ++j)
            if (j != i) order.push_back(j);
        std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return gap[i][x] < gap[i][y]; });
        const size_t partners = last_index >= 0 ? std::min<size_t>(3, order.size()) : 1;
        for (size_t p = 0; p < partners; ++p) {
            const int j = order[p];
            int c = -1;
            for (int x = 0; x < n; ++x)
                if (x != i && x != j &&
                    (c < 0 || std::min(gap[i][x], gap[j][x]) < std::min(gap[i][c], gap[j][c])))
                    c = x;
            if (c < 0) continue;
            std::vector<int> t = {i, j, c};
            std::sort(t.begin(), t.end());
            const double spread = gap[i][j] + std::min(gap[i][c], gap[j][c]);
            if (std::none_of(found.begin(), found.end(), [&t](const auto& f) { return f.second == t; }))
                found.push_back({spread, t});
        }
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<std::vector<int>> out;
    for (size_t i = 0; i < std::min(count, found.size()); ++i) out.push_back(found[i].second);
    return out;
}

// Cuts the body (the sphere with 2g holes the handle annuli leave in w) into g-1 T-shirts with
// g-2 annuli. As a tree of T-shirts (TshirtTree) where its plan separates markedly fewer close
// holes than the chain's (tshirt_plan()): each cut takes the cheapest of the open nodes' triples
// that cuts, of the kTshirtChoices cheapest; when none does (*tree_failed_at: that cut, from 0),
// the cuts left take the chain's compact choices. Else as the chain, a failed cut of the plan
// falling back to those choices (tshirt_choices()). `unit`: one quad's share of the area. Returns w
// with the S-cycles added, and all of them.
std::optional<BodyCut> cut_body(Builder w, std::vector<int> ids, int g, double unit, bool allow_tree,
                                int* tree_failed_at, const Say& say) {
    int last = -1;                       // outer S-cycle of the last body annulus
    std::vector<std::vector<int>> plan;  // the chain: per T-shirt, the holes it takes
    std::optional<TshirtTree> tree;      // or the tree,
    std::vector<int> node_curve;         // and per node of it, its curve
    for (int k = 0; k + 2 < g; ++k) {
        say("body annulus " + std::to_string(k + 1) + " of " + std::to_string(g - 2) + surface_size(w));
        const Surface& s = w.s_;
        const Cut cut = cut_by(w, ids);
        const int body = body_piece(cut, last, g);
        if (body < 0) return std::nullopt;
        const std::vector<char> block = outside_piece(s, cut.label, body);
        std::vector<int> holes;
        for (const Hole& h : cut.holes.at(body)) holes.push_back(h.curve);
        const int n = static_cast<int>(holes.size());
        std::vector<std::vector<double>> gap;  // distances in the body between holes, when first needed
        auto hole_gaps = [&]() -> const std::vector<std::vector<double>>& {
            if (!gap.empty()) return gap;
            gap.assign(n, std::vector<double>(n, kInf));
            for (int i = 0; i < n; ++i) {
                const std::vector<double> d = distances_from(s, block, w.curves_[holes[i]]);
                for (int j = 0; j < n; ++j)
                    for (int v : w.curves_[holes[j]]) gap[i][j] = std::min(gap[i][j], d[v]);
            }
            return gap;
        };
        // The body left holds T-shirts k..g-2 (6 units each) and annuli k..g-3 (2 each).
        const double units = 6.0 * (g - 1 - k) + 2.0 * (g - 2 - k);
        auto cut_off = [&](const std::vector<int>& C, bool crowded = false) {  // the T-shirt takes C
            std::vector<int> D;
            for (int h : holes)
                if (std::find(C.begin(), C.end(), h) == C.end()) D.push_back(h);
            return cut_tshirt(w, ids, last, C, D, g, units, unit, crowded);
        };
        auto take = [&](const std::vector<int>& group) {  // the T-shirt takes `last` and `group`
            std::vector<int> C;
            if (last >= 0) C.push_back(last);
            for (int h : group)
                if (h != last) C.push_back(h);
            return cut_off(C);
        };
        if (k == 0 && n <= kMaxPlannedHoles) {
            double chain_penalty = 0, tree_penalty = 0;
            for (const std::vector<int>& group : tshirt_plan(hole_gaps(), &chain_penalty)) {
                plan.emplace_back();
                for (int i : group) plan.back().push_back(holes[i]);
            }
            if (allow_tree) {
                tshirt_tree(hole_gaps(), &tree_penalty);
                const bool use = tree_penalty < kTreeGain * chain_penalty;
                char line[160];
                std::snprintf(line, sizeof line,
                              "T-shirts: separation %.3g as a tree, %.3g as a chain; cutting the %s",
                              tree_penalty, chain_penalty, use ? "tree" : "chain");
                say(line);
                if (use) {
                    tree.emplace(hole_gaps());
                    node_curve = holes;
                    plan.clear();
                }
            }
        }
        std::optional<BodyCut> best;
        if (tree) {
            // The choices again with C's tree free to pass the rings of D's holes, should each be
            // walled in by them (a plate of genus 20 at its 8th cut). Only then: passing them first
            // cut a plate of genus 15 worse (41k vertices added against 12k).
            for (const bool crowded : {false, true}) {
                for (const auto& [cost, t] : tree->cheapest(kTshirtChoices)) {
                    std::vector<int> C;
                    for (int x : t) C.push_back(node_curve[x]);
                    if ((best = cut_off(C, crowded))) {
                        tree->merge(t);
                        node_curve.push_back(best->outer);
                        break;
                    }
                }
                if (best) break;
            }
            if (!best) {  // the chain's choices from here on (the tree's cuts so far stay)
                say("T-shirts: no triple of the tree cuts at cut " + std::to_string(k + 1) +
                    "; the chain's choices from there");
                tree.reset();
                if (tree_failed_at) *tree_failed_at = k;
            }
        } else if (k < static_cast<int>(plan.size())) {
            best = take(plan[k]);
        }
        if (!best) {  // no plan, or it failed: from here on, holes near each other
            plan.clear();
            const int last_index =
                last < 0 ? -1 : static_cast<int>(std::find(holes.begin(), holes.end(), last) - holes.begin());
            for (const std::vector<int>& t : tshirt_choices(hole_gaps(), last_index, kTshirtChoices)) {
                std::vector<int> group;
                for (int i : t) group.push_back(holes[i]);
                if ((best = take(group))) break;
            }
        }
        if (!best) return std::nullopt;
        w = std::move(best->b);
        ids = std::move(best->ids);
        last = best->outer;
    }
    return BodyCut{std::move(w), std::move(ids), last};
}

}  // namespace

// The annuli round `loops`: two S-cycles parallel to each, added to w and to *ids. False if one
// does not fit.
bool tube_loops(Builder& w, const std::vector<int>& loops, double unit, std::vector<int>* out_ids, const Say& say) {
    std::vector<int>& ids = *out_ids;
    const int count = static_cast<int>(loops.size());
    std::vector<std::array<int, 2>> ends(count);
    for (int i = 0; i < count; ++i) {
        say("handle annulus " + std::to_string(i + 1) + " of " + std::to_string(count) + surface_size(w));
        const double len = cycle_length(w.s_.mesh(), w.curves_[loops[i]]);
        const double width0 = std::min(unit / len, 0.25 * len);
        double width = width0;
        bool ok = false;
        for (int attempt = 0; attempt < 3 && !ok; ++attempt, width *= 0.5) {
            Builder trial = w;
            std::vector<int> trial_ids = ids;
            if (tube_annulus(trial, loops[i], loops, width, &trial_ids, &ends[i])) {
                w = std::move(trial);
                ids = std::move(trial_ids);
                ok = true;
            }
        }
        // Where the handle is crowded or coarse: room beside m, then the S-cycles as close to m
        // as they must be, in m's cell of the Voronoi diagram of the curves; last, half an edge
        // from m (a thin annulus that relaxation widens).
        for (int attempt = 0; attempt < 4 && !ok; ++attempt) {
            Builder trial = w;
            std::vector<int> trial_ids = ids;
            split_chords_beside(trial, loops[i], loops);
            if (attempt == 3) {
                ends[i] = {offset_loop(trial, loops[i], 0), -1};
                if (ends[i][0] >= 0) ends[i][1] = offset_loop(trial, loops[i], 1);
                if (ends[i][1] < 0) break;
                trial_ids.push_back(ends[i][0]);
                trial_ids.push_back(ends[i][1]);
                if (bounds_annulus(trial, trial.curves_[loops[i]], trial_ids, ends[i])) {
                    w = std::move(trial);
                    ids = std::move(trial_ids);
                    ok = true;
                }
                break;
            }
            const double narrower = width0 / (1 << attempt);
            if (tube_annulus(trial, loops[i], loops, narrower, &trial_ids, &ends[i], true)) {
                w = std::move(trial);
                ids = std::move(trial_ids);
                ok = true;
            }
        }
        if (!ok) return false;
    }
    return true;
}

std::optional<std::vector<int>> tube_s_cycles(Builder& b, const std::vector<int>& loops, int g, const Say& say) {
    Builder w = b;
    const double unit = surface_area(w.s_.mesh()) / (10.0 * g - 10);  // one quad's share
    std::vector<int> ids;
    if (!tube_loops(w, loops, unit, &ids, say)) return std::nullopt;
    int tree_failed_at = -1;
    std::optional<BodyCut> cut = cut_body(w, ids, g, unit, true, &tree_failed_at, say);
    if (!cut && tree_failed_at >= 0) {
        say("T-shirts: the tree failed at cut " + std::to_string(tree_failed_at + 1) +
            "; the chain from the start");
        cut = cut_body(w, ids, g, unit, false, nullptr, say);
    }
    if (!cut) return std::nullopt;
    w = std::move(cut->b);
    ids = std::move(cut->ids);
    try {
        find_pieces(w, ids, g);
    } catch (const InternalError&) {
        return std::nullopt;
    }
    b = std::move(w);
    return ids;
}

}  // namespace quadcage::layout::detail

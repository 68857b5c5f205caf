#include "quadcage/layout/quad_layout.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/relax.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/validate.h"

namespace quadcage::layout {
namespace {

using detail::Builder;
using detail::neighbours_on;
using detail::PathResult;
using detail::PathSearch;
using detail::sectors;
using detail::Surface;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Extra cost (in edge lengths) of walking next to an existing curve; see Builder::cost_near().
constexpr double kAdjacency = 4.0;
// Times a search may open the walls around it (split_chords_around) before it gives up.
constexpr int kRoomAttempts = 24;

using Say = std::function<void(const std::string&)>;

// " (N triangles)": how far the surface has been refined, for progress messages.
std::string surface_size(const Builder& b) {
    return " (" + std::to_string(b.s_.mesh().triangles.size()) + " triangles)";
}

// The layout curves, as indices into a Builder's curves (which follow every split), plus the
// corners they carry.
struct Network {
    std::vector<int> corners;                              // mesh vertices
    std::vector<std::pair<int, std::vector<int>>> closed;  // closed curve -> its corners (cut there)
    std::vector<int> arcs;                                 // open curves from a corner to a corner
    std::vector<int> s_cycles;                             // Algorithm 1's S_i (g >= 2)
};

double path_length(const Mesh& m, const std::vector<int>& p) {
    double l = 0;
    for (size_t i = 0; i + 1 < p.size(); ++i) l += norm(m.points[p[i + 1]] - m.points[p[i]]);
    return l;
}

int common_vertex(const Cycle& a, const Cycle& b) {
    for (int v : a)
        if (std::find(b.begin(), b.end(), v) != b.end()) return v;
    return -1;
}

// Position along a closed curve of the vertex at `fraction` of its length, walking from index i0.
int vertex_at_fraction(const Mesh& m, const Cycle& c, size_t i0, double fraction) {
    const double total = cycle_length(m, c);
    double run = 0;
    const size_t n = c.size();
    size_t best = i0;
    double best_err = kInf;
    for (size_t k = 0; k < n; ++k) {
        const size_t i = (i0 + k) % n;
        const double err = std::abs(run - fraction * total);
        if (err < best_err) {
            best_err = err;
            best = i;
        }
        run += norm(m.points[c[(i + 1) % n]] - m.points[c[i]]);
    }
    return c[best];
}

// Triangle labels of the pieces cut out by the given closed curves.
int label_pieces(const Builder& b, const std::vector<int>& curve_ids, std::vector<int>* label) {
    std::vector<std::vector<int>> paths;
    for (int id : curve_ids) {
        std::vector<int> p = b.curves_[id];
        p.push_back(p.front());
        paths.push_back(std::move(p));
    }
    return detail::face_components(b.s_, detail::cut_half_edges(b.s_, paths), label);
}

// Triangle on side `side` of closed curve c: side 0 has the half-edge c[0] -> c[1], side 1 its twin.
int triangle_beside(const Surface& s, const Cycle& c, int side) {
    const int h = s.find_half_edge(c[0], c[1]);
    QC_CHECK(h >= 0, "triangle_beside: curve leaves the mesh edges");
    return (side == 0 ? h : s.twin(h)) / 3;
}

// The neighbours of x (on closed curve c) strictly inside the side of c whose triangles carry
// `piece`, in rotation (counter-clockwise) order.
std::vector<int> side_toward(const Surface& s, const Cycle& c, int x, const std::vector<int>& label,
                             int piece) {
    const auto [prev, next] = neighbours_on(c, x);
    auto sec = sectors(s, x, prev, next);
    if (label[s.find_half_edge(x, prev) / 3] == piece) return sec[0];
    QC_CHECK(label[s.find_half_edge(x, next) / 3] == piece,
             "side_toward: neither side of the curve is in the piece");
    return sec[1];
}

// Vertices that touch no triangle of `piece`.
std::vector<char> outside_piece(const Surface& s, const std::vector<int>& label, int piece) {
    std::vector<char> out(s.num_vertices(), 1);
    for (int t = 0; t < static_cast<int>(label.size()); ++t)
        if (label[t] == piece)
            for (int v : s.mesh().triangles[t]) out[v] = 0;
    return out;
}

std::vector<int> slice(const std::vector<int>& v, int from, int to) {  // [from, to)
    from = std::max(from, 0);
    to = std::min(to, static_cast<int>(v.size()));
    return from < to ? std::vector<int>(v.begin() + from, v.begin() + to) : std::vector<int>{};
}

int index_in(const std::vector<int>& v, int x) {
    const auto it = std::find(v.begin(), v.end(), x);
    return it == v.end() ? -1 : static_cast<int>(it - v.begin());
}

// One side of a closed curve that bounds a piece: the curve and which side faces the piece.
struct Hole {
    int curve = -1;
    int side = 0;
};

// Routes a closed ring through corners x[0..3], corner j on hole j, inside the piece beside the
// holes, one open curve per arc (added to b). With face_right the ring's face lies to the right of
// x0 -> x1 -> x2 -> x3 at every corner, else to the left; at each corner the face sector (between
// the arriving and the leaving arc) is kept clear of the hole: design.md §2, "Routing a ring".
// Returns the new curve ids, or nothing if some arc cannot be routed.
std::optional<std::vector<int>> route_ring(Builder& b, const std::vector<int>& s_ids,
                                           const std::array<Hole, 4>& holes, const std::array<int, 4>& x,
                                           bool face_right, double* length) {
    std::vector<int> arcs;
    std::vector<int> label;
    std::vector<char> reached;
    for (int j = 0, attempt = 0; j < 4; ++attempt) {
        // Room on demand: chords are split only around a search that found no way (splitting all
        // chords before every search lets each new curve hug the last: the mesh grows several-fold).
        if (attempt > 0 && (attempt > kRoomAttempts || b.open_room(reached, attempt) == 0))
            return std::nullopt;
        label_pieces(b, s_ids, &label);
        const int piece = label[triangle_beside(b.s_, b.curves_[holes[0].curve], holes[0].side)];
        const std::vector<char> block = b.blocked();
        const std::vector<char> outside = outside_piece(b.s_, label, piece);
        const auto cost = b.cost_near(block, &outside, kAdjacency);
        const int jn = (j + 1) % 4;
        const std::vector<int> here = side_toward(b.s_, b.curves_[holes[j].curve], x[j], label, piece);
        const std::vector<int> there = side_toward(b.s_, b.curves_[holes[jn].curve], x[jn], label, piece);
        std::vector<int> leave = here, arrive = there;
        if (j > 0) {  // the arc arriving at x[j] fixes on which side of it this one may leave
            const Cycle& in = b.curves_[arcs.back()];
            const int i = index_in(here, in[in.size() - 2]);
            QC_CHECK(i >= 0, "route_ring: arriving arc not in the piece's sector");
            leave = face_right ? slice(here, i + 1, static_cast<int>(here.size())) : slice(here, 0, i);
        }
        if (jn == 0) {  // closing at x[0]: arrive on the right side of the first arc's start
            const int i = index_in(there, b.curves_[arcs.front()][1]);
            QC_CHECK(i >= 0, "route_ring: first arc not in the piece's sector");
            arrive = face_right ? slice(there, 0, i) : slice(there, i + 1, static_cast<int>(there.size()));
        }
        double cost_total = 0;
        const std::vector<int> interior =
            b.sector_path(x[j], leave, x[jn], arrive, block, cost, &cost_total, &reached);
        if (interior.empty()) continue;
        Cycle arc{x[j]};
        arc.insert(arc.end(), interior.begin(), interior.end());
        arc.push_back(x[jn]);
        *length += path_length(b.s_.mesh(), arc);
        arcs.push_back(b.add_curve(arc, false));
        ++j;
        attempt = -1;
    }
    return arcs;
}

// Distances from `vertices` along mesh edges, entering no vertex marked in `block`.
std::vector<double> distances_from(const Surface& s, const std::vector<char>& block, const std::vector<int>& vertices) {
    PathSearch q;
    q.blocked = &block;
    for (int v : vertices) q.sources.push_back({v, 0.0});
    return detail::dijkstra(s, q).distance;
}

// Distances inside `piece` from the vertices of closed curve `from_curve`, crossing no S-cycle.
std::vector<double> hole_distances(const Builder& b, const std::vector<int>& label, int piece, int from_curve,
                                   const std::vector<char>& on_s) {
    std::vector<char> block = outside_piece(b.s_, label, piece);
    for (size_t v = 0; v < block.size(); ++v) block[v] = block[v] || on_s[v];
    return distances_from(b.s_, block, b.curves_[from_curve]);
}

// reach[k][m][i]: distance inside `piece` from vertex i of hole k, leaving through the piece's side,
// to hole m (distance fields `field`); +inf for m = k.
using HoleReach = std::array<std::array<std::vector<double>, 4>, 4>;
HoleReach hole_reach(const Builder& b, const std::vector<Hole>& holes, const std::array<std::vector<double>, 4>& field,
                     const std::vector<int>& label, int piece) {
    HoleReach reach;
    for (int k = 0; k < 4; ++k) {
        const Cycle& c = b.curves_[holes[k].curve];
        for (auto& r : reach[k]) r.assign(c.size(), kInf);
        for (size_t i = 0; i < c.size(); ++i)
            for (int w : side_toward(b.s_, c, c[i], label, piece)) {
                const double step = norm(b.s_.point(w) - b.s_.point(c[i]));
                for (int m = 0; m < 4; ++m)
                    if (m != k && field[m][w] < kInf) reach[k][m][i] = std::min(reach[k][m][i], field[m][w] + step);
            }
    }
    return reach;
}

// Algorithm 1 (paper §4): 4g-4 cycles S_i, each crossing the orthogonal system once, on an arc of
// a b-curve: one per arc of b1 and bg, two per arc of the middle b's. Returns their curve ids.
std::vector<int> place_s_cycles(Builder& b, int g, const Say& say) {
    struct Spot {
        int curve;  // the b-curve
        int u;      // crossing vertex
    };
    std::vector<Spot> spots;
    for (int h = 1; h <= g; ++h) {
        const int bi = 2 * h - 1;
        const int per_arc = (h == 1 || h == g) ? 1 : 2;
        // Room: every arc needs enough vertices for its u's, away from its ends and each other.
        for (int guard = 0;; ++guard) {
            const Cycle& c = b.curves_[bi];
            const int p1 = common_vertex(b.curves_[bi - 1], c);
            const size_t i1 = static_cast<size_t>(index_in(c, p1));
            const int p2 =
                h < g ? common_vertex(c, b.curves_[bi + 1]) : vertex_at_fraction(b.s_.mesh(), c, i1, 0.5);
            const size_t i2 = static_cast<size_t>(index_in(c, p2));
            const size_t n = c.size();
            const size_t arc1 = (i2 + n - i1) % n - 1, arc2 = (i1 + n - i2) % n - 1;
            if (std::min(arc1, arc2) >= static_cast<size_t>(4 * per_arc + 3)) {
                for (int arc = 0; arc < 2; ++arc) {
                    const size_t start = arc == 0 ? i1 : i2, stop = arc == 0 ? i2 : i1;
                    Cycle piece;  // the arc, ends included
                    for (size_t i = start; i != stop; i = (i + 1) % n) piece.push_back(c[i]);
                    piece.push_back(c[stop]);
                    const double len = path_length(b.s_.mesh(), piece);
                    std::vector<int> used;
                    for (int k = 1; k <= per_arc; ++k) {
                        const double want = len * k / (per_arc + 1);
                        double run = 0, best = kInf;
                        int pick = -1;
                        for (size_t i = 1; i + 1 < piece.size(); ++i) {
                            run += norm(b.s_.point(piece[i]) - b.s_.point(piece[i - 1]));
                            if (i < 2 || i + 2 >= piece.size()) continue;  // keep off the crossings
                            if (std::find(used.begin(), used.end(), piece[i]) != used.end()) continue;
                            if (std::abs(run - want) < best) {
                                best = std::abs(run - want);
                                pick = piece[i];
                            }
                        }
                        QC_CHECK(pick >= 0, "no room for an S-cycle on b" + std::to_string(h));
                        used.push_back(pick);
                        spots.push_back({bi, pick});
                    }
                }
                break;
            }
            QC_CHECK(guard < 8, "b" + std::to_string(h) + ": arcs stay too short after refinement");
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i < n; ++i) edges.push_back({c[i], c[(i + 1) % n]});
            b.split_curve_edges(edges);
        }
    }
    std::vector<int> ids;
    for (size_t k = 0; k < spots.size(); ++k) {
        say("S-cycle " + std::to_string(k + 1) + " of " + std::to_string(spots.size()) + surface_size(b));
        std::vector<int> path;
        std::vector<char> reached;
        for (int attempt = 0; attempt <= kRoomAttempts && path.empty(); ++attempt) {
            if (attempt > 0 && b.open_room(reached, attempt) == 0)
                break;  // room on demand, as in route_ring()
            const std::vector<char> block = b.blocked();
            const auto cost = b.cost_near(block, nullptr, kAdjacency);
            const int u = spots[k].u;
            const auto [p, n] = neighbours_on(b.curves_[spots[k].curve], u);
            const auto sec = sectors(b.s_, u, p, n);
            path = b.sector_path(u, sec[0], u, sec[1], block, cost, nullptr, &reached);
        }
        const int u = spots[k].u;
        QC_CHECK(!path.empty(), "no cycle S crosses b at vertex " + std::to_string(u) + " alone");
        Cycle s{u};
        s.insert(s.end(), path.begin(), path.end());
        ids.push_back(b.add_curve(s));
    }
    return ids;
}

// The pieces cut out by closed curves `ids`, and per piece the curves around it, facing it.
struct Cut {
    int count = 0;  // pieces
    std::vector<int> label;
    std::map<int, std::vector<Hole>> holes;
};

Cut cut_by(const Builder& b, const std::vector<int>& ids) {
    Cut c;
    c.count = label_pieces(b, ids, &c.label);
    for (int id : ids)
        for (int side = 0; side < 2; ++side)
            c.holes[c.label[triangle_beside(b.s_, b.curves_[id], side)]].push_back({id, side});
    return c;
}

struct Pieces {
    std::vector<std::vector<Hole>> holes;  // per piece: the S-cycles around it, facing it
};

Pieces find_pieces(const Builder& b, const std::vector<int>& s_ids, int g) {
    const Cut cut = cut_by(b, s_ids);
    const int count = cut.count;
    const std::vector<int>& label = cut.label;
    QC_CHECK(count == 3 * g - 3, "the S-cycles cut " + std::to_string(count) +
                                     " pieces, want 3g-3 = " + std::to_string(3 * g - 3));
    Pieces out;
    out.holes.resize(count);
    for (const auto& [piece, holes] : cut.holes) out.holes[piece] = holes;
    int annuli = 0, shirts = 0;
    for (const auto& h : out.holes) {
        if (h.size() == 2)
            ++annuli;
        else if (h.size() == 4)
            ++shirts;
        else
            QC_CHECK(false, "a piece has " + std::to_string(h.size()) + " boundary cycles (want 2 or 4)");
    }
    QC_CHECK(annuli == 2 * g - 2 && shirts == g - 1,
             "pieces: " + std::to_string(annuli) + " handles and " + std::to_string(shirts) + " T-shirts");
    for (int id : s_ids) {
        const int l0 = label[triangle_beside(b.s_, b.curves_[id], 0)],
                  l1 = label[triangle_beside(b.s_, b.curves_[id], 1)];
        QC_CHECK(out.holes[l0].size() != out.holes[l1].size(),
                 "an S-cycle does not separate a handle from a T-shirt");
    }
    return out;
}

// How strongly a level-set loop keeps to its level: an edge costs its length times
// 1 + kLevelStick * |u - level| (u is a distance ratio in [0, 1], or a distance over a width).
constexpr double kLevelStick = 20.0;

// How strongly a tree's path keeps away from the other tree: an edge within `reach` of it costs
// its length times 1 + kShun * (1 - distance / reach).
constexpr double kShun = 10.0;

// How many choices of holes for the next T-shirt the handle-loop S-cycles try when the plan
// fails, and up to how many holes the plan is made (one bit per hole).
constexpr size_t kTshirtChoices = 4;
constexpr int kMaxPlannedHoles = 62;

// A closed curve near the level set {u = level}: it leaves x, the vertex of `cut` whose u is
// nearest the level, on one side of the cut and comes back on the other, so it crosses the cut
// once; it avoids `wall`, the rest of the cut and where |u - level| > band. Edges cost their length times
// 1 + kLevelStick * |u - level| / scale; x is cut[first] or later. Empty if there is no such curve.
Cycle level_loop(const Builder& b, const std::vector<double>& u, double level, double scale, double band,
                 const std::vector<int>& cut, std::vector<char> wall, size_t first = 1) {
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
    if (path.empty()) return {};
    Cycle loop{x};
    loop.insert(loop.end(), path.begin(), path.end());
    return loop;
}

// The level below which `share` of the area of the triangles marked in `tri` lies (triangles at
// the mean u of their corners).
double area_level(const Surface& s, const std::vector<double>& u, const std::vector<char>& tri, double share) {
    std::vector<std::pair<double, double>> by_level;  // (mean u, area)
    double total = 0;
    for (size_t t = 0; t < tri.size(); ++t) {
        if (!tri[t]) continue;
        const auto& f = s.mesh().triangles[t];
        const double ut = (u[f[0]] + u[f[1]] + u[f[2]]) / 3;
        if (!(ut < kInf)) continue;
        const double a = triangle_area(s.mesh(), static_cast<int>(t));
        by_level.push_back({ut, a});
        total += a;
    }
    std::sort(by_level.begin(), by_level.end());
    double run = 0;
    for (const auto& [ut, a] : by_level) {
        run += a;
        if (run >= share * total) return ut;
    }
    return by_level.empty() ? 0.5 : by_level.back().first;
}

// The handle annulus round handle loop m: two S-cycles parallel to m, one on each side at distance
// about `width` (the distance from m on that side). Adds them to b and to s_ids; returns whether
// they bound an annulus round m.
bool tube_annulus(Builder& b, int m, const std::vector<int>& loops, double width, std::vector<int>* s_ids,
                  std::array<int, 2>* made) {
    const Surface& s = b.s_;
    const Cycle c = b.curves_[m];  // a copy: add_curve() below may move the curves
    for (int side = 0; side < 2; ++side) {
        std::vector<char> block = b.blocked();
        for (int l : loops)
            for (int v : b.curves_[l]) block[v] = 1;
        PathSearch q;
        q.blocked = &block;
        for (int v : c) {
            const auto [p, n] = neighbours_on(c, v);
            const auto sec = sectors(s, v, p, n);  // named: a temporary's [side] would dangle
            for (int w : sec[side])
                if (!block[w]) q.sources.push_back({w, norm(s.point(w) - s.point(v))});
        }
        q.max_distance = 4 * width;
        const PathResult r = detail::dijkstra(s, q);
        int z = -1;
        for (int v = 0; v < s.num_vertices(); ++v)
            if (r.distance[v] < kInf &&
                (z < 0 || std::abs(r.distance[v] - 2 * width) < std::abs(r.distance[z] - 2 * width)))
                z = v;
        if (z < 0) return false;
        const Cycle loop = level_loop(b, r.distance, width, width, 0.75 * width, r.path_to(s, z), block);
        if (loop.empty()) return false;
        (*made)[side] = b.add_curve(loop);
        s_ids->push_back((*made)[side]);
    }
    // The two must bound one piece (the annulus) that holds m and no other curve.
    const Cut cut = cut_by(b, *s_ids);
    const auto& around = cut.holes.at(cut.label[triangle_beside(s, c, 0)]);
    return around.size() == 2 && around[0].curve != around[1].curve &&
           std::all_of(around.begin(), around.end(),
                       [&](const Hole& h) { return h.curve == (*made)[0] || h.curve == (*made)[1]; });
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
// fits, short cuts and chords between the trees are split for room (at most 4 times).
std::optional<BodyCut> cut_tshirt(Builder w, std::vector<int> ids, int last, const std::vector<int>& C,
                                  const std::vector<int>& D, int g, double units, double unit) {
    const Surface& s = w.s_;
    const double reach = std::sqrt(unit);  // how far a tree keeps off the other
    for (int room = 0; room <= 4; ++room) {
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
        // C's tree keeps a vertex off D's holes and shuns them; D's keeps a vertex off C's tree
        // and shuns it.
        std::vector<char> away = block;
        std::vector<int> d_holes;
        for (int c : D)
            for (int v : w.curves_[c]) {
                d_holes.push_back(v);
                away[v] = 1;
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
        const auto d_tree = join(D, near_c, d_c);
        if (!d_tree) {
            if (w.split_chords(joins) == 0) return std::nullopt;
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
        // Lower levels if the loops take in holes of D that lie in C's region (islands).
        for (const double f : {1.0, 0.6, 0.35, 0.2}) {
            BodyCut out{w, ids};
            Builder& trial = out.b;
            std::vector<char> wall = trial.blocked();  // obstacle curves, C's tree and D's
            for (size_t v = 0; v < wall.size(); ++v) wall[v] = wall[v] || off_c[v];
            for (int v : d_vertices) wall[v] = 1;
            const Cycle inner = level_loop(trial, u, f * lo0, 1.0, kInf, cut_path, wall);
            if (inner.empty()) continue;
            for (int v : inner) wall[v] = 1;
            size_t crossed = 0;  // where inner crosses the cut: outer crosses it farther on
            while (crossed < cut_path.size() && std::find(inner.begin(), inner.end(), cut_path[crossed]) == inner.end())
                ++crossed;
            const Cycle outer = level_loop(trial, u, f * hi0, 1.0, kInf, cut_path, wall, crossed + 1);
            if (outer.empty()) continue;
            const int a = trial.add_curve(inner);
            out.outer = trial.add_curve(outer);
            out.ids.push_back(a);
            out.ids.push_back(out.outer);
            // The piece beside `inner` on C's side must have C and inner round it, the piece
            // between inner and outer no other hole.
            const Cut after = cut_by(trial, out.ids);
            int shirt = -1, ring = -1;
            for (int side = 0; side < 2; ++side) {
                const int p = after.label[triangle_beside(s, trial.curves_[a], side)];
                const auto& hs = after.holes.at(p);
                if (hs.size() == 4 && std::all_of(C.begin(), C.end(), [&](int c) {
                        return std::any_of(hs.begin(), hs.end(), [c](const Hole& h) { return h.curve == c; });
                    }))
                    shirt = p;
                else if (hs.size() == 2)
                    ring = p;
            }
            const auto& beside = trial.curves_[out.outer];
            const bool outer_on_ring = ring >= 0 && (after.label[triangle_beside(s, beside, 0)] == ring ||
                                                     after.label[triangle_beside(s, beside, 1)] == ring);
            if (shirt >= 0 && ring >= 0 && outer_on_ring) return out;
        }
        // No loop fits between the trees: split the edges of a short cut, else the chords
        // between the trees, and try again.
        if (cut_path.size() < 6) {
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i + 1 < cut_path.size(); ++i) edges.push_back({cut_path[i], cut_path[i + 1]});
            w.split_curve_edges(edges);
        } else if (w.split_chords(joins) == 0) {
            return std::nullopt;
        }
    }
    return std::nullopt;
}

// The order in which T-shirts take the body's 2g holes (indices into `gap`, their distances in
// the body): g-1 groups of 3, 2, ..., 2, 3, so that body annulus k separates A_k, the holes of the
// first k groups, from the rest. Minimizes the sum over k of sum_{a in A_k, b not} 1/gap(a, b)^2:
// holes close together go to the same side of every body annulus, so that no annulus has to
// squeeze between them. Exact (over the subsets of holes) up to 16 holes, greedy beyond.
std::vector<std::vector<int>> tshirt_plan(const std::vector<std::vector<double>>& gap) {
    const int n = static_cast<int>(gap.size());
    std::vector<std::vector<double>> weight(n, std::vector<double>(n, 0));
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (i != j) weight[i][j] = 1 / std::max(gap[i][j] * gap[i][j], 1e-12);
    auto separation = [&](std::uint64_t set) {  // the penalty of an annulus round `set`
        double p = 0;
        for (int a = 0; a < n; ++a)
            if (set >> a & 1)
                for (int b = 0; b < n; ++b)
                    if (!(set >> b & 1)) p += weight[a][b];
        return p;
    };
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
    } else {
        // Each step adds the triple (first) or pair of holes that adds the least penalty.
        std::uint64_t set = 0;
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

// S-cycles from the handle loops (an alternative to Algorithm 1 that gives the same pieces):
// each handle loop a_i becomes a handle (annulus) between two parallel S-cycles; the rest, a
// sphere with 2g holes, is cut into g-1 T-shirts by g-2 more annuli (cut_tshirt), the T-shirts
// taking the holes in the order of tshirt_plan(); once a cut of the plan fails, each T-shirt takes
// the first of a few compact choices (tshirt_choices(): holes near each other for the first, else
// the last annulus and two holes near it) that cuts. Areas aim at an even share per quad
// (a handle 2, a T-shirt 6). Algorithm 1's S-cycles all cross the orthogonal system once, so on a
// surface whose handles hang off one body they wind round the body side by side in stacks.
// Returns the S-cycles' curve ids, or nothing if some curve cannot be placed (b is then unchanged).
std::optional<std::vector<int>> tube_s_cycles(Builder& b, const std::vector<int>& loops, int g, const Say& say) {
    Builder w = b;
    const double unit = surface_area(w.s_.mesh()) / (10.0 * g - 10);  // one quad's share
    std::vector<int> ids;
    std::vector<std::array<int, 2>> ends(g);
    for (int i = 0; i < g; ++i) {
        say("handle annulus " + std::to_string(i + 1) + " of " + std::to_string(g) + surface_size(w));
        const double len = cycle_length(w.s_.mesh(), w.curves_[loops[i]]);
        double width = std::min(unit / len, 0.25 * len);
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
        if (!ok) return std::nullopt;
    }
    int last = -1;  // outer S-cycle of the last body annulus
    std::vector<std::vector<int>> plan;  // per T-shirt, the holes it takes (tshirt_plan)
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
        auto take = [&](const std::vector<int>& group) {  // the T-shirt takes `last` and `group`
            std::vector<int> C, D;
            if (last >= 0) C.push_back(last);
            for (int h : group)
                if (h != last) C.push_back(h);
            for (int h : holes)
                if (std::find(C.begin(), C.end(), h) == C.end()) D.push_back(h);
            return cut_tshirt(w, ids, last, C, D, g, units, unit);
        };
        if (k == 0 && n <= kMaxPlannedHoles)
            for (const std::vector<int>& group : tshirt_plan(hole_gaps())) {
                plan.emplace_back();
                for (int i : group) plan.back().push_back(holes[i]);
            }
        std::optional<BodyCut> best;
        if (k < static_cast<int>(plan.size())) best = take(plan[k]);
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
    try {
        find_pieces(w, ids, g);
    } catch (const InternalError&) {
        return std::nullopt;
    }
    b = std::move(w);
    return ids;
}

// The T-shirt (paper, Fig. 7; design.md §2): 2 corners on each of its 4 holes, a bottom ring and
// a top ring through them in one cyclic order of the holes. Tries the 3 cyclic orders in both
// directions and keeps the shortest pair of rings. Adds the rings to b and returns, per hole, its
// (bottom, top) corners.
std::vector<std::pair<Hole, std::array<int, 2>>> route_tshirt(Builder& b, const std::vector<int>& s_ids,
                                                              const std::vector<Hole>& holes,
                                                              std::vector<int>* arcs) {
    std::vector<int> label;
    label_pieces(b, s_ids, &label);
    const int piece = label[triangle_beside(b.s_, b.curves_[holes[0].curve], holes[0].side)];
    std::vector<char> on_s(b.s_.num_vertices(), 0);
    for (int id : s_ids)
        for (int v : b.curves_[id]) on_s[v] = 1;
    std::array<std::vector<double>, 4> field;
    for (int k = 0; k < 4; ++k) field[k] = hole_distances(b, label, piece, holes[k].curve, on_s);
    // The 3 cyclic orders of 4 holes, each in both directions (entries 2i and 2i+1).
    static const int kOrders[6][4] = {{0, 1, 2, 3}, {0, 3, 2, 1}, {0, 1, 3, 2},
                                      {0, 2, 3, 1}, {0, 2, 1, 3}, {0, 3, 1, 2}};
    struct Plan {
        std::array<Hole, 4> holes;
        std::array<int, 4> bottom{}, top{};
        double estimate = 0;  // both rings' length, from the hole distance fields
    };
    const HoleReach reach = hole_reach(b, holes, field, label, piece);
    std::array<Plan, 6> plans;
    for (int o = 0; o < 6; ++o) {
        const auto& order = kOrders[o];
        Plan& plan = plans[o];
        for (int j = 0; j < 4; ++j) {
            const int k = order[j], kp = order[(j + 3) % 4], kn = order[(j + 1) % 4];
            plan.holes[j] = holes[k];
            const Cycle& c = b.curves_[holes[k].curve];
            double low = kInf;
            size_t at = 0;
            for (size_t i = 0; i < c.size(); ++i) {
                const double d = reach[k][kp][i] + reach[k][kn][i];
                if (d < low) {
                    low = d;
                    at = i;
                }
            }
            plan.bottom[j] = c[at];
            plan.top[j] = vertex_at_fraction(b.s_.mesh(), c, at, 0.5);
            plan.estimate += 0.5 * low + reach[k][kn][static_cast<size_t>(index_in(c, plan.top[j]))];
        }
    }
    // Route the cyclic orders from the most promising estimate on, both directions each; stop at
    // the first order that gives a pair of rings (each routing is a handful of searches).
    std::array<int, 3> cyclic{0, 1, 2};
    std::stable_sort(cyclic.begin(), cyclic.end(),
                     [&](int x, int y) { return plans[2 * x].estimate < plans[2 * y].estimate; });
    double best = kInf;
    std::optional<Builder> best_builder;
    std::vector<std::pair<Hole, std::array<int, 2>>> best_corners;
    std::vector<int> best_arcs;
    for (int cyc : cyclic) {
        for (int o = 2 * cyc; o < 2 * cyc + 2; ++o) {
            const Plan& plan = plans[o];
            Builder trial = b;
            double length = 0;
            const auto low_ring = route_ring(trial, s_ids, plan.holes, plan.bottom, true, &length);
            if (!low_ring || length >= best) continue;
            const auto high_ring = route_ring(trial, s_ids, plan.holes, plan.top, false, &length);
            if (!high_ring || length >= best) continue;
            best = length;
            best_corners.clear();
            for (int j = 0; j < 4; ++j)
                best_corners.push_back({plan.holes[j], {plan.bottom[j], plan.top[j]}});
            best_arcs = *low_ring;
            best_arcs.insert(best_arcs.end(), high_ring->begin(), high_ring->end());
            best_builder.emplace(std::move(trial));
        }
        if (best_builder) break;
    }
    QC_CHECK(best_builder.has_value(), "no pair of rings could be routed in a T-shirt");
    b = std::move(*best_builder);
    arcs->insert(arcs->end(), best_arcs.begin(), best_arcs.end());
    return best_corners;
}

// A handle (annulus between holes A and B, 2 corners each) becomes 2 quads: two arcs across it.
// Both pairings (twists) are tried; the shorter is kept.
void route_handle(Builder& b, const std::vector<int>& s_ids, const Hole& A, const std::array<int, 2>& a,
                  const Hole& B, const std::array<int, 2>& c, std::vector<int>* arcs) {
    double best = kInf;
    std::optional<Builder> best_builder;
    std::vector<int> best_arcs;
    for (int twist = 0; twist < 2; ++twist) {
        Builder trial = b;
        double length = 0;
        std::vector<int> made;
        std::vector<char> reached;
        for (int k = 0, attempt = 0; k < 2 && attempt <= kRoomAttempts; ++attempt) {
            const int from = a[k], to = c[(k + twist) % 2];
            if (attempt > 0 && trial.open_room(reached, attempt) == 0)
                break;  // room on demand, as in route_ring()
            std::vector<int> label;
            label_pieces(trial, s_ids, &label);
            const int piece = label[triangle_beside(trial.s_, trial.curves_[A.curve], A.side)];
            const std::vector<char> block = trial.blocked();
            const std::vector<char> outside = outside_piece(trial.s_, label, piece);
            const auto cost = trial.cost_near(block, &outside, kAdjacency);
            const auto leave = side_toward(trial.s_, trial.curves_[A.curve], from, label, piece);
            const auto arrive = side_toward(trial.s_, trial.curves_[B.curve], to, label, piece);
            const std::vector<int> interior =
                trial.sector_path(from, leave, to, arrive, block, cost, nullptr, &reached);
            if (interior.empty()) continue;
            Cycle arc{from};
            arc.insert(arc.end(), interior.begin(), interior.end());
            arc.push_back(to);
            length += path_length(trial.s_.mesh(), arc);
            made.push_back(trial.add_curve(arc, false));
            ++k;
            attempt = -1;
        }
        if (made.size() != 2 || length >= best) continue;
        best = length;
        best_arcs = made;
        best_builder.emplace(std::move(trial));
    }
    QC_CHECK(best_builder.has_value(), "no pair of arcs could be routed across a handle");
    b = std::move(*best_builder);
    arcs->insert(arcs->end(), best_arcs.begin(), best_arcs.end());
}

// Genus >= 2: Algorithm 1, then handles (2 quads) and T-shirts (6 quads).
Network network_of_handles_and_tshirts(Builder& b, int g, const std::vector<int>& handle_loops,
                                        bool from_handle_loops, const Say& say) {
    Network net;
    std::optional<std::vector<int>> tubes;
    if (from_handle_loops) {
        for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 0;
        tubes = tube_s_cycles(b, handle_loops, g, say);
        if (!tubes) say("the handle loops gave no S-cycles; Algorithm 1's instead");
        for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 1;
    }
    net.s_cycles = tubes ? *tubes : place_s_cycles(b, g, say);
    // From here on the orthogonal system is scaffolding: layout curves may cross it.
    for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 0;
    const Pieces pieces = find_pieces(b, net.s_cycles, g);
    std::vector<std::array<int, 2>> corners_on(b.curves_.size(), {-1, -1});
    int shirt = 0;
    for (const auto& holes : pieces.holes) {
        if (holes.size() != 4) continue;
        say("T-shirt " + std::to_string(++shirt) + " of " + std::to_string(g - 1) + surface_size(b));
        for (const auto& [hole, cs] : route_tshirt(b, net.s_cycles, holes, &net.arcs)) {
            corners_on[hole.curve] = cs;
            net.corners.push_back(cs[0]);
            net.corners.push_back(cs[1]);
        }
    }
    int handle = 0;
    for (const auto& holes : pieces.holes) {
        if (holes.size() != 2) continue;
        say("handle " + std::to_string(++handle) + " of " + std::to_string(2 * g - 2) + surface_size(b));
        route_handle(b, net.s_cycles, holes[0], corners_on[holes[0].curve], holes[1],
                     corners_on[holes[1].curve], &net.arcs);
    }
    for (int id : net.s_cycles) net.closed.push_back({id, {corners_on[id][0], corners_on[id][1]}});
    return net;
}

// Genus 1 (Remark 1): two disjoint meridians (a1 and a parallel copy) and two disjoint longitudes
// (b1 and a parallel copy); each meridian crosses each longitude once: 4 corners of degree 4.
Network network_of_torus(Builder& b, const Say& say) {
    const int a = 0, bb = 1;
    for (int guard = 0; b.curves_[a].size() < 8 || b.curves_[bb].size() < 8; ++guard) {
        QC_CHECK(guard < 8, "torus: cycles stay too short after refinement");
        for (int id : {a, bb}) {
            const Cycle& c = b.curves_[id];
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i < c.size(); ++i) edges.push_back({c[i], c[(i + 1) % c.size()]});
            b.split_curve_edges(edges);
        }
    }
    const int v = common_vertex(b.curves_[a], b.curves_[bb]);
    say("second meridian");
    // Second meridian: crosses b1 once, at the vertex half-way round from v.
    const int u =
        vertex_at_fraction(b.s_.mesh(), b.curves_[bb], static_cast<size_t>(index_in(b.curves_[bb], v)), 0.5);
    int alpha = -1;
    {
        b.split_chords();
        const std::vector<char> block = b.blocked();
        const auto cost = b.cost_near(block, nullptr, kAdjacency);
        const auto [p, n] = neighbours_on(b.curves_[bb], u);
        const auto sec = sectors(b.s_, u, p, n);
        const std::vector<int> path = b.sector_path(u, sec[0], u, sec[1], block, cost, nullptr);
        QC_CHECK(!path.empty(), "torus: no second meridian");
        Cycle s{u};
        s.insert(s.end(), path.begin(), path.end());
        alpha = b.add_curve(s);
    }
    say("second longitude");
    // Second longitude: from w (half-way round a1 from v) across one annulus to a vertex y of the
    // second meridian, then back across the other annulus; both sides tried.
    const int w =
        vertex_at_fraction(b.s_.mesh(), b.curves_[a], static_cast<size_t>(index_in(b.curves_[a], v)), 0.5);
    double best = kInf;
    std::optional<Builder> best_builder;
    int best_beta = -1, best_y = -1;
    for (int side = 0; side < 2; ++side) {
        Builder t = b;
        t.split_chords();
        const std::vector<char> block = t.blocked();
        const auto cost = t.cost_near(block, nullptr, kAdjacency);
        const auto [pw, nw] = neighbours_on(t.curves_[a], w);
        const auto sec_w = sectors(t.s_, w, pw, nw);
        PathSearch q;
        q.blocked = &block;
        q.cost = cost;
        for (int x : sec_w[side])
            if (!block[x]) q.sources.push_back({x, t.edge_cost(cost, w, x)});
        const Cycle& al = t.curves_[alpha];
        for (int y : al) {
            if (y == u) continue;
            for (int x : t.s_.ring(y))
                if (!block[x]) q.targets.push_back({x, t.edge_cost(cost, x, y)});
        }
        if (q.sources.empty() || q.targets.empty()) continue;
        const PathResult r = detail::dijkstra(t.s_, q);
        if (r.target < 0) continue;
        const std::vector<int> first = r.path_to(t.s_, r.target);
        int y = -1;
        double yc = kInf;
        for (int cand : t.s_.ring(r.target))
            if (cand != u && index_in(al, cand) >= 0 && t.edge_cost(cost, r.target, cand) < yc) {
                yc = t.edge_cost(cost, r.target, cand);
                y = cand;
            }
        QC_CHECK(y >= 0, "torus: second longitude lost its end");
        Cycle half{w};
        half.insert(half.end(), first.begin(), first.end());
        half.push_back(y);
        const int half_id = t.add_curve(half, false);
        t.split_chords();
        const std::vector<char> block2 = t.blocked();
        const auto cost2 = t.cost_near(block2, nullptr, kAdjacency);
        const auto [py, ny] = neighbours_on(t.curves_[alpha], y);
        const auto sec_y = sectors(t.s_, y, py, ny);
        const int arrived = t.curves_[half_id][t.curves_[half_id].size() - 2];
        const int other = index_in(sec_y[0], arrived) >= 0 ? 1 : 0;
        const auto [pw2, nw2] = neighbours_on(t.curves_[a], w);
        const auto sec_w2 = sectors(t.s_, w, pw2, nw2);
        const std::vector<int> second =
            t.sector_path(y, sec_y[other], w, sec_w2[1 - side], block2, cost2, nullptr);
        if (second.empty()) continue;
        Cycle beta = t.curves_[half_id];
        beta.insert(beta.end(), second.begin(), second.end());
        t.obstacle_[half_id] = 0;
        const double len = cycle_length(t.s_.mesh(), beta);
        if (len >= best) continue;
        best = len;
        best_y = y;
        best_beta = t.add_curve(beta);
        best_builder.emplace(std::move(t));
    }
    QC_CHECK(best_builder.has_value(), "torus: no second longitude");
    b = std::move(*best_builder);
    Network net;
    net.corners = {v, u, w, best_y};
    net.closed = {{a, {v, w}}, {bb, {v, u}}, {alpha, {u, best_y}}, {best_beta, {w, best_y}}};
    return net;
}

// Genus 0: a cube. Corners at the extremes of the 8 octant directions of the principal frame;
// a bottom ring, a top ring and 4 vertical arcs.
Network network_of_cube(Builder& b, const Say& say) {
    const Mesh& m = b.s_.mesh();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Vec3& p : m.points) mean += Eigen::Vector3d(p.x, p.y, p.z);
    mean /= static_cast<double>(m.num_vertices());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& p : m.points) {
        const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
        cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    Eigen::Matrix3d axes = eig.eigenvectors();  // columns, ascending eigenvalues
    Eigen::Vector3d e1 = axes.col(2), e2 = axes.col(1);
    Eigen::Vector3d e3 = e1.cross(e2);
    const Eigen::Vector3d scale(std::sqrt(std::max(eig.eigenvalues()(2), 1e-300)),
                                std::sqrt(std::max(eig.eigenvalues()(1), 1e-300)),
                                std::sqrt(std::max(eig.eigenvalues()(0), 1e-300)));
    // Octant (sx, sy, sz) -> corner index: bottom ring (sz < 0) j = 0..3, top ring 4 + j, with j
    // running (-,-), (+,-), (+,+), (-,+): counter-clockwise about e3.
    const int sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    auto score = [&](int v, int k) {
        const Eigen::Vector3d d = Eigen::Vector3d(m.points[v].x, m.points[v].y, m.points[v].z) - mean;
        const int j = k % 4;
        const double sz = k < 4 ? -1 : 1;
        return sx[j] * d.dot(e1) / scale(0) + sy[j] * d.dot(e2) / scale(1) + sz * d.dot(e3) / scale(2);
    };
    // The best-scoring vertex for corner k among those `allowed` and not taken yet.
    std::array<int, 8> corner{};
    std::vector<char> taken(m.num_vertices(), 0);
    auto pick_corner = [&](int k, const std::function<bool(int)>& allowed) {
        double best = -kInf;
        int pick = -1;
        for (int v = 0; v < m.num_vertices(); ++v)
            if (!taken[v] && allowed(v) && score(v, k) > best) best = score(v, k), pick = v;
        QC_CHECK(pick >= 0, "cube: no vertex left for corner " + std::to_string(k));
        corner[k] = pick;
        taken[pick] = 1;
    };
    for (int k = 0; k < 4; ++k) pick_corner(k, [](int) { return true; });

    Network net;
    std::vector<char> is_corner(m.num_vertices(), 0);
    auto route = [&](int from, int to, const char* what) {
        b.split_chords();
        std::vector<char> block = b.blocked();
        for (size_t v = 0; v < block.size(); ++v) block[v] = block[v] || (v < is_corner.size() && is_corner[v]);
        const auto cost = b.cost_near(block, nullptr, kAdjacency);
        const std::vector<int> leave = b.s_.ring(from), arrive = b.s_.ring(to);
        const std::vector<int> interior = b.sector_path(from, leave, to, arrive, block, cost, nullptr);
        QC_CHECK(!interior.empty(), std::string("cube: an arc of the ") + what + " could not be routed");
        Cycle arc{from};
        arc.insert(arc.end(), interior.begin(), interior.end());
        arc.push_back(to);
        net.arcs.push_back(b.add_curve(arc, false));
    };
    // The bottom ring first. It cuts the sphere into two disks; the top corners are chosen in the
    // one that holds the top of the shape, then the four verticals run into it from the ring as
    // disjoint slits, and only then the top ring: the top corners lie on the boundary of the disk
    // left by the slits in the ring's cyclic order, so each top arc joins two consecutive ones
    // inside one region and every step is routable on any sphere. (Choosing the top corners by
    // their octant alone and routing the top ring before the verticals failed on a figure with
    // limbs: a top corner fell on the bottom's side, or the top ring ran against the bottom
    // ring's order, and a vertical found no way.)
    say("cube edges");
    for (int k = 0; k < 4; ++k) is_corner[corner[k]] = 1;
    for (int j = 0; j < 4; ++j) route(corner[j], corner[(j + 1) % 4], "bottom ring");
    std::vector<std::vector<int>> ring;
    for (int id : net.arcs) ring.push_back(b.curves_[id]);
    std::vector<int> label;
    QC_CHECK(detail::face_components(b.s_, detail::cut_half_edges(b.s_, ring), &label) == 2,
             "cube: the bottom ring does not cut the sphere in two");
    const Mesh& cut_mesh = b.s_.mesh();
    const std::vector<char> on_ring = b.blocked();
    std::vector<int> side_of(cut_mesh.num_vertices(), -1);
    for (int t = 0; t < cut_mesh.num_triangles(); ++t)
        for (int v : cut_mesh.triangles[t]) side_of[v] = label[t];
    int top = -1;
    double highest = -kInf;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v) {
        const Eigen::Vector3d d(cut_mesh.points[v].x - mean.x(), cut_mesh.points[v].y - mean.y(), cut_mesh.points[v].z - mean.z());
        if (!on_ring[v] && d.dot(e3) > highest) highest = d.dot(e3), top = v;
    }
    QC_CHECK(top >= 0, "cube: every vertex is on the bottom ring");
    const int top_side = side_of[top];
    // Top corners keep away from the ring (at least a third of the farthest distance from it on
    // that side): one next to it can be walled in by the ring and a vertical.
    std::vector<int> ring_vertices;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v)
        if (on_ring[v]) ring_vertices.push_back(v);
    const std::vector<double> from_ring =
        distances_from(b.s_, std::vector<char>(cut_mesh.num_vertices(), 0), ring_vertices);
    double farthest = 0;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v)
        if (side_of[v] == top_side && !on_ring[v]) farthest = std::max(farthest, from_ring[v]);
    taken.resize(cut_mesh.num_vertices(), 0);
    for (int k = 4; k < 8; ++k) {
        pick_corner(k, [&](int v) { return !on_ring[v] && side_of[v] == top_side && from_ring[v] >= farthest / 3; });
        is_corner.resize(cut_mesh.num_vertices(), 0);
        is_corner[corner[k]] = 1;
    }
    net.corners.assign(corner.begin(), corner.end());
    for (int j = 0; j < 4; ++j) route(corner[j], corner[4 + j], "verticals");
    for (int j = 0; j < 4; ++j) route(corner[4 + j], corner[4 + (j + 1) % 4], "top ring");
    return net;
}

// Removes hairpins from a layout curve: where the curve comes back next to itself (p_i adjacent to
// p_j, j > i + 1) around a small disk that holds nothing else (no vertex of another curve in
// `dirty`, no corner), the detour is replaced by the edge p_i p_j. Shortest paths that must enter
// a corner's sector from one side make such detours; left in place, the one-vertex-wide sliver
// between its branches squeezes the patch map below rounding. Returns the number of shortcuts.
int remove_hairpins(const Surface& s, Cycle& c, bool closed, const std::vector<char>& dirty,
                    const std::vector<char>& corner) {
    int shortcuts = 0;
    const int nt = s.num_half_edges() / 3;
    std::vector<int> pos(s.num_vertices(), -1);
    std::vector<int> seen(nt, -1);
    int stamp = 0;
    for (bool changed = true; changed;) {
        changed = false;
        std::fill(pos.begin(), pos.end(), -1);
        for (size_t i = 0; i < c.size(); ++i) pos[c[i]] = static_cast<int>(i);
        const int n = static_cast<int>(c.size());
        for (int i = 0; i + 2 < n && !changed; ++i) {
            // Shortcuts from p_i: an edge to a later p_j, or two edges through a free vertex m.
            std::vector<std::pair<int, int>> options;  // (j, m or -1)
            for (int w : s.ring(c[i])) {
                if (pos[w] > i + 1)
                    options.push_back({pos[w], -1});
                else if (pos[w] < 0 && !dirty[w] && !corner[w])
                    for (int u : s.ring(w))
                        if (pos[u] > i + 2) options.push_back({pos[u], w});
            }
            std::sort(options.begin(), options.end(), [](const auto& x, const auto& y) {
                return x.first != y.first ? x.first > y.first : x.second < y.second;  // longest detour first
            });
            for (const auto& [j, m] : options) {
                if (closed && i == 0 && j == n - 1) continue;
                bool skips_corner = false;
                for (int k = i + 1; k < j && !skips_corner; ++k) skips_corner = corner[c[k]];
                if (skips_corner) continue;
                // The loop p_i .. p_j (m) p_i; flood each side without crossing it.
                std::vector<std::uint64_t> loop_edges;
                for (int k = i; k < j; ++k) loop_edges.push_back(detail::edge_key(c[k], c[k + 1]));
                if (m < 0)
                    loop_edges.push_back(detail::edge_key(c[j], c[i]));
                else {
                    loop_edges.push_back(detail::edge_key(c[j], m));
                    loop_edges.push_back(detail::edge_key(m, c[i]));
                }
                std::sort(loop_edges.begin(), loop_edges.end());
                auto on_loop = [&](int h) {
                    return std::binary_search(loop_edges.begin(), loop_edges.end(),
                                              detail::edge_key(s.from(h), s.to(h)));
                };
                const size_t limit = 64 + 16 * static_cast<size_t>(j - i) * static_cast<size_t>(j - i);
                const int h0 = s.find_half_edge(c[i], c[i + 1]);
                bool clean_side = false;
                for (int side = 0; side < 2 && !clean_side; ++side) {
                    ++stamp;
                    std::vector<int> queue{(side == 0 ? h0 : s.twin(h0)) / 3};
                    seen[queue[0]] = stamp;
                    bool clean = true;
                    for (size_t q = 0; q < queue.size() && clean; ++q) {
                        if (queue.size() > limit) clean = false;
                        const int t = queue[q];
                        for (int k = 0; k < 3 && clean; ++k) {
                            const int v = s.mesh().triangles[t][k];
                            if ((pos[v] >= i && pos[v] <= j) || v == m) continue;  // on the loop itself
                            if (dirty[v] || corner[v] || pos[v] >= 0) clean = false;
                        }
                        for (int k = 0; k < 3 && clean; ++k) {
                            const int h = 3 * t + k;
                            if (on_loop(h)) continue;
                            const int o = s.twin(h) / 3;
                            if (seen[o] != stamp) {
                                seen[o] = stamp;
                                queue.push_back(o);
                            }
                        }
                    }
                    clean_side = clean;
                }
                if (!clean_side) continue;
                c.erase(c.begin() + i + 1, c.begin() + j);
                if (m >= 0) c.insert(c.begin() + i + 1, m);
                ++shortcuts;
                changed = true;
                break;
            }
        }
    }
    return shortcuts;
}
}  // namespace

std::string QuadLayoutOptions::validate() const {
    if (relax_sweeps < 0) return "relax_sweeps must be >= 0, got " + std::to_string(relax_sweeps);
    if (relax_corner_sweeps < 0)
        return "relax_corner_sweeps must be >= 0, got " + std::to_string(relax_corner_sweeps);
    return cycles.validate();
}

QuadLayout build_quad_layout(const Mesh& input, const QuadLayoutOptions& options) {
    if (const std::string e = options.validate(); !e.empty()) throw InvalidInput("quad layout options: " + e);
    const Say say = [&options](const std::string& m) {
        if (options.progress) options.progress(m);
    };
    auto clock = [start = std::chrono::steady_clock::now()]() {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    OrthogonalSystemOptions cycle_options = options.cycles;
    cycle_options.progress = options.progress;
    // Validates the input (throws InvalidInput as build_orthogonal_system() would).
    const ValidationReport report = validate(input);
    if (!report.quaddable() || report.components.size() != 1)
        throw InvalidInput(
            "build_quad_layout needs one closed, manifold, orientable component: " +
            (report.components.size() > 1
                 ? std::string("the mesh has ") + std::to_string(report.components.size()) + " components"
                 : report.error_summary()));
    // Coarse meshes get room first (1-to-4 splits: input vertices stay, in order; new ones at edge
    // midpoints): every handle needs its 2 loops, 4 S-cycles and their arcs to pass one another.
    const int genus = report.components[0].genus;
    Mesh mesh = input;
    while (mesh.num_vertices() < 1000 + 200 * genus) mesh = subdivide_midpoint(mesh);
    // Builds the cycles (none for a sphere).
    OrthogonalSystem system = build_orthogonal_system(mesh, cycle_options);
    const int g = system.genus;

    const double t_cycles = clock();
    // The layout curves' routes depend on the path costs; a layout whose patch maps fold (a patch
    // squeezed below rounding) is rebuilt with stronger, then weaker repulsion before giving up.
    std::string failure;
    for (const double repulsion_scale : {1.0, 2.0, 0.5}) {
        QuadLayout out;
        out.input_vertices = input.num_vertices();
        out.genus = g;
        OrthogonalSystemOptions curve_options = cycle_options;
        curve_options.repulsion *= repulsion_scale;
        Builder b(system.mesh, curve_options);
        for (const Cycle& c : system.cycles) b.add_curve(c);
        std::vector<int> handle_loops;
        if (options.s_cycles_from_handle_loops)
            for (const Cycle& c : system.handle_loops) handle_loops.push_back(b.add_curve(c, true, false));
        try {
            Network net;
            if (g >= 2)
                net = network_of_handles_and_tshirts(b, g, handle_loops, options.s_cycles_from_handle_loops, say);
            else if (g == 1)
                net = network_of_torus(b, say);
            else
                net = network_of_cube(b, say);

            // Room for the patch maps: no mesh edge may join two boundary vertices of a patch without
            // being a layout edge. The orthogonal system is no obstacle any more.
            say("patches");
            std::vector<char> layout_curve(b.curves_.size(), 0);
            for (const auto& [id, cs] : net.closed) layout_curve[id] = 1;
            for (int id : net.arcs) layout_curve[id] = 1;
            for (size_t c = 0; c < b.curves_.size(); ++c) b.obstacle_[c] = layout_curve[c];
            {
                // Tighten: remove hairpins. An S-cycle must keep its single crossing with the orthogonal
                // system, so for S-cycles the system's vertices count as other curves too.
                std::vector<char> corner(b.s_.num_vertices(), 0), on_system(b.s_.num_vertices(), 0);
                for (int v : net.corners) corner[v] = 1;
                for (int i = 0; i < 2 * g; ++i)
                    for (int v : b.curves_[i]) on_system[v] = 1;
                for (size_t c = 0; c < b.curves_.size(); ++c) {
                    if (!layout_curve[c]) continue;
                    std::vector<char> dirty(b.s_.num_vertices(), 0);
                    for (size_t d = 0; d < b.curves_.size(); ++d)
                        if (d != c && layout_curve[d])
                            for (int v : b.curves_[d]) dirty[v] = 1;
                    const bool is_s = std::find(net.s_cycles.begin(), net.s_cycles.end(),
                                                static_cast<int>(c)) != net.s_cycles.end();
                    if (is_s || g == 1) {  // g = 1: the four curves include the system's two
                        std::vector<char> mine(b.s_.num_vertices(), 0);
                        for (int v : b.curves_[c]) mine[v] = 1;
                        for (size_t v = 0; v < dirty.size(); ++v)
                            dirty[v] = dirty[v] || (on_system[v] && !mine[v]);
                    }
                    remove_hairpins(b.s_, b.curves_[c], b.closed_[c], dirty, corner);
                }
            }
            b.split_chords();

            // Layout edges: each closed curve cut at its two corners, then the arcs.
            auto edge_paths_of = [&](const Builder& bb, const Network& nn) {
                std::vector<std::vector<int>> paths;
                for (const auto& [id, cs] : nn.closed) {
                    Cycle c = bb.curves_[id];
                    const int i0 = index_in(c, cs[0]);
                    QC_CHECK(i0 >= 0 && index_in(c, cs[1]) >= 0, "a layout cycle lost its corners");
                    std::rotate(c.begin(), c.begin() + i0, c.end());
                    const int i1 = index_in(c, cs[1]);
                    paths.emplace_back(c.begin(), c.begin() + i1 + 1);
                    std::vector<int> rest(c.begin() + i1, c.end());
                    rest.push_back(c[0]);
                    paths.push_back(rest);
                }
                for (int id : nn.arcs) paths.push_back(bb.curves_[id]);
                return paths;
            };
            // The cage, patches and maps of a network, verified; "" or what fails. Times the maps
            // and the check of the last call.
            double mapped_seconds = 0, checked_seconds = 0;
            auto finish = [&](const Builder& bb, const Network& nn, QuadLayout* L) {
                L->mesh = bb.s_.mesh();
                const double t0 = clock();
                const std::string problem = detail::extract_cage(bb.s_, nn.corners, edge_paths_of(bb, nn), L);
                if (!problem.empty()) return "the layout curves do not form a quad layout: " + problem;
                detail::parameterize_patches(L);
                const double t1 = clock();
                say("verifying");
                const std::string check = verify_quad_layout(*L);
                mapped_seconds = t1 - t0;
                checked_seconds = clock() - t1;
                return check.empty() ? std::string() : "the quad layout fails its own check: " + check;
            };
            std::vector<std::vector<int>> paths = edge_paths_of(b, net);
            bool finished = false;  // out holds the relaxed layout, built and verified
            std::vector<int> s_cycle_ids = net.s_cycles;
            if (options.relax_sweeps > 0) {
                // Relax: corners towards an even share of their patches' area, every layout edge to
                // the middle of its two patches. The relaxed edges become new curves (the
                // orthogonal system keeps the routes Algorithm 1 gave it; the S-cycles are the
                // relaxed closed curves from then on); chords they make are split as before. Should
                // the relaxed network fail any check below, the unrelaxed one is kept.
                say(options.relax_corner_sweeps > 0 ? "relaxing the layout corners and edges" : "relaxing the layout edges");
                detail::RelaxOptions ro;
                ro.sweeps = options.relax_sweeps;
                try {
                    Builder relaxed = b;
                    std::vector<std::vector<int>> moved = paths;
                    std::vector<int> corners = net.corners;
                    int moves = 0;
                    if (options.relax_corner_sweeps > 0) {
                        // Corners and edges in turn: a moved corner's new edges run straight
                        // through its star, the next edge pass centres them between their patches.
                        detail::RelaxOptions once = ro;
                        once.sweeps = 1;
                        for (int sweep = 0; sweep < ro.sweeps; ++sweep) {
                            if (sweep < options.relax_corner_sweeps)
                                moves += detail::relax_layout_corners(relaxed.s_, &corners, &moved, ro);
                            moves += detail::relax_layout_edges(relaxed.s_, &moved, once);
                        }
                    } else {
                        moves = detail::relax_layout_edges(relaxed.s_, &moved, ro);
                    }
                    if (moves > 0) {
                        Network rn;
                        rn.corners = corners;
                        auto moved_corner = [&](int v) {
                            return corners[std::find(net.corners.begin(), net.corners.end(), v) - net.corners.begin()];
                        };
                        for (auto& o : relaxed.obstacle_) o = 0;
                        size_t k = 0;
                        for (const auto& [id, cs] : net.closed) {
                            Cycle c = moved[k];
                            c.insert(c.end(), moved[k + 1].begin() + 1, moved[k + 1].end() - 1);
                            k += 2;
                            rn.closed.push_back({relaxed.add_curve(c, true, true), {moved_corner(cs[0]), moved_corner(cs[1])}});
                        }
                        for (size_t a = 0; a < net.arcs.size(); ++a)
                            rn.arcs.push_back(relaxed.add_curve(moved[k++], false, true));
                        relaxed.split_chords();
                        QuadLayout trial = out;
                        const std::string problem = finish(relaxed, rn, &trial);
                        if (problem.empty()) {
                            // The S-cycles are now the relaxed closed curves (through the moved corners).
                            for (int& id : s_cycle_ids)
                                for (size_t i = 0; i < net.closed.size(); ++i)
                                    if (net.closed[i].first == id) {
                                        id = rn.closed[i].first;
                                        break;
                                    }
                            b = std::move(relaxed);
                            out = std::move(trial);
                            finished = true;
                        } else {
                            say("the relaxed layout edges fail a check (" + problem + "); keeping them unrelaxed");
                        }
                    }
                } catch (const InternalError& e) {
                    say(std::string("relaxing the layout edges failed (") + e.what() + "); keeping them unrelaxed");
                }
            }

            if (!finished)
                if (const std::string problem = finish(b, net, &out); !problem.empty()) throw InternalError(problem);
            for (int i = 0; i < 2 * g; ++i) out.orthogonal_system.push_back(b.curves_[i]);
            for (int id : s_cycle_ids) out.s_cycles.push_back(b.curves_[id]);
            const double t_quality = clock();
            detail::measure_quality(&out);
            const double t_end = clock();
            const double checked = checked_seconds + (t_end - t_quality);
            out.seconds = {t_cycles, t_end - t_cycles - mapped_seconds - checked, mapped_seconds, checked};
            return out;
        } catch (const InternalError& e) {
            failure = e.what();
            say(std::string("retrying the layout curves: ") + e.what());
        }
    }
    throw InternalError(failure);
}

}  // namespace quadcage::layout

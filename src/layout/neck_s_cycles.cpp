// S-cycles at the surface's necks (QuadLayoutOptions::s_cycles_from_necks): a pants decomposition
// of short loops, taken shortest first; pairs of pants joined into T-shirts along a perfect
// matching of its graph; an annulus round each loop left.

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
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

// Candidates per hole: loops near its kNearHoles nearest holes; kSamples points of each path the
// loops cross. kMaxMatchedPants: the pants matched (one bit each); kMaxMatchingStates: the sets of
// them the exact matching may visit before it gives up.
constexpr int kNearHoles = 3;
constexpr int kSamples = 6;
constexpr int kMaxMatchedPants = 64;
constexpr size_t kMaxMatchingStates = size_t{1} << 20;
// How many times the search makes room (splits chords beside the loops) when a piece that must be
// cut has no candidate.
constexpr int kRoomAttempts = 2;

// What cutting piece `piece` of `cut` along closed curve `loop` (inside it) leaves: one piece
// (nonseparating), or on side 0 a piece with `holes0` holes (the loop's included) and Euler
// characteristic `chi0`. `walls`: the edges of the loops cut along so far.
struct Split {
    bool separating = false;
    int holes0 = 0, chi0 = 0;
};

Split split_by(const Surface& s, const Cut& cut, int piece, const Builder& b, const Cycle& loop,
               const std::unordered_set<std::uint64_t>& walls) {
    std::unordered_set<std::uint64_t> own;  // the loop's edges; `walls` has the earlier loops'
    for (size_t i = 0; i < loop.size(); ++i) own.insert(edge_key(loop[i], loop[(i + 1) % loop.size()]));
    std::vector<char> seen(cut.label.size(), 0);
    std::vector<int> stack{triangle_beside(s, loop, 0)}, side;
    seen[stack[0]] = 1;
    const int other_side = triangle_beside(s, loop, 1);  // reached: the loop does not separate
    while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        side.push_back(t);
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * t + k;
            const int u = s.twin(h) / 3;
            if (seen[u] || cut.label[u] != piece) continue;
            const std::uint64_t e = edge_key(s.from(h), s.to(h));
            if (own.count(e) || walls.count(e)) continue;
            if (u == other_side) return {};
            seen[u] = 1, stack.push_back(u);
        }
    }
    Split out;
    out.separating = true;
    out.holes0 = 1;
    if (const auto it = cut.holes.find(piece); it != cut.holes.end())
        for (const Hole& hole : it->second) out.holes0 += seen[triangle_beside(s, b.curves_[hole.curve], hole.side)];
    out.chi0 = euler_characteristic(s, side, [&seen](int t) { return seen[t] != 0; });
    return out;
}

// Whether closed curve `loop` separates the closed surface: a flood from one side that does not
// cross it misses the other.
bool separates_surface(const Surface& s, const Cycle& loop) {
    std::unordered_set<std::uint64_t> own;
    for (size_t i = 0; i < loop.size(); ++i) own.insert(edge_key(loop[i], loop[(i + 1) % loop.size()]));
    const int other_side = triangle_beside(s, loop, 1);
    std::vector<char> seen(s.num_half_edges() / 3, 0);
    std::vector<int> stack{triangle_beside(s, loop, 0)};
    seen[stack[0]] = 1;
    while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * t + k, u = s.twin(h) / 3;
            if (seen[u] || own.count(edge_key(s.from(h), s.to(h)))) continue;
            if (u == other_side) return false;
            seen[u] = 1, stack.push_back(u);
        }
    }
    return true;
}

struct Candidate {
    Cycle loop;
    double length = 0;
};

// The greedy pants decomposition: the loops so far and the candidates not yet taken.
class PantsSearch {
public:
    // `nonseparating`: only loops that do not separate the closed surface. Then no loop is a bridge
    // of the pants graph and none has both sides on one pair of pants, so the graph (cubic) has a
    // perfect matching (Petersen's theorem).
    PantsSearch(Builder& w, int g, bool nonseparating) : w_(w), g_(g), nonseparating_(nonseparating) {}

    // Cuts the surface into 2g - 2 pairs of pants; false if a piece has no loop left to cut it.
    bool run(const Say& say) {
        for (int k = 0; k < 3 * g_ - 3; ++k) {
            say("neck " + std::to_string(k + 1) + " of " + std::to_string(3 * g_ - 3) + surface_size(w_));
            refresh();
            std::optional<Candidate> best = take();
            for (int room = 0; !best && room <= kRoomAttempts; ++room) {
                // Every piece that must still be cut, searched in full: from each hole to its
                // nearest, then (where no loop is valid yet) to every other hole, then the loops
                // between pairs of holes (generate_between()).
                for (const bool every_hole : {false, true}) {
                    for (int piece = 0; piece < cut_.count; ++piece)
                        if (!done(piece)) generate(piece, std::nullopt, every_hole);
                    best = take();
                    if (best) break;
                }
                if (!best) {
                    for (int piece = 0; piece < cut_.count; ++piece)
                        if (!done(piece)) generate_between(piece);
                    best = take();
                }
                if (best || room == kRoomAttempts) break;
                std::vector<Cycle> extra;
                for (int l : loops_) extra.push_back(w_.curves_[l]);
                if (w_.split_chords(extra) == 0) break;
                pool_.clear();
                refresh();
            }
            if (!best) return false;
            const int id = w_.add_curve(best->loop, true, false);
            loops_.push_back(id);
            lengths_.push_back(best->length);
            refresh();
            // New candidates next to the new loop's two sides. (Searched only up to three times
            // the shortest valid one at hand, botijo's decomposition took about 3 s less but
            // fitted worse: level-3 check_fit.py 5.2e-4 / 1.6e-2 against 2.8e-4 / 2.9e-3.)
            for (int side = 0; side < 2; ++side) {
                const int piece = cut_.label[triangle_beside(w_.s_, w_.curves_[id], side)];
                if (!done(piece)) generate(piece, std::make_pair(id, side));
            }
        }
        return true;
    }

    // First call: the candidates on the whole surface (crossing the orthogonal system's cycles).
    void seed() {
        refresh();
        generate(0, std::nullopt);
    }

    const std::vector<int>& loops() const { return loops_; }
    const std::vector<double>& lengths() const { return lengths_; }

private:
    struct PieceState {
        std::vector<Hole> holes;
        std::vector<char> outside, wall;
        std::function<double(int)> cost;
    };

    void refresh() {
        cut_ = cut_by(w_, loops_);
        const Surface& s = w_.s_;
        on_loop_.assign(s.num_vertices(), 0);
        loop_edges_.clear();
        for (int l : loops_) {
            const Cycle& c = w_.curves_[l];
            for (size_t i = 0; i < c.size(); ++i) {
                on_loop_[c[i]] = 1;
                loop_edges_.insert(edge_key(c[i], c[(i + 1) % c.size()]));
            }
        }
        chi_.assign(cut_.count, 0);
        for (int p = 0; p < cut_.count; ++p) chi_[p] = piece_euler_characteristic(s, cut_.label, p);
    }

    std::vector<Hole> holes_of(int piece) const {
        const auto it = cut_.holes.find(piece);
        return it == cut_.holes.end() ? std::vector<Hole>{} : it->second;
    }

    // A pair of pants needs no cut.
    bool done(int piece) const { return chi_[piece] == -1 && holes_of(piece).size() == 3; }

    // Whether cutting along `loop` (inside one piece, off every loop so far) leaves no disc or
    // annulus: then the pieces can still be cut into pants.
    bool valid(const Cycle& loop) const {
        for (int v : loop)
            if (on_loop_[v]) return false;
        const int piece = cut_.label[triangle_beside(w_.s_, loop, 0)];
        if (done(piece)) return false;
        const Split split = split_by(w_.s_, cut_, piece, w_, loop, loop_edges_);
        if (!split.separating) return true;  // nor on the closed surface
        return split.chi0 <= -1 && chi_[piece] - split.chi0 <= -1 &&
               !(nonseparating_ && separates_surface(w_.s_, loop));
    }

    // The shortest valid candidate, taken from the pool; drops the ones no longer valid.
    std::optional<Candidate> take() {
        std::stable_sort(pool_.begin(), pool_.end(),
                         [](const Candidate& a, const Candidate& b) { return a.length < b.length; });
        size_t i = 0;
        while (i < pool_.size() && !valid(pool_[i].loop)) ++i;
        pool_.erase(pool_.begin(), pool_.begin() + static_cast<long>(i));
        if (pool_.empty()) return std::nullopt;
        Candidate c = std::move(pool_.front());
        pool_.erase(pool_.begin());
        return c;
    }

    PieceState piece_state(int piece) const {
        PieceState ps;
        ps.holes = holes_of(piece);
        ps.outside = outside_piece(w_.s_, cut_.label, piece);
        ps.wall = ps.outside;
        for (size_t v = 0; v < ps.wall.size(); ++v) ps.wall[v] = ps.wall[v] || on_loop_[v];
        ps.cost = memoised(w_.cost_near(on_loop_, &ps.outside));
        return ps;
    }

    // Adds the loops that cross path p once (at kSamples of its inner vertices) without
    // meeting `also`; with `closed`, p is a closed curve (every vertex may be crossed).
    // The searches from the samples run on two threads (each with its own memo of the costs);
    // the candidates join the pool in sample order, as one thread would add them.
    void consider(const PieceState& ps, const std::vector<int>& p, const std::vector<int>& also, bool closed = false) {
        const Surface& s = w_.s_;
        const int len = static_cast<int>(p.size());
        if (len < 3) return;
        std::vector<char> walled = ps.wall;
        for (int v : p) walled[v] = 1;
        for (int v : also) walled[v] = 1;
        const int first = closed ? 0 : 1, inner = closed ? len : len - 2;
        const int count = std::min(kSamples, inner);
        std::vector<Candidate> found(count);
        auto search = [&](int from, const std::function<double(int)>& cost) {
            for (int t = from; t < count; t += 2) {
                const int at = first + (inner <= kSamples ? t : t * (inner - 1) / (kSamples - 1));
                const int x = p[at];
                if (ps.wall[x]) continue;
                const auto sec = sectors(s, x, p[(at + len - 1) % len], p[(at + 1) % len]);
                double total = kInf;
                const std::vector<int> rest = w_.sector_path(x, sec[0], x, sec[1], walled, cost, &total);
                if (rest.empty()) continue;
                found[t].loop.push_back(x);
                found[t].loop.insert(found[t].loop.end(), rest.begin(), rest.end());
                found[t].length = total;
            }
        };
        std::exception_ptr error[2];
        auto guarded = [&](int from, const std::function<double(int)>& cost) {
            try {
                search(from, cost);
            } catch (...) {
                error[from] = std::current_exception();
            }
        };
        std::thread other(guarded, 1, memoised(ps.cost));
        guarded(0, ps.cost);
        other.join();
        for (const std::exception_ptr& e : error)
            if (e) std::rethrow_exception(e);
        // Validated when taken (take()): a loop not valid now never becomes valid, and most are
        // dropped unflooded once they meet a loop taken before them.
        for (Candidate& c : found)
            if (!c.loop.empty()) pool_.push_back(std::move(c));
    }

    // Hole i's rim in the piece: (free neighbour on the piece's side, loop vertex) pairs.
    std::vector<std::pair<int, int>> rim_of(const PieceState& ps, int i) const {
        const Surface& s = w_.s_;
        const Cycle& c = w_.curves_[ps.holes[i].curve];
        std::vector<std::pair<int, int>> rim;
        for (int x : c) {
            const auto [pv, nx] = neighbours_on(c, x);
            const auto sec = sectors(s, x, pv, nx);  // named: a temporary's [side] would dangle
            for (int y : sec[1 - ps.holes[i].side])
                if (!ps.wall[y]) rim.push_back({y, x});
        }
        return rim;
    }

    // The last resort of a piece with holes (where no loop of generate() is valid): per pair of
    // its holes, the loop between the triangles nearer to the two (and a shortest path between
    // them) and those nearer to its other holes: a Voronoi boundary, so it keeps as far as it can
    // from every wall. Kept where it is one simple closed curve off every wall.
    void generate_between(int piece) {
        const Surface& s = w_.s_;
        const PieceState ps = piece_state(piece);
        const std::vector<Hole>& hs = ps.holes;
        const int n = static_cast<int>(hs.size());
        if (n < 3) return;
        std::vector<std::vector<std::pair<int, double>>> rim(n);  // per hole: its rim's vertices, at 0
        for (int i = 0; i < n; ++i)
            for (const auto& [y, x] : rim_of(ps, i)) rim[i].push_back({y, 0.0});
        const int nt = s.num_half_edges() / 3;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) {
                if (rim[i].empty() || rim[j].empty()) continue;
                // Off the other holes' rims, and the others' paths off the pair's rims and that
                // path: the two sides' sources do not touch.
                std::vector<char> off_others = ps.wall, off_p = ps.wall;
                for (int k = 0; k < n; ++k)
                    for (const auto& [y, zero] : rim[k]) (k == i || k == j ? off_p : off_others)[y] = 1;
                PathSearch between;
                between.blocked = &off_others;
                between.sources = rim[i];
                between.targets = rim[j];
                const PathResult r = detail::dijkstra(s, between);
                if (r.target < 0) continue;
                // The pair joined by that path, the other holes by paths that keep off it (else a
                // pair across the piece would leave the others' side in two).
                PathSearch near, far;
                near.blocked = far.blocked = &ps.wall;
                const std::vector<int> p = r.path_to(s, r.target);
                for (int v : p) near.sources.push_back({v, 0.0});
                for (const int k : {i, j}) near.sources.insert(near.sources.end(), rim[k].begin(), rim[k].end());
                for (int v : p) off_p[v] = 1;
                bool joined = true;
                for (int k = 0; k < n && joined; ++k) {
                    if (k == i || k == j) continue;
                    if (!far.sources.empty()) {
                        PathSearch join;
                        join.blocked = &off_p;
                        join.sources = far.sources;
                        join.targets = rim[k];
                        const PathResult q = detail::dijkstra(s, join);
                        if (q.target < 0) joined = false;
                        else
                            for (int v : q.path_to(s, q.target)) far.sources.push_back({v, 0.0});
                    }
                    far.sources.insert(far.sources.end(), rim[k].begin(), rim[k].end());
                }
                if (!joined) continue;
                const std::vector<double> dn = detail::dijkstra(s, near).distance;
                const std::vector<double> df = detail::dijkstra(s, far).distance;
                std::vector<char> pair_loop(s.num_vertices(), 0);
                for (const int k : {i, j})
                    for (int v : w_.curves_[hs[k].curve]) pair_loop[v] = 1;
                // Triangles of the piece: 1 nearer to the pair, 2 nearer to the others (by their
                // free corners' least distances), 0 outside.
                std::vector<char> side(nt, 0);
                for (int t = 0; t < nt; ++t) {
                    if (cut_.label[t] != piece) continue;
                    double a = kInf, b = kInf;
                    for (int k = 0; k < 3; ++k) {
                        const int v = s.mesh().triangles[t][k];
                        if (ps.wall[v]) continue;
                        a = std::min(a, dn[v]), b = std::min(b, df[v]);
                    }
                    if (a == b) {  // no free corner, or one as near to both: by the loops it touches
                        bool on_pair = false;
                        for (int k = 0; k < 3; ++k) on_pair = on_pair || pair_loop[s.mesh().triangles[t][k]];
                        a = on_pair ? 0 : kInf, b = on_pair ? kInf : 0;
                    }
                    side[t] = a < b ? 1 : 2;
                }
                // The half-edges with the pair's side on their left and the others' on their right.
                std::vector<int> next(s.num_vertices(), -1);
                int first = -1, count = 0;
                bool simple = true;
                for (int h = 0; h < 3 * nt && simple; ++h) {
                    if (side[h / 3] != 1 || side[s.twin(h) / 3] != 2) continue;
                    const int a = s.from(h);
                    if (ps.wall[a] || ps.wall[s.to(h)] || next[a] >= 0) simple = false;
                    next[a] = s.to(h), first = a, ++count;
                }
                if (!simple || first < 0) continue;
                Candidate c;
                for (int v = first; c.loop.size() <= static_cast<size_t>(count);) {
                    c.loop.push_back(v);
                    v = next[v];
                    if (v < 0) break;
                    if (v == first) break;
                }
                if (count < 3 || static_cast<int>(c.loop.size()) != count) continue;  // several curves, or open
                for (size_t k = 0; k < c.loop.size(); ++k)
                    c.length += ps.cost(s.find_half_edge(c.loop[k], c.loop[(k + 1) % c.loop.size()]));
                pool_.push_back(std::move(c));
            }
    }

    // Candidates in `piece`: for every hole (or only `from`, a new loop's side), loops across the
    // shortest paths to its kNearHoles nearest holes (`every_hole`: to all of them, nearest first),
    // and round the two holes and such a path.
    void generate(int piece, std::optional<std::pair<int, int>> from, bool every_hole = false) {
        const Surface& s = w_.s_;
        const PieceState ps = piece_state(piece);
        const std::vector<Hole>& hs = ps.holes;
        const int n = static_cast<int>(hs.size());
        if (n == 0) {  // the whole surface
            for (int c = 0; c < 2 * g_; ++c) consider(ps, w_.curves_[c], {}, true);
            return;
        }
        std::vector<std::vector<std::pair<int, int>>> rim(n);  // per hole: (free neighbour, loop vertex)
        for (int i = 0; i < n; ++i) rim[i] = rim_of(ps, i);
        // A shortest path from `sources` to the rim of a hole not in `skip`, ending on its loop.
        auto path_to_rim = [&](const std::vector<char>& blocked, const std::vector<std::pair<int, double>>& sources,
                               const std::vector<char>& skip, int* hole) {
            PathSearch q;
            q.blocked = &blocked;
            q.sources = sources;
            std::vector<std::array<int, 2>> goal;  // per target: hole, loop vertex
            for (int j = 0; j < n; ++j) {
                if (skip[j]) continue;
                for (const auto& [y, x] : rim[j]) {
                    if (blocked[y]) continue;
                    q.targets.push_back({y, norm(s.point(x) - s.point(y))});
                    goal.push_back({j, x});
                }
            }
            std::vector<int> p;
            if (q.targets.empty()) return p;
            const PathResult r = detail::dijkstra(s, q);
            if (r.target < 0) return p;
            // The target reached (a vertex may be beside several loop vertices: the first listed
            // with the least arrival cost, as the search took it).
            size_t k = 0;
            double least = kInf;
            for (size_t t = 0; t < q.targets.size(); ++t)
                if (q.targets[t].first == r.target && q.targets[t].second < least) least = q.targets[t].second, k = t;
            *hole = goal[k][0];
            p = r.path_to(s, r.target);
            p.push_back(goal[k][1]);
            return p;
        };
        auto rim_sources = [&](int i, const std::vector<char>& blocked) {
            std::vector<std::pair<int, double>> out;
            for (const auto& [y, x] : rim[i])
                if (!blocked[y]) out.push_back({y, norm(s.point(x) - s.point(y))});
            return out;
        };
        for (int i = 0; i < n; ++i) {
            if (from && (hs[i].curve != from->first || hs[i].side != from->second)) continue;
            std::vector<char> skip(n, 0);
            skip[i] = 1;
            const auto sources = rim_sources(i, ps.wall);
            for (int round = 0; round < (every_hole ? n - 1 : kNearHoles) && n > 1; ++round) {
                int j = -1;
                std::vector<int> p = path_to_rim(ps.wall, sources, skip, &j);
                if (p.empty()) break;
                skip[j] = 1;
                for (const auto& [y, x] : rim[i])  // the path starts beside i's loop: that vertex first
                    if (y == p[0]) {
                        p.insert(p.begin(), x);
                        break;
                    }
                consider(ps, p, {});
                if (n < 4) continue;
                // Loops round holes i and j and the path between them: across a shortest path q
                // from there to the nearest other hole k, which is joined to its own nearest other
                // hole (else the shortest loop across q goes round k alone).
                std::vector<char> blocked = ps.wall;
                for (int v : p) blocked[v] = 1;
                std::vector<std::pair<int, double>> cluster;
                for (size_t k = 1; k + 1 < p.size(); ++k) cluster.push_back({p[k], 0.0});
                for (int h : {i, j})
                    for (const auto& src : rim_sources(h, blocked)) cluster.push_back(src);
                std::vector<char> skip2(n, 0);
                skip2[i] = skip2[j] = 1;
                int k2 = -1;
                std::vector<int> q = path_to_rim(blocked, cluster, skip2, &k2);
                if (q.size() < 2) continue;
                int before = -1;  // a wall vertex before q's first: on p, or the loop beside it
                if (std::find(p.begin(), p.end(), q[0]) != p.end()) before = q[0];
                for (int h : {i, j})
                    for (const auto& [y, x] : rim[h])
                        if (before < 0 && y == q[0]) before = x;
                if (before >= 0 && before != q[0]) q.insert(q.begin(), before);
                std::vector<char> blocked3 = blocked;
                for (int v : q) blocked3[v] = 1;
                std::vector<char> skip3 = skip2;
                skip3[k2] = 1;
                int m2 = -1;
                const std::vector<int> r = path_to_rim(blocked3, rim_sources(k2, blocked3), skip3, &m2);
                if (r.empty()) continue;
                std::vector<int> also = p;
                also.insert(also.end(), r.begin(), r.end());
                consider(ps, q, also);
            }
        }
    }

    Builder& w_;
    const int g_;
    const bool nonseparating_;
    std::vector<int> loops_;
    std::vector<double> lengths_;
    std::vector<Candidate> pool_;
    Cut cut_;
    std::vector<int> chi_;
    std::vector<char> on_loop_;
    std::unordered_set<std::uint64_t> loop_edges_;
};

}  // namespace

std::optional<std::vector<char>> pants_matching(const std::vector<std::array<int, 2>>& ends,
                                                const std::vector<double>& lengths, int pants, bool* too_many) {
    QC_CHECK(pants >= 0 && pants <= kMaxMatchedPants && ends.size() == lengths.size(),
             "pants_matching: " + std::to_string(pants) + " pants");
    if (too_many) *too_many = false;
    // The loops at each pair of pants (a loop with both sides on one cannot be dropped).
    std::vector<std::vector<int>> at(pants);
    for (size_t e = 0; e < ends.size(); ++e)
        if (ends[e][0] != ends[e][1]) at[ends[e][0]].push_back(static_cast<int>(e)), at[ends[e][1]].push_back(static_cast<int>(e));
    // The pants numbered breadth first, so that the pants matched at any point of the search are
    // the first ones but for a few near the frontier: the matched sets it meets stay few.
    std::vector<int> order, rank(pants, -1);
    for (int root = 0; root < pants; ++root) {
        if (rank[root] >= 0) continue;
        rank[root] = static_cast<int>(order.size()), order.push_back(root);
        for (size_t i = order.size() - 1; i < order.size(); ++i)
            for (const int e : at[order[i]]) {
                const int z = ends[e][0] == order[i] ? ends[e][1] : ends[e][0];
                if (rank[z] < 0) rank[z] = static_cast<int>(order.size()), order.push_back(z);
            }
    }
    // best(matched): the greatest length the unmatched pants can drop, matching the first unmatched
    // one (in that order) first, so that each matching is built once; memoised on the matched set.
    using Set = std::uint64_t;
    const Set all = pants == 64 ? ~Set{0} : (Set{1} << pants) - 1;
    std::unordered_map<Set, std::pair<double, int>> memo;  // best, and the loop dropped there
    bool overflow = false;
    std::function<double(Set)> best = [&](Set matched) -> double {
        if (matched == all) return 0;
        if (const auto it = memo.find(matched); it != memo.end()) return it->second.first;
        if (memo.size() >= kMaxMatchingStates) {
            overflow = true;
            return -kInf;
        }
        const int first = __builtin_ctzll(~matched);
        double value = -kInf;
        int choice = -1;
        for (const int e : at[order[first]]) {
            const int z = rank[ends[e][0] == order[first] ? ends[e][1] : ends[e][0]];
            if (matched >> z & 1) continue;
            const double rest = best(matched | Set{1} << first | Set{1} << z);
            if (rest > -kInf && rest + lengths[e] > value) value = rest + lengths[e], choice = e;
        }
        memo.emplace(matched, std::pair{value, choice});
        return value;
    };
    const double most = best(0);
    if (too_many) *too_many = overflow;
    if (overflow || !(most > -kInf)) return std::nullopt;
    std::vector<char> dropped(ends.size(), 0);
    for (Set matched = 0; matched != all;) {
        const int e = memo.at(matched).second;
        dropped[e] = 1;
        matched |= Set{1} << rank[ends[e][0]] | Set{1} << rank[ends[e][1]];
    }
    return dropped;
}

std::optional<std::vector<int>> neck_s_cycles(Builder& b, int g, const Say& say) {
    static_assert(2 * kMaxNeckGenus - 2 <= kMaxMatchedPants, "the pants of the highest genus tried are matched");
    if (g > kMaxNeckGenus) return std::nullopt;
    // Shortest loops first; where their pants have no perfect matching (a pair of pants with two
    // handles hanging off it: loops round each handle's two feet), again with loops that separate
    // nothing.
    Builder w = b;
    std::vector<int> loops;
    std::optional<std::vector<char>> dropped;
    for (const bool nonseparating : {false, true}) {
        w = b;
        PantsSearch search(w, g, nonseparating);
        search.seed();
        if (!search.run(say)) {
            say("necks: a piece has no loop left to cut it");
            return std::nullopt;
        }
        loops = search.loops();
        const Cut c = cut_by(w, loops);
        if (c.count != 2 * g - 2) return std::nullopt;
        std::vector<std::array<int, 2>> ends;
        for (int l : loops)
            ends.push_back({c.label[triangle_beside(w.s_, w.curves_[l], 0)], c.label[triangle_beside(w.s_, w.curves_[l], 1)]});
        bool too_many = false;
        dropped = pants_matching(ends, search.lengths(), c.count, &too_many);
        if (dropped) break;
        if (too_many) {
            say("necks: the pairs of pants have too many matchings to compare");
            return std::nullopt;
        }
        say(nonseparating ? "necks: the pairs of pants have no perfect matching"
                          : "necks: the pairs of pants have no perfect matching; again with loops that separate nothing");
    }
    if (!dropped) return std::nullopt;
    std::vector<int> kept;
    for (size_t e = 0; e < loops.size(); ++e) {
        if (!(*dropped)[e])
            kept.push_back(loops[e]);
        else
            w.curves_[loops[e]].clear();  // inside a T-shirt: no longer a curve
    }
    std::vector<int> ids;
    if (!tube_loops(w, kept, surface_area(w.s_.mesh()) / (10.0 * g - 10), &ids, say)) {
        say("necks: an annulus round a loop does not fit");
        return std::nullopt;
    }
    try {
        find_pieces(w, ids, g);
    } catch (const InternalError& e) {
        say(std::string("necks: ") + e.what());
        return std::nullopt;
    }
    b = std::move(w);
    return ids;
}

}  // namespace quadcage::layout::detail

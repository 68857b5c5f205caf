#include "detail/curves.h"
#include "detail/search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

// Sectors of vertex x on a curve through prev -> x -> next: the neighbours strictly between prev
// and next in rotation order (sector 0) and between next and prev (sector 1).
std::array<std::vector<int>, 2> sectors(const Surface& s, int x, int prev, int next) {
    const std::vector<int> ring = s.ring(x);
    const int n = static_cast<int>(ring.size());
    const int ip = static_cast<int>(std::find(ring.begin(), ring.end(), prev) - ring.begin());
    const int in = static_cast<int>(std::find(ring.begin(), ring.end(), next) - ring.begin());
    QC_CHECK(ip < n && in < n, "sectors: curve neighbours not adjacent");
    std::array<std::vector<int>, 2> out;
    for (int k = (ip + 1) % n; k != in; k = (k + 1) % n) out[0].push_back(ring[k]);
    for (int k = (in + 1) % n; k != ip; k = (k + 1) % n) out[1].push_back(ring[k]);
    return out;
}

std::pair<int, int> neighbours_on(const Cycle& c, int x) {
    const auto it = std::find(c.begin(), c.end(), x);
    QC_CHECK(it != c.end(), "neighbours_on: vertex not on the curve");
    const size_t i = static_cast<size_t>(it - c.begin());
    return {c[(i + c.size() - 1) % c.size()], c[(i + 1) % c.size()]};
}

std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

// Up to k vertices spread evenly along a curve, skipping those `skip` rejects.
std::vector<int> spread(const Cycle& c, int k, const std::function<bool(int)>& skip) {
    std::vector<int> ok;
    for (int v : c)
        if (!skip(v)) ok.push_back(v);
    std::vector<int> out;
    const int n = static_cast<int>(ok.size());
    for (int i = 0; i < std::min(k, n); ++i) out.push_back(ok[static_cast<size_t>(i) * n / std::min(k, n)]);
    return out;
}

Builder::Builder(const Mesh& mesh, const OrthogonalSystemOptions& o) : s_(mesh), o_(o) {
    sigma_ = o.repulsion_radius * std::sqrt(surface_area(mesh));
}

int Builder::add_curve(Cycle c, bool closed, bool obstacle) {
    curves_.push_back(std::move(c));
    closed_.push_back(closed);
    obstacle_.push_back(obstacle);
    return static_cast<int>(curves_.size()) - 1;
}

std::vector<char> Builder::blocked() const {
    std::vector<char> b(s_.num_vertices(), 0);
    for (size_t c = 0; c < curves_.size(); ++c)
        if (obstacle_[c])
            for (int v : curves_[c]) b[v] = 1;
    return b;
}

std::unordered_set<std::uint64_t> Builder::obstacle_edges() const {
    std::unordered_set<std::uint64_t> keys;
    for (size_t c = 0; c < curves_.size(); ++c) {
        if (!obstacle_[c]) continue;  // an edge of a curve that is no obstacle is a chord too
        const Cycle& cv = curves_[c];
        const size_t n = cv.size();
        for (size_t i = 0; i + (closed_[c] ? 0 : 1) < n; ++i) keys.insert(edge_key(cv[i], cv[(i + 1) % n]));
    }
    return keys;
}

int Builder::split_chords(const std::vector<Cycle>& extra) {
    std::vector<char> on = blocked();
    std::unordered_set<std::uint64_t> curve_edges = obstacle_edges();
    for (const Cycle& c : extra) {
        for (size_t i = 0; i + 1 < c.size(); ++i) curve_edges.insert(edge_key(c[i], c[i + 1]));
        for (int v : c) on[v] = 1;
    }
    std::vector<std::pair<int, int>> chords;
    for (int h = 0; h < s_.num_half_edges(); ++h) {
        const int a = s_.from(h), b = s_.to(h);
        if (a < b && on[a] && on[b] && !curve_edges.count(edge_key(a, b))) chords.push_back({a, b});
    }
    if (chords.empty()) return 0;
    split_curve_edges(chords);
    return static_cast<int>(chords.size());
}

PathsThrough::PathsThrough(int num_vertices, const std::vector<std::vector<int>>& paths) : on_(num_vertices) {
    for (size_t p = 0; p < paths.size(); ++p)
        for (int v : paths[p])
            if (on_[v].empty() || on_[v].back() != static_cast<int>(p)) on_[v].push_back(static_cast<int>(p));
}

bool PathsThrough::share_a_path(int a, int b) const {
    for (int p : on_[a])
        if (std::find(on_[b].begin(), on_[b].end(), p) != on_[b].end()) return true;
    return false;
}

int Builder::split_dividing_chords(const std::vector<std::vector<int>>& paths) {
    const PathsThrough on(s_.num_vertices(), paths);
    std::unordered_set<std::uint64_t> path_edges;
    for (const auto& path : paths)
        for (size_t i = 0; i + 1 < path.size(); ++i) path_edges.insert(edge_key(path[i], path[i + 1]));
    std::vector<std::pair<int, int>> chords;
    for (int h = 0; h < s_.num_half_edges(); ++h) {
        const int a = s_.from(h), b = s_.to(h);
        if (a < b && on.on_any(a) && on.on_any(b) && !path_edges.count(edge_key(a, b)) &&
            on.share_a_path(a, b))
            chords.push_back({a, b});
    }
    if (chords.empty()) return 0;
    split_curve_edges(chords);
    return static_cast<int>(chords.size());
}

int Builder::split_chords_around(const std::vector<char>& reached) {
    const std::vector<char> on = blocked();
    const std::unordered_set<std::uint64_t> curve_edges = obstacle_edges();
    auto is_chord = [&](int h) {
        const int a = s_.from(h), b = s_.to(h);
        return on[a] && on[b] && !curve_edges.count(edge_key(a, b));
    };
    // Flood from the triangles the search touched, across chords, through "wall" triangles (all
    // three corners on curves): a corridor between two curves that run side by side is one strip
    // of wall triangles, opened in one go.
    const int nt = s_.num_half_edges() / 3;
    std::vector<char> seen(nt, 0);
    std::vector<int> queue;
    for (int t = 0; t < nt; ++t) {
        const Triangle& tri = s_.mesh().triangles[t];
        if (reached[tri[0]] || reached[tri[1]] || reached[tri[2]]) {
            seen[t] = 1;
            queue.push_back(t);
        }
    }
    std::vector<std::pair<int, int>> chords;
    std::unordered_set<std::uint64_t> chosen;
    for (size_t i = 0; i < queue.size(); ++i) {
        const int t = queue[i];
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * t + k;
            if (!is_chord(h)) continue;
            const int a = s_.from(h), b = s_.to(h);
            if (chosen.insert(edge_key(a, b)).second) chords.push_back({std::min(a, b), std::max(a, b)});
            const int o = s_.twin(h) / 3;
            const Triangle& ot = s_.mesh().triangles[o];
            if (!seen[o] && on[ot[0]] && on[ot[1]] && on[ot[2]]) {
                seen[o] = 1;
                queue.push_back(o);
            }
        }
    }
    if (chords.empty()) return 0;
    std::sort(chords.begin(), chords.end());
    split_curve_edges(chords);
    return static_cast<int>(chords.size());
}

int Builder::open_route(int x, const std::vector<int>& from_sector, int y, const std::vector<int>& to_sector,
                        const std::vector<char>& block, const std::function<double(int)>& cost) {
    const std::vector<std::pair<int, int>> edges = route_chords(x, from_sector, y, to_sector, block, cost);
    split_curve_edges(edges);
    return static_cast<int>(edges.size());
}

std::vector<std::pair<int, int>> Builder::route_chords(int x, const std::vector<int>& from_sector, int y,
                                                       const std::vector<int>& to_sector,
                                                       const std::vector<char>& block,
                                                       const std::function<double(int)>& cost,
                                                       const std::unordered_set<std::uint64_t>* walls) const {
    // A step through a chord's midpoint costs this many times its length: far above any walk
    // that needs no split, so the route crosses as few chords as it can.
    constexpr double kCrossing = 64.0;
    std::unordered_set<std::uint64_t> curve_edges = obstacle_edges();
    if (walls) curve_edges.insert(walls->begin(), walls->end());
    const int n = s_.num_vertices();
    // Nodes: the vertices [0, n), then one per chord met (its midpoint, once split). Moves that
    // splitting exactly the chords of a route makes edges of the surface: a free vertex to a chord
    // opposite it in a triangle (its other two edges touch a free vertex: no chords, not split);
    // a chord to the free third vertex of one of its triangles; a chord to another chord of one
    // triangle (a triangle with two or three split edges joins their midpoints).
    std::unordered_map<std::uint64_t, int> chord_of;
    std::vector<int> chord_half_edge;
    auto chord = [&](int h) {
        const int a = s_.from(h), b = s_.to(h);
        if (!block[a] || !block[b]) return -1;
        const std::uint64_t key = edge_key(a, b);
        if (curve_edges.count(key)) return -1;
        const auto it = chord_of.find(key);
        if (it != chord_of.end()) return it->second;
        chord_half_edge.push_back(h);
        return chord_of[key] = n + static_cast<int>(chord_half_edge.size()) - 1;
    };
    auto position = [&](int node) {
        if (node < n) return s_.point(node);
        const int h = chord_half_edge[node - n];
        return (s_.point(s_.from(h)) + s_.point(s_.to(h))) * 0.5;
    };
    auto crossing = [&](int from, int to) { return kCrossing * norm(position(to) - position(from)); };
    // The nodes a route may leave `centre` to (or arrive from) within a sector: its free vertices,
    // and the chords from the centre or opposite it in the sector's triangles (those on both sides
    // of each edge centre-s).
    auto sector_nodes = [&](int centre, const std::vector<int>& sector, bool leaving) {
        std::vector<std::pair<int, double>> out;
        for (int w : sector) {
            if (!block[w]) {
                out.push_back({w, leaving ? edge_cost(cost, centre, w) : edge_cost(cost, w, centre)});
                continue;
            }
            const int h = s_.find_half_edge(centre, w);
            if (const int c = chord(h); c >= 0) out.push_back({c, crossing(centre, c)});
            for (const int e : {h, s_.twin(h)})
                for (int k = 0; k < 3; ++k) {
                    const int o = 3 * (e / 3) + k;
                    if (s_.from(o) == centre || s_.to(o) == centre) continue;
                    if (const int c = chord(o); c >= 0) out.push_back({c, crossing(centre, c)});
                }
        }
        return out;
    };
    const std::vector<std::pair<int, double>> sources = sector_nodes(x, from_sector, true);
    const std::vector<std::pair<int, double>> targets = sector_nodes(y, to_sector, false);
    if (sources.empty() || targets.empty()) return {};
    std::unordered_map<int, double> arrival, distance;
    for (const auto& [v, c] : targets)
        if (const auto it = arrival.find(v); it == arrival.end() || c < it->second) arrival[v] = c;
    std::unordered_map<int, int> parent;
    std::unordered_set<int> done;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    auto reach = [&](int from, int to, double d) {
        if (done.count(to)) return;
        if (const auto it = distance.find(to); it != distance.end() && it->second <= d) return;
        distance[to] = d;
        parent[to] = from;
        heap.push({d, to});
    };
    for (const auto& [v, c] : sources) reach(-1, v, c);
    double best = std::numeric_limits<double>::infinity();
    int target = -1;
    while (!heap.empty()) {
        const auto [d, v] = heap.top();
        heap.pop();
        if (!done.insert(v).second) continue;
        if (d >= best) break;
        if (const auto it = arrival.find(v); it != arrival.end() && d + it->second < best) {
            best = d + it->second;
            target = v;
        }
        if (v < n) {
            for (int h : s_.out_half_edges(v)) {
                const int w = s_.to(h);
                if (!block[w]) reach(v, w, d + (cost ? cost(h) : s_.length(h)));
                if (const int c = chord(3 * (h / 3) + (h % 3 + 1) % 3); c >= 0)  // the edge opposite v
                    reach(v, c, d + crossing(v, c));
            }
        } else {
            const int hc = chord_half_edge[v - n];
            for (const int e : {hc, s_.twin(hc)}) {
                const int t = e / 3;
                const int third = s_.mesh().triangles[t][(e % 3 + 2) % 3];
                if (!block[third]) reach(v, third, d + crossing(v, third));
                for (int k = 0; k < 3; ++k)
                    if (const int c = 3 * t + k == e ? -1 : chord(3 * t + k); c >= 0) reach(v, c, d + crossing(v, c));
            }
        }
    }
    std::vector<std::pair<int, int>> edges;
    for (int v = target; v >= 0; v = parent.at(v))
        if (v >= n) {
            const int h = chord_half_edge[v - n];
            edges.push_back({std::min(s_.from(h), s_.to(h)), std::max(s_.from(h), s_.to(h))});
        }
    std::sort(edges.begin(), edges.end());  // empty: no route, or one that needs no split
    return edges;
}

void Builder::split_curve_edges(const std::vector<std::pair<int, int>>& edges) {
    if (edges.empty()) return;
    const std::vector<int> mids = s_.split_edges(edges);
    std::vector<std::array<int, 3>> split;
    for (size_t i = 0; i < edges.size(); ++i) split.push_back({edges[i].first, edges[i].second, mids[i]});
    std::vector<std::vector<int>> closed, open;
    for (size_t c = 0; c < curves_.size(); ++c) (closed_[c] ? closed : open).push_back(std::move(curves_[c]));
    insert_midpoints(closed, split, true);
    insert_midpoints(open, split, false);
    size_t ic = 0, io = 0;
    for (size_t c = 0; c < curves_.size(); ++c)
        curves_[c] = std::move(closed_[c] ? closed[ic++] : open[io++]);
    splits_ += static_cast<int>(edges.size());
    if (max_vertices_ > 0 && s_.num_vertices() > max_vertices_)
        throw OverBudget("the layout curves needed more than " + std::to_string(max_vertices_) + " vertices");
}

std::function<double(int)> Builder::cost_near(const std::vector<char>& block,
                                              const std::vector<char>* outside, double adjacency) const {
    if (o_.repulsion <= 0 && adjacency <= 0) return {};
    PathSearch q;
    for (int v = 0; v < s_.num_vertices(); ++v)
        if (block[v] && !(outside && (*outside)[v])) q.sources.push_back({v, 0.0});
    q.blocked = outside;
    q.max_distance = 8 * sigma_;  // the penalty is below 3e-3 beyond
    auto field = std::make_shared<std::vector<double>>(dijkstra(s_, q).distance);
    auto beside = std::make_shared<std::vector<char>>();
    if (adjacency > 0) {
        beside->assign(s_.num_vertices(), 0);
        for (const auto& [v, c] : q.sources)
            for (int w : s_.ring(v))
                if (!block[w]) (*beside)[w] = 1;
    }
    return NearCost{&s_, std::move(field), std::move(beside), o_.repulsion, sigma_, adjacency, {}};
}

std::function<double(int)> Builder::grown_cost_near(const std::function<double(int)>& previous,
                                                    const std::vector<char>& previous_block,
                                                    const std::vector<char>& block,
                                                    const std::vector<char>* outside) const {
    const NearCost* near = previous.target<NearCost>();
    if (!near) return previous;  // no cost (no repulsion, no adjacency): none now either
    QC_CHECK(near->s == &s_ && near->field->size() == static_cast<size_t>(s_.num_vertices()),
             "grown_cost_near: the surface changed");
    std::vector<int> added;  // the new sources, as cost_near() takes them
    for (int v = 0; v < s_.num_vertices(); ++v)
        if (block[v] && !previous_block[v] && !(outside && (*outside)[v])) added.push_back(v);
    NearCost grown = *near;
    grown.memo = nullptr;
    auto field = std::make_shared<std::vector<double>>(*near->field);
    lower_distances(s_, added, outside, 8 * sigma_, field.get());
    grown.field = std::move(field);
    if (!near->beside->empty()) {
        // Neighbours of a source that are not blocked: the old ones less those blocked now, and the
        // new sources' ones.
        auto beside = std::make_shared<std::vector<char>>(*near->beside);
        for (int v = 0; v < s_.num_vertices(); ++v)
            if (block[v]) (*beside)[v] = 0;
        for (int v : added)
            for (int w : s_.ring(v))
                if (!block[w]) (*beside)[w] = 1;
        grown.beside = std::move(beside);
    }
    return grown;
}

std::function<double(int)> memoised(const std::function<double(int)>& cost) {
    const NearCost* near = cost.target<NearCost>();
    if (!near) return cost;
    NearCost m = *near;
    m.memo = std::make_shared<std::vector<double>>(m.s->num_half_edges(),
                                                   std::numeric_limits<double>::quiet_NaN());
    return m;
}

double Builder::edge_cost(const std::function<double(int)>& cost, int a, int b) const {
    const int h = s_.find_half_edge(a, b);
    return cost ? cost(h) : s_.length(h);
}

std::vector<int> Builder::sector_path(int x, const std::vector<int>& from_sector, int y,
                                      const std::vector<int>& to_sector, const std::vector<char>& block,
                                      const std::function<double(int)>& cost, double* total,
                                      std::vector<char>* reached, double bound) const {
    PathSearch q;
    q.blocked = &block;
    q.cost = cost;
    q.max_distance = bound;
    for (int n : from_sector)
        if (!block[n]) q.sources.push_back({n, edge_cost(cost, x, n)});
    for (int n : to_sector)
        if (!block[n]) q.targets.push_back({n, edge_cost(cost, n, y)});
    if (reached) {  // on failure: what the search settled, and its two ends (their walls count too)
        reached->assign(s_.num_vertices(), 0);
        (*reached)[x] = (*reached)[y] = 1;
    }
    if (q.sources.empty() || q.targets.empty()) return {};
    // The search from both ends, unless a bound and `reached` are both given (the settled set of a
    // bounded search is not the one-way search's).
    if (!reached || bound == std::numeric_limits<double>::infinity()) {
        double t = 0;
        std::vector<int> p;
        const auto length = [this](int h) { return s_.length(h); };
        if (const NearCost* near = cost.target<NearCost>())
            p = search::run_both_ways(s_, q, *near, &t, bound, reached);
        else if (cost)
            p = search::run_both_ways(s_, q, cost, &t, bound, reached);
        else
            p = search::run_both_ways(s_, q, length, &t, bound, reached);
        if (!p.empty() && total) *total = t;
        return p;
    }
    const PathResult r = dijkstra(s_, q);
    if (r.target < 0) {
        if (reached)
            for (int v = 0; v < s_.num_vertices(); ++v)
                if (r.distance[v] < std::numeric_limits<double>::infinity()) (*reached)[v] = 1;
        return {};
    }
    if (total) *total = r.target_cost;
    return r.path_to(s_, r.target);
}

}  // namespace quadcage::layout::detail

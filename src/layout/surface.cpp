#include "detail/surface.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <unordered_map>

#include "detail/curves.h"
#include "detail/search.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

Surface::Surface(Mesh mesh) : mesh_(std::move(mesh)) { rebuild(); }

void Surface::rebuild() {
    const int n = num_vertices();
    const int nh = num_half_edges();
    // Outgoing half-edges per vertex (CSR), then the twin of a->b is the half-edge b->a. Each
    // vertex's outgoing half-edges and their heads sit side by side, so the search for a twin reads
    // one short contiguous run instead of a triangle per candidate (the triangles are out of cache
    // on a large surface, and the layout rebuilds after every batch of splits).
    std::vector<int> start(n + 1, 0);
    for (int h = 0; h < nh; ++h) ++start[from(h) + 1];
    for (int v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<int> fill(start.begin(), start.end() - 1), outs(nh), outs_to(nh);
    for (int h = 0; h < nh; ++h) {
        const int i = fill[from(h)]++;
        outs[i] = h;
        outs_to[i] = to(h);
    }
    twin_.assign(nh, -1);
    out_.assign(n, -1);
    for (int h = 0; h < nh; ++h) {
        const int a = from(h), b = to(h);
        if (out_[a] < 0) out_[a] = h;
        for (int i = start[b]; i < start[b + 1]; ++i)
            if (outs_to[i] == a) {
                QC_CHECK(twin_[h] < 0, "Surface: edge used twice in one direction (not manifold/oriented)");
                twin_[h] = outs[i];
            }
        QC_CHECK(twin_[h] >= 0, "Surface: open edge (the surface must be closed)");
    }
}

std::vector<int> Surface::out_half_edges(int v) const {
    std::vector<int> hs;
    const int h0 = out_[v];
    int h = h0;
    do {
        hs.push_back(h);
        h = rotate(h);
        QC_CHECK(hs.size() < 100000, "Surface: vertex ring does not close");
    } while (h != h0);
    return hs;
}

std::vector<int> Surface::ring(int v) const {
    std::vector<int> r;
    for (int h : out_half_edges(v)) r.push_back(to(h));
    return r;
}

int Surface::find_half_edge(int a, int b) const {
    const int h0 = out_[a];
    int h = h0;
    do {
        if (to(h) == b) return h;
        h = rotate(h);
    } while (h != h0);
    return -1;
}

std::vector<int> Surface::split_edges(const std::vector<std::pair<int, int>>& edges) {
    std::map<std::pair<int, int>, int> mid;  // ordered: deterministic vertex numbering
    std::vector<int> result;
    result.reserve(edges.size());
    for (auto [a, b] : edges) {
        const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
        auto it = mid.find(key);
        if (it == mid.end()) {
            QC_CHECK(find_half_edge(a, b) >= 0, "split_edges: not an edge");
            it = mid.emplace(key, num_vertices()).first;
            mesh_.points.push_back((point(a) + point(b)) * 0.5);
        }
        result.push_back(it->second);
    }
    // Most triangles touch no split edge: a vertex test spares them the map lookups.
    std::vector<char> on_split(mesh_.points.size(), 0);
    for (const auto& [key, m] : mid) on_split[key.first] = on_split[key.second] = 1;
    auto m_of = [&mid, &on_split](int a, int b) {
        if (!on_split[a] || !on_split[b]) return -1;
        auto it = mid.find({std::min(a, b), std::max(a, b)});
        return it == mid.end() ? -1 : it->second;
    };
    std::vector<Triangle> out;
    out.reserve(mesh_.triangles.size() + 3 * mid.size());
    const int old_triangles = mesh_.num_triangles();
    std::vector<int> kept(old_triangles, -1);  // new index of a triangle that is not split
    for (int f = 0; f < old_triangles; ++f) {
        const Triangle& t = mesh_.triangles[f];
        int m[3] = {m_of(t[0], t[1]), m_of(t[1], t[2]), m_of(t[2], t[0])};
        const int count = (m[0] >= 0) + (m[1] >= 0) + (m[2] >= 0);
        if (count == 0) {
            kept[f] = static_cast<int>(out.size());
            out.push_back(t);
            continue;
        }
        if (count == 3) {
            out.push_back({t[0], m[0], m[2]});
            out.push_back({m[0], t[1], m[1]});
            out.push_back({m[2], m[1], t[2]});
            out.push_back({m[0], m[1], m[2]});
            continue;
        }
        // Rotate so that the split edges come first: edge 0 (count 1) or edges 0 and 1 (count 2).
        int r = 0;
        if (count == 1) r = m[0] >= 0 ? 0 : (m[1] >= 0 ? 1 : 2);
        else r = m[2] < 0 ? 0 : (m[0] < 0 ? 1 : 2);
        const int v0 = t[r], v1 = t[(r + 1) % 3], v2 = t[(r + 2) % 3];
        const int m01 = m[r], m12 = m[(r + 1) % 3];
        if (count == 1) {
            out.push_back({v0, m01, v2});
            out.push_back({m01, v1, v2});
        } else {
            out.push_back({m01, v1, m12});
            out.push_back({v0, m01, m12});
            out.push_back({v0, m12, v2});
        }
    }
    mesh_.triangles = std::move(out);
    // The adjacency as rebuild() would make it, but only the split triangles' part searched for: a
    // triangle that is not split keeps its twins across edges to others that are not (renumbered);
    // the half-edges left (in split triangles, or next to them) are matched by their ends. The
    // layout splits a few dozen edges at a time on surfaces of 10^5 triangles.
    const int nh = num_half_edges();
    std::vector<int> old_twin = std::move(twin_);
    twin_.assign(nh, -1);
    for (int f = 0; f < old_triangles; ++f) {
        if (kept[f] < 0) continue;
        for (int k = 0; k < 3; ++k) {
            const int o = old_twin[3 * f + k];
            if (kept[o / 3] >= 0) twin_[3 * kept[f] + k] = 3 * kept[o / 3] + o % 3;
        }
    }
    std::unordered_map<std::uint64_t, int> open;  // unmatched half-edge by (from, to)
    auto directed = [](int a, int b) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
               static_cast<std::uint32_t>(b);
    };
    for (int h = 0; h < nh; ++h) {
        if (twin_[h] >= 0) continue;
        const auto it = open.find(directed(to(h), from(h)));
        if (it == open.end()) {
            QC_CHECK(open.emplace(directed(from(h), to(h)), h).second,
                     "Surface: edge used twice in one direction (not manifold/oriented)");
            continue;
        }
        twin_[h] = it->second;
        twin_[it->second] = h;
        open.erase(it);
    }
    QC_CHECK(open.empty(), "Surface: open edge (the surface must be closed)");
    out_.assign(num_vertices(), -1);
    for (int h = nh - 1; h >= 0; --h) out_[from(h)] = h;
    return result;
}

bool flat_edge(const Surface& s, int h, double min_cos) {
    auto normal = [&s](int t) {
        const Triangle& f = s.mesh().triangles[t];
        return cross(s.point(f[1]) - s.point(f[0]), s.point(f[2]) - s.point(f[0]));
    };
    const Vec3 a = normal(h / 3), b = normal(s.twin(h) / 3);
    return dot(a, b) >= min_cos * norm(a) * norm(b);
}

int split_long_edges(Surface* s, double max_length) {
    const int before = s->num_vertices();
    for (;;) {
        std::vector<std::pair<int, int>> long_edges;
        for (int h = 0; h < s->num_half_edges(); ++h)
            if (s->from(h) < s->to(h) && s->length(h) > max_length)
                long_edges.emplace_back(s->from(h), s->to(h));
        if (long_edges.empty()) break;
        s->split_edges(long_edges);
    }
    return s->num_vertices() - before;
}

void insert_midpoints(std::vector<std::vector<int>>& curves, const std::vector<std::array<int, 3>>& split,
                      bool closed) {
    if (split.empty()) return;
    std::map<std::pair<int, int>, int> mid;
    for (const auto& s : split) mid[{std::min(s[0], s[1]), std::max(s[0], s[1])}] = s[2];
    for (std::vector<int>& c : curves) {
        std::vector<int> out;
        out.reserve(c.size());
        for (size_t i = 0; i < c.size(); ++i) {
            out.push_back(c[i]);
            if (!closed && i + 1 == c.size()) break;
            const int a = c[i], b = c[(i + 1) % c.size()];
            auto it = mid.find({std::min(a, b), std::max(a, b)});
            if (it != mid.end()) out.push_back(it->second);
        }
        c = std::move(out);
    }
}

std::vector<int> PathResult::path_to(const Surface& s, int v) const {
    std::vector<int> path{v};
    while (parent_half_edge[v] >= 0) {
        v = s.from(parent_half_edge[v]);
        path.push_back(v);
    }
    std::reverse(path.begin(), path.end());
    return path;
}

PathResult dijkstra(const Surface& s, const PathSearch& q) {
    // The cost of most searches is Builder::cost_near()'s: called directly, not through
    // std::function, it is inlined into the search's inner loop.
    if (!q.cost) return search::run_dijkstra(s, q, [&s](int h) { return s.length(h); });
    if (const NearCost* near = q.cost.target<NearCost>()) return search::run_dijkstra(s, q, *near);
    return search::run_dijkstra(s, q, q.cost);
}

void lower_distances(const Surface& s, const std::vector<int>& sources, const std::vector<char>* blocked,
                     double max_distance, std::vector<double>* distance) {
    std::vector<double>& d = *distance;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (int v : sources)
        if (0.0 < d[v]) {
            d[v] = 0.0;
            heap.push({0.0, v});
        }
    // Only vertices the new sources bring nearer are pushed: a vertex that keeps its distance
    // brings none of its neighbours nearer either (rounding is monotonic).
    while (!heap.empty()) {
        const auto [dv, v] = heap.top();
        heap.pop();
        if (dv > d[v]) continue;  // lowered again since
        const int h0 = s.out_half_edge(v);
        int h = h0;
        do {
            const int x = s.to(h);
            if (!(blocked && (*blocked)[x])) {
                const double nd = dv + s.length(h);
                if (nd < d[x] && nd <= max_distance) {
                    d[x] = nd;
                    heap.push({nd, x});
                }
            }
            h = s.rotate(h);
        } while (h != h0);
    }
}

Vec3 vertex_normal(const Surface& s, int v) {
    const Mesh& m = s.mesh();
    Vec3 n;
    for (int h : s.out_half_edges(v)) {
        const Triangle& t = m.triangles[h / 3];
        n += cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    }
    const double l = norm(n);
    return l > 0 ? n / l : Vec3{0, 0, 1};
}

std::array<Vec3, 2> tangent_frame(const Vec3& n) {
    Vec3 e1 = cross(n, std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
    e1 = e1 / norm(e1);
    return {e1, cross(n, e1)};
}

}  // namespace quadcage::layout::detail

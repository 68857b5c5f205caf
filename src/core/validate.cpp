#include "quadcage/core/validate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <sstream>
#include <unordered_map>

#include "quadcage/core/errors.h"

namespace quadcage {
namespace {

// Supported scale: bounding-box diagonals in [kMinDiagonal, kMaxDiagonal] keep squared lengths,
// areas and their products finite and normal in double precision.
constexpr double kMinDiagonal = 1e-30;
constexpr double kMaxDiagonal = 1e30;
// volume / area^1.5 below this counts as no volume (a flat surface; 0.094 for a sphere, 3.5e-4 for
// a 1 x 1 x 0.001 slab).
constexpr double kMinVolumeRatio = 1e-10;

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    }
    void unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // smallest index is the root: deterministic
    }
};

// One side of an undirected edge: triangle t walks it from `from` to `to`.
struct HalfEdge {
    std::uint64_t key;  // (min vertex, max vertex)
    int t;
    int from, to;
};

std::string fmt_point(const Vec3& p) {
    std::ostringstream s;
    s.precision(6);
    s << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return s.str();
}

std::string plural(long n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The undirected edges of the triangles in `tris`, grouped: runs of equal keys in the returned vector.
std::vector<HalfEdge> sorted_half_edges(const Mesh& mesh, const std::vector<int>& tris) {
    std::vector<HalfEdge> he;
    he.reserve(tris.size() * 3);
    for (int t : tris) {
        const Triangle& f = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3];
            const std::uint64_t lo = static_cast<std::uint64_t>(std::min(a, b));
            const std::uint64_t hi = static_cast<std::uint64_t>(std::max(a, b));
            he.push_back({(lo << 32) | hi, t, a, b});
        }
    }
    std::sort(he.begin(), he.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.key != y.key ? x.key < y.key : x.t < y.t;
    });
    return he;
}

template <class F>
void for_each_edge_group(const std::vector<HalfEdge>& he, F&& f) {
    for (size_t i = 0; i < he.size();) {
        size_t j = i;
        while (j < he.size() && he[j].key == he[i].key) ++j;
        f(i, j);
        i = j;
    }
}

int corner_of(const Mesh& mesh, int t, int v) {
    const Triangle& f = mesh.triangles[t];
    return 3 * t + (f[0] == v ? 0 : (f[1] == v ? 1 : 2));
}

}  // namespace

int minimal_quad_count(int genus) {
    if (genus < 0) return -1;
    if (genus == 0) return 6;
    if (genus == 1) return 4;
    return 10 * genus - 10;
}

bool ValidationReport::quaddable() const {
    for (const ValidationIssue& i : issues)
        if (i.severity == ValidationIssue::Severity::error) return false;
    if (components.empty()) return false;
    return std::all_of(components.begin(), components.end(),
                       [](const ComponentReport& c) { return c.quaddable(); });
}

std::string ValidationReport::error_summary() const {
    std::string out;
    for (const ValidationIssue& i : issues) {
        if (i.severity != ValidationIssue::Severity::error) continue;
        if (!out.empty()) out += "; ";
        out += i.message;
    }
    return out;
}

ValidationReport validate(const Mesh& mesh) {
    ValidationReport r;
    const int n = mesh.num_vertices();
    const int nt = mesh.num_triangles();
    r.vertices_in_file = n;
    r.triangles = nt;
    auto add = [&r](ValidationIssue::Severity s, std::string code, long count, std::string msg) {
        r.issues.push_back({s, std::move(code), count, std::move(msg)});
    };
    const auto E = ValidationIssue::Severity::error;
    const auto W = ValidationIssue::Severity::warning;

    if (nt == 0) {
        add(E, "empty", 0, "the mesh has no triangles");
        return r;
    }

    int first_bad_point = -1;
    for (int v = 0; v < n; ++v)
        if (!is_finite(mesh.points[v])) {
            if (first_bad_point < 0) first_bad_point = v;
            ++r.non_finite_vertices;
        }

    // Triangles whose indices are usable for topology.
    std::vector<int> good;
    good.reserve(nt);
    int first_oob = -1, first_rep = -1;
    for (int t = 0; t < nt; ++t) {
        const Triangle& f = mesh.triangles[t];
        if (f[0] < 0 || f[0] >= n || f[1] < 0 || f[1] >= n || f[2] < 0 || f[2] >= n) {
            if (first_oob < 0) first_oob = t;
            ++r.out_of_range_triangles;
        } else if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
            if (first_rep < 0) first_rep = t;
            ++r.repeated_index_triangles;
        } else {
            good.push_back(t);
        }
    }
    std::vector<char> used(n, 0);
    for (int t : good)
        for (int v : mesh.triangles[t]) used[v] = 1;
    // Vertices named only by triangles with repeated indices still count as used.
    for (int t = 0; t < nt; ++t) {
        const Triangle& f = mesh.triangles[t];
        if (f[0] >= 0 && f[0] < n && f[1] >= 0 && f[1] < n && f[2] >= 0 && f[2] < n)
            for (int v : f) used[v] = 1;
    }
    r.vertices_used = static_cast<int>(std::count(used.begin(), used.end(), 1));
    r.unused_vertices = n - r.vertices_used;
    const BoundingBox box = bounding_box(mesh);
    r.bbox_diagonal = box.diagonal();
    // The pipeline's figures (areas, squared lengths, angles) stay finite only within a sane scale.
    const bool bad_scale = r.non_finite_vertices == 0 &&
                           (!std::isfinite(r.bbox_diagonal) || r.bbox_diagonal > kMaxDiagonal ||
                            (r.bbox_diagonal > 0 && r.bbox_diagonal < kMinDiagonal));
    if (bad_scale) {
        std::ostringstream d;
        d.precision(3);
        d << r.bbox_diagonal;
        add(E, "scale", 1,
            (std::isfinite(r.bbox_diagonal) ? "the bounding-box diagonal " + d.str() + " is outside the supported range "
                                            : std::string("the bounding-box diagonal overflows (coordinates too large to "
                                                          "measure); the supported range is ")) +
                "[1e-30, 1e30]; rescale the mesh (e.g. to unit size) first");
    }

    if (r.non_finite_vertices > 0)
        add(E, "non_finite", r.non_finite_vertices,
            plural(r.non_finite_vertices, "vertex has", "vertices have") +
                " NaN or infinite coordinates (e.g. vertex " + std::to_string(first_bad_point) +
                "); fix or remove them in the source mesh");
    if (r.out_of_range_triangles > 0)
        add(E, "index_out_of_range", r.out_of_range_triangles,
            plural(r.out_of_range_triangles, "triangle refers", "triangles refer") +
                " to vertices that do not exist (e.g. triangle " + std::to_string(first_oob) +
                " = {" + std::to_string(mesh.triangles[first_oob][0]) + ", " +
                std::to_string(mesh.triangles[first_oob][1]) + ", " +
                std::to_string(mesh.triangles[first_oob][2]) + "} with " + std::to_string(n) +
                " vertices); the file is corrupt or truncated");
    if (r.repeated_index_triangles > 0)
        add(E, "repeated_index", r.repeated_index_triangles,
            plural(r.repeated_index_triangles, "triangle names", "triangles name") +
                " the same vertex twice (e.g. triangle " + std::to_string(first_rep) +
                "); remove these degenerate triangles");
    if (r.unused_vertices > 0)
        add(W, "unused_vertices", r.unused_vertices,
            plural(r.unused_vertices, "vertex is", "vertices are") + " used by no triangle (ignored)");

    // Zero-area triangles (relative to the model's size, so units do not matter).
    const double eps_area = 1e-14 * r.bbox_diagonal * r.bbox_diagonal;
    int first_zero = -1;
    if (r.non_finite_vertices == 0 && !bad_scale)
        for (int t : good)
            if (triangle_area(mesh, t) <= eps_area) {
                if (first_zero < 0) first_zero = t;
                ++r.zero_area_triangles;
            }
    if (r.zero_area_triangles > 0)
        add(W, "zero_area", r.zero_area_triangles,
            plural(r.zero_area_triangles, "triangle has", "triangles have") +
                " zero area (e.g. triangle " + std::to_string(first_zero) + " near " +
                fmt_point(mesh.points[mesh.triangles[first_zero][0]]) +
                "); they are kept, but may hurt the parameterization");

    // Duplicate triangles: same vertex set.
    {
        std::vector<std::pair<std::array<int, 3>, int>> keys;
        keys.reserve(good.size());
        for (int t : good) {
            std::array<int, 3> k = mesh.triangles[t];
            std::sort(k.begin(), k.end());
            keys.push_back({k, t});
        }
        std::sort(keys.begin(), keys.end());
        int first_dup = -1;
        for (size_t i = 1; i < keys.size(); ++i)
            if (keys[i].first == keys[i - 1].first) {
                ++r.duplicate_triangles;
                if (first_dup < 0 || keys[i].second < first_dup) first_dup = keys[i].second;
            }
        if (r.duplicate_triangles > 0)
            add(E, "duplicate_triangles", r.duplicate_triangles,
                plural(r.duplicate_triangles, "triangle duplicates", "triangles duplicate") +
                    " another one on the same three vertices (e.g. triangle " +
                    std::to_string(first_dup) + " near " +
                    fmt_point(mesh.points[mesh.triangles[first_dup][0]]) + "); remove the copies");
    }

    // Edges: boundary (1 triangle), manifold (2), non-manifold (more).
    const std::vector<HalfEdge> he = sorted_half_edges(mesh, good);
    UnionFind corners(3 * nt);
    UnionFind boundary_uf(n);
    std::vector<char> boundary_vertex(n, 0);
    std::vector<char> vertex_on_nm_edge(n, 0);
    // Orientation constraints between neighbouring triangles: same = 1 if they walk the edge the same way.
    std::vector<std::array<int, 3>> links;  // {t1, t2, same}
    std::vector<std::uint64_t> nm_edge_keys, boundary_edge_keys, inconsistent_keys;
    int num_edges_total = 0;
    for_each_edge_group(he, [&](size_t i, size_t j) {
        ++num_edges_total;
        const int a = static_cast<int>(he[i].key >> 32), b = static_cast<int>(he[i].key & 0xffffffffu);
        const size_t c = j - i;
        if (c == 1) {
            boundary_edge_keys.push_back(he[i].key);
            boundary_uf.unite(a, b);
            boundary_vertex[a] = boundary_vertex[b] = 1;
        } else if (c == 2) {
            const HalfEdge &x = he[i], &y = he[i + 1];
            corners.unite(corner_of(mesh, x.t, a), corner_of(mesh, y.t, a));
            corners.unite(corner_of(mesh, x.t, b), corner_of(mesh, y.t, b));
            const int same = x.from == y.from ? 1 : 0;
            if (same) inconsistent_keys.push_back(x.key);
            links.push_back({x.t, y.t, same});
        } else {
            nm_edge_keys.push_back(he[i].key);
            vertex_on_nm_edge[a] = vertex_on_nm_edge[b] = 1;
        }
    });
    r.non_manifold_edges = static_cast<int>(nm_edge_keys.size());
    r.boundary_edges = static_cast<int>(boundary_edge_keys.size());
    r.inconsistently_oriented_edges = static_cast<int>(inconsistent_keys.size());

    // Vertex fans: the corners at a vertex joined through its manifold edges must form one group.
    std::vector<int> fan_root(n, -1);
    std::vector<char> nm_vertex(n, 0);
    for (int t : good)
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles[t][k];
            const int root = corners.find(3 * t + k);
            if (fan_root[v] < 0) fan_root[v] = root;
            else if (fan_root[v] != root) nm_vertex[v] = 1;
        }
    int first_nm_vertex = -1;
    for (int v = 0; v < n; ++v)
        if (nm_vertex[v]) {
            if (first_nm_vertex < 0) first_nm_vertex = v;
            ++r.non_manifold_vertices;
        }

    // Components through shared vertices.
    UnionFind vuf(n);
    for (int t : good) {
        vuf.unite(mesh.triangles[t][0], mesh.triangles[t][1]);
        vuf.unite(mesh.triangles[t][0], mesh.triangles[t][2]);
    }
    std::unordered_map<int, int> comp_of_root;
    std::vector<int> tri_comp(nt, -1);
    for (int t : good) {  // `good` is increasing, so components come in order of first triangle
        const int root = vuf.find(mesh.triangles[t][0]);
        auto it = comp_of_root.find(root);
        if (it == comp_of_root.end()) {
            it = comp_of_root.emplace(root, static_cast<int>(r.components.size())).first;
            r.components.emplace_back();
            r.components.back().first_triangle = t;
        }
        tri_comp[t] = it->second;
        ComponentReport& c = r.components[it->second];
        ++c.triangles;
        c.area += r.non_finite_vertices == 0 && !bad_scale ? triangle_area(mesh, t) : 0.0;
    }
    auto comp_of_vertex = [&](int v) { return comp_of_root.at(vuf.find(v)); };
    for (int v = 0; v < n; ++v) {
        if (fan_root[v] < 0) continue;  // unused (or only in rejected triangles)
        ComponentReport& c = r.components[comp_of_vertex(v)];
        ++c.vertices;
        if (nm_vertex[v]) ++c.non_manifold_vertices;
    }
    for_each_edge_group(he, [&](size_t i, size_t) { ++r.components[tri_comp[he[i].t]].edges; });
    for (std::uint64_t k : boundary_edge_keys)
        ++r.components[comp_of_vertex(static_cast<int>(k >> 32))].boundary_edges;
    for (std::uint64_t k : nm_edge_keys)
        ++r.components[comp_of_vertex(static_cast<int>(k >> 32))].non_manifold_edges;
    {
        std::vector<char> seen_root(n, 0);
        for (int v = 0; v < n; ++v)
            if (boundary_vertex[v]) {
                const int root = boundary_uf.find(v);
                if (!seen_root[root]) {
                    seen_root[root] = 1;
                    ++r.components[comp_of_vertex(v)].boundary_loops;
                    ++r.boundary_loops;
                }
            }
    }

    // Orientation: propagate a flip bit over manifold edges; a contradiction means non-orientable.
    std::vector<std::vector<std::pair<int, int>>> adj(nt);
    for (const auto& l : links) {
        adj[l[0]].push_back({l[1], l[2]});
        adj[l[1]].push_back({l[0], l[2]});
    }
    std::vector<signed char> flip(nt, -1);
    std::vector<char> comp_orientable(r.components.size(), 1);
    for (int s : good) {
        if (flip[s] >= 0) continue;
        flip[s] = 0;
        std::queue<int> q;
        q.push(s);
        while (!q.empty()) {
            const int t = q.front();
            q.pop();
            for (auto [u, same] : adj[t]) {
                const signed char want = static_cast<signed char>(flip[t] ^ same);
                if (flip[u] < 0) {
                    flip[u] = want;
                    q.push(u);
                } else if (flip[u] != want) {
                    comp_orientable[tri_comp[t]] = 0;
                }
            }
        }
    }
    // Enclosed volume of each closed orientable component (divergence theorem, triangles turned to
    // agree), in coordinates centred on the bounding box so that the sum does not cancel badly.
    std::vector<double> comp_volume(r.components.size(), 0.0);
    if (r.non_finite_vertices == 0 && !bad_scale) {
        const Vec3 centre = (box.min + box.max) * 0.5;
        for (int t : good) {
            const Triangle& f = mesh.triangles[t];
            const Vec3 a = mesh.points[f[0]] - centre, b = mesh.points[f[1]] - centre, c = mesh.points[f[2]] - centre;
            const double v = dot(a, cross(b, c)) / 6.0;
            comp_volume[tri_comp[t]] += flip[t] == 1 ? -v : v;
        }
    }
    std::vector<int> comp_inconsistent(r.components.size(), 0);
    for (std::uint64_t k : inconsistent_keys) ++comp_inconsistent[comp_of_vertex(static_cast<int>(k >> 32))];

    for (size_t ci = 0; ci < r.components.size(); ++ci) {
        ComponentReport& c = r.components[ci];
        c.closed = c.boundary_edges == 0 && c.non_manifold_edges == 0;
        c.manifold = c.non_manifold_edges == 0 && c.non_manifold_vertices == 0;
        c.orientable = c.manifold && comp_orientable[ci];
        c.consistently_oriented = comp_inconsistent[ci] == 0 && c.orientable;
        c.euler_characteristic = c.vertices - c.edges + c.triangles;
        const int twice = 2 - c.euler_characteristic - c.boundary_loops;
        if (c.manifold && c.orientable && twice >= 0 && twice % 2 == 0) c.genus = twice / 2;
        if (c.closed && c.manifold && c.orientable && c.genus >= 0) c.minimal_quads = minimal_quad_count(c.genus);
        if (c.closed && c.orientable) c.volume = std::fabs(comp_volume[ci]);
    }

    // Degenerate geometry: a closed surface of zero area or enclosing no volume (all its vertices
    // at one point, on a line or in a plane) has no quad layout. Both are measured relative to the
    // component's own size (volume / area^1.5, which is 0.094 for a sphere), so units do not matter.
    if (r.non_finite_vertices == 0 && !bad_scale) {
        long degenerate = 0;
        std::string example;
        for (size_t ci = 0; ci < r.components.size(); ++ci) {
            ComponentReport& c = r.components[ci];
            if (!c.quaddable()) continue;
            const double eps = 1e-14 * r.bbox_diagonal * r.bbox_diagonal;
            const bool flat_area = !(c.area > eps);
            const bool flat_volume = !flat_area && !(c.volume > kMinVolumeRatio * c.area * std::sqrt(c.area));
            if (!flat_area && !flat_volume) continue;
            c.degenerate = true;
            if (degenerate++ == 0)
                example = "component " + std::to_string(ci) + (flat_area ? " has zero area (all its vertices coincide or lie on a line)"
                                                                        : " encloses no volume (its vertices lie in a plane, or nearly)");
        }
        if (degenerate > 0)
            add(E, "degenerate", degenerate,
                plural(degenerate, "closed component is", "closed components are") + " degenerate: " + example +
                    "; a cage needs a surface that encloses a solid");
    }

    // Errors, with an example each.
    if (r.non_manifold_edges > 0) {
        const int a = static_cast<int>(nm_edge_keys[0] >> 32);
        const int b = static_cast<int>(nm_edge_keys[0] & 0xffffffffu);
        add(E, "non_manifold_edge", r.non_manifold_edges,
            plural(r.non_manifold_edges, "edge is", "edges are") +
                " shared by more than two triangles (non-manifold; e.g. edge " + std::to_string(a) +
                "-" + std::to_string(b) + " at " + fmt_point(mesh.points[a]) +
                "); make the surface manifold first (e.g. split it where sheets meet)");
    }
    if (r.non_manifold_vertices > 0)
        add(E, "non_manifold_vertex", r.non_manifold_vertices,
            plural(r.non_manifold_vertices, "vertex joins", "vertices join") +
                " separate fans of triangles (pinched, non-manifold; e.g. vertex " +
                std::to_string(first_nm_vertex) + " at " + fmt_point(mesh.points[first_nm_vertex]) +
                "); duplicate the vertex per fan or repair the mesh");
    if (r.boundary_edges > 0) {
        const int a = static_cast<int>(boundary_edge_keys[0] >> 32);
        // Vertices at exactly the position of another one: a file that stores every triangle with
        // its own corners (an unwelded "triangle soup") looks open although its surface is closed.
        std::vector<int> order;
        for (int v = 0; v < n && r.non_finite_vertices == 0; ++v)  // NaN breaks the sort's ordering
            if (used[v]) order.push_back(v);
        auto less = [&](int x, int y) {
            const Vec3 &p = mesh.points[x], &q = mesh.points[y];
            return p.x != q.x ? p.x < q.x : (p.y != q.y ? p.y < q.y : p.z < q.z);
        };
        std::sort(order.begin(), order.end(), less);
        long coincident = 0;
        for (size_t i = 1; i < order.size(); ++i)
            if (!less(order[i - 1], order[i]) && !less(order[i], order[i - 1])) ++coincident;
        std::string weld;
        if (coincident > 0)
            weld = "; " + plural(coincident, "vertex lies", "vertices lie") +
                   " exactly on another vertex: if the file stores each triangle with its own corners (an unwelded "
                   "triangle soup), merge coincident vertices first (e.g. MeshLab's Merge Close Vertices, or save "
                   "it as STL, which quadcage welds)";
        add(E, "boundary", r.boundary_edges,
            "the surface is open: " + plural(r.boundary_edges, "boundary edge", "boundary edges") +
                " in " + plural(r.boundary_loops, "loop", "loops") + " (e.g. at vertex " +
                std::to_string(a) + " " + fmt_point(mesh.points[a]) +
                "); a cage needs a closed surface: fill the holes first" + weld);
    }
    const long non_orientable = std::count(comp_orientable.begin(), comp_orientable.end(), 0);
    if (r.non_manifold_edges == 0 && r.non_manifold_vertices == 0 && non_orientable > 0)
        add(E, "non_orientable", non_orientable,
            plural(non_orientable, "component is", "components are") +
                " non-orientable (like a Moebius strip or Klein bottle); quadcage needs an orientable surface");
    if (r.inconsistently_oriented_edges > 0 && non_orientable == 0) {
        const int a = static_cast<int>(inconsistent_keys[0] >> 32);
        add(W, "inconsistent_orientation", r.inconsistently_oriented_edges,
            "triangles are not consistently oriented (" +
                plural(r.inconsistently_oriented_edges, "edge is", "edges are") +
                " walked the same way by both its triangles, e.g. at vertex " + std::to_string(a) +
                "); the surface is orientable, so later stages re-orient it");
    } else if (r.inconsistently_oriented_edges > 0 && r.non_manifold_edges > 0) {
        add(W, "inconsistent_orientation", r.inconsistently_oriented_edges,
            "triangles are not consistently oriented (" +
                plural(r.inconsistently_oriented_edges, "edge is", "edges are") +
                " walked the same way by both its triangles)");
    }
    if (r.components.size() > 1)
        add(W, "components", static_cast<long>(r.components.size()),
            "the mesh has " + std::to_string(r.components.size()) +
                " connected components; each gets its own cage");

    std::stable_sort(r.issues.begin(), r.issues.end(), [](const ValidationIssue& a, const ValidationIssue& b) {
        return a.severity == ValidationIssue::Severity::error && b.severity != ValidationIssue::Severity::error;
    });
    return r;
}

ValidationReport require_quaddable(const Mesh& mesh, const std::string& what) {
    ValidationReport r = validate(mesh);
    if (!r.quaddable()) {
        std::string why = r.error_summary();
        if (why.empty()) why = "not a closed, manifold, orientable surface";
        throw InvalidInput(what + ": cannot be quadded: " + why);
    }
    return r;
}

int orient_outward(Mesh& mesh) {
    const ValidationReport r = validate(mesh);
    for (const ComponentReport& c : r.components)
        if (!c.manifold || !c.orientable)
            throw InvalidInput("orient_outward: the mesh is not manifold and orientable: " + r.error_summary());
    const int nt = mesh.num_triangles();
    std::vector<int> all(nt);
    std::iota(all.begin(), all.end(), 0);
    const std::vector<HalfEdge> he = sorted_half_edges(mesh, all);
    std::vector<std::vector<std::pair<int, int>>> adj(nt);
    for_each_edge_group(he, [&](size_t i, size_t j) {
        if (j - i != 2) return;
        const int same = he[i].from == he[i + 1].from ? 1 : 0;
        adj[he[i].t].push_back({he[i + 1].t, same});
        adj[he[i + 1].t].push_back({he[i].t, same});
    });
    std::vector<signed char> flip(nt, -1);
    int flipped = 0;
    for (int s = 0; s < nt; ++s) {
        if (flip[s] >= 0) continue;
        std::vector<int> comp{s};
        flip[s] = 0;
        for (size_t k = 0; k < comp.size(); ++k)
            for (auto [u, same] : adj[comp[k]])
                if (flip[u] < 0) {
                    flip[u] = static_cast<signed char>(flip[comp[k]] ^ same);
                    comp.push_back(u);
                }
        // Signed volume after the consistent flips decides outward vs inward.
        double volume = 0;
        for (int t : comp) {
            Triangle f = mesh.triangles[t];
            if (flip[t]) std::swap(f[1], f[2]);
            volume += dot(mesh.points[f[0]], cross(mesh.points[f[1]], mesh.points[f[2]]));
        }
        const bool invert_all = volume < 0;
        for (int t : comp)
            if ((flip[t] != 0) != invert_all) {
                std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
                ++flipped;
            }
    }
    return flipped;
}

std::vector<int> remove_unused_vertices(Mesh& mesh) {
    const int n = mesh.num_vertices();
    std::vector<int> map(n, -1);
    for (const Triangle& t : mesh.triangles)
        for (int v : t) {
            QC_CHECK(v >= 0 && v < n, "remove_unused_vertices: index out of range");
            map[v] = 0;
        }
    std::vector<Vec3> kept;
    for (int v = 0; v < n; ++v)  // keeps the original relative order of vertices
        if (map[v] == 0) {
            map[v] = static_cast<int>(kept.size());
            kept.push_back(mesh.points[v]);
        }
    for (Triangle& t : mesh.triangles)
        for (int& v : t) v = map[v];
    mesh.points = std::move(kept);
    return map;
}

std::vector<Mesh> split_components(const Mesh& mesh, std::vector<std::vector<int>>* vertex_maps) {
    const int n = mesh.num_vertices();
    UnionFind vuf(n);
    for (const Triangle& t : mesh.triangles) {
        QC_CHECK(t[0] >= 0 && t[0] < n && t[1] >= 0 && t[1] < n && t[2] >= 0 && t[2] < n,
                 "split_components: index out of range");
        vuf.unite(t[0], t[1]);
        vuf.unite(t[0], t[2]);
    }
    // Components in order of their first triangle; vertices keep their relative order.
    std::unordered_map<int, int> comp_of_root;
    for (const Triangle& t : mesh.triangles) comp_of_root.emplace(vuf.find(t[0]), static_cast<int>(comp_of_root.size()));
    std::vector<Mesh> out(comp_of_root.size());
    std::vector<std::vector<int>> maps(comp_of_root.size());
    std::vector<char> used(n, 0);
    for (const Triangle& t : mesh.triangles)
        for (int v : t) used[v] = 1;
    std::vector<int> local(n, -1);
    for (int v = 0; v < n; ++v)
        if (used[v]) {
            const int c = comp_of_root.at(vuf.find(v));
            local[v] = out[c].num_vertices();
            out[c].points.push_back(mesh.points[v]);
            maps[c].push_back(v);
        }
    for (const Triangle& t : mesh.triangles)
        out[comp_of_root.at(vuf.find(t[0]))].triangles.push_back({local[t[0]], local[t[1]], local[t[2]]});
    if (vertex_maps) *vertex_maps = std::move(maps);
    return out;
}

}  // namespace quadcage

namespace quadcage {

PreparedMesh prepare_for_quadding(const Mesh& mesh, const std::string& what) {
    PreparedMesh out;
    out.report = require_quaddable(mesh, what);
    out.components = split_components(mesh, &out.vertex_maps);
    for (Mesh& c : out.components) {
        const ValidationReport r = validate(c);
        if (!r.components[0].consistently_oriented) out.flipped_triangles += orient_outward(c);
    }
    return out;
}

}  // namespace quadcage

#include "quadcage/core/mesh.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace quadcage {

double triangle_area(const Mesh& mesh, int t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.points[tri[0]];
    return 0.5 * norm(cross(mesh.points[tri[1]] - a, mesh.points[tri[2]] - a));
}

double surface_area(const Mesh& mesh) {
    double sum = 0;
    for (int t = 0; t < mesh.num_triangles(); ++t) sum += triangle_area(mesh, t);
    return sum;
}

double folded_area_fraction(const Mesh& mesh) {
    const int nt = mesh.num_triangles();
    std::vector<Vec3> normal(nt);  // unit, or zero for a degenerate triangle
    double total = 0;
    for (int t = 0; t < nt; ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vec3& a = mesh.points[tri[0]];
        const Vec3 n = cross(mesh.points[tri[1]] - a, mesh.points[tri[2]] - a);
        const double len = norm(n);
        total += len / 2;
        if (len > 0) normal[t] = n / len;
    }
    if (!(total > 0)) return 0;
    // Each edge once per triangle side, as (smaller vertex, larger vertex, triangle); sorted, the
    // two sides of an edge used twice are neighbours.
    struct Side {
        int a, b, t;
        bool operator<(const Side& o) const { return a != o.a ? a < o.a : b != o.b ? b < o.b : t < o.t; }
    };
    std::vector<Side> sides;
    sides.reserve(3 * static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const int u = mesh.triangles[t][k], v = mesh.triangles[t][(k + 1) % 3];
            sides.push_back({std::min(u, v), std::max(u, v), t});
        }
    std::sort(sides.begin(), sides.end());
    std::vector<char> folded(nt, 0);
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        while (j < sides.size() && sides[j].a == sides[i].a && sides[j].b == sides[i].b) ++j;
        if (j - i == 2 && dot(normal[sides[i].t], normal[sides[i + 1].t]) < 0)
            folded[sides[i].t] = folded[sides[i + 1].t] = 1;
        i = j;
    }
    double on_folds = 0;
    for (int t = 0; t < nt; ++t)
        if (folded[t]) on_folds += triangle_area(mesh, t);
    return on_folds / total;
}

BoundingBox bounding_box(const Mesh& mesh) {
    const double inf = std::numeric_limits<double>::infinity();
    BoundingBox box{{inf, inf, inf}, {-inf, -inf, -inf}};
    auto grow = [&box](const Vec3& p) {
        for (int k = 0; k < 3; ++k) {
            if (p[k] < box.min[k]) box.min[k] = p[k];
            if (p[k] > box.max[k]) box.max[k] = p[k];
        }
    };
    const int n = mesh.num_vertices();
    bool any = false;
    for (const Triangle& t : mesh.triangles)
        for (int v : t)
            if (v >= 0 && v < n) { grow(mesh.points[v]); any = true; }
    if (!any)
        for (const Vec3& p : mesh.points) grow(p);
    if (mesh.points.empty()) box = BoundingBox{};
    return box;
}

Mesh subdivide_midpoint(const Mesh& mesh) {
    Mesh out;
    out.points = mesh.points;
    out.triangles.reserve(mesh.triangles.size() * 4);
    std::unordered_map<std::uint64_t, int> mid;
    mid.reserve(mesh.triangles.size() * 2);
    auto midpoint = [&](int a, int b) {
        const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
        auto [it, fresh] = mid.emplace(key, out.num_vertices());
        if (fresh) out.points.push_back((mesh.points[a] + mesh.points[b]) * 0.5);
        return it->second;
    };
    for (const Triangle& t : mesh.triangles) {
        const int m01 = midpoint(t[0], t[1]), m12 = midpoint(t[1], t[2]), m20 = midpoint(t[2], t[0]);
        out.triangles.push_back({t[0], m01, m20});
        out.triangles.push_back({m01, t[1], m12});
        out.triangles.push_back({m20, m12, t[2]});
        out.triangles.push_back({m01, m12, m20});
    }
    return out;
}

}  // namespace quadcage

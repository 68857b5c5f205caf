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

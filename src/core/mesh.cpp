#include "quadcage/core/mesh.h"

#include <limits>

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

}  // namespace quadcage

#include "detail/sampling.h"

#include <algorithm>

#include "quadcage/core/errors.h"

namespace quadcage::fit::detail {

std::vector<MeshSample> sample_by_area(const Mesh& mesh, int count, std::uint64_t seed) {
    std::vector<double> cumulative(mesh.triangles.size());
    double total = 0;
    for (int t = 0; t < mesh.num_triangles(); ++t) cumulative[t] = total += triangle_area(mesh, t);
    QC_CHECK(total > 0, "sample_by_area: the mesh has no area");
    Rng rng(seed);
    std::vector<MeshSample> out(std::max(0, count));
    for (MeshSample& s : out) {
        const double target = rng.uniform() * total;
        const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
        s.triangle = static_cast<int>(std::min<std::ptrdiff_t>(it - cumulative.begin(), mesh.num_triangles() - 1));
        // Uniform on the triangle: sqrt(r1) picks the distance from the first corner.
        const double r = std::sqrt(rng.uniform()), r2 = rng.uniform();
        s.bary = {1 - r, r * (1 - r2), r * r2};
        const Triangle& tri = mesh.triangles[s.triangle];
        s.point = mesh.points[tri[0]] * s.bary[0] + mesh.points[tri[1]] * s.bary[1] + mesh.points[tri[2]] * s.bary[2];
    }
    return out;
}

std::vector<MeshSample> sample_vertices(const Mesh& mesh) {
    std::vector<MeshSample> by_vertex(mesh.points.size());
    for (int t = 0; t < mesh.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            MeshSample& s = by_vertex[mesh.triangles[t][k]];
            if (s.triangle >= 0) continue;
            s.triangle = t;
            s.bary = {0, 0, 0};
            s.bary[k] = 1;
            s.point = mesh.points[mesh.triangles[t][k]];
        }
    std::vector<MeshSample> out;
    out.reserve(by_vertex.size());
    for (const MeshSample& s : by_vertex)
        if (s.triangle >= 0) out.push_back(s);
    return out;
}

}  // namespace quadcage::fit::detail

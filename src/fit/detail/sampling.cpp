#include "detail/sampling.h"

#include <algorithm>

#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::fit::detail {

std::vector<MeshSample> sample_by_area(const Mesh& mesh, int count, std::uint64_t seed, int threads) {
    const int nt = mesh.num_triangles();
    std::vector<double> cumulative(nt);
    parallel_for(nt, threads, [&](int t) { cumulative[t] = triangle_area(mesh, t); });
    double total = 0;
    for (double& a : cumulative) a = total += a;  // summed in triangle order, as one loop would
    QC_CHECK(total > 0, "sample_by_area: the mesh has no area");
    // The generator's draws in their order (three per sample), then each sample from its own.
    Rng rng(seed);
    const int n = std::max(0, count);
    std::vector<std::array<double, 3>> draws(n);
    for (auto& d : draws)
        for (double& x : d) x = rng.uniform();
    std::vector<MeshSample> out(n);
    parallel_for(n, threads, [&](int i) {
        MeshSample& s = out[i];
        const double target = draws[i][0] * total;
        const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
        s.triangle = static_cast<int>(std::min<std::ptrdiff_t>(it - cumulative.begin(), nt - 1));
        // Uniform on the triangle: sqrt(r1) picks the distance from the first corner.
        const double r = std::sqrt(draws[i][1]), r2 = draws[i][2];
        s.bary = {1 - r, r * (1 - r2), r * r2};
        const Triangle& tri = mesh.triangles[s.triangle];
        s.point = mesh.points[tri[0]] * s.bary[0] + mesh.points[tri[1]] * s.bary[1] + mesh.points[tri[2]] * s.bary[2];
    });
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

// The fit's deterministic mesh sampling (src/fit/detail/sampling.h).

#include "detail/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "quadcage/core/shapes.h"

namespace quadcage::fit::detail {
namespace {

// The sampler as one loop: each sample's three draws in turn, then its triangle and point.
std::vector<MeshSample> sequential_reference(const Mesh& mesh, int count, std::uint64_t seed) {
    std::vector<double> cumulative(mesh.triangles.size());
    double total = 0;
    for (int t = 0; t < mesh.num_triangles(); ++t) cumulative[t] = total += triangle_area(mesh, t);
    Rng rng(seed);
    std::vector<MeshSample> out(count);
    for (MeshSample& s : out) {
        const double target = rng.uniform() * total;
        const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
        s.triangle =
            static_cast<int>(std::min<std::ptrdiff_t>(it - cumulative.begin(), mesh.num_triangles() - 1));
        const double r = std::sqrt(rng.uniform()), r2 = rng.uniform();
        s.bary = {1 - r, r * (1 - r2), r * r2};
        const Triangle& tri = mesh.triangles[s.triangle];
        s.point = mesh.points[tri[0]] * s.bary[0] + mesh.points[tri[1]] * s.bary[1] +
                  mesh.points[tri[2]] * s.bary[2];
    }
    return out;
}

TEST(FitSampling, SampleByAreaIsTheSameBitsOnAnyThreadCount) {
    const Mesh mesh = shapes::torus(40, 24);
    const std::vector<MeshSample> expected = sequential_reference(mesh, 5000, 17);
    for (int threads : {1, 2, 3, 0}) {
        const std::vector<MeshSample> got = sample_by_area(mesh, 5000, 17, threads);
        ASSERT_EQ(got.size(), expected.size());
        for (size_t i = 0; i < got.size(); ++i) {
            EXPECT_EQ(got[i].triangle, expected[i].triangle) << "sample " << i << ", threads " << threads;
            EXPECT_EQ(got[i].bary, expected[i].bary);
            EXPECT_EQ(got[i].point, expected[i].point);
        }
    }
    EXPECT_TRUE(sample_by_area(mesh, 0, 17, 2).empty());
}

TEST(FitSampling, SampleByAreaRejectsAMeshWithoutArea) {
    Mesh flat = shapes::icosphere(1);
    for (Vec3& p : flat.points) p = Vec3{};
    EXPECT_ANY_THROW(sample_by_area(flat, 10, 1, 2));
}

}  // namespace
}  // namespace quadcage::fit::detail

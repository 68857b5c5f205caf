// The level fields the layout's constructions follow (pieces.cpp): ratio_across() of a cycle and
// area_quantiles(), on a round torus whose meridians and halves are known.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"

namespace quadcage::layout::detail {
namespace {

constexpr int kMajor = 32, kMinor = 16;  // shapes::torus(): vertex (i, j) is i * kMinor + j

int id(int i, int j) {
    return ((i + kMajor) % kMajor) * kMinor + (j + kMinor) % kMinor;
}

Cycle meridian(int i) {
    Cycle c;
    for (int j = 0; j < kMinor; ++j) c.push_back(id(i, j));
    return c;
}

TEST(PiecesRatioAcross, RunsFromOneSideOfAMeridianToTheOther) {
    const Surface s(shapes::torus(kMajor, kMinor));
    const std::vector<double> u = ratio_across(s, meridian(0));
    for (int j = 0; j < kMinor; ++j) {
        EXPECT_FALSE(u[id(0, j)] < kInf) << "on the cycle";
        // Beside the cycle on its two sides: near 0 and near 1, one on each side.
        const double before = u[id(-1, j)], after = u[id(1, j)];
        EXPECT_LT(std::min(before, after), 0.1);
        EXPECT_GT(std::max(before, after), 0.9);
        EXPECT_NEAR(before + after, 1.0, 1e-9);  // the torus is symmetric about the meridian
        // Half-way round the major circle the two distances are about equal (edge paths on a
        // grid triangulated one way are not symmetric: up to 0.02 off).
        EXPECT_NEAR(u[id(kMajor / 2, j)], 0.5, 0.03);
    }
    for (int v = 0; v < s.num_vertices(); ++v)
        if (u[v] < kInf) {
            EXPECT_GE(u[v], 0.0);
            EXPECT_LE(u[v], 1.0);
        }
}

TEST(PiecesAreaQuantiles, LevelOneHalfHalvesTheArea) {
    const Surface s(shapes::torus(kMajor, kMinor));
    const std::vector<double> u = ratio_across(s, meridian(0));
    const std::vector<double> q = area_quantiles(s, u);
    ASSERT_EQ(q.size(), u.size());
    for (int a = 0; a < s.num_vertices(); ++a) {
        EXPECT_EQ(q[a] < kInf, u[a] < kInf) << "+inf exactly where u is";
        if (!(q[a] < kInf)) continue;
        EXPECT_GE(q[a], 0.0);
        EXPECT_LE(q[a], 1.0);
        for (int b : {id(3, 5), id(17, 2), id(29, 11)})  // monotone in u
            if (u[a] < u[b]) EXPECT_LE(q[a], q[b]);
    }
    double below = 0, total = 0;
    for (int t = 0; t < s.mesh().num_triangles(); ++t) {
        const auto& f = s.mesh().triangles[t];
        const double mean = (q[f[0]] + q[f[1]] + q[f[2]]) / 3;
        if (!(mean < kInf)) continue;
        const double area = triangle_area(s.mesh(), t);
        total += area;
        if (mean < 0.5) below += area;
    }
    EXPECT_NEAR(below / total, 0.5, 0.05);
    // area_level() gives the same level of u.
    const double level = area_level(s, u, std::vector<char>(s.mesh().num_triangles(), 1), 0.5);
    EXPECT_NEAR(level, 0.5, 0.05);
}

}  // namespace
}  // namespace quadcage::layout::detail

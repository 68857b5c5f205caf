// The level fields the layout's constructions follow (pieces.cpp): harmonic_across() of a cycle and
// area_quantiles(), on a round torus whose meridians and halves are known, and on a big body with a
// small handle, where a field with an extremum beside the handle's foot misled the torus layout.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/orthogonal_system.h"

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

TEST(PiecesHarmonicAcross, RunsFromOneSideOfAMeridianToTheOther) {
    const Surface s(shapes::torus(kMajor, kMinor));
    const std::vector<double> u = harmonic_across(s, meridian(0));
    for (int j = 0; j < kMinor; ++j) {
        EXPECT_FALSE(u[id(0, j)] < kInf) << "on the cycle";
        // Beside the cycle on its two sides: one step (of 32 round the major circle) from 0 and 1.
        const double before = u[id(-1, j)], after = u[id(1, j)];
        EXPECT_LT(std::min(before, after), 0.1);
        EXPECT_GT(std::max(before, after), 0.9);
        EXPECT_NEAR(before + after, 1.0, 0.02);        // the torus is nearly symmetric about the meridian
        EXPECT_NEAR(u[id(kMajor / 2, j)], 0.5, 0.02);  // half-way round
    }
    for (int v = 0; v < s.num_vertices(); ++v)
        if (u[v] < kInf) {
            EXPECT_GE(u[v], 0.0);
            EXPECT_LE(u[v], 1.0);
        }
}

// The number of pieces of the vertices `in` (edge-connected among themselves).
int components(const Surface& s, const std::vector<char>& in) {
    std::vector<char> seen(in.size(), 0);
    int count = 0;
    for (int v = 0; v < s.num_vertices(); ++v) {
        if (!in[v] || seen[v]) continue;
        ++count;
        std::vector<int> stack{v};
        seen[v] = 1;
        while (!stack.empty()) {
            const int x = stack.back();
            stack.pop_back();
            for (int y : s.ring(x))
                if (in[y] && !seen[y]) {
                    seen[y] = 1;
                    stack.push_back(y);
                }
        }
    }
    return count;
}

// A big body with one small handle (`generate handles -g 1 -r 4`). Across either cycle of its
// orthogonal system the field has no extremum off the cycle (each vertex lies between its
// neighbours' values), so the area-halving level leaves one piece on each side: one closed curve
// parallel to the cycle. The distance ratio it replaced dipped beside the handle's foot, where a
// second piece closed round the foot, and the torus layout's second meridian took that short loop
// (patch area max/min 13.4).
TEST(PiecesHarmonicAcross, HasNoExtremumOnABodyWithASmallHandle) {
    shapes::HandleBodyOptions o;
    o.handles = 1;
    o.resolution = 4;
    const OrthogonalSystem system = build_orthogonal_system(shapes::body_with_handles(o));
    ASSERT_EQ(system.cycles.size(), 2u);
    const Surface s(system.mesh);
    for (const Cycle& c : system.cycles) {
        const std::vector<double> u = harmonic_across(s, c);
        for (int v = 0; v < s.num_vertices(); ++v) {
            if (!(u[v] < kInf)) continue;
            double lo = kInf, hi = -kInf;
            for (int y : s.ring(v)) {
                // A neighbour on the cycle counts as 0 or 1, whichever side v is on: both bound u.
                lo = std::min(lo, u[y] < kInf ? u[y] : 0.0);
                hi = std::max(hi, u[y] < kInf ? u[y] : 1.0);
            }
            EXPECT_GE(u[v], lo - 1e-12) << v;
            EXPECT_LE(u[v], hi + 1e-12) << v;
        }
        const std::vector<double> q = area_quantiles(s, u);
        std::vector<char> below(s.num_vertices(), 0), above(s.num_vertices(), 0);
        for (int v = 0; v < s.num_vertices(); ++v)
            if (q[v] < kInf) (q[v] < 0.5 ? below : above)[v] = 1;
        EXPECT_EQ(components(s, below), 1);
        EXPECT_EQ(components(s, above), 1);
    }
}

TEST(PiecesAreaQuantiles, LevelOneHalfHalvesTheArea) {
    const Surface s(shapes::torus(kMajor, kMinor));
    const std::vector<double> u = harmonic_across(s, meridian(0));
    const std::vector<double> q = area_quantiles(s, u);
    ASSERT_EQ(q.size(), u.size());
    for (int a = 0; a < s.num_vertices(); ++a) {
        EXPECT_EQ(q[a] < kInf, u[a] < kInf) << "+inf exactly where u is";
        if (!(q[a] < kInf)) continue;
        EXPECT_GE(q[a], 0.0);
        EXPECT_LE(q[a], 1.0);
        for (int b : {id(3, 5), id(17, 2), id(29, 11)})  // monotone in u
            if (u[a] < u[b]) {
                EXPECT_LE(q[a], q[b]);
            }
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

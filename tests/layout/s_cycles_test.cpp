// The S-cycles and the pieces they cut (handle_loop_s_cycles.cpp, pieces.cpp): the Euler
// characteristic that tells an annulus from a torus with two holes.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"

namespace quadcage::layout::detail {
namespace {

TEST(SCyclesPieceEuler, TellsAnAnnulusFromATorusWithTwoHoles) {
    // shapes::torus(32, 16) has two triangles per grid square, square (i, j) = triangles
    // 2 (16 i + j) and the next. Cut along two meridians: two annuli.
    const Mesh torus = shapes::torus(32, 16);
    const Surface s(torus);
    std::vector<int> label(torus.num_triangles());
    for (int t = 0; t < torus.num_triangles(); ++t) label[t] = t / 2 / 16 < 16 ? 0 : 1;
    EXPECT_EQ(piece_euler_characteristic(s, label, 0), 0);
    EXPECT_EQ(piece_euler_characteristic(s, label, 1), 0);
    // Two squares cut out as pieces of their own: disks, and the rest a torus with two holes (two
    // boundary loops, as an annulus has, but a handle in it).
    std::fill(label.begin(), label.end(), 0);
    for (int t : {0, 1}) label[t] = 1;
    for (int t : {2 * (16 * 16 + 8), 2 * (16 * 16 + 8) + 1}) label[t] = 2;
    EXPECT_EQ(piece_euler_characteristic(s, label, 1), 1);
    EXPECT_EQ(piece_euler_characteristic(s, label, 2), 1);
    EXPECT_EQ(piece_euler_characteristic(s, label, 0), -2);
    const Mesh sphere = shapes::icosphere(1);
    EXPECT_EQ(piece_euler_characteristic(Surface(sphere), std::vector<int>(sphere.num_triangles(), 0), 0), 2);
}

}  // namespace
}  // namespace quadcage::layout::detail

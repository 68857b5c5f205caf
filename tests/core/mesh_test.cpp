#include "quadcage/core/mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "quadcage/core/shapes.h"

namespace quadcage {
namespace {

/// A strip of three unit squares (six triangles) along x, the middle one laid at the angle `fold`
/// (radians) to the first, the last back at the first's direction: a Z when fold > 90 degrees.
Mesh folded_strip(double fold) {
    const double c = std::cos(fold), s = std::sin(fold);
    // Cross-section points along the strip: 0, 1, 1 + (c, s), 2 + (c, s).
    const double xs[4] = {0, 1, 1 + c, 2 + c}, zs[4] = {0, 0, s, s};
    Mesh m;
    for (int i = 0; i < 4; ++i) m.points.push_back({xs[i], 0, zs[i]}), m.points.push_back({xs[i], 1, zs[i]});
    for (int i = 0; i < 3; ++i) {
        const int a = 2 * i, b = 2 * i + 1, d = 2 * i + 2, e = 2 * i + 3;
        m.triangles.push_back({a, d, e});
        m.triangles.push_back({a, e, b});
    }
    return m;
}

TEST(FoldedAreaFraction, FlatAndGentlyBentStripsHaveNoFold) {
    EXPECT_EQ(folded_area_fraction(folded_strip(0.0)), 0.0);
    EXPECT_EQ(folded_area_fraction(folded_strip(1.0)), 0.0);  // turns by 57 degrees twice
    EXPECT_EQ(folded_area_fraction(Mesh{}), 0.0);
}

TEST(FoldedAreaFraction, APleatFoldsTheTrianglesOnItsEdges) {
    // Turned by 150 degrees and back: both creases fold. The edge triangles of each crease fold,
    // the others (one per outer square) do not: 4 of the 6 equal triangles.
    EXPECT_NEAR(folded_area_fraction(folded_strip(150 * M_PI / 180)), 4.0 / 6.0, 1e-12);
}

TEST(FoldedAreaFraction, ASmoothClosedSurfaceHasNoneATetrahedronIsAllCreases) {
    EXPECT_EQ(folded_area_fraction(shapes::icosphere(3)), 0.0);
    Mesh tet;
    tet.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tet.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    EXPECT_EQ(folded_area_fraction(tet), 1.0);  // normals 109.5 degrees apart on every edge
}

TEST(FoldedAreaFraction, EdgesNotSharedByTwoTrianglesAndDegenerateTrianglesDoNotFold) {
    // A triangle and its copy turned over share all three edges with normals opposite: a fold on
    // each. A third copy makes every edge used three times: no fold is counted.
    Mesh two;
    two.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    two.triangles = {{0, 1, 2}, {0, 2, 1}};
    EXPECT_EQ(folded_area_fraction(two), 1.0);
    two.triangles.push_back({0, 1, 2});
    EXPECT_EQ(folded_area_fraction(two), 0.0);
    Mesh flat;
    flat.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
    flat.triangles = {{0, 1, 2}, {0, 2, 3}};  // the first has no area, so no normal
    EXPECT_EQ(folded_area_fraction(flat), 0.0);
}

}  // namespace
}  // namespace quadcage

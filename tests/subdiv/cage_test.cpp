#include "quadcage/subdiv/cage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "quadcage/core/errors.h"
#include "support/quad_shapes.h"

namespace quadcage::subdiv {
namespace {

using test::cage_from_simple;
using test::torus_cage;
QuadMesh cube() { return test::cube_quads(); }

TEST(SubdivCage, CubeStepEqualsOpenSubdivUniformRefinement) {
    const QuadMesh m = cube();
    const Cage cage = cage_from_simple(m);
    ASSERT_EQ(check_cage(cage), "");
    const CageRefinement ours = refine_cage(cage);
    const QuadMesh theirs = refine_uniform(m, 1);
    ASSERT_EQ(ours.level1.num_quads(), theirs.num_quads());
    // Same faces in the same order with the same corner positions (vertex numbering may differ).
    for (int f = 0; f < theirs.num_quads(); ++f)
        for (int k = 0; k < 4; ++k) {
            const Vec3 a = ours.level1.points[ours.level1.quads[f][k]];
            const Vec3 b = theirs.points[theirs.quads[f][k]];
            EXPECT_LT(norm(a - b), 1e-12) << "face " << f << " corner " << k;
        }
}

TEST(SubdivCage, StencilsReproduceThePointsAndSumToOne) {
    const Cage cage = torus_cage();
    const CageRefinement r = refine_cage(cage);
    ASSERT_EQ(r.stencils.size(), r.level1.points.size());
    for (size_t i = 0; i < r.stencils.size(); ++i) {
        double sum = 0;
        Vec3 p;
        for (const auto& [j, w] : r.stencils[i]) sum += w, p += cage.points[j] * w;
        EXPECT_NEAR(sum, 1.0, 1e-14) << i;
        EXPECT_LT(norm(p - r.level1.points[i]), 1e-12) << i;
    }
}

TEST(SubdivCage, TorusWithMultiEdgesRefinesToASimpleClosedMesh) {
    const Cage cage = torus_cage();
    ASSERT_EQ(check_cage(cage), "");
    const CageRefinement r = refine_cage(cage);
    EXPECT_EQ(r.level1.num_quads(), 16);
    EXPECT_EQ(r.level1.num_vertices(), 4 + 8 + 4);  // V + E + F: V - E + F = 0 at level 1 too
    // refine_uniform() rejects multi-edges, so accepting the level-1 mesh proves it is simple.
    const QuadMesh next = refine_uniform(r.level1, 1);
    EXPECT_EQ(next.num_quads(), 64);
    // Every corner of the 2 x 2 torus has valence 4: its vertex point is (Q + 2R + S) / 4.
    Vec3 q, rr;
    for (int k = 0; k < 4; ++k) q += cage.points[k] * 0.25;  // all four quads use all four corners
    // corner 0's four edges go to corners 2, 2, 1, 1 (two around u, two around v)
    rr = ((cage.points[0] + cage.points[2]) * 0.5 * 2 + (cage.points[0] + cage.points[1]) * 0.5 * 2) * 0.25;
    const Vec3 expected = (q + rr * 2 + cage.points[0]) * 0.25;
    EXPECT_LT(norm(r.level1.points[0] - expected), 1e-12);
}

TEST(SubdivCage, CheckCageNamesTheProblem) {
    Cage cage = torus_cage();
    cage.quads[1].edges[0] = cage.quads[0].edges[0];
    EXPECT_NE(check_cage(cage), "");
    Cage flipped = cage_from_simple(cube());
    std::swap(flipped.quads[0].corners[1], flipped.quads[0].corners[3]);
    EXPECT_NE(check_cage(flipped), "");
    Cage empty;
    EXPECT_EQ(check_cage(empty), "the cage has no quads");
    EXPECT_THROW(refine_cage(flipped), InvalidInput);
}

TEST(SubdivCage, ToChildPicksTheQuadrantAndRescales) {
    const FacePoint a = to_child({3, 0.25, 0.75});
    EXPECT_EQ(a.face, 4 * 3 + 3);
    EXPECT_DOUBLE_EQ(a.u, 0.5);
    EXPECT_DOUBLE_EQ(a.v, 0.5);
    const FacePoint b = to_child({0, 0.9, 0.1});
    EXPECT_EQ(b.face, 1);
    EXPECT_NEAR(b.u, 0.8, 1e-15);
    EXPECT_NEAR(b.v, 0.2, 1e-15);
    const FacePoint c = descend({2, 1.0, 1.0}, 3);
    EXPECT_EQ(c.face, ((2 * 4 + 2) * 4 + 2) * 4 + 2);
    EXPECT_DOUBLE_EQ(c.u, 1.0);
}

}  // namespace
}  // namespace quadcage::subdiv

namespace quadcage::subdiv {
namespace {

PolygonMesh as_polygons(const QuadMesh& q) {
    PolygonMesh p{q.points, {}};
    for (const auto& f : q.quads) p.faces.emplace_back(f.begin(), f.end());
    return p;
}

TEST(PolygonCage, QuadCageRefinesLikeOpenSubdiv) {
    // On an all-quad cage the hand-made step must give OpenSubdiv's level 1 face by face (same
    // child order and corner order: the quadrant convention).
    for (const QuadMesh& q : {test::cube_quads(1.0), test::torus_quads(6, 4), test::icosahedron_quads()}) {
        const CageRefinement r = refine_polygon_cage(as_polygons(q));
        const QuadMesh osd = refine_uniform(q, 1);
        ASSERT_EQ(r.level1.num_quads(), osd.num_quads());
        ASSERT_EQ(r.level1.num_vertices(), osd.num_vertices());
        for (int f = 0; f < osd.num_quads(); ++f)
            for (int k = 0; k < 4; ++k)
                EXPECT_LT(norm(r.level1.points[r.level1.quads[f][k]] - osd.points[osd.quads[f][k]]), 1e-12);
    }
}

TEST(PolygonCage, MixedPolygonsGiveOneQuadPerCorner) {
    // A triangular prism: 2 triangles and 3 quads, 6 + 9 + 5 level-1 points, 2*3 + 3*4 quads.
    PolygonMesh prism;
    prism.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    prism.faces = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
    ASSERT_EQ(check_polygon_cage(prism), "");
    const CageRefinement r = refine_polygon_cage(prism);
    EXPECT_EQ(r.level1.num_vertices(), 20);
    EXPECT_EQ(r.level1.num_quads(), 18);
    for (const Stencil& s : r.stencils) {
        double sum = 0;
        for (const auto& [i, w] : s) sum += w;
        EXPECT_NEAR(sum, 1.0, 1e-14);
    }
    // A simple closed quad mesh: OpenSubdiv takes it, and its limit is finite.
    EXPECT_NO_THROW(refine_uniform(r.level1, 1));
}

TEST(PolygonCage, NamesWhatIsWrong) {
    const PolygonMesh cube = as_polygons(test::cube_quads(1.0));
    auto why = [](PolygonMesh m) { return check_polygon_cage(m); };
    PolygonMesh open = cube;
    open.faces.pop_back();
    EXPECT_NE(why(open).find("open"), std::string::npos) << why(open);
    PolygonMesh flipped = cube;
    std::reverse(flipped.faces[0].begin(), flipped.faces[0].end());
    EXPECT_NE(why(flipped).find("consistently oriented"), std::string::npos) << why(flipped);
    PolygonMesh repeated = cube;
    repeated.faces[0][1] = repeated.faces[0][0];
    EXPECT_NE(why(repeated).find("repeats the"), std::string::npos) << why(repeated);
    PolygonMesh nan = cube;
    nan.points[3].y = std::nan("");
    EXPECT_NE(why(nan).find("NaN"), std::string::npos) << why(nan);
    PolygonMesh extra = cube;
    extra.faces.push_back(cube.faces[0]);
    EXPECT_NE(why(extra).find("non-manifold"), std::string::npos) << why(extra);
    // Two cubes sharing one vertex: every edge has two faces, but the vertex is pinched.
    PolygonMesh pinched = cube;
    for (int i = 0; i < 8; ++i) pinched.points.push_back(cube.points[i] + Vec3{2, 2, 2});
    for (const auto& f : cube.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(v == 7 ? 7 : v + 8);  // vertex 7 (1,1,1) is shared
        pinched.faces.push_back(g);
    }
    pinched.points.pop_back();  // the copy of vertex 7 is not used
    EXPECT_NE(why(pinched).find("more than one fan"), std::string::npos) << why(pinched);
    EXPECT_THROW(refine_polygon_cage(open), InvalidInput);
}

}  // namespace
}  // namespace quadcage::subdiv

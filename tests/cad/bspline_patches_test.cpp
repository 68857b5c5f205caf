#include "quadcage/fit/bspline_patches.h"

#include <gtest/gtest.h>

#include <cmath>

#include "quadcage/core/errors.h"
#include "quadcage/core/shapes.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"
#include "quadcage/subdiv/limit_surface.h"
#include "support/quad_shapes.h"

namespace quadcage::fit {
namespace {

// Control points moved off their symmetric places so nothing is exact by symmetry.
subdiv::QuadMesh wobbled(subdiv::QuadMesh m, double amount) {
    for (size_t i = 0; i < m.points.size(); ++i) {
        const double s = static_cast<double>(i);
        m.points[i] += Vec3{std::sin(1.3 * s), std::cos(2.1 * s), std::sin(0.7 * s + 1)} * amount;
    }
    return m;
}

// The cube (6 quads, valence-3 corners) as a fit at `level`.
FittedSurface cube_surface(int level) {
    const subdiv::QuadMesh cage = wobbled(test::cube_quads(1.0), 0.05);
    return FittedSurface(subdiv::refine_uniform(cage, std::max(level, 1)), level, 6);
}

// A torus grid of 8 x 6 quads (all corners regular) as a user's quad cage fitted at `level`.
FittedSurface torus_surface(int level) {
    const subdiv::QuadMesh cage = wobbled(test::torus_quads(8, 6), 0.03);
    return FittedSurface(subdiv::refine_uniform(cage, std::max(level, 1)), level, 48);
}

// The icosahedron split into 60 quads (valence 5, 3 and 4 corners) as a user's quad cage.
FittedSurface icosa_surface(int level) {
    const subdiv::QuadMesh cage = wobbled(test::icosahedron_quads(), 0.02);
    return FittedSurface(subdiv::refine_uniform(cage, std::max(level, 1)), level, 60);
}

void expect_sound(const BSplinePatches& p, const std::string& what) {
    SCOPED_TRACE(what + ": " + p.message);
    std::printf(
        "%s: %s\n  deviation regular %.3g corner %.3g, normal jump regular %.3g deg corner %.3g deg, "
        "exactness %.3g\n",
        what.c_str(), p.message.c_str(), p.measurement.max_deviation_regular,
        p.measurement.max_deviation_corner, p.measurement.max_normal_jump_regular_deg,
        p.measurement.max_normal_jump_corner_deg, p.measurement.exactness);
    EXPECT_TRUE(p.tolerance_met);
    EXPECT_LE(p.measurement.max_deviation, p.tolerance);
    EXPECT_LE(p.measurement.max_deviation_regular, 1e-12 * p.diagonal);
    EXPECT_LE(p.measurement.exactness, 1e-11 * p.diagonal);
    EXPECT_LE(p.measurement.max_normal_jump_regular_deg, 0.01);
    EXPECT_LE(p.measurement.max_normal_jump_corner_deg, 1.0);
    for (const BSplinePatch& q : p.patches) EXPECT_EQ(q.n + 4, static_cast<int>(p.knots.size()));
}

TEST(BSplinePatches, TorusIsExactWithUniformKnots) {
    for (int level : {0, 1, 2}) {
        const BSplinePatches p = bspline_patches(torus_surface(level));
        expect_sound(p, "torus level " + std::to_string(level));
        EXPECT_EQ(p.patches.size(), 48u);
        EXPECT_EQ(p.edges.size(), 96u);
        EXPECT_EQ(p.depth, 0);
        EXPECT_TRUE(p.exact_everywhere);
        EXPECT_LE(p.measurement.max_deviation, 1e-12 * p.diagonal);
        EXPECT_EQ(static_cast<int>(p.knots.size()), (1 << std::max(level, 1)) + 7);
    }
}

TEST(BSplinePatches, CubeMeetsTheToleranceAtItsValenceThreeCorners) {
    for (int level : {1, 3}) {
        const BSplinePatches p = bspline_patches(cube_surface(level));
        expect_sound(p, "cube level " + std::to_string(level));
        EXPECT_EQ(p.patches.size(), 6u);
        EXPECT_EQ(p.edges.size(), 12u);
        EXPECT_GE(p.depth, 1);
        EXPECT_FALSE(p.exact_everywhere);
    }
}

TEST(BSplinePatches, ValenceFiveCornersMeetTheTolerance) {
    const BSplinePatches p = bspline_patches(icosa_surface(1));
    expect_sound(p, "icosahedron quads level 1");
    EXPECT_EQ(p.patches.size(), 60u);
    EXPECT_EQ(p.edges.size(), 120u);
}

// A cage with triangles (the icosahedron as a user's cage): one patch per quad of the cage refined
// once, whose corners (valence 5 and the valence-3 face points) may all be extraordinary.
FittedSurface triangle_cage_surface(int level) {
    const Mesh ico = shapes::icosphere(0, 1.0);
    PolygonMesh cage;
    cage.points = ico.points;
    for (const Triangle& t : ico.triangles) cage.faces.push_back({t[0], t[1], t[2]});
    const subdiv::QuadMesh level1 = subdiv::refine_polygon_cage(cage).level1;
    auto limit =
        std::make_shared<const subdiv::LimitSurface>(subdiv::refine_uniform(level1, std::max(level, 1) - 1));
    return FittedSurface(limit, level, 20, level1.num_quads());
}

TEST(BSplinePatches, CageWithTrianglesGetsOnePatchPerQuadOfItsRefinement) {
    for (int level : {1, 2}) {
        const BSplinePatches p = bspline_patches(triangle_cage_surface(level));
        expect_sound(p, "icosahedron triangles level " + std::to_string(level));
        EXPECT_EQ(p.patches.size(), 60u);
        EXPECT_EQ(p.edges.size(), 120u);
    }
}

TEST(BSplinePatches, TighterToleranceRefinesDeeperOrSaysItCannot) {
    BSplinePatchOptions o;
    o.tolerance = 1e-9;
    const BSplinePatches p = bspline_patches(cube_surface(1), o);
    std::printf("cube at 1e-9: %s\n", p.message.c_str());
    if (!p.tolerance_met) {
        EXPECT_EQ(p.depth, o.max_depth);
    }
    BSplinePatchOptions loose;
    loose.tolerance = 1e-3;
    EXPECT_LE(bspline_patches(cube_surface(1), loose).depth, p.depth);
}

TEST(BSplinePatches, RejectsBadOptions) {
    BSplinePatchOptions o;
    o.tolerance = 1e-10;
    EXPECT_THROW(bspline_patches(cube_surface(1), o), InvalidInput);
    EXPECT_THROW(bspline_patches(FittedSurface{}), InvalidInput);
}

}  // namespace
}  // namespace quadcage::fit

// fit_control_mesh(): fitting a user's control mesh (`quadcage fit --cage`), and its checks.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/shapes.h"
#include "quadcage/fit/fit.h"
#include "quadcage/subdiv/cage.h"
#include "support/quad_shapes.h"

namespace quadcage::fit {
namespace {


FitOptions fast_options(int level) {
    FitOptions o;
    o.level = level;
    o.area_samples = 3000;
    o.error_samples = 20000;
    return o;
}

PolygonMesh polygons_of(const subdiv::QuadMesh& q) {
    PolygonMesh p{q.points, {}};
    for (const auto& f : q.quads) p.faces.emplace_back(f.begin(), f.end());
    return p;
}

// A 4 x 4 torus grid (R, r) whose vertices are pushed `push` along the tube's normal and then
// rotated by `degrees` about the torus axis (z).
PolygonMesh moved_torus_cage(double R, double r, double push, double degrees) {
    PolygonMesh cage = polygons_of(test::torus_quads(4, 4, R, r));
    const double a = degrees * test::kPi / 180, c = std::cos(a), s = std::sin(a);
    for (Vec3& p : cage.points) {
        const double rho = std::hypot(p.x, p.y);
        const Vec3 ring{R * p.x / rho, R * p.y / rho, 0};
        const Vec3 n = (p - ring) / norm(p - ring);
        const Vec3 q = p + n * push;
        p = {c * q.x - s * q.y, s * q.x + c * q.y, q.z};
    }
    return cage;
}

TEST(ControlMesh, TorusCageOffTheSurfaceAndRotatedFitsAtLevelTwo) {
    // The mesh: a torus with R = 1, r = 0.35. The cage: 16 quads 5% of the diagonal outside it,
    // turned by 10 degrees, so neither its vertices nor any patch map says where the surface is:
    // the start has to come from the closest points of the cage's limit surface.
    const Mesh mesh = shapes::torus(96, 48, 1.0, 0.35);
    const double diagonal = bounding_box(mesh).diagonal();
    const PolygonMesh cage = moved_torus_cage(1.0, 0.35, 0.05 * diagonal, 10.0);
    EXPECT_EQ(check_control_mesh(mesh, cage), "");
    const FitResult r = fit_control_mesh(mesh, cage, fast_options(2));
    ASSERT_EQ(r.levels.size(), 2u);  // levels 1 and 2 in turn
    EXPECT_EQ(r.levels[0].level, 1);
    EXPECT_EQ(r.levels[1].level, 2);
    EXPECT_EQ(r.levels[1].control_points, 256);  // 16 quads refined twice: 256 vertices
    EXPECT_LT(r.levels[1].relative.rms, 1e-3) << r.levels[1].stop_reason;
    EXPECT_LE(r.levels[1].relative.rms, r.levels[0].relative.rms);
    EXPECT_EQ(r.surface.level(), 2);
    EXPECT_EQ(r.surface.cage_faces(), 16);
    EXPECT_EQ(r.surface.control_mesh().num_quads(), 256);
    EXPECT_TRUE(r.fitted_cage.faces.empty());
    // The fitted surface really is where the report says: an independent measurement agrees.
    const ErrorMeasurement m = measure_fit_error(mesh, r.surface);
    EXPECT_NEAR(m.relative.rms, r.levels[1].relative.rms, 0.2 * r.levels[1].relative.rms);
}

TEST(ControlMesh, TheFitDoesNotDependOnTheUnits) {
    // The same torus and cage in units about a million times smaller: the same relative errors
    // (Ceres' absolute tolerances once ended such a fit before its first step). The scale is a power
    // of two, so every product is rounded as at scale 1: a scale like 1e-6 changes the last bits,
    // and those alone moved this fit by 3.7% with OpenBLAS.
    Mesh mesh = shapes::torus(64, 32, 1.0, 0.35);
    PolygonMesh cage = moved_torus_cage(1.0, 0.35, 0.1, 5.0);
    const double at_one = fit_control_mesh(mesh, cage, fast_options(1)).levels.back().relative.rms;
    const double scale = std::ldexp(1.0, -20);
    for (Vec3& p : mesh.points) p *= scale;
    for (Vec3& p : cage.points) p *= scale;
    const double small = fit_control_mesh(mesh, cage, fast_options(1)).levels.back().relative.rms;
    EXPECT_NEAR(small, at_one, 1e-6 * at_one);
}

TEST(ControlMesh, LevelZeroFitsTheCagesOwnVerticesAndKeepsItsFaces) {
    const Mesh mesh = shapes::torus(64, 32, 1.0, 0.35);
    const PolygonMesh cage = polygons_of(test::torus_quads(8, 6, 1.0, 0.35));
    const FitResult r = fit_control_mesh(mesh, cage, fast_options(0));
    ASSERT_EQ(r.levels.size(), 1u);
    EXPECT_EQ(r.levels[0].level, 0);
    EXPECT_EQ(r.levels[0].control_points, 48);
    ASSERT_EQ(r.fitted_cage.num_vertices(), 48);
    EXPECT_EQ(r.fitted_cage.faces, cage.faces);
    // The grid's vertices lie on the torus, so its limit surface shrinks inside: the fit moves them out.
    const ErrorMeasurement unfitted =
        measure_fit_error(mesh, FittedSurface(subdiv::refine_polygon_cage(cage).level1, 0, 48));
    EXPECT_LT(r.levels[0].relative.rms, 0.5 * unfitted.relative.rms);
    // The surface is the fitted cage refined once.
    const subdiv::CageRefinement again = subdiv::refine_polygon_cage(r.fitted_cage);
    for (int i = 0; i < again.level1.num_vertices(); ++i)
        EXPECT_LT(norm(again.level1.points[i] - r.surface.control_mesh().points[i]), 1e-12);
}

TEST(ControlMesh, TriangleCageOfASphereIsRefinedToQuads) {
    // An icosahedron (20 triangles) as the control mesh of a sphere: after one step, 60 quads.
    const Mesh mesh = shapes::icosphere(4, 1.0);
    const Mesh ico = shapes::icosphere(0, 1.2);
    PolygonMesh cage{ico.points, {}};
    for (const Triangle& t : ico.triangles) cage.faces.push_back({t[0], t[1], t[2]});
    const FitResult r = fit_control_mesh(mesh, cage, fast_options(1));
    EXPECT_EQ(r.surface.cage_faces(), 20);
    EXPECT_EQ(r.surface.cage_quads(), 0);
    EXPECT_EQ(r.surface.control_mesh().num_quads(), 60);
    EXPECT_THROW(r.surface.evaluate_on_cage({0, 0.5, 0.5}), InvalidInput);
    EXPECT_LT(r.levels.back().relative.rms, 2e-3);
}

TEST(ControlMesh, RejectsAWrongGenus) {
    const Mesh torus = shapes::torus(48, 24, 1.0, 0.35);
    const PolygonMesh cube = polygons_of(test::cube_quads(0.8));
    const std::string why = check_control_mesh(torus, cube);
    EXPECT_NE(why.find("genus is 0, the mesh's 1"), std::string::npos) << why;
    EXPECT_THROW(fit_control_mesh(torus, cube, fast_options(1)), InvalidInput);
}

TEST(ControlMesh, RejectsAnOpenCage) {
    const Mesh sphere = shapes::icosphere(3, 1.0);
    PolygonMesh cube = polygons_of(test::cube_quads(0.7));
    cube.faces.pop_back();
    const std::string why = check_control_mesh(sphere, cube);
    EXPECT_NE(why.find("open"), std::string::npos) << why;
    EXPECT_THROW(fit_control_mesh(sphere, cube, fast_options(1)), InvalidInput);
}

TEST(ControlMesh, RejectsACageFarFromTheMesh) {
    // The limit surface of the cube [-h, h]^3 is a rounded box about as wide as the unit sphere
    // for h = 1.2; moved by a diagonal of the sphere's box (3.46) it is far away.
    const Mesh sphere = shapes::icosphere(3, 1.0);
    PolygonMesh far = polygons_of(test::cube_quads(1.2));
    for (Vec3& p : far.points) p.x += 3.46;
    const std::string why = check_control_mesh(sphere, far);
    EXPECT_NE(why.find("far from the mesh"), std::string::npos) << why;
    EXPECT_THROW(fit_control_mesh(sphere, far, fast_options(1)), InvalidInput);
    // 5% of the diagonal off is within reach, and fits.
    PolygonMesh near = polygons_of(test::cube_quads(1.2));
    for (Vec3& p : near.points) p.x += 0.05 * 3.46;
    EXPECT_EQ(check_control_mesh(sphere, near), "");
    EXPECT_LT(fit_control_mesh(sphere, near, fast_options(2)).levels.back().relative.rms, 2e-3);
}

TEST(ControlMesh, MatchesComponentsByOverlap) {
    Mesh a = shapes::icosphere(2, 1.0), b = shapes::icosphere(2, 1.0);
    for (Vec3& p : b.points) p.x += 5;
    PolygonMesh cage = polygons_of(test::cube_quads(0.7));
    const PolygonMesh cube = cage;
    for (const Vec3& p : cube.points) cage.points.push_back(p);  // second cube, around a
    for (int i = 0; i < 8; ++i) cage.points[i].x += 5;           // first cube, around b
    for (const auto& f : cube.faces) cage.faces.push_back({f[0] + 8, f[1] + 8, f[2] + 8, f[3] + 8});
    const std::vector<PolygonMesh> parts = match_control_mesh({a, b}, cage);
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_LT(parts[0].points[0].x, 2.0);
    EXPECT_GT(parts[1].points[0].x, 2.0);
    EXPECT_EQ(parts[0].num_faces(), 6);
    EXPECT_THROW(match_control_mesh({a}, cage), InvalidInput);
}

}  // namespace
}  // namespace quadcage::fit

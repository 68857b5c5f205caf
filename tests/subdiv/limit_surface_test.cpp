#include "quadcage/subdiv/limit_surface.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <random>
#include <string>

#include "quadcage/core/errors.h"
#include "support/quad_shapes.h"

namespace quadcage::subdiv {
namespace {

using test::cube_quads;
using test::icosahedron_quads;
using test::torus_quads;

// The shapes every property is checked on: valence 3 (cube), regular (torus grid), valence 5
// (split icosahedron) and the level-1 mesh of the 4-quad torus cage with multi-edges.
std::map<std::string, QuadMesh> shapes_to_test() {
    return {{"cube", cube_quads()},
            {"torus", torus_quads(6, 4)},
            {"icosahedron", icosahedron_quads()},
            {"torus_cage_level1", refine_cage(test::torus_cage()).level1}};
}

// Deterministic (face, u, v) samples, including face corners and sides.
std::vector<FacePoint> sample_points(int faces, int per_face, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<FacePoint> out;
    const double fixed[][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0}, {1, 0.5}, {0.5, 0.5}};
    for (int f = 0; f < faces; ++f) {
        for (const auto& uv : fixed) out.push_back({f, uv[0], uv[1]});
        for (int k = 0; k < per_face; ++k) out.push_back({f, uni(rng), uni(rng)});
    }
    return out;
}

double max_abs(const std::vector<double>& w) {
    double m = 0;
    for (double x : w) m = std::max(m, std::abs(x));
    return m;
}

TEST(SubdivLimitSurface, StencilWeightsSumToOneAndDerivativeWeightsToZero) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        const LimitSurface surface(mesh);
        for (const FacePoint& p : sample_points(surface.num_faces(), 3, 1)) {
            const LimitStencil s = surface.stencil(p);
            double sp = 0, su = 0, sv = 0;
            for (size_t i = 0; i < s.indices.size(); ++i) {
                sp += s.position_weights[i], su += s.du_weights[i], sv += s.dv_weights[i];
                if (i > 0) {
                    EXPECT_LT(s.indices[i - 1], s.indices[i]) << name << ": indices must be unique and sorted";
                }
            }
            EXPECT_NEAR(sp, 1.0, 1e-12) << name << " face " << p.face;
            EXPECT_NEAR(su, 0.0, 1e-11 * std::max(1.0, max_abs(s.du_weights))) << name;
            EXPECT_NEAR(sv, 0.0, 1e-11 * std::max(1.0, max_abs(s.dv_weights))) << name;
        }
    }
}

TEST(SubdivLimitSurface, StencilIntoReusedStorageEqualsAFreshStencil) {
    // One LimitStencil reused across shapes and faces of other sizes (valence 3, 4 and 5, merged
    // repeats on the torus cage), in the reverse order of the fresh ones: the same bits.
    std::vector<std::pair<const LimitSurface*, FacePoint>> points;
    std::vector<LimitStencil> fresh;
    std::vector<std::unique_ptr<LimitSurface>> surfaces;
    for (const auto& [name, mesh] : shapes_to_test()) {
        surfaces.push_back(std::make_unique<LimitSurface>(mesh));
        for (const FacePoint& p : sample_points(surfaces.back()->num_faces(), 1, 5)) {
            points.push_back({surfaces.back().get(), p});
            fresh.push_back(surfaces.back()->stencil(p));
        }
    }
    LimitStencil reused;
    for (size_t k = points.size(); k-- > 0;) {
        points[k].first->stencil(points[k].second, &reused);
        EXPECT_EQ(reused.indices, fresh[k].indices) << "point " << k;
        EXPECT_EQ(reused.position_weights, fresh[k].position_weights) << "point " << k;
        EXPECT_EQ(reused.du_weights, fresh[k].du_weights) << "point " << k;
        EXPECT_EQ(reused.dv_weights, fresh[k].dv_weights) << "point " << k;
    }
}

TEST(SubdivLimitSurface, StencilAppliedToThePointsEqualsEvaluate) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        const LimitSurface surface(mesh);
        for (const FacePoint& p : sample_points(surface.num_faces(), 2, 2)) {
            const LimitStencil s = surface.stencil(p);
            Vec3 pos, du, dv;
            for (size_t i = 0; i < s.indices.size(); ++i) {
                const Vec3& x = mesh.points[s.indices[i]];
                pos += x * s.position_weights[i], du += x * s.du_weights[i], dv += x * s.dv_weights[i];
            }
            const LimitPoint e = surface.evaluate(p);
            EXPECT_LT(norm(pos - e.position), 1e-12) << name;
            EXPECT_LT(norm(du - e.du), 1e-10) << name;
            EXPECT_LT(norm(dv - e.dv), 1e-10) << name;
        }
    }
}

TEST(SubdivLimitSurface, CornersMatchPrimvarRefinerLimitAtManyLevels) {
    // Face corners of refine_uniform(mesh, k) are its vertices; their limit positions come from
    // OpenSubdiv's PrimvarRefiner::Limit (limit_positions()), an independent code path.
    for (const auto& [name, mesh] : shapes_to_test()) {
        for (int level = 0; level <= 3; ++level) {
            const QuadMesh refined = refine_uniform(mesh, level);
            const std::vector<Vec3> expected = limit_positions(mesh, level);
            const LimitSurface surface(refined);
            double worst = 0;
            for (int f = 0; f < refined.num_quads(); ++f)
                for (int k = 0; k < 4; ++k) {
                    const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                    const Vec3 got = surface.evaluate({f, uv[k][0], uv[k][1]}).position;
                    worst = std::max(worst, norm(got - expected[refined.quads[f][k]]));
                }
            EXPECT_LT(worst, 1e-9) << name << " level " << level;
        }
    }
}

TEST(SubdivLimitSurface, OneMoreUniformLevelIsTheSameSurface) {
    // S_k(f, u, v) = S_{k+1}(descend((f, u, v), 1)): the children of face f, in OpenSubdiv's order,
    // parameterise the same piece of the limit surface. Exact for regular faces; faces at
    // extraordinary vertices are approximated to the irregular level (6), so allow ~1e-6.
    for (const auto& [name, mesh] : shapes_to_test()) {
        for (int level = 0; level <= 2; ++level) {
            const QuadMesh coarse = refine_uniform(mesh, level);
            const LimitSurface a(coarse), b(refine_uniform(coarse, 1));
            double worst = 0;
            for (const FacePoint& p : sample_points(a.num_faces(), 4, 3))
                worst = std::max(worst, norm(a.evaluate(p).position - b.evaluate(descend(p, 1)).position));
            EXPECT_LT(worst, 2e-6) << name << " level " << level;
        }
    }
}

TEST(SubdivLimitSurface, WrapCrossesIntoTheNeighbourContinuously) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        const LimitSurface surface(mesh);
        for (int f = 0; f < surface.num_faces(); ++f) {
            const double t = 0.3;
            const FacePoint inside[4] = {{f, t, 0}, {f, 1, t}, {f, 1 - t, 1}, {f, 0, 1 - t}};
            const FacePoint outside[4] = {{f, t, -1e-9}, {f, 1 + 1e-9, t}, {f, 1 - t, 1 + 1e-9}, {f, -1e-9, 1 - t}};
            for (int k = 0; k < 4; ++k) {
                const FacePoint w = surface.wrap(outside[k]);
                EXPECT_NE(w.face, f) << name;
                EXPECT_LT(norm(surface.evaluate(w).position - surface.evaluate(inside[k]).position), 1e-7) << name;
            }
        }
        const FacePoint in{0, 0.25, 0.75};
        const FacePoint same = surface.wrap(in);
        EXPECT_EQ(same.face, 0);
        EXPECT_EQ(same.u, 0.25);
    }
}

TEST(SubdivLimitSurface, ProjectFindsTheFootPoint) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        // The limit of the 2 x 2 torus cage folds onto itself (a periodic cubic B-spline on 2 points
        // runs back and forth along a segment), so a point off it can lie on another sheet.
        if (name == "torus_cage_level1") continue;
        const LimitSurface surface(mesh);
        for (const FacePoint& p : sample_points(surface.num_faces(), 1, 4)) {
            const LimitPoint e = surface.evaluate(p);
            if (norm(e.normal) == 0) continue;
            // A point off the surface along the normal, searched from a neighbouring parameter.
            const Vec3 q = e.position + e.normal * 0.01;
            const FacePoint start = surface.wrap({p.face, p.u + 0.2, p.v - 0.15});
            const FacePoint found = surface.project(q, start, 30);
            const LimitPoint f = surface.evaluate(found);
            EXPECT_NEAR(norm(f.position - q), 0.01, 1e-6) << name << " face " << p.face;
            // The same foot with the distance it ends at, exactly that of the foot evaluated again.
            const LimitSurface::Projection with = surface.project_with_distance(q, start, 30);
            EXPECT_EQ(with.foot.face, found.face);
            EXPECT_EQ(with.foot.u, found.u);
            EXPECT_EQ(with.foot.v, found.v);
            EXPECT_EQ(with.distance2, dot(f.position - q, f.position - q));
        }
    }
}

TEST(SubdivLimitSurface, TessellationIsWatertightAndOnTheSurface) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        const LimitSurface surface(mesh);
        const int n = 3;
        const LimitTessellation t = surface.tessellate(n);
        EXPECT_EQ(t.mesh.num_triangles(), 2 * n * n * surface.num_faces());
        // Closed 2-manifold: every directed edge once, and its reverse once.
        std::map<std::pair<int, int>, int> directed;
        for (const Triangle& tri : t.mesh.triangles)
            for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
        for (const auto& [e, count] : directed) {
            EXPECT_EQ(count, 1) << name;
            EXPECT_EQ(directed.count({e.second, e.first}), 1u) << name;
        }
        // V - E + F of the tessellation equals that of the control mesh.
        const long long v = t.mesh.num_vertices(), e = directed.size() / 2, f = t.mesh.num_triangles();
        const long long cv = mesh.num_vertices(), ce = 2 * mesh.num_quads(), cf = mesh.num_quads();
        EXPECT_EQ(v - e + f, cv - ce + cf) << name;
        for (size_t i = 0; i < t.params.size(); ++i)
            EXPECT_LT(norm(surface.evaluate(t.params[i]).position - t.mesh.points[i]), 1e-12);
    }
}

TEST(SubdivLimitSurface, SetPointsMovesTheSurfaceAndStencilsDoNot) {
    const QuadMesh mesh = icosahedron_quads();
    LimitSurface surface(mesh);
    const FacePoint p{7, 0.2, 0.6};
    const LimitStencil before = surface.stencil(p);
    std::vector<Vec3> moved = mesh.points;
    for (Vec3& x : moved) x = x * 2.0 + Vec3{1, 0, 0};
    const Vec3 a = surface.evaluate(p).position;
    surface.set_points(moved);
    const Vec3 b = surface.evaluate(p).position;
    EXPECT_LT(norm(b - (a * 2.0 + Vec3{1, 0, 0})), 1e-12);  // affine invariance
    const LimitStencil after = surface.stencil(p);
    EXPECT_EQ(before.indices, after.indices);
    EXPECT_EQ(before.position_weights, after.position_weights);
}

TEST(SubdivLimitSurface, NormalsPointOutward) {
    for (const auto& [name, mesh] : shapes_to_test()) {
        if (name.rfind("torus", 0) == 0) continue;  // star-shaped about the origin only for the others
        const LimitSurface surface(mesh);
        for (const FacePoint& p : sample_points(surface.num_faces(), 2, 5)) {
            const LimitPoint e = surface.evaluate(p);
            EXPECT_GT(dot(e.normal, e.position), 0) << name;
        }
    }
}

TEST(SubdivLimitSurface, RejectsBadInput) {
    QuadMesh bad = cube_quads();
    bad.quads[0][1] = 42;
    EXPECT_THROW(LimitSurface{bad}, InvalidInput);
    LimitSurfaceOptions options;
    options.irregular_level = 0;
    EXPECT_THROW(LimitSurface(cube_quads(), options), InvalidInput);
    LimitSurface surface(cube_quads());
    EXPECT_THROW(surface.evaluate({6, 0, 0}), InvalidInput);
    EXPECT_THROW(surface.stencil({-1, 0, 0}), InvalidInput);
    EXPECT_THROW(surface.set_points({}), InvalidInput);
    EXPECT_THROW(surface.tessellate(0), InvalidInput);
}

}  // namespace
}  // namespace quadcage::subdiv

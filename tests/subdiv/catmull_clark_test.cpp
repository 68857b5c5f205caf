#include "quadcage/subdiv/catmull_clark.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "quadcage/core/errors.h"

namespace quadcage::subdiv {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The cube [-h, h]^3, faces counter-clockwise seen from outside. Vertex i has x = bit 0, y = bit 1,
// z = bit 2 of i.
QuadMesh cube(double h = 1.0) {
    QuadMesh m;
    for (int i = 0; i < 8; ++i) m.points.push_back({i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h});
    m.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return m;
}

// A torus as an nu x nv grid of quads (major radius R around z, minor radius r).
QuadMesh torus(int nu, int nv, double R = 2.0, double r = 0.7) {
    QuadMesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            m.points.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                                r * std::sin(v)});
        }
    auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    return m;
}

// An open n x n grid of unit quads in the plane z = 0.
QuadMesh planar_grid(int n) {
    QuadMesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) m.points.push_back({double(i), double(j), 0.0});
    auto id = [&](int i, int j) { return i * (n + 1) + j; };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    return m;
}

// Undirected edges -> number of quads using them; also checks that no directed edge repeats.
std::map<std::pair<int, int>, int> edge_use(const QuadMesh& m, bool* consistent) {
    std::map<std::pair<int, int>, int> use;
    std::set<std::pair<int, int>> directed;
    *consistent = true;
    for (const auto& q : m.quads)
        for (int k = 0; k < 4; ++k) {
            const int a = q[k], b = q[(k + 1) % 4];
            if (!directed.insert({a, b}).second) *consistent = false;
            ++use[{std::min(a, b), std::max(a, b)}];
        }
    return use;
}

// Checks the mesh is closed and consistently oriented; returns V - E + F.
int closed_euler_characteristic(const QuadMesh& m) {
    bool consistent = false;
    const auto use = edge_use(m, &consistent);
    EXPECT_TRUE(consistent);
    for (const auto& [edge, count] : use) EXPECT_EQ(count, 2) << edge.first << "-" << edge.second;
    for (const auto& q : m.quads)
        for (int v : q) {
            EXPECT_GE(v, 0);
            EXPECT_LT(v, m.num_vertices());
        }
    return m.num_vertices() - static_cast<int>(use.size()) + m.num_quads();
}

// Signed volume enclosed by a closed quad mesh (each quad split into two triangles).
double signed_volume(const QuadMesh& m) {
    double v = 0;
    for (const auto& q : m.quads) {
        const Vec3 &a = m.points[q[0]], &b = m.points[q[1]], &c = m.points[q[2]], &d = m.points[q[3]];
        v += dot(a, cross(b, c)) + dot(a, cross(c, d));
    }
    return v / 6;
}

double max_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    EXPECT_EQ(a.size(), b.size());
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, norm(a[i] - b[i]));
    return worst;
}

TEST(SubdivRefine, CubeCountsAndClosedness) {
    const int expected_quads[] = {6, 24, 96, 384};
    for (int level = 0; level <= 3; ++level) {
        const QuadMesh r = refine_uniform(cube(), level);
        EXPECT_EQ(r.num_quads(), expected_quads[level]) << "level " << level;
        EXPECT_EQ(closed_euler_characteristic(r), 2) << "level " << level;
        EXPECT_EQ(r.num_vertices(), r.num_quads() + 2);  // V = F + 2 for a closed quad sphere
        // Orientation kept: outward normals give a positive volume, which shrinks under refinement.
        EXPECT_GT(signed_volume(r), 0.0);
        EXPECT_LE(signed_volume(r), 8.0 + 1e-12);
    }
}

TEST(SubdivRefine, TorusVertexCountMatchesEuler) {
    const QuadMesh cage = torus(8, 6);
    for (int level = 1; level <= 3; ++level) {
        const QuadMesh r = refine_uniform(cage, level);
        const int faces = 48 << (2 * level);
        EXPECT_EQ(r.num_quads(), faces);
        EXPECT_EQ(closed_euler_characteristic(r), 0);  // genus 1
        EXPECT_EQ(r.num_vertices(), faces);            // V = F on a closed quad torus (E = 2F)
    }
    // One step adds a vertex per face and per edge: V1 = V0 + E0 + F0.
    EXPECT_EQ(refine_uniform(cage, 1).num_vertices(), 48 + 96 + 48);
}

TEST(SubdivRefine, RefinedPointsConvergeToTheLimit) {
    double previous = std::numeric_limits<double>::infinity();
    for (int level = 0; level <= 5; ++level) {
        const QuadMesh r = refine_uniform(cube(), level);
        const std::vector<Vec3> limit = limit_positions(cube(), level);
        const double gap = max_distance(r.points, limit);
        EXPECT_LT(gap, previous) << "level " << level;
        if (level > 0) {
            EXPECT_LT(gap, 0.4 * previous) << "level " << level;  // about 1/4 per level
        }
        previous = gap;
    }
    EXPECT_LT(previous, 1e-3);
}

TEST(SubdivLimit, CubeCornerMatchesTheClosedForm) {
    // Catmull-Clark limit mask at a valence-n vertex: (n^2 v + 4 sum(edge neighbours) +
    // sum(diagonal neighbours)) / (n (n + 5)); at the corner (1,1,1) of [-1,1]^3 it gives (1,1,1)/2.
    const std::vector<Vec3> limit = limit_positions(cube(), 0);
    ASSERT_EQ(limit.size(), 8u);
    for (int i = 0; i < 8; ++i) {
        const Vec3 expected = cube(0.5).points[i];
        EXPECT_LT(norm(limit[i] - expected), 1e-14) << "vertex " << i;
    }
    // Children of cage vertices come first and share their parent's limit point.
    for (int level = 1; level <= 4; ++level) {
        const std::vector<Vec3> deeper = limit_positions(cube(), level);
        for (int i = 0; i < 8; ++i) EXPECT_LT(norm(deeper[i] - limit[i]), 1e-14) << "level " << level;
    }
}

TEST(SubdivLimit, CubeLimitIsInsideTheCubeAndSymmetric) {
    const std::vector<Vec3> limit = limit_positions(cube(), 3);
    ASSERT_EQ(limit.size(), refine_uniform(cube(), 3).points.size());
    for (const Vec3& p : limit)
        for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(p[k]), 1.0);
    // x -> -x maps the set of limit points onto itself (and so do the other axis mirrors).
    for (int axis = 0; axis < 3; ++axis)
        for (const Vec3& p : limit) {
            Vec3 mirror = p;
            mirror[axis] = -mirror[axis];
            double nearest = std::numeric_limits<double>::infinity();
            for (const Vec3& q : limit) nearest = std::min(nearest, norm(q - mirror));
            EXPECT_LT(nearest, 1e-12) << "axis " << axis;
        }
    // A sphere-like surface: every limit point lies between the inscribed radius of the corner
    // limit (|(.5,.5,.5)| ~ 0.866) and the face-centre limit (interior of a face, < 1).
    for (const Vec3& p : limit) {
        EXPECT_GT(norm(p), 0.7);
        EXPECT_LT(norm(p), 1.0);
    }
}

TEST(SubdivLimit, TorusLimitStaysNearTheTorus) {
    const QuadMesh cage = torus(16, 12, 2.0, 0.7);
    for (const Vec3& p : limit_positions(cage, 2)) {
        const double ring = std::hypot(p.x, p.y) - 2.0;
        // B-spline limits lie inside the control net: the ring and the tube shrink by a few percent.
        EXPECT_NEAR(std::hypot(ring, p.z), 0.7, 0.1);
    }
}

TEST(SubdivBoundary, OpenGridStaysPlanarWithSharpBoundary) {
    const QuadMesh cage = planar_grid(3);
    const QuadMesh r = refine_uniform(cage, 2);
    EXPECT_EQ(r.num_quads(), 9 * 16);
    EXPECT_EQ(r.num_vertices(), 13 * 13);
    for (const Vec3& p : r.points) {
        EXPECT_EQ(p.z, 0.0);
        EXPECT_GE(p.x, 0.0);
        EXPECT_LE(p.x, 3.0);
    }
    // EDGE_ONLY: boundary edges are sharp, so the boundary limit is the cubic B-spline of the
    // boundary points, and corners are NOT sharp (that would be EDGE_AND_CORNER): the corner
    // (0,0) with boundary neighbours (1,0), (0,1) goes to ((1,0) + 4 (0,0) + (0,1)) / 6.
    const std::vector<Vec3> corner_limit = limit_positions(cage, 0);
    EXPECT_LT(norm(corner_limit[0] - Vec3{1.0 / 6, 1.0 / 6, 0}), 1e-15);
    // On the boundary x = 0 (7 level-1 points), the 3 whose boundary neighbours are all on the
    // straight part of the edge keep their limit on it; the 2 at each end are pulled to the corner.
    const std::vector<Vec3> limit = limit_positions(cage, 1);
    int on_edge = 0;
    for (const Vec3& p : limit) {
        EXPECT_NEAR(p.z, 0.0, 1e-15);
        if (std::abs(p.x) < 1e-12) ++on_edge;
    }
    EXPECT_EQ(on_edge, 3);
}

TEST(SubdivVersion, OpenSubdivVersionIsReportedAtRunTime) {
    const std::string v = opensubdiv_version();
    EXPECT_FALSE(v.empty());
    EXPECT_EQ(v.rfind("OpenSubdiv v3_", 0), 0u) << v;
    EXPECT_NE(v.find("24 faces"), std::string::npos) << v;
}

TEST(SubdivRefine, RejectsBadInput) {
    EXPECT_THROW(refine_uniform(cube(), -1), InvalidInput);
    EXPECT_THROW(refine_uniform(cube(), kMaxRefinementLevel + 1), InvalidInput);
    EXPECT_THROW(limit_positions(cube(), 9), InvalidInput);
    EXPECT_THROW(refine_uniform(QuadMesh{}, 1), InvalidInput);

    QuadMesh bad_index = cube();
    bad_index.quads[3][1] = 8;
    EXPECT_THROW(refine_uniform(bad_index, 1), InvalidInput);
    bad_index.quads[3][1] = -1;
    EXPECT_THROW(limit_positions(bad_index, 1), InvalidInput);

    QuadMesh repeated = cube();
    repeated.quads[0] = {0, 2, 2, 1};
    EXPECT_THROW(refine_uniform(repeated, 1), InvalidInput);

    QuadMesh flipped = cube();
    std::swap(flipped.quads[2][1], flipped.quads[2][3]);  // orientation inconsistent with neighbours
    EXPECT_THROW(refine_uniform(flipped, 1), InvalidInput);

    // A level-0 handle (design.md §3): two quads with the same four corners make 2-gon edges.
    QuadMesh handle;
    handle.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    handle.quads = {{0, 1, 2, 3}, {1, 0, 3, 2}, {0, 1, 2, 3}};
    EXPECT_THROW(refine_uniform(handle, 1), InvalidInput);

    QuadMesh nan = cube();
    nan.points[5].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(limit_positions(nan, 2), InvalidInput);

    QuadMesh unused = cube();
    unused.points.push_back({5, 5, 5});
    EXPECT_THROW(refine_uniform(unused, 1), InvalidInput);

    // The rejected-input messages name what is wrong.
    try {
        refine_uniform(bad_index, 1);
        FAIL() << "expected InvalidInput";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("quad 3"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace quadcage::subdiv

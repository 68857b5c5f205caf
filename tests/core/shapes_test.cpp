#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "quadcage/core/errors.h"
#include "quadcage/core/mesh.h"

namespace quadcage {
namespace {

using shapes::PlateOptions;

constexpr double kPi = 3.14159265358979323846;

std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
}

int find_root(std::vector<int>& parent, int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

// Checks, from the triangles alone, every property shapes.h promises, and that the Euler
// characteristic V - E + F equals 2 - 2*genus.
::testing::AssertionResult is_closed_oriented_manifold(const Mesh& mesh, int genus) {
    const int nv = mesh.num_vertices(), nt = mesh.num_triangles();
    if (nv == 0 || nt == 0) return ::testing::AssertionFailure() << "empty mesh";

    for (int t = 0; t < nt; ++t) {
        const Triangle& tri = mesh.triangles[t];
        for (int v : tri)
            if (v < 0 || v >= nv)
                return ::testing::AssertionFailure() << "triangle " << t << " index out of range";
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            return ::testing::AssertionFailure() << "triangle " << t << " repeats a vertex";
    }

    // Every directed edge used once and its reverse present: closed, edge-manifold, oriented.
    std::unordered_map<std::uint64_t, int> directed;
    directed.reserve(3 * static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) {
            const int a = mesh.triangles[t][c], b = mesh.triangles[t][(c + 1) % 3];
            if (!directed.emplace(edge_key(a, b), t).second)
                return ::testing::AssertionFailure()
                       << "directed edge " << a << "->" << b << " used twice (non-manifold or "
                       << "inconsistent orientation)";
        }
    for (const auto& [key, t] : directed) {
        const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
        if (!directed.count(edge_key(b, a)))
            return ::testing::AssertionFailure() << "edge " << a << "-" << b << " is a boundary";
    }

    // Vertex-manifold: around v, triangle (v, a, b) links a -> b; these links must form one cycle.
    std::vector<std::vector<std::pair<int, int>>> fan(nv);
    for (const Triangle& tri : mesh.triangles)
        for (int c = 0; c < 3; ++c) fan[tri[c]].push_back({tri[(c + 1) % 3], tri[(c + 2) % 3]});
    for (int v = 0; v < nv; ++v) {
        if (fan[v].empty()) return ::testing::AssertionFailure() << "vertex " << v << " unused";
        std::unordered_map<int, int> next;
        for (const auto& [a, b] : fan[v]) next[a] = b;
        int steps = 0, cur = fan[v].front().first;
        do {
            const auto it = next.find(cur);
            if (it == next.end()) return ::testing::AssertionFailure() << "open fan at " << v;
            cur = it->second;
            ++steps;
        } while (cur != fan[v].front().first && steps <= static_cast<int>(fan[v].size()));
        if (steps != static_cast<int>(fan[v].size()))
            return ::testing::AssertionFailure()
                   << "vertex " << v << " is not manifold (" << fan[v].size()
                   << " triangles, fan of " << steps << ")";
    }

    std::vector<int> parent(nv);
    std::iota(parent.begin(), parent.end(), 0);
    for (const Triangle& tri : mesh.triangles)
        for (int c = 1; c < 3; ++c) parent[find_root(parent, tri[c])] = find_root(parent, tri[0]);
    for (int v = 0; v < nv; ++v)
        if (find_root(parent, v) != find_root(parent, 0))
            return ::testing::AssertionFailure() << "more than one connected component";

    const long long edges = static_cast<long long>(directed.size()) / 2;
    const long long euler = static_cast<long long>(nv) - edges + nt;
    if (euler != 2 - 2LL * genus)
        return ::testing::AssertionFailure()
               << "Euler characteristic " << euler << ", expected " << 2 - 2 * genus;

    std::vector<Vec3> sorted = mesh.points;
    std::sort(sorted.begin(), sorted.end(), [](const Vec3& a, const Vec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    });
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        return ::testing::AssertionFailure() << "duplicate vertex positions";

    const double diag = bounding_box(mesh).diagonal();
    double volume = 0;
    for (int t = 0; t < nt; ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vec3 &a = mesh.points[tri[0]], &b = mesh.points[tri[1]], &c = mesh.points[tri[2]];
        if (!is_finite(a) || !(triangle_area(mesh, t) > 1e-12 * diag * diag))
            return ::testing::AssertionFailure() << "triangle " << t << " is degenerate";
        volume += dot(a, cross(b, c)) / 6.0;
    }
    if (!(volume > 0)) return ::testing::AssertionFailure() << "signed volume " << volume;
    return ::testing::AssertionSuccess();
}

Mesh tetrahedron(Vec3 offset) {
    Mesh m;
    m.points = {offset + Vec3{0, 0, 0}, offset + Vec3{1, 0, 0}, offset + Vec3{0, 1, 0},
                offset + Vec3{0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    return m;
}

Mesh merged(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    for (const Vec3& p : b.points) m.points.push_back(p);
    for (Triangle t : b.triangles) {
        for (int& v : t) v += a.num_vertices();
        m.triangles.push_back(t);
    }
    return m;
}

// The checker must itself reject what it is meant to catch, or the sweeps below prove nothing.
TEST(ShapesChecker, RejectsBrokenMeshes) {
    const Mesh tet = tetrahedron({0, 0, 0});
    EXPECT_TRUE(is_closed_oriented_manifold(tet, 0));
    EXPECT_FALSE(is_closed_oriented_manifold(tet, 1));  // wrong Euler characteristic

    Mesh flipped = tet;
    std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
    EXPECT_FALSE(is_closed_oriented_manifold(flipped, 0));

    Mesh inside_out = tet;
    for (Triangle& t : inside_out.triangles) std::swap(t[1], t[2]);
    EXPECT_FALSE(is_closed_oriented_manifold(inside_out, 0));  // negative volume

    Mesh open = tet;
    open.triangles.pop_back();
    EXPECT_FALSE(is_closed_oriented_manifold(open, 0));

    Mesh unused = tet;
    unused.points.push_back({5, 5, 5});
    EXPECT_FALSE(is_closed_oriented_manifold(unused, 0));

    Mesh duplicate = tet;
    duplicate.points[3] = duplicate.points[0];
    EXPECT_FALSE(is_closed_oriented_manifold(duplicate, 0));

    Mesh flat = tet;
    flat.points[3] = {1.0 / 3, 1.0 / 3, 0};
    EXPECT_FALSE(is_closed_oriented_manifold(flat, 0));  // zero volume

    Mesh degenerate = tet;
    degenerate.points[3] = {0.5, 0, 0};  // on edge 0-1: triangle {0, 1, 3} has zero area
    EXPECT_FALSE(is_closed_oriented_manifold(degenerate, 0));

    // Two tetrahedra apart: Euler characteristic 4 (= 2 - 2*(-1)), caught as two components.
    const auto apart = is_closed_oriented_manifold(merged(tet, tetrahedron({3, 0, 0})), -1);
    EXPECT_FALSE(apart);
    EXPECT_NE(std::string(apart.message()).find("component"), std::string::npos);

    // Two tetrahedra sharing one vertex: caught by the fan walk.
    Mesh pinched = merged(tet, tetrahedron({1, 0, 0}));  // its vertex 0 sits on tet's vertex 1
    for (Triangle& t : pinched.triangles)
        for (int& v : t) {
            if (v == 4)
                v = 1;
            else if (v > 4)
                --v;
        }
    pinched.points.erase(pinched.points.begin() + 4);
    const auto pinch = is_closed_oriented_manifold(pinched, 0);
    EXPECT_FALSE(pinch);
    EXPECT_NE(std::string(pinch.message()).find("not manifold"), std::string::npos);
}

long long expected_plate_triangles(int genus, const PlateOptions& o) {
    int cols = 0;
    while (cols * cols < genus) ++cols;
    const int rows = cols == 0 ? 0 : (genus + cols - 1) / cols;
    const long long w = 2 * cols + 1, h = 2 * rows + 1, res = o.resolution;
    const long long layers = std::max(1L, std::lround(o.thickness * o.resolution));
    return 4 * res * res * (w * h - genus) + 2 * res * layers * (2 * (w + h) + 4 * genus);
}

// ---------------------------------------------------------------------------------------------

class ShapesPlate : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(ShapesPlate, ClosedManifoldOfRequestedGenus) {
    const auto [genus, bend] = GetParam();
    PlateOptions options;
    options.bend = bend;
    const Mesh mesh = shapes::plate_with_holes(genus, options);
    EXPECT_TRUE(is_closed_oriented_manifold(mesh, genus));
    EXPECT_EQ(mesh.num_triangles(), expected_plate_triangles(genus, options));
}

INSTANTIATE_TEST_SUITE_P(ShapesGenus0To40, ShapesPlate,
                         ::testing::Combine(::testing::Range(0, 41), ::testing::Bool()),
                         [](const auto& info) {
                             return "g" + std::to_string(std::get<0>(info.param)) +
                                    (std::get<1>(info.param) ? "_bent" : "_flat");
                         });

TEST(ShapesPlateOptions, OtherResolutionsAndThicknesses) {
    for (int res : {1, 3, 4})
        for (double thickness : {0.2, 0.6, 1.5})
            for (bool bend : {false, true})
                for (int genus : {0, 1, 3, 7}) {
                    PlateOptions o;
                    o.resolution = res;
                    o.thickness = thickness;
                    o.bend = bend;
                    SCOPED_TRACE(::testing::Message() << "res=" << res << " t=" << thickness
                                                      << " bend=" << bend << " g=" << genus);
                    const Mesh mesh = shapes::plate_with_holes(genus, o);
                    EXPECT_TRUE(is_closed_oriented_manifold(mesh, genus));
                    EXPECT_EQ(mesh.num_triangles(), expected_plate_triangles(genus, o));
                }
}

TEST(ShapesPlateOptions, DefaultGenus20StaysSmall) {
    const Mesh mesh = shapes::plate_with_holes(20);
    EXPECT_LE(mesh.num_triangles(), 20000);
    EXPECT_EQ(mesh.num_triangles(), 1744);
}

TEST(ShapesPlateLayout, FlatBoundingBoxMatchesDocumentedLayout) {
    PlateOptions o;
    o.bend = false;
    // {genus, W, H}: W = 2*ceil(sqrt(g)) + 1, H = 2*ceil(g/cols) + 1.
    const int cases[][3] = {{0, 1, 1},  {1, 3, 3},  {2, 5, 3},  {3, 5, 5},
                            {5, 7, 5},  {12, 9, 7}, {20, 11, 9}};
    for (const auto& c : cases) {
        const BoundingBox box = bounding_box(shapes::plate_with_holes(c[0], o));
        SCOPED_TRACE(::testing::Message() << "genus " << c[0]);
        EXPECT_EQ(box.min.x, 0.0);
        EXPECT_EQ(box.min.y, 0.0);
        EXPECT_EQ(box.min.z, 0.0);
        EXPECT_EQ(box.max.x, c[1]);
        EXPECT_EQ(box.max.y, c[2]);
        EXPECT_EQ(box.max.z, o.thickness);
    }
}

TEST(ShapesPlateLayout, FlatHolesAreWhereDocumented) {
    PlateOptions o;
    o.bend = false;
    const int genus = 5;  // cols = 3, rows = 2: hole 5's slot (column 2, row 1) stays solid
    const Mesh mesh = shapes::plate_with_holes(genus, o);
    // With resolution 2 a slot's centre is a grid point: it carries top and bottom vertices only
    // if the slot is solid; a hole's mid-edge points carry wall vertices at both heights.
    auto has_vertex = [&](double x, double y, double z) {
        return std::any_of(mesh.points.begin(), mesh.points.end(),
                           [&](const Vec3& p) { return p == Vec3{x, y, z}; });
    };
    for (int k = 0; k < 6; ++k) {
        const int c = k % 3, r = k / 3;
        const double x0 = 2 * c + 1, y0 = 2 * r + 1;
        SCOPED_TRACE(::testing::Message() << "slot " << k);
        EXPECT_EQ(has_vertex(x0 + 0.5, y0 + 0.5, o.thickness), k >= genus);
        EXPECT_EQ(has_vertex(x0 + 0.5, y0 + 0.5, 0.0), k >= genus);
        EXPECT_TRUE(has_vertex(x0 + 0.5, y0, 0.0));
        EXPECT_TRUE(has_vertex(x0 + 0.5, y0, o.thickness));
    }
}

// Length, in `eval`, of the closed edge path through the vertices of `flat` that satisfy `pick`,
// ordered by angle around `centre` in the plane of coordinates (u, w). Fails if consecutive
// vertices are not joined by a mesh edge.
double loop_length(const Mesh& flat, const Mesh& eval, int u, int w, double cu, double cw,
                   const std::function<bool(const Vec3&)>& pick, std::string* error) {
    std::vector<int> loop;
    for (int v = 0; v < flat.num_vertices(); ++v)
        if (pick(flat.points[v])) loop.push_back(v);
    std::sort(loop.begin(), loop.end(), [&](int a, int b) {
        const Vec3 &p = flat.points[a], &q = flat.points[b];
        return std::atan2(p[w] - cw, p[u] - cu) < std::atan2(q[w] - cw, q[u] - cu);
    });
    std::unordered_map<std::uint64_t, int> edges;
    for (const Triangle& t : flat.triangles)
        for (int c = 0; c < 3; ++c) edges[edge_key(t[c], t[(c + 1) % 3])] = 1;
    double length = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
        const int a = loop[i], b = loop[(i + 1) % loop.size()];
        if (!edges.count(edge_key(a, b))) *error = "loop vertices are not joined by an edge";
        length += norm(eval.points[b] - eval.points[a]);
    }
    if (loop.size() < 4) *error = "loop too short";
    return length;
}

TEST(ShapesPlateLayout, TightCyclesHaveDocumentedLength) {
    for (int genus : {1, 2, 5, 12, 20}) {
        for (double thickness : {0.6, 0.25}) {
            PlateOptions flat_options;
            flat_options.bend = false;
            flat_options.thickness = thickness;
            PlateOptions bent_options = flat_options;
            bent_options.bend = true;
            const Mesh flat = shapes::plate_with_holes(genus, flat_options);
            const Mesh bent = shapes::plate_with_holes(genus, bent_options);
            ASSERT_EQ(flat.triangles, bent.triangles);  // documented: same order, moved points
            SCOPED_TRACE(::testing::Message() << "genus " << genus << " t " << thickness);
            const double t = thickness, bar = 2 * (1 + t);
            std::string error;

            // Bar below hole 0 (between it and the rim), cut by the planes x = 1 and x = 1.5.
            for (double x : {1.0, 1.5}) {
                auto pick = [x](const Vec3& p) { return p.x == x && p.y <= 1.0; };
                EXPECT_NEAR(loop_length(flat, flat, 1, 2, 0.5, t / 2, pick, &error), bar, 1e-12);
                EXPECT_NEAR(loop_length(flat, bent, 1, 2, 0.5, t / 2, pick, &error), bar,
                            0.01 * bar);
            }
            // Bar left of hole 0 (the y = 1.5 cut crosses the bending direction).
            {
                auto pick = [](const Vec3& p) { return p.y == 1.5 && p.x <= 1.0; };
                EXPECT_NEAR(loop_length(flat, flat, 0, 2, 0.5, t / 2, pick, &error), bar, 1e-12);
                EXPECT_NEAR(loop_length(flat, bent, 0, 2, 0.5, t / 2, pick, &error), bar,
                            0.01 * bar);
            }
            // Bar between the last hole and the one before it, in its row (genus >= 2).
            if (genus >= 2) {
                int cols = 0;
                while (cols * cols < genus) ++cols;
                const int k = genus - 1, c = k % cols, r = k / cols;
                if (c > 0) {
                    const double x0 = 2 * c, y = 2 * r + 1.5;
                    auto pick = [x0, y](const Vec3& p) {
                        return p.y == y && p.x >= x0 && p.x <= x0 + 1;
                    };
                    EXPECT_NEAR(loop_length(flat, flat, 0, 2, x0 + 0.5, t / 2, pick, &error), bar,
                                1e-12);
                    EXPECT_NEAR(loop_length(flat, bent, 0, 2, x0 + 0.5, t / 2, pick, &error), bar,
                                0.01 * bar);
                }
            }
            // Rim of hole 0 on the bottom and top faces: length 4, changed by the bend by about
            // t/rho (plus a little for the shears).
            const double width = bounding_box(flat).max.x;  // W
            const double rho = std::max(3 * width / kPi, t + 1);
            for (double z : {0.0, t}) {
                auto pick = [z](const Vec3& p) {
                    return p.z == z && p.x >= 1 && p.x <= 2 && p.y >= 1 && p.y <= 2 &&
                           (p.x == 1 || p.x == 2 || p.y == 1 || p.y == 2);
                };
                EXPECT_NEAR(loop_length(flat, flat, 0, 1, 1.5, 1.5, pick, &error), 4.0, 1e-12);
                const double bent_length = loop_length(flat, bent, 0, 1, 1.5, 1.5, pick, &error);
                EXPECT_NEAR(bent_length, 4.0, t / rho + 0.02);
                if (z == 0) {
                    EXPECT_LT(bent_length, 4.0);
                }
            }
            EXPECT_EQ(error, "");
        }
    }
}

TEST(ShapesPlateLayout, BendMovesThePlateOffTheAxes) {
    const Mesh flat = shapes::plate_with_holes(4, PlateOptions{2, 0.6, false});
    const Mesh bent = shapes::plate_with_holes(4, PlateOptions{2, 0.6, true});
    // Count triangles whose normal is axis-aligned (one coordinate carries all of it).
    auto aligned = [](const Mesh& m) {
        int n = 0;
        for (const Triangle& t : m.triangles) {
            const Vec3& a = m.points[t[0]];
            const Vec3 nrm = cross(m.points[t[1]] - a, m.points[t[2]] - a);
            const double len = norm(nrm);
            for (int k = 0; k < 3; ++k)
                if (std::abs(std::abs(nrm[k]) - len) < 1e-9 * len) ++n;
        }
        return n;
    };
    EXPECT_EQ(aligned(flat), flat.num_triangles());
    EXPECT_LT(aligned(bent), bent.num_triangles() / 20);
}

// ---------------------------------------------------------------------------------------------

class ShapesIcosphere : public ::testing::TestWithParam<int> {};

TEST_P(ShapesIcosphere, ClosedSphereOnTheSphere) {
    const int n = GetParam();
    const double radius = 2.5;
    const Mesh mesh = shapes::icosphere(n, radius);
    EXPECT_EQ(mesh.num_triangles(), 20 * (1 << (2 * n)));
    EXPECT_EQ(mesh.num_vertices(), 10 * (1 << (2 * n)) + 2);
    EXPECT_TRUE(is_closed_oriented_manifold(mesh, 0));
    for (const Vec3& p : mesh.points) EXPECT_NEAR(norm(p), radius, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(ShapesSubdivisions0To4, ShapesIcosphere, ::testing::Range(0, 5));

TEST(ShapesIcosphereDefaults, UnitRadius) {
    for (const Vec3& p : shapes::icosphere(1).points) EXPECT_NEAR(norm(p), 1.0, 1e-12);
}

class ShapesTorus : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(ShapesTorus, ClosedGenusOne) {
    const auto [n_major, n_minor] = GetParam();
    const Mesh mesh = shapes::torus(n_major, n_minor, 2.0, 0.5);
    EXPECT_EQ(mesh.num_triangles(), 2 * n_major * n_minor);
    EXPECT_EQ(mesh.num_vertices(), n_major * n_minor);
    EXPECT_TRUE(is_closed_oriented_manifold(mesh, 1));
    for (const Vec3& p : mesh.points) {
        const double ring = std::hypot(p.x, p.y) - 2.0;
        EXPECT_NEAR(std::hypot(ring, p.z), 0.5, 1e-12);
    }
}

INSTANTIATE_TEST_SUITE_P(ShapesSizes, ShapesTorus,
                         ::testing::Values(std::make_tuple(3, 3), std::make_tuple(4, 3),
                                           std::make_tuple(3, 7), std::make_tuple(16, 8),
                                           std::make_tuple(48, 24), std::make_tuple(7, 40)));

TEST(ShapesTorusDefaults, DefaultRadii) {
    EXPECT_TRUE(is_closed_oriented_manifold(shapes::torus(24, 12), 1));
}

// ---------------------------------------------------------------------------------------------

TEST(ShapesBadArguments, ThrowInvalidInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_THROW(shapes::icosphere(-1), InvalidInput);
    EXPECT_THROW(shapes::icosphere(11), InvalidInput);
    EXPECT_THROW(shapes::icosphere(1, 0.0), InvalidInput);
    EXPECT_THROW(shapes::icosphere(1, -1.0), InvalidInput);
    EXPECT_THROW(shapes::icosphere(1, nan), InvalidInput);

    EXPECT_THROW(shapes::torus(2, 8), InvalidInput);
    EXPECT_THROW(shapes::torus(8, 2), InvalidInput);
    EXPECT_THROW(shapes::torus(8, 8, 1.0, 1.0), InvalidInput);
    EXPECT_THROW(shapes::torus(8, 8, 1.0, 2.0), InvalidInput);
    EXPECT_THROW(shapes::torus(8, 8, 1.0, 0.0), InvalidInput);
    EXPECT_THROW(shapes::torus(8, 8, inf, 0.5), InvalidInput);
    EXPECT_THROW(shapes::torus(100000, 100000), InvalidInput);

    EXPECT_THROW(shapes::plate_with_holes(-1), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{0, 0.6, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{-3, 0.6, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{2, 0.0, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{2, -0.5, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{2, nan, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{2, 1e300, true}), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(std::numeric_limits<int>::max()), InvalidInput);
    EXPECT_THROW(shapes::plate_with_holes(1, PlateOptions{1 << 20, 0.6, true}), InvalidInput);
}

}  // namespace
}  // namespace quadcage

namespace quadcage {
namespace {

TEST(ShapesLimbs, ClosedGenusZeroDeterministicAndLimbsReachOut) {
    for (unsigned seed : {1u, 7u, 23u}) {
        shapes::LimbOptions o;
        o.seed = seed;
        o.limbs = 5;
        const Mesh m = shapes::body_with_limbs(o);
        EXPECT_EQ(m.num_triangles(), 20 * 256);
        const ValidationReport r = validate(m);
        ASSERT_TRUE(r.quaddable()) << r.error_summary();
        ASSERT_EQ(r.components.size(), 1u);
        EXPECT_EQ(r.components[0].genus, 0);
        // The body is about 1.3 across; limbs reach at least 1 body radius further out.
        double reach = 0;
        for (const Vec3& p : m.points) reach = std::max(reach, norm(p));
        EXPECT_GT(reach, 2.0) << "seed " << seed;
        const Mesh again = shapes::body_with_limbs(o);
        EXPECT_EQ(again.points, m.points);
    }
    shapes::LimbOptions none;
    none.limbs = 0;
    EXPECT_EQ(validate(shapes::body_with_limbs(none)).components[0].genus, 0);
    shapes::LimbOptions bad;
    bad.limbs = 33;
    EXPECT_THROW(shapes::body_with_limbs(bad), InvalidInput);
}

TEST(ShapesHandles, ClosedManifoldOfTheGenusAskedDeterministicBigBodySmallHandles) {
    for (bool row : {false, true})
        for (int g : {0, 1, 2, 3, 5, 9}) {
            shapes::HandleBodyOptions o;
            o.handles = g;
            o.in_a_row = row;
            o.resolution = 2;
            const Mesh m = shapes::body_with_handles(o);
            const ValidationReport r = validate(m);
            ASSERT_TRUE(r.quaddable()) << "genus " << g << (row ? " in a row: " : ": ") << r.error_summary();
            ASSERT_EQ(r.components.size(), 1u);
            EXPECT_EQ(r.components[0].genus, g) << (row ? "in a row" : "spread");
            EXPECT_EQ(shapes::body_with_handles(o).points, m.points);
            // The body is a ball at least 8 cells across (more when the handles need room); the
            // handles stand at most two cells above its top: small against the body.
            const BoundingBox box = bounding_box(m);
            const double across = box.max.x - box.min.x, high = box.max.z - box.min.z;
            EXPECT_GT(across, 7.5);
            EXPECT_LT(high - across, 3.5) << "genus " << g;
        }
    shapes::HandleBodyOptions bad;
    bad.handles = 65;
    EXPECT_THROW(shapes::body_with_handles(bad), InvalidInput);
    bad.handles = 1;
    bad.resolution = 1;
    EXPECT_THROW(shapes::body_with_handles(bad), InvalidInput);
}

// A body with handles given relief (bumps, fins) against the same body without: checks it is closed,
// manifold, of the same genus, the same for the same options and the same voxels moved; returns
// how far its vertices moved at most, overall and within `top_depth` of the top (the handles).
std::array<double, 2> relief_moves(const shapes::HandleBodyOptions& plain, const shapes::HandleBodyOptions& o,
                                   double top_depth) {
    const Mesh ball = shapes::body_with_handles(plain), m = shapes::body_with_handles(o);
    const ValidationReport r = validate(m);
    EXPECT_TRUE(r.quaddable()) << r.error_summary();
    if (!r.quaddable() || m.points.size() != ball.points.size()) {
        ADD_FAILURE() << "not the same voxels moved";
        return {0, 0};
    }
    EXPECT_EQ(r.components[0].genus, plain.handles);
    EXPECT_EQ(shapes::body_with_handles(o).points, m.points);
    std::array<double, 2> moved{0, 0};
    const double top = bounding_box(ball).max.z;
    for (size_t v = 0; v < m.points.size(); ++v) {
        const double d = norm(m.points[v] - ball.points[v]);
        moved[0] = std::max(moved[0], d);
        if (ball.points[v].z > top - top_depth) moved[1] = std::max(moved[1], d);
    }
    return moved;
}

// With bumps the body has relief of its own (issue #20's genus-1 figure, whose body carries the
// detail): still closed, manifold, of the genus asked and the same for the same seed; the relief
// changes the body below the top and leaves the handles on the top where they were.
TEST(ShapesHandles, BumpsGiveTheBodyReliefAndKeepTheHandles) {
    shapes::HandleBodyOptions plain;
    plain.handles = 1;
    plain.resolution = 2;
    for (unsigned seed : {1u, 2u, 3u}) {
        shapes::HandleBodyOptions o = plain;
        o.bumps = 12;
        o.seed = seed;
        const std::array<double, 2> moved = relief_moves(plain, o, 1.0);  // the handles' cell
        EXPECT_GT(moved[0], 0.5) << "seed " << seed;
        EXPECT_EQ(moved[1], 0.0) << "seed " << seed;
    }
    shapes::HandleBodyOptions bad = plain;
    bad.bumps = 65;
    EXPECT_THROW(shapes::body_with_handles(bad), InvalidInput);
}

// The vertices of a figure pushed out past `radius` (one protrusion's, where there is one) and the
// square roots of their covariance's eigenvalues, least first: their spread across and along.
std::array<double, 3> spread_beyond(const Mesh& m, double radius) {
    std::vector<Vec3> far;
    for (const Vec3& p : m.points)
        if (norm(p) > radius) far.push_back(p);
    if (far.size() < 10) return {0, 0, 0};
    Vec3 mean{0, 0, 0};
    for (const Vec3& p : far) mean = mean + p / static_cast<double>(far.size());
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    for (const Vec3& p : far) {
        const Eigen::Vector3d q(p.x - mean.x, p.y - mean.y, p.z - mean.z);
        c += q * q.transpose() / static_cast<double>(far.size());
    }
    const Eigen::Vector3d e = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c, Eigen::EigenvaluesOnly).eigenvalues();
    return {std::sqrt(std::max(e[0], 0.0)), std::sqrt(std::max(e[1], 0.0)), std::sqrt(std::max(e[2], 0.0))};
}

// Fins (issue 20's long protrusions, the flat kind): a figure with one fin and no limb is closed,
// of genus 0 and the same for the same seed, and what sticks out is flat, where a limb is round:
// across the protrusion its spread one way is a fraction of the other's. Fins are drawn after the
// limbs, so adding them leaves a figure's limbs where they were.
TEST(ShapesLimbs, FinsAreFlatWhereLimbsAreRound) {
    for (unsigned seed : {1u, 2u, 3u, 4u}) {
        shapes::LimbOptions fin;
        fin.seed = seed;
        fin.limbs = 0;
        fin.fins = 1;
        fin.subdivisions = 5;
        const Mesh m = shapes::body_with_limbs(fin);
        const ValidationReport r = validate(m);
        ASSERT_TRUE(r.quaddable()) << r.error_summary();
        EXPECT_EQ(r.components[0].genus, 0);
        EXPECT_EQ(shapes::body_with_limbs(fin).points, m.points);
        shapes::LimbOptions limb = fin;
        limb.limbs = 1;
        limb.fins = 0;
        // The body reaches about 1.4 from its centre; both protrusions are at least a body radius long.
        const std::array<double, 3> f = spread_beyond(m, 1.8), l = spread_beyond(shapes::body_with_limbs(limb), 1.8);
        ASSERT_GT(f[2], 0.0) << "seed " << seed;
        ASSERT_GT(l[2], 0.0) << "seed " << seed;
        // Seeds 1-12 gave 0.12-0.39 for a fin and 0.64-0.93 for a limb (the figure's squash into an
        // uneven ellipsoid keeps a limb from being quite round).
        EXPECT_LT(f[0] / f[1], 0.45) << "seed " << seed << ": " << f[0] / f[1];  // a fin: thin one way across
        EXPECT_GT(l[0] / l[1], 0.55) << "seed " << seed << ": " << l[0] / l[1];  // a limb: round
    }
    shapes::LimbOptions limbs;
    limbs.limbs = 3;
    shapes::LimbOptions both = limbs;
    both.fins = 2;
    const Mesh a = shapes::body_with_limbs(limbs), b = shapes::body_with_limbs(both);
    ASSERT_EQ(a.points.size(), b.points.size());
    size_t unmoved = 0;  // the limbs are the same: only the fins' vertices move
    for (size_t v = 0; v < a.points.size(); ++v) unmoved += a.points[v] == b.points[v];
    EXPECT_GT(unmoved, a.points.size() / 2);
    shapes::LimbOptions bad;
    bad.fins = 17;
    EXPECT_THROW(shapes::body_with_limbs(bad), InvalidInput);
}

// Fins on a body with handles (a creature with fins and handles): closed, manifold, of the genus
// asked, the same for the same seed; they reach out from the body below its top and leave the
// handles where they were.
TEST(ShapesHandles, FinsReachOutAndKeepTheHandles) {
    shapes::HandleBodyOptions plain;
    plain.handles = 3;
    plain.resolution = 2;
    const BoundingBox box = bounding_box(shapes::body_with_handles(plain));
    const double radius = 0.5 * (box.max.x - box.min.x);
    for (unsigned seed : {1u, 2u}) {
        shapes::HandleBodyOptions o = plain;
        o.fins = 3;
        o.seed = seed;
        const std::array<double, 2> moved = relief_moves(plain, o, 2.0);  // the handles' two cells
        EXPECT_GT(moved[0], 0.8 * radius) << "seed " << seed;  // fins 1-2 radii long, at their axis
        EXPECT_EQ(moved[1], 0.0) << "seed " << seed;
    }
    shapes::HandleBodyOptions bad = plain;
    bad.fins = 17;
    EXPECT_THROW(shapes::body_with_handles(bad), InvalidInput);
}

// input_wheel's class (issue 20): holes in a ring round an axle through a hub. Closed, manifold, of
// genus holes + 1 at every resolution and rib count, the same bits for the same options; at least
// 20 cells across and, with the hub two cells proud of the one-cell disc, about 3 cells high.
TEST(ShapesWheel, ClosedManifoldOfGenusHolesPlusOneDeterministic) {
    for (int res : {2, 3})
        for (int ribs : {0, 16})
            for (int holes : {0, 1, 2, 5, 10}) {
                shapes::WheelOptions o;
                o.holes = holes;
                o.resolution = res;
                o.ribs = ribs;
                const Mesh m = shapes::wheel(o);
                const ValidationReport r = validate(m);
                const std::string what = "holes " + std::to_string(holes) + ", ribs " + std::to_string(ribs) +
                                         ", resolution " + std::to_string(res);
                ASSERT_TRUE(r.quaddable()) << what << ": " << r.error_summary();
                ASSERT_EQ(r.components.size(), 1u) << what;
                EXPECT_EQ(r.components[0].genus, holes + 1) << what;
                EXPECT_EQ(shapes::wheel(o).points, m.points) << what;
                // The disc is at least 2 * (6 + 1.5 + 2.5) = 20 cells across; the hub makes it
                // about 3 cells high (Taubin's inflating step pushes sharp edges out a little:
                // up to 3.2 at 2 voxels a cell).
                const BoundingBox box = bounding_box(m);
                EXPECT_GT(box.max.x - box.min.x, 19.0) << what;
                EXPECT_GT(box.max.z - box.min.z, 2.5) << what;
                EXPECT_LT(box.max.z - box.min.z, 3.5) << what;
            }
    shapes::WheelOptions ribbed;
    ribbed.holes = 10;
    ribbed.ribs = 16;
    shapes::WheelOptions plain = ribbed;
    plain.ribs = 0;
    EXPECT_GT(shapes::wheel(ribbed).num_triangles(), shapes::wheel(plain).num_triangles());
    // Each option out of its range, the others at their defaults.
    const std::vector<std::function<void(shapes::WheelOptions*)>> out_of_range = {
        [](shapes::WheelOptions* w) { w->holes = 65; }, [](shapes::WheelOptions* w) { w->holes = -1; },
        [](shapes::WheelOptions* w) { w->resolution = 1; }, [](shapes::WheelOptions* w) { w->resolution = 17; },
        [](shapes::WheelOptions* w) { w->ribs = -1; }, [](shapes::WheelOptions* w) { w->smoothing = 201; }};
    for (const auto& make_bad : out_of_range) {
        shapes::WheelOptions w;
        make_bad(&w);
        EXPECT_THROW(shapes::wheel(w), InvalidInput);
    }
}

// A cube's faces tessellated as a CAD export (flat_faces_as_fans): split 1-to-4 three times, every
// vertex inside a face goes and those on its 12 edges stay (their rings are not flat), on the same
// surface.
TEST(ShapesFlatFacesAsFans, CubeKeepsOnlyTheVerticesOfItsEdges) {
    Mesh cube;
    for (int i = 0; i < 8; ++i)
        cube.points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    // Two outward triangles per face (corners listed counter-clockwise seen from outside).
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        cube.triangles.push_back({f[0], f[1], f[2]});
        cube.triangles.push_back({f[0], f[2], f[3]});
    }
    ASSERT_TRUE(validate(cube).quaddable());
    Mesh fine = cube;
    for (int i = 0; i < 3; ++i) fine = subdivide_midpoint(fine);
    const Mesh fans = shapes::flat_faces_as_fans(fine, 1e-9);
    const ValidationReport r = validate(fans);
    ASSERT_TRUE(r.quaddable()) << r.error_summary();
    EXPECT_EQ(r.components[0].genus, 0);
    EXPECT_EQ(fans.num_vertices(), 8 + 12 * 7);  // 8 segments an edge after three splits
    auto area = [](const Mesh& m) {
        double a = 0;
        for (const Triangle& t : m.triangles)
            a += 0.5 * norm(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
        return a;
    };
    EXPECT_NEAR(area(fans), 24.0, 1e-12);
    for (const Vec3& p : fans.points) {
        const int on_faces = (std::abs(std::abs(p.x) - 1) < 1e-15) + (std::abs(std::abs(p.y) - 1) < 1e-15) +
                             (std::abs(std::abs(p.z) - 1) < 1e-15);
        EXPECT_GE(on_faces, 2) << "a vertex inside a face stayed: " << p.x << " " << p.y << " " << p.z;
    }
}

// The wheel tessellated as a CAD export (issue 20: input_wheel's back face, fans of long, thin
// triangles): a subset of the smoothed wheel's vertices, the same genus (wheel() checks it), the
// same bits each time, and a large part of its area in thin triangles, which the smoothed wheel has
// none of.
TEST(ShapesWheel, CadTessellationHasFansOfThinTrianglesOnTheSameVertices) {
    shapes::WheelOptions o;
    o.holes = 6;
    const Mesh smooth = shapes::wheel(o);
    o.cad = true;
    const Mesh cad = shapes::wheel(o);
    EXPECT_EQ(shapes::wheel(o).points, cad.points);
    const ValidationReport r = validate(cad);
    ASSERT_TRUE(r.quaddable()) << r.error_summary();
    EXPECT_EQ(r.components[0].genus, 7);
    EXPECT_LT(cad.num_vertices(), smooth.num_vertices() * 3 / 4);
    std::vector<Vec3> kept = smooth.points;
    auto less = [](const Vec3& a, const Vec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    };
    std::sort(kept.begin(), kept.end(), less);
    for (const Vec3& p : cad.points) EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), p, less));
    // The share of the area in triangles whose longest edge is over 10 times their height.
    auto thin_share = [](const Mesh& m) {
        double thin = 0, all = 0;
        for (const Triangle& t : m.triangles) {
            const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
            const double area = 0.5 * norm(cross(b - a, c - a));
            const double longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
            all += area;
            if (longest * longest > 10 * 2 * area) thin += area;
        }
        return thin / all;
    };
    EXPECT_GT(thin_share(cad), 0.1);
    EXPECT_EQ(thin_share(smooth), 0.0);
}

}  // namespace
}  // namespace quadcage

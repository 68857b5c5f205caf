#include "quadcage/core/validate.h"

#include <gtest/gtest.h>

#include "support/names.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"

namespace quadcage {
namespace {

Mesh tetrahedron() {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

// Appends b to a (vertex indices shifted).
void append(Mesh& a, const Mesh& b, Vec3 offset = {}) {
    const int base = a.num_vertices();
    for (const Vec3& p : b.points) a.points.push_back(p + offset);
    for (Triangle t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

bool has_issue(const ValidationReport& r, const std::string& code, ValidationIssue::Severity s) {
    for (const ValidationIssue& i : r.issues)
        if (i.code == code && i.severity == s) return true;
    return false;
}

const auto kError = ValidationIssue::Severity::error;
const auto kWarning = ValidationIssue::Severity::warning;

TEST(Validate, ClosedTetrahedronIsGenusZero) {
    const ValidationReport r = validate(tetrahedron());
    ASSERT_EQ(r.components.size(), 1u);
    const ComponentReport& c = r.components[0];
    EXPECT_TRUE(c.closed);
    EXPECT_TRUE(c.manifold);
    EXPECT_TRUE(c.orientable);
    EXPECT_TRUE(c.consistently_oriented);
    EXPECT_EQ(c.euler_characteristic, 2);
    EXPECT_EQ(c.genus, 0);
    EXPECT_EQ(c.minimal_quads, 6);
    EXPECT_TRUE(r.quaddable());
    EXPECT_TRUE(r.issues.empty());
}

TEST(Validate, OpenSurfaceCountsBoundaryLoops) {
    Mesh m = tetrahedron();
    m.triangles.pop_back();
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.boundary_edges, 3);
    EXPECT_EQ(r.boundary_loops, 1);
    EXPECT_FALSE(r.components[0].closed);
    EXPECT_EQ(r.components[0].genus, 0);  // a disk
    EXPECT_EQ(r.components[0].minimal_quads, -1);
    EXPECT_FALSE(r.quaddable());
    EXPECT_TRUE(has_issue(r, "boundary", kError));
    EXPECT_NE(r.error_summary().find("1 loop"), std::string::npos) << r.error_summary();
}

TEST(Validate, PinchedVertexIsNonManifold) {
    Mesh m = tetrahedron();
    Mesh other = tetrahedron();
    // Second tetrahedron mirrored through vertex 0 so that both share only vertex 0.
    for (Vec3& p : other.points) p = p * -1.0;
    for (Triangle& t : other.triangles) std::swap(t[1], t[2]);
    append(m, other);
    for (Triangle& t : m.triangles)
        for (int& v : t)
            if (v == 4) v = 0;  // glue the two apexes
    m.points.erase(m.points.begin() + 4);
    for (Triangle& t : m.triangles)
        for (int& v : t)
            if (v > 4) --v;
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.non_manifold_vertices, 1);
    EXPECT_EQ(r.non_manifold_edges, 0);
    EXPECT_EQ(r.boundary_edges, 0);
    EXPECT_EQ(r.components.size(), 1u);
    EXPECT_EQ(r.components[0].euler_characteristic, 3);  // 2 + 2 - 1: genus is meaningless
    EXPECT_EQ(r.components[0].genus, -1);
    EXPECT_TRUE(has_issue(r, "non_manifold_vertex", kError));
    EXPECT_NE(r.error_summary().find("vertex 0"), std::string::npos) << r.error_summary();
}

TEST(Validate, ThreeTrianglesOnAnEdgeAreNonManifold) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.non_manifold_edges, 1);
    EXPECT_TRUE(has_issue(r, "non_manifold_edge", kError));
    EXPECT_NE(r.error_summary().find("edge 0-1"), std::string::npos) << r.error_summary();
    EXPECT_FALSE(r.quaddable());
}

TEST(Validate, FlippedTriangleIsInconsistentButOrientable) {
    Mesh m = tetrahedron();
    std::swap(m.triangles[1][1], m.triangles[1][2]);
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.inconsistently_oriented_edges, 3);
    EXPECT_TRUE(r.components[0].orientable);
    EXPECT_FALSE(r.components[0].consistently_oriented);
    EXPECT_TRUE(has_issue(r, "inconsistent_orientation", kWarning));
    EXPECT_TRUE(r.quaddable());
    EXPECT_EQ(orient_outward(m), 1);
    const ValidationReport fixed = validate(m);
    EXPECT_TRUE(fixed.components[0].consistently_oriented);
}

TEST(Validate, OrientOutwardTurnsAnInsideOutSphere) {
    Mesh m = shapes::icosphere(2);
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
    EXPECT_EQ(orient_outward(m), m.num_triangles());
    double volume = 0;
    for (const Triangle& t : m.triangles)
        volume += dot(m.points[t[0]], cross(m.points[t[1]], m.points[t[2]]));
    EXPECT_GT(volume, 0);
}

TEST(Validate, ProjectivePlaneIsNonOrientable) {
    // The 6-vertex triangulation of RP^2: closed, manifold, chi = 1.
    Mesh m;
    for (int i = 0; i < 6; ++i) m.points.push_back({std::cos(i * 1.0), std::sin(i * 1.0), 0.1 * i});
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1},
                   {1, 2, 4}, {2, 3, 5}, {3, 4, 1}, {4, 5, 2}, {5, 1, 3}};
    const ValidationReport r = validate(m);
    ASSERT_EQ(r.components.size(), 1u);
    EXPECT_TRUE(r.components[0].closed);
    EXPECT_TRUE(r.components[0].manifold);
    EXPECT_EQ(r.components[0].euler_characteristic, 1);
    EXPECT_FALSE(r.components[0].orientable);
    EXPECT_EQ(r.components[0].genus, -1);
    EXPECT_TRUE(has_issue(r, "non_orientable", kError));
    EXPECT_FALSE(r.quaddable());
    EXPECT_THROW(orient_outward(m), InvalidInput);
}

TEST(Validate, NonFiniteCoordinatesAreErrors) {
    Mesh m = tetrahedron();
    m.points[2].y = std::numeric_limits<double>::quiet_NaN();
    m.points[3].z = std::numeric_limits<double>::infinity();
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.non_finite_vertices, 2);
    EXPECT_TRUE(has_issue(r, "non_finite", kError));
    EXPECT_NE(r.error_summary().find("vertex 2"), std::string::npos) << r.error_summary();
    EXPECT_FALSE(r.quaddable());
}

TEST(Validate, OutOfRangeAndRepeatedIndicesAreErrors) {
    Mesh m = tetrahedron();
    m.triangles.push_back({0, 1, 7});
    m.triangles.push_back({-1, 1, 2});
    m.triangles.push_back({1, 1, 2});
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.out_of_range_triangles, 2);
    EXPECT_EQ(r.repeated_index_triangles, 1);
    EXPECT_TRUE(has_issue(r, "index_out_of_range", kError));
    EXPECT_TRUE(has_issue(r, "repeated_index", kError));
    EXPECT_NE(r.error_summary().find("triangle 4"), std::string::npos) << r.error_summary();
}

TEST(Validate, DuplicateTrianglesAreErrors) {
    Mesh m = tetrahedron();
    m.triangles.push_back({2, 1, 0});  // same vertex set as triangle 0, reversed
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.duplicate_triangles, 1);
    EXPECT_TRUE(has_issue(r, "duplicate_triangles", kError));
    EXPECT_FALSE(r.quaddable());
}

TEST(Validate, ZeroAreaTrianglesAndUnusedVerticesAreWarnings) {
    Mesh m;
    // A flat "tetrahedron" (all four points in the plane z = 0) with one zero-area triangle: the
    // triangle and the unused vertex are warnings; the flat whole is an error (issue 23: it
    // encloses no volume, ValidateDegenerate below).
    m.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {5, 5, 5}};
    m.triangles = {{0, 1, 3}, {1, 2, 3}, {0, 2, 1}, {0, 3, 2}};
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.zero_area_triangles, 1);
    EXPECT_EQ(r.unused_vertices, 1);
    EXPECT_TRUE(has_issue(r, "zero_area", kWarning));
    EXPECT_TRUE(has_issue(r, "unused_vertices", kWarning));
    EXPECT_TRUE(has_issue(r, "degenerate", kError));
    EXPECT_FALSE(r.quaddable());
}

TEST(Validate, EmptyMeshIsAnError) {
    const ValidationReport r = validate(Mesh{});
    EXPECT_FALSE(r.quaddable());
    EXPECT_TRUE(has_issue(r, "empty", kError));
}

TEST(Validate, ComponentsGetTheirOwnGenus) {
    Mesh m = shapes::torus(16, 8);
    append(m, shapes::icosphere(1), {5, 0, 0});
    append(m, shapes::plate_with_holes(3), {0, 10, 0});
    const ValidationReport r = validate(m);
    ASSERT_EQ(r.components.size(), 3u);
    EXPECT_EQ(r.components[0].genus, 1);
    EXPECT_EQ(r.components[1].genus, 0);
    EXPECT_EQ(r.components[2].genus, 3);
    EXPECT_EQ(r.components[0].minimal_quads, 4);
    EXPECT_EQ(r.components[1].minimal_quads, 6);
    EXPECT_EQ(r.components[2].minimal_quads, 20);
    EXPECT_TRUE(r.quaddable());
    EXPECT_TRUE(has_issue(r, "components", kWarning));

    std::vector<std::vector<int>> maps;
    const std::vector<Mesh> parts = split_components(m, &maps);
    ASSERT_EQ(parts.size(), 3u);
    for (size_t c = 0; c < parts.size(); ++c) {
        EXPECT_EQ(parts[c].num_triangles(), r.components[c].triangles);
        EXPECT_EQ(parts[c].num_vertices(), r.components[c].vertices);
        for (int v = 0; v < parts[c].num_vertices(); ++v) EXPECT_EQ(parts[c].points[v], m.points[maps[c][v]]);
        EXPECT_EQ(validate(parts[c]).components[0].genus, r.components[c].genus);
    }
}

TEST(Validate, RemoveUnusedVerticesKeepsOrder) {
    Mesh m = tetrahedron();
    m.points.insert(m.points.begin() + 1, Vec3{9, 9, 9});
    for (Triangle& t : m.triangles)
        for (int& v : t)
            if (v >= 1) ++v;
    const std::vector<int> map = remove_unused_vertices(m);
    EXPECT_EQ(map, (std::vector<int>{0, -1, 1, 2, 3}));
    EXPECT_EQ(m.num_vertices(), 4);
    EXPECT_TRUE(validate(m).issues.empty());
}

TEST(Validate, RequireQuaddableNamesTheInput) {
    Mesh m = tetrahedron();
    m.triangles.pop_back();
    try {
        require_quaddable(m, "holey.obj");
        FAIL() << "expected InvalidInput";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("holey.obj"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("open"), std::string::npos);
    }
    EXPECT_NO_THROW(require_quaddable(tetrahedron(), "tet"));
}

TEST(Validate, MinimalQuadCount) {
    EXPECT_EQ(minimal_quad_count(0), 6);
    EXPECT_EQ(minimal_quad_count(1), 4);
    EXPECT_EQ(minimal_quad_count(2), 10);
    EXPECT_EQ(minimal_quad_count(12), 110);
}

// The shared real meshes: genus as documented in their README, and the bad ones rejected.
struct SharedMeshCase {
    const char* file;
    int genus;  // -1: must be rejected
    const char* problem;
};

class ValidateShared : public ::testing::TestWithParam<SharedMeshCase> {};

TEST_P(ValidateShared, MatchesTheReadme) {
    const std::string dir = std::string(QUADCAGE_SHARED_DIR) + "/data/meshes/";
    const SharedMeshCase& c = GetParam();
    const std::string path = dir + c.file;
    if (!std::ifstream(path)) GTEST_SKIP() << "shared meshes not found at " << dir;
    const ValidationReport r = validate(read_mesh(path));
    if (c.genus >= 0) {
        ASSERT_TRUE(r.quaddable()) << r.error_summary();
        ASSERT_EQ(r.components.size(), 1u);
        EXPECT_EQ(r.components[0].genus, c.genus);
    } else {
        EXPECT_FALSE(r.quaddable());
        EXPECT_NE(r.error_summary().find(c.problem), std::string::npos) << r.error_summary();
    }
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, ValidateShared,
    ::testing::Values(SharedMeshCase{"bunny.obj", 0, ""}, SharedMeshCase{"igea.ply", 0, ""},
                      SharedMeshCase{"kitten.off", 1, ""}, SharedMeshCase{"torus.obj", 1, ""},
                      SharedMeshCase{"eight.off", 2, ""}, SharedMeshCase{"skull.obj", 2, ""},
                      SharedMeshCase{"3holes.off", 3, ""}, SharedMeshCase{"fertility.off", 4, ""},
                      SharedMeshCase{"botijo.off", 5, ""}, SharedMeshCase{"input_wheel.off", 11, ""},
                      SharedMeshCase{"boot.obj", 12, ""},
                      SharedMeshCase{"stanford-bunny.obj", -1, "5 loops"},
                      SharedMeshCase{"cow.obj", -1, "pinched"},
                      SharedMeshCase{"truck.obj", -1, "non-manifold"}),
    [](const ::testing::TestParamInfo<SharedMeshCase>& info) { return test::identifier(info.param.file); });

}  // namespace
}  // namespace quadcage

namespace quadcage {
namespace {

// Issue 23: degenerate geometry, scale and unwelded soups are rejected by validate() itself, so that
// `info` (which prints validate()) and `layout` (prepare_for_quadding()) agree.

Mesh scaled(Mesh m, double s, Vec3 axes = {1, 1, 1}) {
    for (Vec3& p : m.points) p = {p.x * s * axes.x, p.y * s * axes.y, p.z * s * axes.z};
    return m;
}

TEST(ValidateDegenerate, TetrahedronWithAllFourVerticesEqualIsRejected) {
    Mesh m = tetrahedron();
    for (Vec3& p : m.points) p = {0.5, 0.25, 2};
    const ValidationReport r = validate(m);
    EXPECT_FALSE(r.quaddable());
    ASSERT_TRUE(has_issue(r, "degenerate", kError)) << r.error_summary();
    EXPECT_NE(r.error_summary().find("zero area"), std::string::npos) << r.error_summary();
    EXPECT_THROW(prepare_for_quadding(m, "points.obj"), InvalidInput);
}

TEST(ValidateDegenerate, TetrahedronWithFourCoplanarVerticesIsRejected) {
    Mesh m = tetrahedron();
    m.points[3] = {1, 1, 0};  // in the plane z = 0 of the other three
    const ValidationReport r = validate(m);
    EXPECT_FALSE(r.quaddable());
    ASSERT_TRUE(has_issue(r, "degenerate", kError)) << r.error_summary();
    EXPECT_NE(r.error_summary().find("encloses no volume"), std::string::npos) << r.error_summary();
    try {
        prepare_for_quadding(m, "flat.obj");
        FAIL() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("flat.obj: cannot be quadded"), std::string::npos) << e.what();
    }
}

TEST(ValidateDegenerate, CollinearVerticesAreRejected) {
    Mesh m = tetrahedron();
    m.points = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
    const ValidationReport r = validate(m);
    EXPECT_TRUE(has_issue(r, "degenerate", kError)) << r.error_summary();
}

TEST(ValidateDegenerate, ThinSolidsAndTheRegularTetrahedronPass) {
    const ValidationReport tet = validate(tetrahedron());
    EXPECT_TRUE(tet.quaddable()) << tet.error_summary();
    EXPECT_NEAR(tet.components[0].volume, 1.0 / 6.0, 1e-15);
    // A sphere squashed to a 1000:1 disc still encloses a solid.
    const ValidationReport disc = validate(scaled(shapes::icosphere(2), 1.0, {1, 1, 1e-3}));
    EXPECT_TRUE(disc.quaddable()) << disc.error_summary();
    EXPECT_FALSE(disc.components[0].degenerate);
}

TEST(ValidateDegenerate, OneDegenerateComponentAmongGoodOnesIsNamed) {
    Mesh m = shapes::icosphere(1);
    Mesh flat = tetrahedron();
    flat.points[3] = {1, 1, 0};
    append(m, flat, {5, 0, 0});
    const ValidationReport r = validate(m);
    ASSERT_EQ(r.components.size(), 2u);
    EXPECT_FALSE(r.components[0].degenerate);
    EXPECT_TRUE(r.components[1].degenerate);
    EXPECT_NE(r.error_summary().find("component 1 encloses no volume"), std::string::npos) << r.error_summary();
}

TEST(ValidateScale, DiagonalsOutsideTheSupportedRangeAreRejected) {
    for (double s : {1e-150, 1e-40, 1e40, 1e150}) {
        const ValidationReport r = validate(scaled(shapes::icosphere(1), s));
        EXPECT_FALSE(r.quaddable()) << s;
        EXPECT_TRUE(has_issue(r, "scale", kError)) << s << ": " << r.error_summary();
        EXPECT_NE(r.error_summary().find("rescale"), std::string::npos) << r.error_summary();
    }
    for (double s : {1e-25, 1e25}) {
        const ValidationReport r = validate(scaled(shapes::icosphere(1), s));
        EXPECT_TRUE(r.quaddable()) << s << ": " << r.error_summary();
        EXPECT_TRUE(std::isfinite(r.components[0].area) && r.components[0].area > 0) << s;
    }
}

TEST(ValidateScale, CoordinatesNear1e308OverflowTheDiagonalAndAreRejected) {
    Mesh m = tetrahedron();
    for (Vec3& p : m.points) p = p * 1e308 + Vec3{-1e308, 0, 0};
    const ValidationReport r = validate(m);
    EXPECT_EQ(r.non_finite_vertices, 0);
    EXPECT_FALSE(std::isfinite(r.bbox_diagonal));
    EXPECT_TRUE(has_issue(r, "scale", kError)) << r.error_summary();
    EXPECT_NE(r.error_summary().find("overflows"), std::string::npos) << r.error_summary();
}

TEST(ValidateSoup, AnUnweldedClosedSurfaceGetsAHintToWeld) {
    // Every triangle of an icosahedron with its own three corners: 20 open components.
    const Mesh welded = shapes::icosphere(0);
    Mesh soup;
    for (const Triangle& t : welded.triangles) {
        const int base = soup.num_vertices();
        for (int v : t) soup.points.push_back(welded.points[v]);
        soup.triangles.push_back({base, base + 1, base + 2});
    }
    const ValidationReport r = validate(soup);
    EXPECT_EQ(r.components.size(), welded.triangles.size());
    ASSERT_TRUE(has_issue(r, "boundary", kError));
    EXPECT_NE(r.error_summary().find("merge coincident vertices"), std::string::npos) << r.error_summary();
    // An open surface whose vertices are all distinct gets no such hint.
    Mesh open = welded;
    open.triangles.pop_back();
    EXPECT_EQ(validate(open).error_summary().find("coincident"), std::string::npos);
}

}  // namespace
}  // namespace quadcage

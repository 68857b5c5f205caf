// Tests of the orthogonal system of cycles (paper §2: Definition 6, Corollary 1; design.md §4):
// generated solids of genus 0..20, the verifier on broken systems, the refined surface, determinism,
// cycle quality on plates with known tight cycles, the shared real meshes, and the CLI end to end
// against the independent Python checker.

#include "quadcage/layout/orthogonal_system.h"

#include <gtest/gtest.h>

#include "support/files.h"
#include "support/names.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;
using layout::build_orthogonal_system;
using layout::Cycle;
using layout::cycle_length;
using layout::OrthogonalSystem;
using layout::verify_orthogonal_system;
using test::closed_genus;
using test::have_shared_meshes;
using test::load_shared;
using test::python_unavailable;
using test::report_without_measurements;
using test::run_shell;
using test::shared_meshes_dir;
using test::shell_quoted;
using test::slurp;

fs::path scratch_dir() { return test::scratch_dir("quadcage_cycles_test_"); }

constexpr double kThickness = 0.6;                  // shapes::PlateOptions default
constexpr double kBarCycle = 2 * (1 + kThickness);  // tight cycle around a bar (shapes.h)
constexpr double kHoleCycle = 4;                    // tight cycle around a hole (shapes.h)

// ---------------------------------------------------------------------------------------------
// Meshes

Mesh plate(int genus, bool bend = true) {
    shapes::PlateOptions options;
    options.bend = bend;
    return shapes::plate_with_holes(genus, options);
}

double signed_volume(const Mesh& mesh) {
    double v = 0;
    for (const Triangle& t : mesh.triangles)
        v += dot(mesh.points[t[0]], cross(mesh.points[t[1]], mesh.points[t[2]])) / 6.0;
    return v;
}

std::vector<std::set<int>> vertex_neighbours(const Mesh& mesh) {
    std::vector<std::set<int>> nb(mesh.num_vertices());
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            nb[t[k]].insert(t[(k + 1) % 3]);
            nb[t[(k + 1) % 3]].insert(t[k]);
        }
    return nb;
}

bool same_point_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

::testing::AssertionResult same_mesh(const Mesh& a, const Mesh& b) {
    if (a.num_vertices() != b.num_vertices() || a.num_triangles() != b.num_triangles())
        return ::testing::AssertionFailure() << a.num_vertices() << "/" << a.num_triangles() << " vs "
                                             << b.num_vertices() << "/" << b.num_triangles()
                                             << " vertices/triangles";
    for (int v = 0; v < a.num_vertices(); ++v)
        if (!same_point_bits(a.points[v], b.points[v]))
            return ::testing::AssertionFailure() << "point " << v << " differs";
    for (int t = 0; t < a.num_triangles(); ++t)
        if (a.triangles[t] != b.triangles[t]) return ::testing::AssertionFailure() << "triangle " << t << " differs";
    return ::testing::AssertionSuccess();
}

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double inv = 1.0 / (va + vb + vc);
    return a + ab * (vb * inv) + ac * (vc * inv);
}

// Brute force: distance from p to the nearest triangle of `mesh`.
double distance_to_surface(const Vec3& p, const Mesh& mesh) {
    double best = std::numeric_limits<double>::infinity();
    for (const Triangle& t : mesh.triangles)
        best = std::min(best, norm(p - closest_point_on_triangle(p, mesh.points[t[0]], mesh.points[t[1]],
                                                                 mesh.points[t[2]])));
    return best;
}

// ---------------------------------------------------------------------------------------------
// Shell, files and the Python checker

fs::path checker_path() { return fs::path(QUADCAGE_SHARED_DIR) / "tools" / "check_cycles.py"; }

// Runs check_cycles.py; returns its exit status and leaves its output in *log.
int run_checker(const fs::path& mesh, const fs::path& cycles, std::string* log) {
    const fs::path out = cycles.parent_path() / (cycles.stem().string() + "_checker.txt");
    const int code = run_shell(shell_quoted(checker_path()) + " --mesh " + shell_quoted(mesh) + " --cycles " + shell_quoted(cycles) +
                               " >" + shell_quoted(out) + " 2>&1 </dev/null");
    *log = slurp(out);
    return code;
}

void write_cycles_json(const fs::path& path, const std::vector<Cycle>& cycles) {
    std::string text = "{\"orthogonal_system\": [";
    for (size_t i = 0; i < cycles.size(); ++i) {
        text += i ? ", [" : "[";
        for (size_t k = 0; k < cycles[i].size(); ++k) text += (k ? ", " : "") + std::to_string(cycles[i][k]);
        text += "]";
    }
    write_text_file(path.string(), text + "]}\n");
}

// Runs `quadcage cycles MESH -o DIR -q`; returns its exit status.
int run_cli_cycles(const fs::path& mesh, const fs::path& dir) {
    return run_shell(shell_quoted(QUADCAGE_CLI) + " cycles " + shell_quoted(mesh) + " -o " + shell_quoted(dir) + " -q >" +
                     shell_quoted(dir.string() + ".log") + " 2>&1 </dev/null");
}

// ---------------------------------------------------------------------------------------------
// Broken variants of a valid system, for the verifier and the checker

struct BrokenSystem {
    std::string name;
    std::vector<Cycle> cycles;
    std::string expected;  // a fragment of verify_orthogonal_system()'s message
};

// Expects a valid chain a1, b1, c1, b2 of genus 2 on `mesh`.
std::vector<BrokenSystem> broken_variants(const Mesh& mesh, const std::vector<Cycle>& valid) {
    QC_CHECK(valid.size() == 4, "broken_variants wants a genus-2 system");
    std::vector<BrokenSystem> out;

    std::vector<Cycle> dropped = valid;  // (a) 3 cycles for genus 2
    dropped.pop_back();
    out.push_back({"dropped_cycle", dropped, "want 2g"});

    std::vector<Cycle> backtrack = valid;  // (b) ... x, y, x, y ...: along edges, but x and y twice
    Cycle& c = backtrack[1];
    c.insert(c.begin() + 2, {c[2], c[1]});
    out.push_back({"non_simple", backtrack, "not simple"});

    std::vector<Cycle> overlap = valid;  // (c) b2 := a1: cycles 0 and 3 are not consecutive
    overlap[3] = valid[0];
    out.push_back({"non_consecutive_intersect", overlap, "not consecutive"});

    // (d) a1 with one vertex replaced by the farthest vertex on no cycle: two steps leave the edges.
    std::set<int> on_cycles;
    for (const Cycle& cy : valid) on_cycles.insert(cy.begin(), cy.end());
    const Cycle& a1 = valid[0];
    const Vec3 from = mesh.points[a1[1]];
    int far = -1;
    for (int v = 0; v < mesh.num_vertices(); ++v)
        if (!on_cycles.count(v) && (far < 0 || norm(mesh.points[v] - from) > norm(mesh.points[far] - from))) far = v;
    std::vector<Cycle> jump = valid;
    jump[0][1] = far;
    out.push_back({"jump", jump, "leaves the mesh edges"});

    std::vector<Cycle> swapped = valid;  // (e) a1, b1, b2, c1: b1 and b2 are disjoint
    std::swap(swapped[2], swapped[3]);
    out.push_back({"swapped_order", swapped, "share 0 vertices (want 1)"});
    return out;
}

// Two cycles on torus(n_major, n_minor) (index i*n_minor + j, shapes.h) that meet in exactly one
// vertex without crossing: the meridian i = 0 and a small loop on its i > 0 side through (0, 0).
std::vector<Cycle> touching_cycles_on_torus(const Mesh& torus, int n_minor) {
    const auto id = [n_minor](int i, int j) { return i * n_minor + (j + n_minor) % n_minor; };
    const std::vector<std::set<int>> nb = vertex_neighbours(torus);
    const int s = nb[id(0, 0)].count(id(1, 1)) ? 1 : -1;  // the diagonal of the quad next to (0, 0)
    Cycle meridian;
    for (int j = 0; j < n_minor; ++j) meridian.push_back(id(0, j));
    const Cycle loop{id(0, 0), id(1, 0), id(2, 0), id(2, s), id(1, s)};
    for (size_t k = 0; k < loop.size(); ++k)
        QC_CHECK(nb[loop[k]].count(loop[(k + 1) % loop.size()]), "touching loop is not an edge walk");
    return {meridian, loop};
}

// ---------------------------------------------------------------------------------------------
// 1. Generated solids of genus 1..20

class OrthogonalSystemPlateGenus : public ::testing::TestWithParam<int> {};

TEST_P(OrthogonalSystemPlateGenus, TwoGCyclesPassTheVerifier) {
    const int g = GetParam();
    const Mesh mesh = plate(g);
    const OrthogonalSystem sys = build_orthogonal_system(mesh);
    EXPECT_EQ(sys.genus, g);
    EXPECT_EQ(sys.input_vertices, mesh.num_vertices());
    ASSERT_EQ(sys.cycles.size(), static_cast<size_t>(2 * g));
    EXPECT_EQ(verify_orthogonal_system(sys.mesh, sys.cycles), "");
    ASSERT_EQ(sys.handle_lengths.size(), static_cast<size_t>(g));
    EXPECT_TRUE(std::is_sorted(sys.handle_lengths.begin(), sys.handle_lengths.end()));
    EXPECT_GT(sys.handle_lengths.front(), 0.0);
    for (const Cycle& c : sys.cycles) EXPECT_GT(cycle_length(sys.mesh, c), 0.0);
}

INSTANTIATE_TEST_SUITE_P(OrthogonalSystemGenus1To20, OrthogonalSystemPlateGenus, ::testing::Range(1, 21),
                         [](const ::testing::TestParamInfo<int>& info) {
                             return "genus_" + std::to_string(info.param);
                         });

// ---------------------------------------------------------------------------------------------
// 2. Torus and sphere

TEST(OrthogonalSystemTorus, TwoCyclesPassTheVerifier) {
    const Mesh mesh = shapes::torus(24, 12);
    const OrthogonalSystem sys = build_orthogonal_system(mesh);
    EXPECT_EQ(sys.genus, 1);
    ASSERT_EQ(sys.cycles.size(), 2u);
    EXPECT_EQ(verify_orthogonal_system(sys.mesh, sys.cycles), "");
    ASSERT_EQ(sys.handle_lengths.size(), 1u);
    // The shortest non-separating loop is a meridian: 12 chords of the tube circle of radius 0.35.
    EXPECT_NEAR(sys.handle_lengths[0], 24 * 0.35 * std::sin(3.14159265358979323846 / 12), 1e-9);
}

TEST(OrthogonalSystemSphere, GenusZeroHasNoCyclesAndKeepsTheMesh) {
    const Mesh mesh = shapes::icosphere(2);
    const OrthogonalSystem sys = build_orthogonal_system(mesh);
    EXPECT_EQ(sys.genus, 0);
    EXPECT_TRUE(sys.cycles.empty());
    EXPECT_TRUE(sys.handle_lengths.empty());
    EXPECT_EQ(sys.refinement_splits, 0);
    EXPECT_EQ(sys.input_vertices, mesh.num_vertices());
    EXPECT_TRUE(same_mesh(sys.mesh, mesh));
}

// ---------------------------------------------------------------------------------------------
// 3. The verifier rejects broken systems

class OrthogonalSystemVerifier : public ::testing::Test {
protected:
    static void SetUpTestSuite() { system_ = new OrthogonalSystem(build_orthogonal_system(plate(2))); }
    static void TearDownTestSuite() {
        delete system_;
        system_ = nullptr;
    }
    static OrthogonalSystem* system_;
};
OrthogonalSystem* OrthogonalSystemVerifier::system_ = nullptr;

TEST_F(OrthogonalSystemVerifier, AcceptsTheValidSystem) {
    ASSERT_EQ(system_->cycles.size(), 4u);
    EXPECT_EQ(verify_orthogonal_system(system_->mesh, system_->cycles), "");
}

TEST_F(OrthogonalSystemVerifier, RejectsEachBrokenVariant) {
    const std::vector<BrokenSystem> broken = broken_variants(system_->mesh, system_->cycles);
    ASSERT_EQ(broken.size(), 5u);
    for (const BrokenSystem& b : broken) {
        SCOPED_TRACE(b.name);
        const std::string message = verify_orthogonal_system(system_->mesh, b.cycles);
        EXPECT_FALSE(message.empty());
        EXPECT_NE(message.find(b.expected), std::string::npos) << message;
    }
}

TEST_F(OrthogonalSystemVerifier, JumpVariantReallyLeavesTheEdges) {
    // Guards the test itself: (d) must contain a step between non-adjacent vertices.
    const std::vector<std::set<int>> nb = vertex_neighbours(system_->mesh);
    const std::vector<BrokenSystem> broken = broken_variants(system_->mesh, system_->cycles);
    ASSERT_EQ(broken[3].name, "jump");
    const Cycle& jump = broken[3].cycles[0];
    int off_edge_steps = 0;
    for (size_t k = 0; k < jump.size(); ++k) off_edge_steps += !nb[jump[k]].count(jump[(k + 1) % jump.size()]);
    EXPECT_EQ(off_edge_steps, 2);
}

TEST_F(OrthogonalSystemVerifier, RejectsMissingAndExtraCycles) {
    EXPECT_NE(verify_orthogonal_system(system_->mesh, {}), "");
    std::vector<Cycle> extra = system_->cycles;
    extra.push_back(system_->cycles.back());
    EXPECT_NE(verify_orthogonal_system(system_->mesh, extra), "");
}

TEST_F(OrthogonalSystemVerifier, RejectsAnOutOfRangeVertex) {
    std::vector<Cycle> cycles = system_->cycles;
    cycles[2][0] = system_->mesh.num_vertices();
    EXPECT_NE(verify_orthogonal_system(system_->mesh, cycles).find("leaves the mesh edges"), std::string::npos);
}

TEST_F(OrthogonalSystemVerifier, RejectsAnOpenMesh) {
    Mesh open = system_->mesh;
    open.triangles.pop_back();
    EXPECT_NE(verify_orthogonal_system(open, system_->cycles), "");
}

TEST(OrthogonalSystemVerifierTouch, RejectsCyclesThatTouchWithoutCrossing) {
    const Mesh torus = shapes::torus(24, 12);
    const std::string message = verify_orthogonal_system(torus, touching_cycles_on_torus(torus, 12));
    EXPECT_NE(message.find("without crossing"), std::string::npos) << message;
}

// ---------------------------------------------------------------------------------------------
// Preconditions of build_orthogonal_system

TEST(OrthogonalSystemInput, RejectsOpenMeshesTwoComponentsAndBadOptions) {
    Mesh open = plate(1);
    open.triangles.pop_back();
    EXPECT_THROW(build_orthogonal_system(open), InvalidInput);

    Mesh two = shapes::torus(8, 6);
    const Mesh other = shapes::icosphere(1);
    for (Triangle t : other.triangles) {
        for (int& v : t) v += two.num_vertices();
        two.triangles.push_back(t);
    }
    two.points.insert(two.points.end(), other.points.begin(), other.points.end());
    EXPECT_THROW(build_orthogonal_system(two), InvalidInput);

    layout::OrthogonalSystemOptions bad;
    bad.root_samples = 0;
    EXPECT_NE(bad.validate(), "");
    EXPECT_THROW(build_orthogonal_system(plate(1), bad), InvalidInput);
}

// ---------------------------------------------------------------------------------------------
// 4. The refined mesh is the input surface

struct SurfaceCase {
    const char* name;
    std::function<std::optional<Mesh>()> make;  // nullopt: the input is not available here
};

class OrthogonalSystemRefinement : public ::testing::TestWithParam<SurfaceCase> {};

TEST_P(OrthogonalSystemRefinement, KeepsTheInputSurface) {
    const std::optional<Mesh> made = GetParam().make();
    if (!made) GTEST_SKIP() << "shared meshes not found in " << shared_meshes_dir();
    const Mesh& input = *made;
    const int genus = closed_genus(input);
    ASSERT_GT(genus, 0);
    const OrthogonalSystem sys = build_orthogonal_system(input);
    const Mesh& out = sys.mesh;

    ASSERT_EQ(sys.input_vertices, input.num_vertices());
    ASSERT_GE(out.num_vertices(), input.num_vertices());
    for (int v = 0; v < input.num_vertices(); ++v)
        ASSERT_TRUE(same_point_bits(out.points[v], input.points[v])) << "input vertex " << v << " moved";

    const double area = surface_area(input);
    EXPECT_NEAR(surface_area(out), area, 1e-9 * area);
    const double volume = signed_volume(input);
    EXPECT_NEAR(signed_volume(out), volume, 1e-9 * std::abs(volume));
    const BoundingBox a = bounding_box(input), b = bounding_box(out);
    EXPECT_EQ(a.min, b.min);
    EXPECT_EQ(a.max, b.max);
    EXPECT_EQ(closed_genus(out), genus);

    const double tolerance = 1e-9 * a.diagonal();
    for (int v = input.num_vertices(); v < out.num_vertices(); ++v)
        ASSERT_LE(distance_to_surface(out.points[v], input), tolerance) << "new vertex " << v << " is off the input";
    // Splits add vertices one per split edge.
    EXPECT_EQ(out.num_vertices() - input.num_vertices(), sys.refinement_splits);
}

INSTANTIATE_TEST_SUITE_P(
    OrthogonalSystemSurfaces, OrthogonalSystemRefinement,
    ::testing::Values(SurfaceCase{"plate_genus_2", [] { return std::optional<Mesh>(plate(2)); }},
                      SurfaceCase{"plate_genus_7", [] { return std::optional<Mesh>(plate(7)); }},
                      SurfaceCase{"plate_genus_20", [] { return std::optional<Mesh>(plate(20)); }},
                      SurfaceCase{"flat_plate_genus_4", [] { return std::optional<Mesh>(plate(4, false)); }},
                      SurfaceCase{"torus_24x12", [] { return std::optional<Mesh>(shapes::torus(24, 12)); }},
                      SurfaceCase{"eight",
                                  [] {
                                      return have_shared_meshes() ? std::optional<Mesh>(load_shared("eight.off"))
                                                                  : std::nullopt;
                                  }},
                      SurfaceCase{"fertility",
                                  [] {
                                      return have_shared_meshes() ? std::optional<Mesh>(load_shared("fertility.off"))
                                                                  : std::nullopt;
                                  }}),
    [](const ::testing::TestParamInfo<SurfaceCase>& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------------------------
// 5. Determinism

void expect_identical_runs(const Mesh& mesh) {
    const OrthogonalSystem first = build_orthogonal_system(mesh);
    const OrthogonalSystem second = build_orthogonal_system(mesh);
    EXPECT_EQ(first.cycles, second.cycles);
    EXPECT_EQ(first.handle_lengths, second.handle_lengths);
    EXPECT_EQ(first.refinement_splits, second.refinement_splits);
    EXPECT_TRUE(same_mesh(first.mesh, second.mesh));
}

TEST(OrthogonalSystemDeterminism, PlateGenus6) { expect_identical_runs(plate(6)); }

TEST(OrthogonalSystemDeterminism, Torus) { expect_identical_runs(shapes::torus(24, 12)); }

TEST(OrthogonalSystemDeterminism, Eight) {
    if (!have_shared_meshes()) GTEST_SKIP() << "shared meshes not found in " << shared_meshes_dir();
    expect_identical_runs(load_shared("eight.off"));
}

// ---------------------------------------------------------------------------------------------
// 6. Quality: flat plates have tight bar cycles of length 2*(1+t) = 3.2 (shapes.h)

::testing::AssertionResult within_quarter_of(double value, double target) {
    if (std::abs(value - target) <= 0.25 * target) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << value << " is not within 25% of " << target << " (ratio "
                                         << value / target << ")";
}

class OrthogonalSystemQuality : public ::testing::TestWithParam<int> {};

TEST_P(OrthogonalSystemQuality, HandleLoopsAreNearlyTight) {
    const int g = GetParam();
    const OrthogonalSystem sys = build_orthogonal_system(plate(g, false));
    ASSERT_EQ(sys.handle_lengths.size(), static_cast<size_t>(g));
    ASSERT_EQ(sys.cycles.size(), static_cast<size_t>(2 * g));
    const double a1 = cycle_length(sys.mesh, sys.cycles[0]);
    std::string lengths;
    for (double h : sys.handle_lengths) lengths += (lengths.empty() ? "" : ", ") + std::to_string(h);
    std::printf("[ measured ] flat plate genus %d: a1 = %.6f, handle_lengths = [%s], tight bar cycle %.6f\n", g, a1,
                lengths.c_str(), kBarCycle);
    RecordProperty("a1_length", std::to_string(a1));
    RecordProperty("handle_lengths", lengths);

    EXPECT_TRUE(within_quarter_of(sys.handle_lengths[0], kBarCycle)) << "shortest handle";
    EXPECT_TRUE(within_quarter_of(a1, kBarCycle)) << "a1";
    const double tight = std::min(kBarCycle, kHoleCycle);
    for (size_t i = 0; i < sys.handle_lengths.size(); ++i)
        EXPECT_TRUE(within_quarter_of(sys.handle_lengths[i], tight)) << "handle " << i;
}

INSTANTIATE_TEST_SUITE_P(OrthogonalSystemFlatPlates, OrthogonalSystemQuality, ::testing::Values(1, 2, 4),
                         [](const ::testing::TestParamInfo<int>& info) {
                             return "genus_" + std::to_string(info.param);
                         });

// ---------------------------------------------------------------------------------------------
// 7. Shared real meshes

struct RealMeshCase {
    const char* file;
    int genus;
};

class OrthogonalSystemRealMesh : public ::testing::TestWithParam<RealMeshCase> {};

TEST_P(OrthogonalSystemRealMesh, VerifiesWithTheDocumentedGenus) {
    if (!have_shared_meshes()) GTEST_SKIP() << "shared meshes not found in " << shared_meshes_dir();
    const RealMeshCase& c = GetParam();
    const std::string path = (shared_meshes_dir() / c.file).string();
    const PreparedMesh prepared = prepare_for_quadding(read_mesh(path), path);
    ASSERT_EQ(prepared.components.size(), 1u);
    ASSERT_EQ(prepared.report.components[0].genus, c.genus);
    const OrthogonalSystem sys = build_orthogonal_system(prepared.components[0]);
    EXPECT_EQ(sys.genus, c.genus);
    EXPECT_EQ(sys.input_vertices, prepared.components[0].num_vertices());
    ASSERT_EQ(sys.cycles.size(), static_cast<size_t>(2 * c.genus));
    EXPECT_EQ(verify_orthogonal_system(sys.mesh, sys.cycles), "");
    EXPECT_EQ(closed_genus(sys.mesh), c.genus);
}

INSTANTIATE_TEST_SUITE_P(
    OrthogonalSystemSharedMeshes, OrthogonalSystemRealMesh,
    ::testing::Values(RealMeshCase{"kitten.off", 1}, RealMeshCase{"torus.obj", 1}, RealMeshCase{"eight.off", 2},
                      RealMeshCase{"3holes.off", 3}, RealMeshCase{"fertility.off", 4},
                      RealMeshCase{"botijo.off", 5}, RealMeshCase{"boot.obj", 12}, RealMeshCase{"skull.obj", 2},
                      RealMeshCase{"input_wheel.off", 11}),
    [](const ::testing::TestParamInfo<RealMeshCase>& info) {
        const std::string file = info.param.file;
        return file.substr(0, file.find('.'));
    });

// ---------------------------------------------------------------------------------------------
// 8. The CLI end to end, against the independent checker

class OrthogonalSystemCli : public ::testing::Test {
protected:
    void SetUp() override { dir_ = scratch_dir(); }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir_, ignored);
    }

    // Runs the CLI twice on `mesh`, checks that the outputs are identical, then runs the checker.
    void run_and_check(const fs::path& mesh) {
        const fs::path first = dir_ / "run1", second = dir_ / "run2";
        ASSERT_EQ(run_cli_cycles(mesh, first), 0) << slurp(first.string() + ".log");
        ASSERT_EQ(run_cli_cycles(mesh, second), 0) << slurp(second.string() + ".log");
        for (const char* file : {"layout.ply", "cycles.json", "report.json"})
            ASSERT_TRUE(fs::is_regular_file(first / file)) << file << " not written";
        for (const char* file : {"layout.ply", "cycles.json"}) {
            const std::string bytes = slurp(first / file);
            EXPECT_FALSE(bytes.empty()) << file;
            EXPECT_TRUE(bytes == slurp(second / file)) << file << " differs between two runs";
        }
        EXPECT_EQ(report_without_measurements(first / "report.json"), report_without_measurements(second / "report.json"));

        const std::string why = python_unavailable();
        if (!why.empty()) GTEST_SKIP() << "check_cycles.py not run: " << why;
        ASSERT_TRUE(fs::exists(checker_path())) << checker_path() << " is missing";
        std::string log;
        EXPECT_EQ(run_checker(first / "layout.ply", first / "cycles.json", &log), 0) << log;
    }

    fs::path dir_;
};

TEST_F(OrthogonalSystemCli, EightPassesTheCheckerAndIsDeterministic) {
    if (!have_shared_meshes()) GTEST_SKIP() << "shared meshes not found in " << shared_meshes_dir();
    run_and_check(shared_meshes_dir() / "eight.off");
}

TEST_F(OrthogonalSystemCli, PlateGenus3PassesTheCheckerAndIsDeterministic) {
    const fs::path input = dir_ / "plate3.ply";
    write_ply(input.string(), plate(3));
    run_and_check(input);
}

TEST_F(OrthogonalSystemCli, CheckerRejectsBrokenSystems) {
    // The end-to-end check means something only if the checker fails on broken input too.
    const std::string why = python_unavailable();
    if (!why.empty()) GTEST_SKIP() << "check_cycles.py not run: " << why;
    ASSERT_TRUE(fs::exists(checker_path())) << checker_path() << " is missing";
    const OrthogonalSystem sys = build_orthogonal_system(plate(2));
    const fs::path mesh = dir_ / "layout.ply";
    write_ply(mesh.string(), sys.mesh);
    std::string log;
    write_cycles_json(dir_ / "valid.json", sys.cycles);
    ASSERT_EQ(run_checker(mesh, dir_ / "valid.json", &log), 0) << log;
    for (const BrokenSystem& b : broken_variants(sys.mesh, sys.cycles)) {
        const fs::path json = dir_ / (b.name + ".json");
        write_cycles_json(json, b.cycles);
        EXPECT_NE(run_checker(mesh, json, &log), 0) << b.name << " passed the checker:\n" << log;
        EXPECT_NE(log.find("FAIL "), std::string::npos) << b.name << ": the checker did not run its checks:\n" << log;
    }
    const Mesh torus = shapes::torus(24, 12);
    write_ply((dir_ / "torus.ply").string(), torus);
    write_cycles_json(dir_ / "touch.json", touching_cycles_on_torus(torus, 12));
    EXPECT_NE(run_checker(dir_ / "torus.ply", dir_ / "touch.json", &log), 0) << log;
    EXPECT_NE(log.find("without crossing"), std::string::npos) << log;
}

}  // namespace
}  // namespace quadcage

// Tests of the minimal quad layout (paper §3-4: Lemma 4, Corollary 2, Theorem 2, Algorithm 1,
// Remark 1; design.md §2-3): generated solids of genus 0..20 and the shared real meshes through the
// C++ verifier, the verifier and the Python checker on broken layouts, determinism, the level-1
// cage, and the CLI end to end against check_layout.py, check_cycles.py and OpenMesh.

#include "quadcage/layout/quad_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/openmesh_bridge.h"
#include "quadcage/core/shapes.h"
#include "quadcage/subdiv/cage.h"
#include "support/files.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;
using layout::build_quad_layout;
using layout::QuadLayout;
using layout::verify_quad_layout;
using layout::vertices_added_bound;

int want_quads(int g) {
    return g >= 2 ? 10 * g - 10 : (g == 1 ? 4 : 6);
}
int want_corners(int g) {
    return g >= 2 ? 8 * g - 8 : (g == 1 ? 4 : 8);
}
int want_degree(int g) {
    return g >= 2 ? 5 : (g == 1 ? 4 : 3);
}

Mesh plate(int genus) {
    return shapes::plate_with_holes(genus);
}

// Everything a valid layout of `input` (genus g) must satisfy, checked here independently of the
// verifier where that is cheap.
void expect_valid_layout(const QuadLayout& L, const Mesh& input, int g) {
    EXPECT_EQ(verify_quad_layout(L), "");
    EXPECT_EQ(L.genus, g);
    EXPECT_EQ(test::closed_genus(L.mesh), g);
    EXPECT_EQ(L.cage.num_quads(), want_quads(g));
    EXPECT_EQ(L.cage.num_corners(), want_corners(g));
    EXPECT_EQ(L.cage.num_edges(), 2 * want_quads(g));
    std::map<int, int> degree;
    for (const auto& e : L.cage.edges)
        for (int c : e.corners) ++degree[c];
    for (const auto& [c, d] : degree) EXPECT_EQ(d, want_degree(g)) << "corner " << c;
    EXPECT_EQ(L.quality.flipped_triangles, 0);
    // The layout mesh is the input, refined: the input's points first, bit-identical.
    ASSERT_EQ(L.input_vertices, input.num_vertices());
    ASSERT_GE(L.mesh.num_vertices(), input.num_vertices());
    for (int v = 0; v < input.num_vertices(); ++v)
        ASSERT_EQ(std::memcmp(&L.mesh.points[v], &input.points[v], sizeof(Vec3)), 0)
            << "input vertex " << v << " moved";
    EXPECT_NEAR(surface_area(L.mesh), surface_area(input), 1e-9 * surface_area(input));
    // Every triangle has a patch; every patch has triangles.
    std::set<int> used(L.triangle_patch.begin(), L.triangle_patch.end());
    EXPECT_EQ(static_cast<int>(used.size()), L.cage.num_quads());
    // S-cycles: 4g-4 for g >= 2, 2 corners on each.
    if (g >= 2) {
        ASSERT_EQ(static_cast<int>(L.s_cycles.size()), 4 * g - 4);
        std::set<int> corners(L.corner_vertex.begin(), L.corner_vertex.end());
        for (const auto& s : L.s_cycles)
            EXPECT_EQ(std::count_if(s.begin(), s.end(), [&](int v) { return corners.count(v) > 0; }), 2);
    }
    EXPECT_EQ(static_cast<int>(L.orthogonal_system.size()), 2 * g);
    // The level-1 cage: one Catmull-Clark step, a simple closed quad mesh of 4x the quads.
    const subdiv::CageRefinement r = subdiv::refine_cage(L.cage);
    EXPECT_EQ(r.level1.num_quads(), 4 * want_quads(g));
    EXPECT_EQ(r.level1.num_vertices() - 2 * r.level1.num_quads() + r.level1.num_quads(), 2 - 2 * g);
    EXPECT_EQ(subdiv::refine_uniform(r.level1, 1).num_quads(), 16 * want_quads(g));  // rejects multi-edges
}

// The layout of plate(g), checked as expect_valid_layout() does, with its progress messages.
QuadLayout valid_plate_layout(int g, std::vector<std::string>* said) {
    const Mesh input = plate(g);
    layout::QuadLayoutOptions o;
    o.progress = [said](const std::string& m) { said->push_back(m); };
    QuadLayout L = build_quad_layout(input, o);
    expect_valid_layout(L, input, g);
    return L;
}

// Whether one of the progress messages `said` contains `part`.
bool says(const std::vector<std::string>& said, const std::string& part) {
    return std::any_of(said.begin(), said.end(),
                       [&part](const std::string& m) { return m.find(part) != std::string::npos; });
}

// ---------------------------------------------------------------------------------------------
// 1. Generated solids, genus 0..20

class QuadLayoutGenerated : public ::testing::TestWithParam<int> {};

TEST_P(QuadLayoutGenerated, MinimalLayoutPassesTheVerifier) {
    const int g = GetParam();
    const Mesh input = plate(g);
    expect_valid_layout(build_quad_layout(input), input, g);
}

// Genus 0..18 (9 and 13 pass since the layout edges are relaxed: before, two edges left a corner
// together and a patch map squeezed triangles below rounding). 17..20 took 15 minutes or more each
// while the room made for the curves cascaded; with the T-shirts cut as a tree (tools/bench/
// layout.sh --plates 2 20 on 46d41f0) 17 and 18 take 7.4 and 5.6 s, 19 and 20 23 and 18 s (those
// two: QuadLayoutTshirtTree below).
std::string genus_name(const ::testing::TestParamInfo<int>& info) {
    return "genus" + std::to_string(info.param);
}
INSTANTIATE_TEST_SUITE_P(QuadLayoutGenus0To16, QuadLayoutGenerated, ::testing::Range(0, 17), genus_name);
INSTANTIATE_TEST_SUITE_P(QuadLayoutHighGenus, QuadLayoutGenerated, ::testing::Values(17, 18), genus_name);

TEST(QuadLayoutShapes, SphereIsACube) {
    const Mesh input = shapes::icosphere(3);
    expect_valid_layout(build_quad_layout(input), input, 0);
}

// Genus-0 figures with long limbs (the class of a cartoon character that ended in "cube: an edge
// could not be routed"): the cube is built as bottom ring, verticals, top ring. Seeds 4, 20 and 23
// failed with the top ring routed before the verticals.
class QuadLayoutLimbs : public ::testing::TestWithParam<unsigned> {};

TEST_P(QuadLayoutLimbs, FigureWithLimbsGetsACube) {
    shapes::LimbOptions o;
    o.seed = GetParam();
    o.limbs = 2 + static_cast<int>(o.seed % 5);
    const Mesh input = shapes::body_with_limbs(o);
    expect_valid_layout(build_quad_layout(input), input, 0);
}
INSTANTIATE_TEST_SUITE_P(Seeds, QuadLayoutLimbs, ::testing::Values(1u, 2u, 4u, 6u, 20u, 23u, 35u));

// A big smooth body with small handles, spread or in a row (issue 20's failure classes): the
// minimal layout exists and verifies. (Its balance is measured by tools/bench/layout_classes.sh.)
class QuadLayoutHandles : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(QuadLayoutHandles, BigBodyWithSmallHandlesGetsAMinimalLayout) {
    shapes::HandleBodyOptions o;
    o.handles = std::get<0>(GetParam());
    o.in_a_row = std::get<1>(GetParam());
    const Mesh input = shapes::body_with_handles(o);
    expect_valid_layout(build_quad_layout(input), input, o.handles);
}
INSTANTIATE_TEST_SUITE_P(Handles, QuadLayoutHandles,
                         ::testing::Values(std::make_tuple(1, false), std::make_tuple(2, false), std::make_tuple(3, true),
                                           std::make_tuple(4, true)));

// input_wheel's class: holes in a ring round an axle through a hub (with ribs round it, as
// input_wheel's fins). A minimal layout exists, verifies and stays within the refinement bound.
// (Its balance is measured by tools/bench/layout_classes.sh.)
class QuadLayoutWheel : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(QuadLayoutWheel, HolesInARingRoundAHubGetAMinimalLayout) {
    shapes::WheelOptions o;
    o.holes = std::get<0>(GetParam());
    o.ribs = std::get<1>(GetParam());
    o.resolution = 2;
    const Mesh input = shapes::wheel(o);
    const QuadLayout L = build_quad_layout(input);
    expect_valid_layout(L, input, o.holes + 1);
    EXPECT_LE(L.mesh.num_vertices() - L.input_vertices, vertices_added_bound(L.input_vertices, L.cage.num_corners()));
}
INSTANTIATE_TEST_SUITE_P(Wheels, QuadLayoutWheel,
                         ::testing::Values(std::make_tuple(0, 0), std::make_tuple(3, 0), std::make_tuple(5, 8)));

// input_wheel's tessellation (issue 20): a wheel exported as a CAD system does, its flat faces fans
// of long, thin triangles (shapes::flat_faces_as_fans()). The layout curves, routed along mesh
// edges, would follow the fans; the long edges are split first (QuadLayoutOptions::
// split_long_edges), and that layout verifies, stays within the bound and is better balanced than
// the one without (tools/bench/layout_classes.sh measures the fits).
TEST(QuadLayoutWheel, CadTessellationGetsItsLongEdgesSplitAndABetterBalance) {
    shapes::WheelOptions w;
    w.holes = 6;
    w.cad = true;
    const Mesh input = shapes::wheel(w);
    std::vector<std::string> said;
    layout::QuadLayoutOptions o;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout split = build_quad_layout(input, o);
    expect_valid_layout(split, input, 7);
    EXPECT_TRUE(says(said, "long edges split: "));
    EXPECT_LE(split.mesh.num_vertices() - split.input_vertices,
              vertices_added_bound(split.input_vertices, split.cage.num_corners()));
    o.split_long_edges = false;
    said.clear();
    const QuadLayout plain = build_quad_layout(input, o);
    expect_valid_layout(plain, input, 7);
    EXPECT_FALSE(says(said, "long edges split: "));
    EXPECT_LT(split.quality.patch_area_max_over_min, plain.quality.patch_area_max_over_min);
    std::cout << "CAD wheel, genus 7: patch area max/min " << plain.quality.patch_area_max_over_min << " -> "
              << split.quality.patch_area_max_over_min << ", corner angle deviation "
              << plain.quality.corner_angle_mean_deviation_deg << " -> "
              << split.quality.corner_angle_mean_deviation_deg << " deg\n";
}

// Room for the curves is made by splitting edges, and must stay within vertices_added_bound()
// (issue #20). When a failed search split every chord round it, and the patch maps every chord
// between layout curves, each new curve hugged the room made for the last: a plate of genus 8
// grew by 15113 vertices (bound 11308), boot by 93550 (bound 22583).
class QuadLayoutRefinement : public ::testing::TestWithParam<int> {};

TEST_P(QuadLayoutRefinement, PlateStaysWithinTheBound) {
    const Mesh input = plate(GetParam());
    const QuadLayout L = build_quad_layout(input);
    EXPECT_LE(L.mesh.num_vertices() - L.input_vertices, vertices_added_bound(L.input_vertices, L.cage.num_corners()));
}
// Genus 2: its 150 vertices get two 1-to-4 splits for room before any curve, as eight.off gets one
// (build_quad_layout()); 2290 stayed added (bound 1637) until the splits no curve runs through were
// undone (remove_unused_refinement(): 572). Genus 10 and 11: the holes in a row made the chain of
// T-shirts nest its annuli round the row and squeeze each past the holes (16055 added, bound 14537;
// 29336, bound 16137) until the T-shirts were cut as a tree (tshirt_tree(): 7060 and 9473).
INSTANTIATE_TEST_SUITE_P(Plates, QuadLayoutRefinement, ::testing::Values(2, 6, 8, 10, 11, 12));

TEST(QuadLayoutRefinementHandles, BodyWithHandlesStaysWithinTheBound) {
    shapes::HandleBodyOptions o;
    o.handles = 4;
    const Mesh input = shapes::body_with_handles(o);
    const QuadLayout L = build_quad_layout(input);
    EXPECT_LE(L.mesh.num_vertices() - L.input_vertices, vertices_added_bound(L.input_vertices, L.cage.num_corners()));
}

// A copy of `mesh` whose every coordinate moves by a uniform amount in [-amplitude, amplitude]
// times the mean edge length, the triangles kept (as tools/bench/jitter.py's copies, from a
// generator whose bits do not depend on the standard library): another scan of the same shape.
Mesh jittered(const Mesh& mesh, double amplitude, std::uint64_t seed) {
    double length = 0;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) length += norm(mesh.points[t[k]] - mesh.points[t[(k + 1) % 3]]);
    length /= 3.0 * static_cast<double>(mesh.triangles.size());
    std::mt19937_64 bits(seed);
    Mesh out = mesh;
    for (Vec3& p : out.points)
        for (int c = 0; c < 3; ++c) {
            const double u = static_cast<double>(bits() >> 11) * 0x1.0p-53;  // [0, 1)
            p[c] += (2 * u - 1) * amplitude * length;
        }
    return out;
}

// Jittered copies of boot.obj, whose twelve handles (the laces) crowd into one region. On one of
// them a band round one lace took in the whole lace beside it: two S-cycles round it, so it passed
// for an annulus, but it was a torus with two holes, the body had no piece with 24 holes, and the
// layout fell back to Algorithm 1's S-cycles (35k vertices added, bound 22582). Others nested the
// chain of T-shirts round the laces (up to 50k added). Each copy must keep the handle loops'
// S-cycles and stay within the bound.
class QuadLayoutJitteredBoot : public ::testing::TestWithParam<int> {};

TEST_P(QuadLayoutJitteredBoot, KeepsTheHandleLoopSCyclesWithinTheBound) {
    if (!test::have_shared_meshes())
        GTEST_SKIP() << "shared meshes not found in " << test::shared_meshes_dir();
    const Mesh input = jittered(test::load_shared("boot.obj"), 0.05, static_cast<std::uint64_t>(GetParam()));
    layout::QuadLayoutOptions o;
    std::vector<std::string> said;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout L = build_quad_layout(input, o);
    expect_valid_layout(L, input, 12);
    for (const std::string& m : said) EXPECT_EQ(m.find("Algorithm 1's instead"), std::string::npos) << m;
    EXPECT_LE(L.mesh.num_vertices() - L.input_vertices,
              vertices_added_bound(L.input_vertices, L.cage.num_corners()));
}
INSTANTIATE_TEST_SUITE_P(Seeds, QuadLayoutJitteredBoot, ::testing::Range(1, 13));

TEST(QuadLayoutRefinementBound, IsAQuarterOfTheInputPlus200PerCorner) {
    EXPECT_EQ(vertices_added_bound(19931, 88), 4982 + 17600);
    EXPECT_EQ(vertices_added_bound(766, 8), 191 + 1600);
}

TEST(QuadLayoutShapes, TorusHasFourQuadsOfDegreeFourCorners) {
    const Mesh input = shapes::torus(32, 16);
    const QuadLayout L = build_quad_layout(input);
    expect_valid_layout(L, input, 1);
    // On a round torus the four patches are close to equal.
    EXPECT_LT(L.quality.patch_area_max_over_min, 3.0);
}

// A big body with one small handle (issue #20's failure class, genus 1), plain and with relief of
// its own: the torus layout's second cycles follow the levels that halve the area across the first
// ones (harmonic_across()), so the four quads share the body; the relaxation, which pulled a
// body-halving cycle back round the handle, is not kept when the unrelaxed layout is better
// balanced and has better corner angles. Patch area max/min with the distance-ratio field before:
// 1.15, 13.4, 18.6 and 17.5 (cheapest loops before that: 37.6 for the first).
TEST(QuadLayoutShapes, GenusOneBodyIsShared) {
    struct Case {
        int resolution, bumps;
        unsigned seed;
    };
    for (const Case c : {Case{2, 0, 1}, Case{4, 0, 1}, Case{3, 12, 2}, Case{3, 12, 3}}) {
        SCOPED_TRACE("generate handles -g 1 -r " + std::to_string(c.resolution) + " --bumps " +
                     std::to_string(c.bumps) + " --seed " + std::to_string(c.seed));
        shapes::HandleBodyOptions o;
        o.handles = 1;
        o.resolution = c.resolution;
        o.bumps = c.bumps;
        o.seed = c.seed;
        const Mesh input = shapes::body_with_handles(o);
        const QuadLayout L = build_quad_layout(input);
        expect_valid_layout(L, input, 1);
        EXPECT_LE(L.quality.patch_area_max_over_min, 4.0);  // issue #20's balance targets
        EXPECT_LE(L.quality.corner_angle_mean_deviation_deg, 20.0);
    }
}

// The same body with its handle at the edge of its top (`generate handles -g 1 --in-a-row`): there
// the relaxation pulled the body-halving cycles back round the handle (area max/min 1.14 -> 47.7)
// for corner angles 26.6 -> 23.3 deg, and the rule that kept the unrelaxed layout only when it was
// better in both figures kept the relaxed one. The unrelaxed one is nearer both targets
// (balance_excess()). Neither meets the angle target of 20 deg; the area target is checked.
TEST(QuadLayoutShapes, GenusOneBodyWithItsHandleAtTheEdgeIsShared) {
    shapes::HandleBodyOptions o;
    o.handles = 1;
    o.in_a_row = true;
    const Mesh input = shapes::body_with_handles(o);
    const QuadLayout L = build_quad_layout(input);
    expect_valid_layout(L, input, 1);
    EXPECT_LE(L.quality.patch_area_max_over_min, 4.0);
}

TEST(QuadLayoutShapes, TinyMeshIsRefinedForRoom) {
    // A tetrahedron has 4 vertices; a cube needs 8 corners and room for 12 arcs.
    Mesh tet;
    tet.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tet.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    const QuadLayout L = build_quad_layout(tet);
    expect_valid_layout(L, tet, 0);
}

// ---------------------------------------------------------------------------------------------
// 2. Shared real meshes: the C++ verifier on all of them

struct RealMeshCase {
    const char* file;
    int genus;
};

class QuadLayoutRealMesh : public ::testing::TestWithParam<RealMeshCase> {};

TEST_P(QuadLayoutRealMesh, MinimalLayoutPassesTheVerifier) {
    if (!test::have_shared_meshes())
        GTEST_SKIP() << "shared meshes not found in " << test::shared_meshes_dir();
    const Mesh input = test::load_shared(GetParam().file);
    const QuadLayout L = build_quad_layout(input);
    expect_valid_layout(L, input, GetParam().genus);
    // Issue #20's refinement bound: boot added 29333 vertices (bound 22582), input_wheel 24424
    // (22981) and eight 2310 (1791) before the splits no curve runs through were undone.
    EXPECT_LE(L.mesh.num_vertices() - L.input_vertices,
              vertices_added_bound(L.input_vertices, L.cage.num_corners()));
}

INSTANTIATE_TEST_SUITE_P(QuadLayoutSharedMeshes, QuadLayoutRealMesh,
                         ::testing::Values(RealMeshCase{"bunny.obj", 0}, RealMeshCase{"igea.ply", 0},
                                           RealMeshCase{"kitten.off", 1}, RealMeshCase{"torus.obj", 1},
                                           RealMeshCase{"eight.off", 2}, RealMeshCase{"skull.obj", 2},
                                           RealMeshCase{"3holes.off", 3}, RealMeshCase{"fertility.off", 4},
                                           RealMeshCase{"botijo.off", 5}, RealMeshCase{"input_wheel.off", 11},
                                           RealMeshCase{"boot.obj", 12}),
                         [](const ::testing::TestParamInfo<RealMeshCase>& info) {
                             const std::string file = info.param.file;
                             return file.substr(0, file.find('.'));
                         });

// ---------------------------------------------------------------------------------------------
// 3. Determinism

TEST(QuadLayoutDeterminism, TwoRunsAreIdentical) {
    const Mesh input = plate(3);
    const QuadLayout a = build_quad_layout(input), b = build_quad_layout(input);
    ASSERT_EQ(a.mesh.num_vertices(), b.mesh.num_vertices());
    EXPECT_EQ(std::memcmp(a.mesh.points.data(), b.mesh.points.data(), a.mesh.points.size() * sizeof(Vec3)),
              0);
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
    EXPECT_EQ(a.triangle_patch, b.triangle_patch);
    EXPECT_EQ(a.corner_vertex, b.corner_vertex);
    EXPECT_EQ(a.edge_paths, b.edge_paths);
    EXPECT_EQ(a.s_cycles, b.s_cycles);
    ASSERT_EQ(a.corner_uv.size(), b.corner_uv.size());
    EXPECT_EQ(
        std::memcmp(a.corner_uv.data(), b.corner_uv.data(), a.corner_uv.size() * sizeof(a.corner_uv[0])), 0);
}

// ---------------------------------------------------------------------------------------------
// 3b. Relaxation moves layout edges and corners, never the cage's combinatorics

std::multiset<std::vector<int>> quad_corner_sets(const QuadLayout& L) {
    std::multiset<std::vector<int>> out;
    for (const auto& q : L.cage.quads) {
        std::vector<int> c(q.corners.begin(), q.corners.end());
        std::sort(c.begin(), c.end());
        out.insert(c);
    }
    return out;
}

std::set<std::vector<std::array<double, 3>>> paths_in_space(const QuadLayout& L) {
    std::set<std::vector<std::array<double, 3>>> out;
    for (const auto& p : L.edge_paths) {
        std::vector<std::array<double, 3>> q;
        for (int v : p) q.push_back({L.mesh.points[v].x, L.mesh.points[v].y, L.mesh.points[v].z});
        out.insert(q);
    }
    return out;
}

TEST(QuadLayoutRelax, EdgeRelaxationMovesEdgesAndKeepsTheCorners) {
    for (const int g : {0, 3}) {
        const Mesh input = g == 0 ? shapes::icosphere(3) : plate(g);
        layout::QuadLayoutOptions fixed, edges;
        fixed.relax_sweeps = 0;
        edges.relax_corner_sweeps = 0;
        // The relaxation alone: the global edge embedding after it moves the edges again.
        fixed.edge_embedding_iterations = edges.edge_embedding_iterations = 0;
        const QuadLayout a = build_quad_layout(input, fixed), b = build_quad_layout(input, edges);
        expect_valid_layout(a, input, g);
        expect_valid_layout(b, input, g);
        // The corners stay where the construction put them; the quads keep their corners.
        ASSERT_EQ(a.corner_vertex.size(), b.corner_vertex.size());
        for (size_t c = 0; c < a.corner_vertex.size(); ++c)
            EXPECT_EQ(norm(a.mesh.points[a.corner_vertex[c]] - b.mesh.points[b.corner_vertex[c]]), 0.0);
        EXPECT_EQ(quad_corner_sets(a), quad_corner_sets(b));
        EXPECT_NE(paths_in_space(a), paths_in_space(b)) << "genus " << g << ": relaxation moved no edge";
        std::cout << "  genus " << g << ": patch area max/min " << a.quality.patch_area_max_over_min << " -> "
                  << b.quality.patch_area_max_over_min << ", corner angle deviation "
                  << a.quality.corner_angle_mean_deviation_deg << " -> " << b.quality.corner_angle_mean_deviation_deg
                  << " deg\n";
        // The edge relaxation balances each pair of patches conformally, not by area; on the
        // icosphere's cube, already balanced (1.22), the ratio may move by a fraction of a percent.
        EXPECT_LE(b.quality.patch_area_max_over_min, 1.01 * a.quality.patch_area_max_over_min);
    }
}

// The skull's construction puts all 8 corners round its small handles (the zygomatic arches), so
// two patches hold 36% and 29% of the surface (area max/min 34). Moving the corners spreads them
// over the cranium. The stars of its corners all meet themselves (every corner has two edges to one
// neighbour), so this also covers the cut-open star.
TEST(QuadLayoutRelax, CornerRelaxationSpreadsTheSkullsCorners) {
    if (!test::have_shared_meshes())
        GTEST_SKIP() << "shared meshes not found in " << test::shared_meshes_dir();
    const Mesh input = test::load_shared("skull.obj");
    layout::QuadLayoutOptions edges;
    edges.relax_corner_sweeps = 0;
    const QuadLayout a = build_quad_layout(input, edges), b = build_quad_layout(input);
    expect_valid_layout(a, input, 2);
    expect_valid_layout(b, input, 2);
    EXPECT_EQ(quad_corner_sets(a), quad_corner_sets(b));
    int moved = 0;
    for (size_t c = 0; c < a.corner_vertex.size(); ++c)
        moved += norm(a.mesh.points[a.corner_vertex[c]] - b.mesh.points[b.corner_vertex[c]]) > 0;
    std::cout << "  skull: " << moved << " of 8 corners moved; patch area max/min "
              << a.quality.patch_area_max_over_min << " -> " << b.quality.patch_area_max_over_min << "\n";
    EXPECT_GE(moved, 4);
    EXPECT_LT(b.quality.patch_area_max_over_min, 0.5 * a.quality.patch_area_max_over_min);
}

TEST(QuadLayoutRelax, RejectsNegativeSweeps) {
    layout::QuadLayoutOptions bad;
    bad.relax_sweeps = -1;
    EXPECT_NE(bad.validate(), "");
    EXPECT_THROW(build_quad_layout(plate(2), bad), InvalidInput);
    bad.relax_sweeps = 3;
    bad.relax_corner_sweeps = -1;
    EXPECT_NE(bad.validate(), "");
}

// S-cycles from the handle loops (the default): on plates of genus 2..5 the construction is used
// (no fall-back to Algorithm 1's S-cycles) and the layout passes the verifier; with the option off,
// Algorithm 1's S-cycles are used and the layout passes too.
TEST(QuadLayoutHandleLoopSCycles, PlatesUseThemAndVerify) {
    for (int g = 2; g <= 5; ++g) {
        for (const bool from_handle_loops : {true, false}) {
            SCOPED_TRACE("genus " + std::to_string(g) + (from_handle_loops ? ", handle loops" : ", Algorithm 1"));
            const Mesh input = plate(g);
            layout::QuadLayoutOptions o;
            EXPECT_TRUE(o.s_cycles_from_handle_loops);  // the default
            o.s_cycles_from_handle_loops = from_handle_loops;
            std::vector<std::string> said;
            o.progress = [&said](const std::string& m) { said.push_back(m); };
            const QuadLayout L = build_quad_layout(input, o);
            expect_valid_layout(L, input, g);
            EXPECT_EQ(L.s_cycles.size(), static_cast<size_t>(4 * g - 4));
            EXPECT_EQ(says(said, "handle annulus"), from_handle_loops);
            EXPECT_FALSE(says(said, "Algorithm 1's instead"));
        }
    }
}

// Which S-cycles make the better layout depends on the shape (issue #20): on a big body with small
// handles Algorithm 1's (patch area max/min 36 against 56, level-3 Hausdorff 3.7e-3 against
// 1.5e-2), on fertility the handle loops'. The layout builds both and keeps Algorithm 1's only when
// it is better balanced on both counts. Algorithm 1's is not tried when the first layout is past the
// refinement bound already (eight, through its 1-to-4 pre-split: 2,310 added, bound 1,792), and is
// abandoned once it refines past the bound.
TEST(QuadLayoutSCycleChoice, ABodyWithSmallHandlesKeepsAlgorithmOnesSCycles) {
    shapes::HandleBodyOptions ho;
    ho.handles = 3;
    ho.resolution = 2;  // `generate handles -g 3`; at 3 voxels a cell the handle loops' balance better
    const Mesh input = shapes::body_with_handles(ho);
    layout::QuadLayoutOptions one;
    one.s_cycles_compare = false;
    const QuadLayout from_loops = build_quad_layout(input, one);
    one.s_cycles_from_handle_loops = false;
    const QuadLayout algorithm1 = build_quad_layout(input, one);
    layout::QuadLayoutOptions o;
    EXPECT_TRUE(o.s_cycles_compare);  // the default
    std::vector<std::string> said;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout L = build_quad_layout(input, o);
    expect_valid_layout(L, input, 3);
    EXPECT_TRUE(std::any_of(said.begin(), said.end(), [](const std::string& m) {
        return m.find("keeping Algorithm 1's") != std::string::npos;
    }));
    // Algorithm 1's layout is built in a second thread; its messages still come as if it were built
    // after the handle loops' one: all of them after the handle loops' last, before the choice.
    const std::string prefix = "Algorithm 1's S-cycles: ";
    auto is_other = [&prefix](const std::string& m) { return m.compare(0, prefix.size(), prefix) == 0; };
    const auto first_other = std::find_if(said.begin(), said.end(), is_other);
    const auto choice = std::find_if(
        said.begin(), said.end(), [](const std::string& m) { return m.compare(0, 10, "S-cycles: ") == 0; });
    ASSERT_NE(first_other, said.end());
    ASSERT_NE(choice, said.end());
    EXPECT_TRUE(std::all_of(first_other, choice, is_other));
    EXPECT_TRUE(std::none_of(choice, said.end(), is_other));
    EXPECT_EQ(*std::prev(first_other), "verifying");  // the handle loops' layout's last step
    EXPECT_LT(L.quality.patch_area_max_over_min, from_loops.quality.patch_area_max_over_min);
    EXPECT_LT(L.quality.corner_angle_mean_deviation_deg, from_loops.quality.corner_angle_mean_deviation_deg);
    EXPECT_EQ(L.mesh.points, algorithm1.mesh.points);
    EXPECT_EQ(L.triangle_patch, algorithm1.triangle_patch);
}

TEST(QuadLayoutSCycleChoice, AlgorithmOnesAreNotTriedPastTheRefinementBound) {
    const Mesh input = read_mesh(std::string(QUADCAGE_DATA_DIR) + "/eight.off");
    layout::QuadLayoutOptions o;
    std::vector<std::string> said;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    layout::QuadLayoutOptions one;
    one.s_cycles_compare = false;
    const QuadLayout from_loops = build_quad_layout(input, one);
    const QuadLayout L = build_quad_layout(input, o);
    EXPECT_TRUE(std::any_of(said.begin(), said.end(), [](const std::string& m) {
        return m.find("keeping the handle loops' (past the refinement bound already") != std::string::npos;
    }));
    EXPECT_EQ(L.mesh.points, from_loops.mesh.points);
    EXPECT_EQ(L.triangle_patch, from_loops.triangle_patch);
}

// A mesh far from the origin for its size (a part placed in a CAD assembly, a georeferenced scan):
// eight moved by 1e6 along each axis gets the layout eight gets at the origin, moved: as many
// vertices, the same patches, the embedded edges, and the input's points exactly. Built where it
// lies, its unused splits were not undone and it kept its edges along mesh edges, with 1,699
// vertices added against 832.
TEST(QuadLayoutFarFromTheOrigin, GetsTheLayoutItGetsAtTheOrigin) {
    const Mesh input = read_mesh(std::string(QUADCAGE_DATA_DIR) + "/eight.off");
    Mesh far = input;
    for (Vec3& p : far.points) p = p + Vec3{1e6, 1e6, 1e6};
    std::vector<std::string> said;
    layout::QuadLayoutOptions o;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout here = build_quad_layout(input), there = build_quad_layout(far, o);
    ASSERT_EQ(verify_quad_layout(there), "");
    EXPECT_EQ(there.mesh.num_vertices(), here.mesh.num_vertices());
    EXPECT_EQ(there.triangle_patch, here.triangle_patch);
    EXPECT_TRUE(there.edges_smoothed);
    EXPECT_TRUE(std::any_of(said.begin(), said.end(), [](const std::string& m) {
        return m.rfind("edge embedding: keeping the embedded edges", 0) == 0;
    }));
    EXPECT_NEAR(there.quality.patch_area_max_over_min, here.quality.patch_area_max_over_min,
                1e-6 * here.quality.patch_area_max_over_min);
    for (int v = 0; v < input.num_vertices(); ++v) {
        ASSERT_EQ(there.mesh.points[v].x, far.points[v].x) << v;
        ASSERT_EQ(there.mesh.points[v].y, far.points[v].y) << v;
        ASSERT_EQ(there.mesh.points[v].z, far.points[v].z) << v;
    }
    for (int c = 0; c < there.cage.num_corners(); ++c) {
        EXPECT_EQ(there.cage.points[c].x, there.mesh.points[there.corner_vertex[c]].x);
        EXPECT_EQ(there.cage.points[c].y, there.mesh.points[there.corner_vertex[c]].y);
        EXPECT_EQ(there.cage.points[c].z, there.mesh.points[there.corner_vertex[c]].z);
    }
}

// A wheel (input_wheel's class, `generate wheel -g 7 -r 3`): the handle loops' body annuli wind
// round the ring of holes in bundles; the S-cycles round the necks are kept instead, better on
// both counts, and the layout verifies. Without s_cycles_from_necks they are not built.
TEST(QuadLayoutSCycleChoice, AWheelKeepsTheSCyclesAtItsNecks) {
    shapes::WheelOptions wo;
    wo.holes = 6;
    wo.resolution = 3;
    const Mesh input = shapes::wheel(wo);
    layout::QuadLayoutOptions o;
    EXPECT_TRUE(o.s_cycles_from_necks);  // the default
    std::vector<std::string> said;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout L = build_quad_layout(input, o);
    expect_valid_layout(L, input, 7);
    EXPECT_TRUE(says(said, "keeping the necks'"));
    layout::QuadLayoutOptions off;
    off.s_cycles_from_necks = false;
    std::vector<std::string> said_off;
    off.progress = [&said_off](const std::string& m) { said_off.push_back(m); };
    const QuadLayout without = build_quad_layout(input, off);
    expect_valid_layout(without, input, 7);
    EXPECT_FALSE(says(said_off, "at the necks"));
    std::cout << "  wheel: patch area max/min " << without.quality.patch_area_max_over_min << " -> "
              << L.quality.patch_area_max_over_min << ", corner angle deviation "
              << without.quality.corner_angle_mean_deviation_deg << " -> "
              << L.quality.corner_angle_mean_deviation_deg << " deg\n";
}

// QuadLayoutOptions::score decides the choice in place of the rule. On 3 handles in a row all three
// constructions are built (the handle loops', Algorithm 1's, the necks'), each scored once as a
// verified layout; a score that prefers the worst-balanced layout gets it, a score that fails, or
// whose values are within score_margin of each other, leaves the rule's choice.
TEST(QuadLayoutSCycleChoice, AScoreChoosesAmongTheConstructions) {
    shapes::HandleBodyOptions ho;
    ho.handles = 3;
    ho.in_a_row = true;
    const Mesh input = shapes::body_with_handles(ho);
    struct Scored {
        std::vector<Vec3> corners;
        double area_ratio;
    };
    std::vector<Scored> scored;
    layout::QuadLayoutOptions o;
    o.score = [&scored](const QuadLayout& L) {
        EXPECT_EQ(verify_quad_layout(L), "");
        std::vector<Vec3> corners;
        for (int v : L.corner_vertex) corners.push_back(L.mesh.points[v]);
        scored.push_back({corners, L.quality.patch_area_max_over_min});
        return 1 / L.quality.patch_area_max_over_min;  // these differ by more than the margin here
    };
    const QuadLayout L = build_quad_layout(input, o);
    expect_valid_layout(L, input, 3);
    ASSERT_EQ(scored.size(), 3u);
    const auto worst = std::max_element(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) {
        return a.area_ratio < b.area_ratio;
    });
    // The edges are placed after the choice; the corners stay where they are.
    std::vector<Vec3> corners;
    for (int v : L.corner_vertex) corners.push_back(L.mesh.points[v]);
    EXPECT_EQ(corners, worst->corners);
    // Without a score, or with one that fails, the rule chooses.
    layout::QuadLayoutOptions rule;
    const QuadLayout by_rule = build_quad_layout(input, rule);
    layout::QuadLayoutOptions failing;
    std::vector<std::vector<Vec3>> asked;  // the corners of each layout the score was asked of
    failing.score = [&asked](const QuadLayout& L) -> double {
        std::vector<Vec3> corners;
        for (int v : L.corner_vertex) corners.push_back(L.mesh.points[v]);
        asked.push_back(corners);
        throw InternalError("no score");
    };
    std::vector<std::string> said;
    failing.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout fallen_back = build_quad_layout(input, failing);
    // The kept layout's score fails at the first choice, so the rule decides; at the second, the
    // score of the layout kept then is asked unless it was asked already, and fails too (a score is
    // not asked twice of one layout; the candidates' are not asked once the kept one's failed).
    // Which layout the rule keeps first decides whether that is one call or two: one before
    // 2b4c276, two since (the corner angles measured as check_layout.py measures them).
    ASSERT_GE(asked.size(), 1u);
    EXPECT_LE(asked.size(), 2u);
    for (size_t i = 0; i < asked.size(); ++i)
        for (size_t j = i + 1; j < asked.size(); ++j) EXPECT_NE(asked[i], asked[j]) << "asked twice of one layout";
    EXPECT_TRUE(says(said, "not scored (no score), so by those"));
    EXPECT_EQ(fallen_back.mesh.points, by_rule.mesh.points);
    EXPECT_EQ(fallen_back.triangle_patch, by_rule.triangle_patch);
    // Scores within score_margin of each other do not decide either.
    layout::QuadLayoutOptions close;
    close.score = [](const QuadLayout& L) { return 1 + 1e-3 / L.quality.patch_area_max_over_min; };
    std::vector<std::string> said_close;
    close.progress = [&said_close](const std::string& m) { said_close.push_back(m); };
    const QuadLayout too_close = build_quad_layout(input, close);
    EXPECT_TRUE(says(said_close, "too close to decide, so by those"));
    EXPECT_EQ(too_close.mesh.points, by_rule.mesh.points);
    EXPECT_EQ(too_close.triangle_patch, by_rule.triangle_patch);
    close.score_margin = 1;
    EXPECT_NE(close.validate(), "");
    EXPECT_THROW(build_quad_layout(input, close), InvalidInput);
    std::vector<Vec3> rule_corners;  // the rule keeps another layout: the score made the choice above
    for (int v : by_rule.corner_vertex) rule_corners.push_back(by_rule.mesh.points[v]);
    EXPECT_NE(rule_corners, corners);
}

// QuadLayoutOptions::tie_score breaks the ties the score leaves (values within score_margin): a tie
// score that prefers the worst-balanced layout gets it, as a deciding score does; one whose values
// are within the margin again, or none, leaves the rule's choice. It is asked only where the score
// ties, of both layouts then, and once of a layout.
TEST(QuadLayoutSCycleChoice, ATieScoreBreaksTheScoresTies) {
    shapes::HandleBodyOptions ho;
    ho.handles = 3;
    ho.in_a_row = true;
    const Mesh input = shapes::body_with_handles(ho);
    auto corners_of = [](const QuadLayout& L) {
        std::vector<Vec3> corners;
        for (int v : L.corner_vertex) corners.push_back(L.mesh.points[v]);
        return corners;
    };
    // The layout a deciding score that prefers the worst balance keeps.
    layout::QuadLayoutOptions deciding;
    deciding.score = [](const QuadLayout& L) { return 1 / L.quality.patch_area_max_over_min; };
    const std::vector<Vec3> worst = corners_of(build_quad_layout(input, deciding));
    const std::vector<Vec3> by_rule = corners_of(build_quad_layout(input, layout::QuadLayoutOptions{}));
    ASSERT_NE(worst, by_rule);  // else this shape tells the two apart by nothing

    layout::QuadLayoutOptions tied;
    tied.score = [](const QuadLayout&) { return 1.0; };  // every score ties
    int tie_calls = 0;
    tied.tie_score = [&tie_calls](const QuadLayout& L) {
        ++tie_calls;
        EXPECT_EQ(verify_quad_layout(L), "");
        return 1 / L.quality.patch_area_max_over_min;
    };
    std::vector<std::string> said;
    tied.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout broken = build_quad_layout(input, tied);
    expect_valid_layout(broken, input, 3);
    EXPECT_EQ(corners_of(broken), worst);
    EXPECT_EQ(tie_calls, 3);  // the three constructions' layouts, the one kept at the first choice not again
    EXPECT_TRUE(says(said, "too close to decide; finer scores"));

    // A tie score that ties too leaves the rule's choice.
    tied.tie_score = [](const QuadLayout& L) { return 1 + 1e-3 / L.quality.patch_area_max_over_min; };
    said.clear();
    EXPECT_EQ(corners_of(build_quad_layout(input, tied)), by_rule);
    EXPECT_TRUE(says(said, "too close again, so by those"));

    // A deciding score leaves the tie score unasked.
    deciding.tie_score = [](const QuadLayout&) -> double {
        ADD_FAILURE() << "the tie score was asked where the score decided";
        return 0;
    };
    EXPECT_EQ(corners_of(build_quad_layout(input, deciding)), worst);
}

// Plates of genus 9 and more: the handle annuli or the body annuli of the handle-loop S-cycles
// found no room between close holes, and Algorithm 1's S-cycles took over; they wind round the
// plate side by side, each T-shirt ring then squeezed along corridors between them and the mesh
// was refined many times over (plate -g 10: 309481 vertices added, bound 14537). The handle-loop
// S-cycles must now be placed (room made where they pinch) and the layout verify.
class QuadLayoutHighGenusHandleLoops : public ::testing::TestWithParam<int> {};

TEST_P(QuadLayoutHighGenusHandleLoops, PlateKeepsTheHandleLoopSCycles) {
    const int g = GetParam();
    std::vector<std::string> said;
    const QuadLayout L = valid_plate_layout(g, &said);
    EXPECT_TRUE(says(said, "body annulus " + std::to_string(g - 2) + " of " + std::to_string(g - 2)));
    EXPECT_FALSE(says(said, "Algorithm 1's instead"));
    EXPECT_EQ(L.s_cycles.size(), static_cast<size_t>(4 * g - 4));
}
INSTANTIATE_TEST_SUITE_P(Plates, QuadLayoutHighGenusHandleLoops, ::testing::Values(10, 12), genus_name);

// Plates of genus 19 and 20, whose holes crowd so that some cut of the tree of T-shirts finds no
// room. Genus 20: at the 8th cut the rings of the other holes walled each chosen hole in, every
// choice failed, and the chain was cut from the start instead (488,829 vertices added, bound
// 30,608, 145 s); the choices are now tried again with only the other holes as walls (cut_tshirt's
// `crowded`) and the tree is cut to the end. Genus 19: at the 14th cut no triple cuts even so; the
// chain's choices take over from there, keeping the tree's 13 cuts (88,855 added against 195,406
// from the start, 23 s against 58 s).
class QuadLayoutTshirtTree : public ::testing::TestWithParam<int> {};

TEST_P(QuadLayoutTshirtTree, CrowdedPlateKeepsTheTreesCuts) {
    const int g = GetParam();
    std::vector<std::string> said;
    const QuadLayout L = valid_plate_layout(g, &said);
    EXPECT_TRUE(says(said, "cutting the tree"));
    EXPECT_FALSE(says(said, "the chain from the start"));
    if (g == 20) {
        EXPECT_FALSE(says(said, "no triple of the tree cuts"));
    }
}
INSTANTIATE_TEST_SUITE_P(Plates, QuadLayoutTshirtTree, ::testing::Values(19, 20), genus_name);

// ---------------------------------------------------------------------------------------------
// 4. The verifier rejects broken layouts

class QuadLayoutVerifier : public ::testing::Test {
protected:
    static void SetUpTestSuite() { valid_ = new QuadLayout(build_quad_layout(plate(2))); }
    static void TearDownTestSuite() {
        delete valid_;
        valid_ = nullptr;
    }
    static QuadLayout* valid_;
};
QuadLayout* QuadLayoutVerifier::valid_ = nullptr;

TEST_F(QuadLayoutVerifier, AcceptsTheValidLayout) {
    EXPECT_EQ(verify_quad_layout(*valid_), "");
}

// A triangle with directed edge a -> b, or -1.
int triangle_with(const Mesh& m, int a, int b) {
    for (int t = 0; t < m.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k)
            if (m.triangles[t][k] == a && m.triangles[t][(k + 1) % 3] == b) return t;
    return -1;
}

TEST_F(QuadLayoutVerifier, RejectsATriangleInTheWrongPatch) {
    QuadLayout L = *valid_;
    // A triangle on a layout edge, given to the patch across that edge.
    const auto& path = L.edge_paths[0];
    int t = triangle_with(L.mesh, path[1], path[2]);
    if (L.triangle_patch[t] == L.cage.edges[0].quads[0])
        L.triangle_patch[t] = L.cage.edges[0].quads[1];
    else
        L.triangle_patch[t] = L.cage.edges[0].quads[0];
    EXPECT_NE(verify_quad_layout(L), "");
}

TEST_F(QuadLayoutVerifier, RejectsAReversedQuad) {
    QuadLayout L = *valid_;
    auto& q = L.cage.quads[3];
    std::reverse(q.corners.begin(), q.corners.end());
    EXPECT_NE(verify_quad_layout(L), "");
}

TEST_F(QuadLayoutVerifier, RejectsAFlippedTriangleInAPatchMap) {
    QuadLayout L = *valid_;
    std::swap(L.corner_uv[10][0], L.corner_uv[10][1]);
    EXPECT_NE(verify_quad_layout(L), "");
}

TEST_F(QuadLayoutVerifier, RejectsASideVertexOffItsArcLengthPosition) {
    QuadLayout L = *valid_;
    const int v = L.edge_paths[2][1];  // interior vertex of a layout edge
    bool moved = false;
    for (int t = 0; t < L.mesh.num_triangles() && !moved; ++t)
        for (int k = 0; k < 3; ++k)
            if (L.mesh.triangles[t][k] == v) {
                L.corner_uv[t][k][0] = 0.5 * (L.corner_uv[t][k][0] + 0.5);
                L.corner_uv[t][k][1] = 0.5 * (L.corner_uv[t][k][1] + 0.5);
                moved = true;
                break;
            }
    ASSERT_TRUE(moved);
    EXPECT_NE(verify_quad_layout(L), "");
}

TEST_F(QuadLayoutVerifier, RejectsAnEdgePathThatLeavesTheMesh) {
    QuadLayout L = *valid_;
    auto& path = L.edge_paths[1];
    path.erase(path.begin() + static_cast<long>(path.size() / 2));
    EXPECT_NE(verify_quad_layout(L), "");
}

TEST_F(QuadLayoutVerifier, RejectsTheWrongCorners) {
    QuadLayout L = *valid_;
    L.corner_vertex[0] = L.corner_vertex[1];
    EXPECT_NE(verify_quad_layout(L), "");
    QuadLayout M = *valid_;
    M.genus = 3;
    EXPECT_NE(verify_quad_layout(M), "");
}

// ---------------------------------------------------------------------------------------------
// 5. The CLI end to end: check_layout.py, check_cycles.py, OpenMesh on the level-1 cage

class QuadLayoutCli : public ::testing::Test {
protected:
    void SetUp() override { dir_ = test::scratch_dir("quadcage_layout_test_"); }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir_, ignored);
    }

    int run_layout(const fs::path& mesh, const fs::path& out, std::string* log) {
        return test::run_logged(test::shell_quoted(QUADCAGE_CLI) + " layout -q " + test::shell_quoted(mesh) +
                                    " -o " + test::shell_quoted(out),
                                out.string() + ".log", log);
    }

    // Runs `quadcage layout` twice, compares the outputs, then the checkers and OpenMesh.
    void run_and_check(const fs::path& mesh, int g) {
        const fs::path first = dir_ / "run1", second = dir_ / "run2";
        std::string log;
        ASSERT_EQ(run_layout(mesh, first, &log), 0) << log;
        ASSERT_EQ(run_layout(mesh, second, &log), 0) << log;
        for (const char* file : {"layout.ply", "cage.obj", "cage.json", "cage_level1.obj", "cycles.json"}) {
            const std::string bytes = test::slurp(first / file);
            EXPECT_FALSE(bytes.empty()) << file;
            EXPECT_TRUE(bytes == test::slurp(second / file)) << file << " differs between two runs";
        }
        EXPECT_EQ(test::report_without_measurements(first / "report.json"),
                  test::report_without_measurements(second / "report.json"));

        const PolygonMeshSummary level1 = read_with_openmesh((first / "cage_level1.obj").string());
        EXPECT_EQ(level1.faces, 4 * want_quads(g));
        EXPECT_TRUE(level1.closed());
        EXPECT_TRUE(level1.all_quads());
        EXPECT_EQ(level1.euler_characteristic(), 2 - 2 * g);
        EXPECT_EQ(level1.isolated_vertices, 0);

        const std::string why = test::python_unavailable();
        if (!why.empty()) GTEST_SKIP() << "checkers not run: " << why;
        EXPECT_EQ(test::run_logged(test::shell_quoted(test::shared_tool("check_layout.py")) + " --patches " +
                                       test::shell_quoted(first / "layout.ply") + " --cage " +
                                       test::shell_quoted(first / "cage.obj") + " --input " +
                                       test::shell_quoted(mesh),
                                   dir_ / "check_layout.txt", &log),
                  0)
            << log;
        if (g == 0) return;  // no cycles on a sphere (check_cycles.py fails the empty system by design)
        EXPECT_EQ(test::run_logged(test::shell_quoted(test::shared_tool("check_cycles.py")) + " --mesh " +
                                       test::shell_quoted(first / "layout.ply") + " --cycles " +
                                       test::shell_quoted(first / "cycles.json"),
                                   dir_ / "check_cycles.txt", &log),
                  0)
            << log;
    }

    fs::path dir_;
};

TEST_F(QuadLayoutCli, EightPassesTheCheckers) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    run_and_check(test::shared_meshes_dir() / "eight.off", 2);
}

TEST_F(QuadLayoutCli, FertilityPassesTheCheckers) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    run_and_check(test::shared_meshes_dir() / "fertility.off", 4);
}

TEST_F(QuadLayoutCli, KittenPassesTheCheckers) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    run_and_check(test::shared_meshes_dir() / "kitten.off", 1);
}

TEST_F(QuadLayoutCli, BunnyPassesTheCheckers) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    run_and_check(test::shared_meshes_dir() / "bunny.obj", 0);
}

TEST_F(QuadLayoutCli, PlateGenus6PassesTheCheckers) {
    const fs::path input = dir_ / "plate6.ply";
    write_ply(input.string(), plate(6));
    run_and_check(input, 6);
}

TEST_F(QuadLayoutCli, CheckerRejectsABrokenLayout) {
    // The end-to-end check means something only if the checker fails on a broken layout too:
    // two neighbouring patches merged into one (a hexagon with 6 corners; 9 quads for genus 2).
    const std::string why = test::python_unavailable();
    if (!why.empty()) GTEST_SKIP() << "checkers not run: " << why;
    QuadLayout L = build_quad_layout(plate(2));
    const int keep = L.cage.edges[0].quads[0], gone = L.cage.edges[0].quads[1];
    ASSERT_NE(keep, gone);
    for (int& p : L.triangle_patch)
        if (p == gone) p = keep;
    PlyExtras extras;
    extras.face_int_name = "patch";
    extras.face_ints = L.triangle_patch;
    write_ply((dir_ / "broken.ply").string(), L.mesh, extras);
    std::string log;
    EXPECT_NE(test::run_logged(test::shell_quoted(test::shared_tool("check_layout.py")) + " --patches " +
                                   test::shell_quoted(dir_ / "broken.ply"),
                               dir_ / "check.txt", &log),
              0)
        << log;
    EXPECT_NE(log.find("FAIL "), std::string::npos) << log;
}

TEST_F(QuadLayoutCli, RejectsAnOpenMeshWithExitCode3AndWritesNothing) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    std::string log;
    EXPECT_EQ(run_layout(test::shared_meshes_dir() / "stanford-bunny.obj", dir_ / "out", &log), 3) << log;
    EXPECT_NE(log.find("boundary"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "layout.ply"));
}

}  // namespace
}  // namespace quadcage

// Smoothing the layout edges (issue #20: "layout edges run as smooth curves across triangles, split
// where they cross: no mesh-edge staircase"): smooth_layout_edges() on layouts built without it;
// and the global edge embedding (embed_layout_edges()), which also places them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "detail/embedding.h"
#include "detail/patches.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/quad_layout.h"
#include "support/files.h"

namespace quadcage::layout::detail {
namespace {

QuadLayout staircase_layout(const Mesh& mesh, bool necks = true) {
    QuadLayoutOptions o;
    o.smooth_edges = false;
    o.s_cycles_from_necks = necks;
    return build_quad_layout(mesh, o);
}

// A torus whose mesh lines are not the layout's cycles: every vertex moved along the surface by up
// to 0.3 of a grid cell each way (a fixed pseudo-random offset), so a cycle along mesh edges zigzags.
// On the regular grid the torus's cycles ran along grid lines without a staircase, and its
// unrelaxed layout is kept there (patch area max/min 1.12 and corner angle deviation 1.2 deg
// against the relaxed 1.06 and 29.9 deg), which left these tests nothing to straighten.
Mesh jittered_torus() {
    constexpr int kMajor = 64, kMinor = 24;
    constexpr double kRadius = 1.0, kTube = 0.35, kPi = 3.14159265358979323846;
    Mesh m = shapes::torus(kMajor, kMinor, kRadius, kTube);
    for (size_t i = 0; i < m.points.size(); ++i) {
        Vec3& p = m.points[i];
        const double ring = std::hypot(p.x, p.y);
        const double u = std::atan2(p.y, p.x) + 0.3 * std::sin(12.9898 * i) * 2 * kPi / kMajor;
        const double v = std::atan2(p.z, ring - kRadius) + 0.3 * std::sin(78.233 * i) * 2 * kPi / kMinor;
        p = Vec3{(kRadius + kTube * std::cos(v)) * std::cos(u), (kRadius + kTube * std::cos(v)) * std::sin(u),
                 kTube * std::sin(v)};
    }
    return m;
}

// The shapes: a plate of genus 2, a big body with three small handles (the failure class), a
// torus and a sphere (the 4-quad and 6-quad special cases).
struct Shape {
    const char* name;
    Mesh (*make)();
};
const Shape kShapes[] = {
    {"plate2", [] { return shapes::plate_with_holes(2); }},
    {"handles3",
     [] {
         shapes::HandleBodyOptions o;
         o.handles = 3;
         return shapes::body_with_handles(o);
     }},
    {"torus", [] { return jittered_torus(); }},
    {"sphere", [] { return shapes::icosphere(4); }},
};

// The fraction of the layout edges' inner points where the edge turns by more than 20 degrees
// within the surface (the angle between its two segments projected onto the tangent plane, whose
// normal is the point's area-weighted vertex normal). A path along mesh edges zigzags across the
// triangles, turning at most of its vertices by tens of degrees (the staircase); a smooth curve
// turns by a few degrees a point, however the surface bends under it. Counted beyond 0.15 of the
// edge's length from either end (smoothing holds the first and last 0.12, where the relaxation set
// the directions the edges leave the corners in).
double sharp_turns(const QuadLayout& L) {
    const Mesh& m = L.mesh;
    std::vector<Vec3> normal(m.num_vertices(), Vec3{0, 0, 0});
    for (const Triangle& t : m.triangles) {
        const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
        for (int v : t) normal[v] = normal[v] + n;
    }
    int sharp = 0, points = 0;
    for (const auto& path : L.edge_paths) {
        std::vector<double> at{0};
        for (size_t i = 0; i + 1 < path.size(); ++i)
            at.push_back(at.back() + norm(m.points[path[i + 1]] - m.points[path[i]]));
        for (size_t i = 1; i + 1 < path.size(); ++i) {
            if (std::min(at[i], at.back() - at[i]) <= 0.15 * at.back()) continue;
            const Vec3 n = normal[path[i]] * (1 / norm(normal[path[i]]));
            Vec3 a = m.points[path[i]] - m.points[path[i - 1]];
            Vec3 b = m.points[path[i + 1]] - m.points[path[i]];
            a = a - n * dot(a, n);
            b = b - n * dot(b, n);
            ++points;
            if (std::atan2(norm(cross(a, b)), dot(a, b)) > 20 * std::acos(-1.0) / 180) ++sharp;
        }
    }
    return points > 0 ? static_cast<double>(sharp) / points : 0;
}

double length(const QuadLayout& L) {
    double total = 0;
    for (const auto& path : L.edge_paths)
        for (size_t i = 0; i + 1 < path.size(); ++i)
            total += norm(L.mesh.points[path[i + 1]] - L.mesh.points[path[i]]);
    return total;
}

// S is L with its edges moved: the same cage, its corners on the same mesh points, every vertex of
// L in order and in place, and every new vertex on an edge of L whose ends are its neighbours (new
// vertices only where a curve crosses a mesh edge).
void expect_same_corners_on_the_same_surface(const QuadLayout& L, const QuadLayout& S) {
    ASSERT_EQ(S.cage.num_quads(), L.cage.num_quads());
    for (int q = 0; q < L.cage.num_quads(); ++q) EXPECT_EQ(S.cage.quads[q].corners, L.cage.quads[q].corners);
    ASSERT_EQ(S.corner_vertex.size(), L.corner_vertex.size());
    for (size_t c = 0; c < L.corner_vertex.size(); ++c) {
        const Vec3 d = S.mesh.points[S.corner_vertex[c]] - L.mesh.points[L.corner_vertex[c]];
        EXPECT_EQ(norm(d), 0.0) << "corner " << c;
    }
    ASSERT_GE(S.mesh.num_vertices(), L.mesh.num_vertices());
    for (int v = 0; v < L.mesh.num_vertices(); ++v) ASSERT_EQ(norm(S.mesh.points[v] - L.mesh.points[v]), 0.0);
    std::set<std::pair<int, int>> old_edges;
    for (const Triangle& t : L.mesh.triangles)
        for (int k = 0; k < 3; ++k) old_edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    std::vector<std::set<int>> ring(S.mesh.num_vertices());
    for (const Triangle& t : S.mesh.triangles)
        for (int k = 0; k < 3; ++k) ring[t[k]].insert(t[(k + 1) % 3]), ring[t[(k + 1) % 3]].insert(t[k]);
    const int n0 = L.mesh.num_vertices();
    for (int m = n0; m < S.mesh.num_vertices(); ++m) {
        // The edge's ends are old vertices within two rings of m (an edge crossed twice puts the
        // other crossing between m and one end).
        std::set<int> near;
        for (int a : ring[m]) {
            near.insert(a);
            for (int b : ring[a]) near.insert(b);
        }
        bool on_edge = false;
        for (int a : near)
            for (int b : near) {
                if (a >= b || a >= n0 || b >= n0 || !old_edges.count({a, b})) continue;
                const Vec3 &pa = S.mesh.points[a], &pb = S.mesh.points[b], &p = S.mesh.points[m];
                const double ab = norm(pb - pa);
                on_edge = on_edge || (norm(cross(p - pa, pb - pa)) <= 1e-9 * ab * ab &&
                                      dot(p - pa, pb - pa) > 0 && dot(p - pb, pa - pb) > 0);
            }
        EXPECT_TRUE(on_edge) << "new vertex " << m << " lies on no edge of the layout mesh";
    }
}

class LayoutSmoothEdges : public ::testing::TestWithParam<Shape> {};

TEST_P(LayoutSmoothEdges, SmoothCurvesThroughTheSameCornersOnTheSameSurface) {
    const QuadLayout L = staircase_layout(GetParam().make());
    ASSERT_EQ(verify_quad_layout(L), "");
    QuadLayout S;
    SmoothingReport r;
    ASSERT_EQ(smooth_layout_edges(L, &S, &r), "");
    EXPECT_EQ(verify_quad_layout(S), "");
    EXPECT_GT(r.band_vertices, 0);

    expect_same_corners_on_the_same_surface(L, S);

    // No staircase: sharp turns at under 0.4 of the share of points they were at (measured: plate
    // 0.479 -> 0.173, body with handles 0.379 -> 0.084, torus 0.056 -> 0, sphere 0.473 -> 0.043;
    // what is left lies at the creases of the voxel shapes and where two edges cross one mesh
    // edge), and shorter curves.
    const double before = sharp_turns(L), after = sharp_turns(S);
    std::printf("%s: sharp turns at %.3f of the points -> %.3f\n", GetParam().name, before, after);
    EXPECT_LT(after, 0.4 * before);
    EXPECT_LT(after, 0.2);
    EXPECT_LT(length(S), length(L));
}

INSTANTIATE_TEST_SUITE_P(Shapes, LayoutSmoothEdges, ::testing::ValuesIn(kShapes),
                         [](const auto& info) { return std::string(info.param.name); });

// The number of points of `path` within `fraction` of its length from its start.
size_t points_within(const Mesh& mesh, const std::vector<int>& path, double fraction) {
    std::vector<double> at{0};
    for (size_t i = 0; i + 1 < path.size(); ++i)
        at.push_back(at.back() + norm(mesh.points[path[i + 1]] - mesh.points[path[i]]));
    size_t k = 0;
    while (k < path.size() && at[k] <= fraction * at.back()) ++k;
    return k;
}

class LayoutEmbedEdges : public ::testing::TestWithParam<Shape> {};

TEST_P(LayoutEmbedEdges, OneMapMovesTheEdgesButNotTheCornersOrTheirDirections) {
    // handles3: the handle loops' S-cycles, the layout the balance below was measured on (30.4 ->
    // 27.2). Since the corner angles are measured as check_layout.py measures them (2b4c276), the
    // choice without a score keeps the necks' layout there (28.6 and 25.8 deg against 30.4 and 26.2),
    // whose balance the embedding hardly moves (28.6 -> 28.5).
    const bool handles3 = std::string(GetParam().name) == "handles3";
    const QuadLayout L = staircase_layout(GetParam().make(), !handles3);
    ASSERT_EQ(verify_quad_layout(L), "");
    QuadLayout E;
    EdgeEmbeddingReport r;
    ASSERT_EQ(embed_layout_edges(L, 30, &E, &r), "");
    EXPECT_EQ(verify_quad_layout(E), "");
    EXPECT_GT(r.variables, 0);
    EXPECT_GT(r.iterations, 0);
    EXPECT_LT(r.final_energy, r.initial_energy);
    expect_same_corners_on_the_same_surface(L, E);

    // Each edge leaves its corners as it did: its first and last tenth (by its old length; held)
    // are the same mesh vertices in the same order.
    ASSERT_EQ(E.edge_paths.size(), L.edge_paths.size());
    for (size_t e = 0; e < L.edge_paths.size(); ++e) {
        for (int end = 0; end < 2; ++end) {
            std::vector<int> old_path = L.edge_paths[e], new_path = E.edge_paths[e];
            if (end == 1)
                std::reverse(old_path.begin(), old_path.end()),
                    std::reverse(new_path.begin(), new_path.end());
            const size_t k = points_within(L.mesh, old_path, 0.1);
            ASSERT_GE(new_path.size(), k);
            EXPECT_TRUE(std::equal(old_path.begin(), old_path.begin() + k, new_path.begin()))
                << "edge " << e << " end " << end << ": its first " << k << " points moved";
        }
    }

    // The edges run across the triangles (as smooth_layout_edges() makes them), and the area
    // spreads more evenly over the patches.
    measure_quality(&E);
    const double before = sharp_turns(L), after = sharp_turns(E);
    std::printf(
        "%s: energy %.4g -> %.4g in %d steps; sharp turns %.3f -> %.3f; patch area max/min %.3g -> %.3g\n",
        GetParam().name, r.initial_energy, r.final_energy, r.iterations, before, after,
        L.quality.patch_area_max_over_min, E.quality.patch_area_max_over_min);
    EXPECT_LT(after, 0.4 * before);
    EXPECT_LT(after, 0.2);
    if (handles3) {  // the class it is for: a big body, small handles
        EXPECT_LT(E.quality.patch_area_max_over_min,
                  0.95 * L.quality.patch_area_max_over_min);  // 30.4 -> 27.2
    }
}

INSTANTIATE_TEST_SUITE_P(Shapes, LayoutEmbedEdges, ::testing::ValuesIn(kShapes),
                         [](const auto& info) { return std::string(info.param.name); });

// The embedding stops once a step lowers the energy by less than kEdgeEmbeddingTolerance: on a real
// layout it ends sooner than with every step taken, almost as low, and as well balanced.
TEST(LayoutEmbedEdges, StopsWhereAStepGainsLittleNearlyAsLowAsWithEveryStep) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no shared meshes";
    const QuadLayout L = staircase_layout(test::load_shared("fertility.off"));
    QuadLayout E, all;
    EdgeEmbeddingReport r, r_all;
    ASSERT_EQ(embed_layout_edges(L, 30, &E, &r), "");
    ASSERT_EQ(embed_layout_edges(L, 30, &all, &r_all, 0.0), "");
    std::printf("fertility: %d steps (%s), energy %.5g; every step: %d (%s), %.5g\n", r.iterations,
                r.stopped.c_str(), r.final_energy, r_all.iterations, r_all.stopped.c_str(), r_all.final_energy);
    EXPECT_NE(r.stopped.find("converged"), std::string::npos) << r.stopped;
    EXPECT_LT(r.iterations, r_all.iterations);
    EXPECT_LE(r_all.final_energy, r.final_energy);
    EXPECT_LT(r.final_energy, 1.02 * r_all.final_energy);
    EXPECT_EQ(verify_quad_layout(E), "");
    measure_quality(&E);
    measure_quality(&all);
    EXPECT_LT(E.quality.patch_area_max_over_min, 1.1 * all.quality.patch_area_max_over_min)
        << E.quality.patch_area_max_over_min << " vs " << all.quality.patch_area_max_over_min;
}

// By default the driver embeds the edges, or smooths them where the embedded ones are no better
// balanced or pass the refinement bound, and says which.
TEST(LayoutSmoothEdges, TheDriverEmbedsOrSmoothsTheEdgesByDefaultAndSaysSo) {
    for (const Shape& shape : kShapes) {
        SCOPED_TRACE(shape.name);
        const Mesh mesh = shape.make();
        std::vector<std::string> said;
        QuadLayoutOptions o;
        o.progress = [&](const std::string& m) { said.push_back(m); };
        const QuadLayout moved = build_quad_layout(mesh, o);
        bool embedded = false, smoothed = false;
        for (const auto& m : said) {
            embedded = embedded || m.rfind("edge embedding: keeping the embedded edges", 0) == 0;
            smoothed = smoothed || m.rfind("smoothing: the map made harmonic", 0) == 0;
        }
        EXPECT_NE(embedded, smoothed);
        EXPECT_TRUE(moved.edges_smoothed);
        const QuadLayout staircase = staircase_layout(mesh);
        if (embedded) {
            EXPECT_LT(moved.quality.patch_area_max_over_min, staircase.quality.patch_area_max_over_min);
        }
        EXPECT_LT(sharp_turns(moved), 0.4 * sharp_turns(staircase));
        EXPECT_LE(moved.mesh.num_vertices() - moved.input_vertices,
                  vertices_added_bound(moved.input_vertices, moved.cage.num_corners()));
    }
}

}  // namespace
}  // namespace quadcage::layout::detail

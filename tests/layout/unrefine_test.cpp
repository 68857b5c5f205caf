// remove_unused_refinement: splits no curve runs through are undone exactly, and nothing else moves.

#include "detail/unrefine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <utility>

#include "detail/curves.h"
#include "detail/patches.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {
namespace {

// Splits mesh edge a-b at its midpoint (both its triangles in two, each half keeps its patch and
// its part of the map).
// Returns the new vertex.
int split_edge(QuadLayout* L, int a, int b) {
    Mesh& m = L->mesh;
    const int mid = m.num_vertices();
    m.points.push_back((m.points[a] + m.points[b]) * 0.5);
    const int nt = m.num_triangles();
    int found = 0;
    for (int t = 0; t < nt; ++t) {
        Triangle& f = m.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int x = f[k], y = f[(k + 1) % 3], z = f[(k + 2) % 3];
            if (!((x == a && y == b) || (x == b && y == a))) continue;
            const std::array<UV, 3> uv = L->corner_uv[t];
            const UV ux = uv[k], uy = uv[(k + 1) % 3], uz = uv[(k + 2) % 3];
            const UV um{0.5 * (ux[0] + uy[0]), 0.5 * (ux[1] + uy[1])};
            f = {x, mid, z};
            L->corner_uv[t] = {ux, um, uz};
            m.triangles.push_back({mid, y, z});
            L->corner_uv.push_back({um, uy, uz});
            L->triangle_patch.push_back(L->triangle_patch[t]);
            ++found;
            break;
        }
    }
    EXPECT_EQ(found, 2) << "edge " << a << "-" << b;
    return mid;
}

// The triangles as a set of (rotated so the least vertex is first) corner triples with patches.
std::set<std::pair<std::array<int, 3>, int>> triangle_set(const QuadLayout& L) {
    std::set<std::pair<std::array<int, 3>, int>> out;
    for (int t = 0; t < L.mesh.num_triangles(); ++t) {
        std::array<int, 3> f = L.mesh.triangles[t];
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        out.insert({f, L.triangle_patch[t]});
    }
    return out;
}

// A vertex of an edge of patch `patch` that lies on no layout edge and no cycle, with a neighbour
// across that edge in the same patch; -1 if none.
std::pair<int, int> interior_edge(const QuadLayout& L, const std::vector<char>& on_curve, int skip) {
    for (int t = 0; t < L.mesh.num_triangles(); ++t) {
        const Triangle& f = L.mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3];
            if (on_curve[a] || on_curve[b] || skip-- > 0) continue;
            return {a, b};
        }
    }
    return {-1, -1};
}

// Per vertex: does a layout edge or a cycle of the orthogonal system run through it.
std::vector<char> curve_vertices(const QuadLayout& L) {
    std::vector<char> on(L.mesh.num_vertices(), 0);
    for (const auto& p : L.edge_paths)
        for (int v : p) on[v] = 1;
    for (const auto& c : L.orthogonal_system)
        for (int v : c) on[v] = 1;
    return on;
}

// A torus whose points are jittered, so that no two of its triangles are coplanar (a torus grid
// cell is a planar trapezoid, whose other diagonal an exact undo may take as well).
QuadLayout torus_layout() {
    Mesh mesh = shapes::torus(40, 20, 1.0, 0.4);
    unsigned state = 12345;
    auto jitter = [&state]() {
        state = state * 1664525u + 1013904223u;
        return 2e-3 * (static_cast<double>(state >> 8) / (1u << 24) - 0.5);
    };
    for (Vec3& p : mesh.points) p += Vec3{jitter(), jitter(), jitter()};
    return build_quad_layout(mesh, QuadLayoutOptions{});
}

TEST(Unrefine, UndoesSplitsInsidePatchesExactlyAndKeepsEveryCurve) {
    const QuadLayout original = torus_layout();
    ASSERT_EQ(verify_quad_layout(original), "");
    {
        QuadLayout again;
        std::vector<char> changed;
        EXPECT_EQ(remove_unused_refinement(original, &again, &changed), 0)
            << "build_quad_layout() leaves nothing to remove";
    }
    const std::vector<char> on_curve = curve_vertices(original);

    QuadLayout L = original;
    // Splits on edges of the input torus (every one a crease: its two faces are not coplanar), a
    // split of an edge from such a midpoint (a point inside an input face), and a split of a split.
    int splits = 0;
    for (int i = 0; i < 12; ++i) {
        const auto [a, b] = interior_edge(original, on_curve, 97 * i);
        ASSERT_GE(a, 0);
        const int m = split_edge(&L, a, b);
        ++splits;
        if (i % 3 == 0) {
            // m's neighbours other than a and b: split m-c, then that new edge's half again.
            int c = -1;
            for (const Triangle& f : L.mesh.triangles)
                if (std::find(f.begin(), f.end(), m) != f.end())
                    for (int x : f)
                        if (x != m && x != a && x != b) c = x;
            ASSERT_GE(c, 0);
            const int m2 = split_edge(&L, m, c);
            const int m3 = split_edge(&L, m2, c);
            (void)m3;
            splits += 2;
        }
    }
    ASSERT_TRUE(validate(L.mesh).quaddable()) << validate(L.mesh).error_summary();
    std::set<int> split_patches;  // the patches of the split edges' triangles
    for (int t = original.mesh.num_triangles(); t < L.mesh.num_triangles(); ++t)
        split_patches.insert(L.triangle_patch[t]);
    std::vector<char> changed;
    QuadLayout lean;
    EXPECT_EQ(remove_unused_refinement(L, &lean, &changed), splits);
    L = std::move(lean);
    for (int q = 0; q < L.cage.num_quads(); ++q)
        EXPECT_EQ(changed[q] != 0, split_patches.count(q) == 1) << "patch " << q;

    // The same points in the same order, the same triangles in the same patches.
    ASSERT_EQ(L.mesh.num_vertices(), original.mesh.num_vertices());
    for (int v = 0; v < L.mesh.num_vertices(); ++v) EXPECT_EQ(L.mesh.points[v], original.mesh.points[v]) << v;
    EXPECT_EQ(triangle_set(L), triangle_set(original));
    EXPECT_EQ(L.edge_paths, original.edge_paths);
    EXPECT_EQ(L.orthogonal_system, original.orthogonal_system);
    EXPECT_EQ(L.corner_vertex, original.corner_vertex);
    // The patches no split touched keep their maps; mapping only the others gives every patch the
    // map a full mapping gives.
    QuadLayout full = L;
    parameterize_patches(&full);
    parameterize_patches(&L, &changed);
    for (int t = 0; t < L.mesh.num_triangles(); ++t)
        ASSERT_EQ(L.corner_uv[t], full.corner_uv[t]) << "triangle " << t;
    EXPECT_EQ(verify_quad_layout(L), "");
}

TEST(Unrefine, KeepsVerticesCyclesRunThroughAndRenumbersThem) {
    const QuadLayout original = torus_layout();
    const std::vector<char> on_curve = curve_vertices(original);
    ASSERT_FALSE(original.orthogonal_system.empty());
    QuadLayout L = original;
    // An unused split first (lower index), then a split of a mesh edge of a cycle of the orthogonal
    // system that no layout edge runs along, which the cycle then runs through: the first goes, the
    // second stays (cycles are never straightened) and moves down by one.
    const auto [a, b] = interior_edge(original, on_curve, 0);
    const int unused = split_edge(&L, a, b);
    std::vector<int>& cycle = L.orthogonal_system[0];
    const PathsThrough paths(L.mesh.num_vertices(), original.edge_paths);
    size_t i = 0;
    while (i < cycle.size() && paths.share_a_path(cycle[i], cycle[(i + 1) % cycle.size()])) ++i;
    ASSERT_LT(i, cycle.size());
    const int c0 = cycle[i], c1 = cycle[(i + 1) % cycle.size()];
    const int used = split_edge(&L, c0, c1);
    cycle.insert(cycle.begin() + static_cast<std::ptrdiff_t>(i) + 1, used);
    ASSERT_EQ(used, unused + 1);
    std::vector<char> changed;
    QuadLayout lean;
    EXPECT_EQ(remove_unused_refinement(L, &lean, &changed), 1);
    L = std::move(lean);
    ASSERT_EQ(L.mesh.num_vertices(), original.mesh.num_vertices() + 1);
    EXPECT_EQ(L.orthogonal_system[0][i + 1], unused) << "the kept split takes the removed one's index";
    EXPECT_EQ(L.mesh.points[unused], (original.mesh.points[c0] + original.mesh.points[c1]) * 0.5);
    EXPECT_EQ(L.edge_paths, original.edge_paths);
    parameterize_patches(&L);
    EXPECT_EQ(verify_quad_layout(L), "");
}

TEST(Unrefine, TakesVerticesOutOfStraightStretchesOfLayoutEdgesOnlyWhenAsked) {
    // A split of a layout edge's first mesh edge, which the layout edge runs straight through: it
    // stays unless asked to straighten. Then it goes (a vertex on an input edge slides along it
    // exactly), with the other added vertices of the (smoothed) layout edges where they run
    // straight, and the layout is the same surface with the same corners and edge ends.
    const QuadLayout original = torus_layout();
    QuadLayout L = original;
    const std::vector<int>& path = original.edge_paths[0];
    const int used = split_edge(&L, path[0], path[1]);
    L.edge_paths[0].insert(L.edge_paths[0].begin() + 1, used);
    parameterize_patches(&L);
    ASSERT_EQ(verify_quad_layout(L), "");
    std::vector<char> changed;
    QuadLayout lean;
    EXPECT_EQ(remove_unused_refinement(L, &lean, &changed), 0);
    const int removed = remove_unused_refinement(L, &lean, &changed, true);
    EXPECT_GE(removed, 1);
    ASSERT_EQ(lean.mesh.num_vertices(), L.mesh.num_vertices() - removed);
    for (const Vec3& p : lean.mesh.points) EXPECT_NE(p, L.mesh.points[used]) << "the split stayed";
    for (int v = 0; v < lean.input_vertices; ++v) EXPECT_EQ(lean.mesh.points[v], L.mesh.points[v]) << v;
    ASSERT_EQ(lean.edge_paths.size(), L.edge_paths.size());
    for (size_t e = 0; e < L.edge_paths.size(); ++e) {
        EXPECT_EQ(lean.mesh.points[lean.edge_paths[e].front()], L.mesh.points[L.edge_paths[e].front()]) << e;
        EXPECT_EQ(lean.mesh.points[lean.edge_paths[e].back()], L.mesh.points[L.edge_paths[e].back()]) << e;
        EXPECT_LT(lean.edge_paths[e].size(), L.edge_paths[e].size() + (e == 0 ? 0 : 1)) << e;
    }
    for (size_t c = 0; c < L.corner_vertex.size(); ++c)
        EXPECT_EQ(lean.mesh.points[lean.corner_vertex[c]], L.mesh.points[L.corner_vertex[c]]) << c;
    auto area = [](const Mesh& m) {
        double a = 0;
        for (const Triangle& f : m.triangles)
            a += 0.5 * norm(cross(m.points[f[1]] - m.points[f[0]], m.points[f[2]] - m.points[f[0]]));
        return a;
    };
    EXPECT_NEAR(area(lean.mesh), area(L.mesh), 1e-12 * area(L.mesh));
    parameterize_patches(&lean, &changed);
    EXPECT_EQ(verify_quad_layout(lean), "");
}

// undo_unused_refinement() straightens only a layout over the bound it is given.
TEST(Unrefine, StraightensOnlyOverTheBound) {
    const QuadLayout original = torus_layout();
    const int added = original.mesh.num_vertices() - original.input_vertices;
    ASSERT_GT(added, 0);
    for (const long long bound : {-1LL, static_cast<long long>(added), 0LL}) {
        QuadLayout L = original;
        std::vector<std::string> said;
        undo_unused_refinement(
            &L, [&said](const std::string& m) { said.push_back(m); }, bound);
        const bool straightened = std::any_of(said.begin(), said.end(), [](const std::string& m) {
            return m.find("taken out of straight stretches") != std::string::npos;
        });
        EXPECT_EQ(straightened, bound == 0) << "bound " << bound;
        EXPECT_EQ(L.mesh.num_vertices() < original.mesh.num_vertices(), bound == 0) << "bound " << bound;
        EXPECT_EQ(verify_quad_layout(L), "") << "bound " << bound;
    }
}

}  // namespace
}  // namespace quadcage::layout::detail

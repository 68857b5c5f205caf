// retrace_on_input: the layout's curves traced again on the input's own triangles keep the layout
// (same cage, corners, curves' order) and its surface, and add only the points where curves cross
// input edges or meet inside input triangles.

#include "detail/retrace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "detail/unrefine.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {
namespace {

// The input triangles point p lies in (within a relative 1e-9 of the plane, inside up to 1e-7).
std::vector<int> triangles_holding(const Mesh& input, const Vec3& p) {
    std::vector<int> out;
    for (int f = 0; f < input.num_triangles(); ++f) {
        const Triangle& t = input.triangles[f];
        const Vec3 a = input.points[t[0]], b = input.points[t[1]], c = input.points[t[2]];
        const Vec3 n = cross(b - a, c - a);
        const double area2 = dot(n, n);
        if (std::abs(dot(p - a, n)) > 1e-9 * std::sqrt(area2) * norm(b - a)) continue;
        const double w0 = dot(cross(b - p, c - p), n) / area2, w1 = dot(cross(c - p, a - p), n) / area2,
                     w2 = dot(cross(a - p, b - p), n) / area2;
        if (std::min({w0, w1, w2}) >= -1e-7) out.push_back(f);
    }
    return out;
}

struct Traced {
    Mesh input;
    QuadLayout before, after;
    std::string problem;
};

// A genus-3 plate of 1,300 triangles: its layout, along mesh edges, is refined densely round the
// holes.
const Traced& traced() {
    static const Traced T = [] {
        Traced t;
        t.input = shapes::plate_with_holes(3);
        QuadLayoutOptions o;
        o.smooth_edges = false;
        t.before = build_quad_layout(t.input, o);
        t.problem = retrace_on_input(t.input, t.before, &t.after);
        return t;
    }();
    return T;
}

TEST(Retrace, KeepsTheLayoutAndAddsFewerVertices) {
    const Traced& t = traced();
    ASSERT_EQ(t.problem, "");
    EXPECT_EQ(verify_quad_layout(t.after), "");
    const int before = t.before.mesh.num_vertices() - t.before.input_vertices;
    const int after = t.after.mesh.num_vertices() - t.after.input_vertices;
    EXPECT_LT(after, before);
    std::printf("  vertices added: %d along mesh edges, %d traced again\n", before, after);
    // The input's points first, unmoved.
    ASSERT_EQ(t.after.input_vertices, t.input.num_vertices());
    for (int v = 0; v < t.input.num_vertices(); ++v) EXPECT_EQ(t.after.mesh.points[v], t.input.points[v]);
    // The same cage: corners where they were.
    ASSERT_EQ(t.after.cage.num_quads(), t.before.cage.num_quads());
    ASSERT_EQ(t.after.corner_vertex.size(), t.before.corner_vertex.size());
    for (size_t k = 0; k < t.after.corner_vertex.size(); ++k)
        EXPECT_EQ(t.after.mesh.points[t.after.corner_vertex[k]],
                  t.before.mesh.points[t.before.corner_vertex[k]]);
    EXPECT_EQ(t.after.edge_paths.size(), t.before.edge_paths.size());
    EXPECT_EQ(t.after.orthogonal_system.size(), t.before.orthogonal_system.size());
    EXPECT_EQ(t.after.s_cycles.size(), t.before.s_cycles.size());
}

// Every new triangle lies inside one input triangle: no mesh edge crosses an input edge, and new
// vertices lie on input edges and triangles only.
TEST(Retrace, EveryTriangleLiesInOneInputTriangle) {
    const Traced& t = traced();
    ASSERT_EQ(t.problem, "");
    const Mesh& m = t.after.mesh;
    std::vector<std::vector<int>> holding(m.num_vertices());
    for (int v = 0; v < m.num_vertices(); ++v) {
        holding[v] = triangles_holding(t.input, m.points[v]);
        EXPECT_FALSE(holding[v].empty()) << "vertex " << v;
    }
    int outside = 0;
    for (const Triangle& f : m.triangles) {
        bool shared = false;
        for (int g : holding[f[0]])
            shared |= std::count(holding[f[1]].begin(), holding[f[1]].end(), g) &&
                      std::count(holding[f[2]].begin(), holding[f[2]].end(), g);
        outside += !shared;
    }
    EXPECT_EQ(outside, 0);
    double area_in = 0, area_out = 0;
    for (const Triangle& f : t.input.triangles)
        area_in += 0.5 * norm(cross(t.input.points[f[1]] - t.input.points[f[0]],
                                    t.input.points[f[2]] - t.input.points[f[0]]));
    for (const Triangle& f : m.triangles)
        area_out += 0.5 * norm(cross(m.points[f[1]] - m.points[f[0]], m.points[f[2]] - m.points[f[0]]));
    EXPECT_NEAR(area_out, area_in, 1e-9 * area_in);
}

// The curves are walks along mesh edges (cycles closed), and consecutive vertices of a layout edge
// or cycle differ.
TEST(Retrace, CurvesRunAlongMeshEdges) {
    const Traced& t = traced();
    ASSERT_EQ(t.problem, "");
    std::set<std::pair<int, int>> edges;
    for (const Triangle& f : t.after.mesh.triangles)
        for (int k = 0; k < 3; ++k)
            edges.insert({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])});
    auto along = [&](const std::vector<int>& c, bool closed) {
        int missing = 0;
        for (size_t i = 0; i + (closed ? 0 : 1) < c.size(); ++i) {
            const int a = c[i], b = c[(i + 1) % c.size()];
            missing += !edges.count({std::min(a, b), std::max(a, b)});
        }
        return missing;
    };
    for (const auto& p : t.after.edge_paths) EXPECT_EQ(along(p, false), 0);
    for (const auto& c : t.after.orthogonal_system) EXPECT_EQ(along(c, true), 0);
    for (const auto& c : t.after.s_cycles) EXPECT_EQ(along(c, true), 0);
}

// undo_unused_refinement() traces the curves again only for a layout still over its bound, and only
// when it is given the input.
TEST(Retrace, UndoingTheRefinementTracesAgainOnlyOverTheBound) {
    const Traced& t = traced();
    auto run = [&](long long bound, const Mesh* input) {
        QuadLayout L = t.before;
        std::vector<std::string> said;
        undo_unused_refinement(
            &L, [&said](const std::string& m) { said.push_back(m); }, bound, input);
        const bool retraced = std::any_of(said.begin(), said.end(), [](const std::string& m) {
            return m.find("traced again on the input's triangles:") != std::string::npos;
        });
        EXPECT_EQ(verify_quad_layout(L), "");
        return retraced;
    };
    const long long added = t.before.mesh.num_vertices() - t.before.input_vertices;
    EXPECT_TRUE(run(0, &t.input));
    EXPECT_FALSE(run(0, nullptr));
    EXPECT_FALSE(run(added, &t.input));
}

}  // namespace
}  // namespace quadcage::layout::detail

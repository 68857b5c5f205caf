// The layout built on a decimated copy and carried onto the input (decimated(),
// trace_from_proxy(), QuadLayoutOptions::proxy_vertices): the copy keeps the surface's genus, the
// carried layout is a verified layout of the input's own triangles with the copy's cage, and an
// input too small for a copy gets the layout it gets without one.

#include "detail/retrace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "quadcage/core/errors.h"
#include "quadcage/core/openmesh_bridge.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "quadcage/layout/quad_layout.h"
#include "support/files.h"

namespace quadcage::layout::detail {
namespace {

// A body with two small handles on its top, of about 25k vertices.
const Mesh& body() {
    static const Mesh m = [] {
        shapes::HandleBodyOptions o;
        o.handles = 2;
        o.resolution = 6;
        return shapes::body_with_handles(o);
    }();
    return m;
}

TEST(Decimated, KeepsTheGenusAndReachesTheCount) {
    const Mesh& input = body();
    ASSERT_GT(input.num_vertices(), 8000);
    const Mesh copy = decimated(input, 2000);
    EXPECT_GE(copy.num_vertices(), 2000);
    EXPECT_LE(copy.num_vertices(), 2100);
    const ValidationReport r = validate(copy);
    ASSERT_EQ(r.components.size(), 1u);
    EXPECT_TRUE(r.quaddable()) << r.error_summary();
    EXPECT_EQ(r.zero_area_triangles, 0);
    EXPECT_EQ(r.components[0].genus, 2);
    // Deterministic.
    const Mesh again = decimated(input, 2000);
    EXPECT_EQ(again.points, copy.points);
    EXPECT_EQ(again.triangles, copy.triangles);
}

TEST(Decimated, RejectsTooFewVertices) {
    EXPECT_THROW(decimated(body(), 3), InvalidInput);
}

struct Carried {
    QuadLayout proxy, out;
    std::string problem;
};

const Carried& carried() {
    static const Carried C = [] {
        Carried c;
        const Mesh copy = decimated(body(), 8000);
        c.proxy = build_quad_layout(copy);
        c.problem = trace_from_proxy(body(), c.proxy, &c.out);
        return c;
    }();
    return C;
}

TEST(TraceFromProxy, GivesAVerifiedLayoutOfTheInputWithTheCopysCage) {
    const Carried& c = carried();
    ASSERT_EQ(c.problem, "");
    EXPECT_EQ(verify_quad_layout(c.out), "");
    const Mesh& input = body();
    ASSERT_EQ(c.out.input_vertices, input.num_vertices());
    for (int v = 0; v < input.num_vertices(); ++v) ASSERT_EQ(c.out.mesh.points[v], input.points[v]) << v;
    EXPECT_EQ(c.out.genus, 2);
    EXPECT_EQ(c.out.cage.num_quads(), 10);
    EXPECT_EQ(c.out.cage.num_corners(), 8);
    EXPECT_EQ(c.out.edge_paths.size(), c.proxy.edge_paths.size());
    EXPECT_EQ(c.out.orthogonal_system.size(), 4u);
    EXPECT_EQ(c.out.s_cycles.size(), 4u);
    for (size_t k = 0; k < c.out.cage.quads.size(); ++k)
        EXPECT_EQ(c.out.cage.quads[k].corners, c.proxy.cage.quads[k].corners);
    // The cage's corners are the layout corners' points, on the input.
    for (size_t k = 0; k < c.out.corner_vertex.size(); ++k)
        EXPECT_EQ(c.out.cage.points[k], c.out.mesh.points[c.out.corner_vertex[k]]);
}

// The surface is the input's: the same area, and each patch near the copy's patch of that number.
TEST(TraceFromProxy, KeepsTheSurfaceAndThePatchesWhereTheCopyHadThem) {
    const Carried& c = carried();
    ASSERT_EQ(c.problem, "");
    EXPECT_NEAR(surface_area(c.out.mesh), surface_area(body()), 1e-9 * surface_area(body()));
    const int quads = c.out.cage.num_quads();
    std::vector<double> area_out(quads, 0), area_proxy(quads, 0);
    for (int t = 0; t < c.out.mesh.num_triangles(); ++t) area_out[c.out.triangle_patch[t]] += triangle_area(c.out.mesh, t);
    for (int t = 0; t < c.proxy.mesh.num_triangles(); ++t)
        area_proxy[c.proxy.triangle_patch[t]] += triangle_area(c.proxy.mesh, t);
    const double total_out = surface_area(c.out.mesh), total_proxy = surface_area(c.proxy.mesh);
    for (int q = 0; q < quads; ++q)
        EXPECT_NEAR(area_out[q] / total_out, area_proxy[q] / total_proxy, 0.02) << "patch " << q;
}

// skull (50k vertices) from a copy of 1,500: carried to their closest points, two of the curves
// cross in an input triangle; carried along the copy's normals they do not, and the layout is the
// input's own, verified.
TEST(TraceFromProxy, TriesTheCopysNormalsWhereTheClosestPointsFold) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found in " << test::shared_meshes_dir();
    const Mesh input = test::load_shared("skull.obj");
    const QuadLayout proxy = build_quad_layout(decimated(input, 1500));
    QuadLayout out;
    std::string how;
    ASSERT_EQ(trace_from_proxy(input, proxy, &out, &how), "");
    EXPECT_EQ(how, "along the copy's normals");
    EXPECT_EQ(verify_quad_layout(out), "");
    ASSERT_EQ(out.input_vertices, input.num_vertices());
    for (int v = 0; v < input.num_vertices(); ++v) ASSERT_EQ(out.mesh.points[v], input.points[v]) << v;
    EXPECT_EQ(out.cage.num_quads(), 10);
    EXPECT_NEAR(surface_area(out.mesh), surface_area(input), 1e-9 * surface_area(input));
}

TEST(ProxyVertices, AnInputTooSmallForACopyGetsItsOwnLayout) {
    const Mesh input = shapes::torus(24, 12);
    QuadLayoutOptions with;
    with.proxy_vertices = input.num_vertices() / 2;  // not more than twice as many vertices
    with.proxy_above = 0;
    const QuadLayout a = build_quad_layout(input), b = build_quad_layout(input, with);
    EXPECT_EQ(a.mesh.points, b.mesh.points);
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
    EXPECT_EQ(a.triangle_patch, b.triangle_patch);
}

// proxy_above: an input of that many vertices is laid out on itself, one more and on the copy.
TEST(ProxyVertices, OnlyInputsOfMoreThanProxyAboveVerticesUseTheCopy) {
    const Mesh input = shapes::torus(24, 12);
    for (const long long above : {static_cast<long long>(input.num_vertices()), input.num_vertices() - 1LL}) {
        QuadLayoutOptions o;
        o.proxy_vertices = 60;
        o.proxy_above = above;
        std::vector<std::string> said;
        o.progress = [&said](const std::string& m) { said.push_back(m); };
        const QuadLayout L = build_quad_layout(input, o);
        EXPECT_EQ(verify_quad_layout(L), "");
        const bool on_copy = std::any_of(said.begin(), said.end(),
                                         [](const std::string& m) { return m.rfind("proxy: ", 0) == 0; });
        EXPECT_EQ(on_copy, above < input.num_vertices()) << "proxy_above " << above;
    }
}

TEST(ProxyVertices, BuildsOnTheCopyAndSaysSo) {
    QuadLayoutOptions o;
    o.proxy_vertices = 8000;
    o.proxy_above = 0;
    std::vector<std::string> said;
    o.progress = [&said](const std::string& m) { said.push_back(m); };
    const QuadLayout L = build_quad_layout(body(), o);
    EXPECT_EQ(verify_quad_layout(L), "");
    EXPECT_EQ(L.input_vertices, body().num_vertices());
    EXPECT_EQ(L.cage.num_quads(), 10);
    const bool carried_over = std::any_of(said.begin(), said.end(), [](const std::string& m) {
        return m.rfind("proxy: carried onto the input", 0) == 0;
    });
    EXPECT_TRUE(carried_over);
}

TEST(ProxyVertices, NegativeIsRejected) {
    QuadLayoutOptions o;
    o.proxy_vertices = -1;
    EXPECT_NE(o.validate(), "");
    EXPECT_THROW(build_quad_layout(body(), o), InvalidInput);
    QuadLayoutOptions above;
    above.proxy_above = -1;
    EXPECT_NE(above.validate(), "");
}

}  // namespace
}  // namespace quadcage::layout::detail

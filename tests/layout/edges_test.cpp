// Where the layout edges finally run (place_layout_edges(), edges.cpp): along the edge embedding's
// iso-lines where that is kept, else smoothed, else along mesh edges; within the refinement bound;
// and the progress lines say which, and why.

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "detail/embedding.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {
namespace {

// A verified layout of a genus-2 plate with its edges along mesh edges, as the relaxation leaves
// them (place_layout_edges()'s input in build_quad_layout()).
const Mesh& plate() {
    static const Mesh m = shapes::plate_with_holes(2);
    return m;
}

const QuadLayout& staircase() {
    static const QuadLayout L = [] {
        QuadLayoutOptions o;
        o.smooth_edges = false;
        return build_quad_layout(plate(), o);
    }();
    return L;
}

long long bound_of(const QuadLayout& L) {
    return vertices_added_bound(L.input_vertices, L.cage.num_corners());
}

bool said(const std::vector<std::string>& lines, const std::string& start) {
    for (const std::string& m : lines)
        if (m.rfind(start, 0) == 0) return true;
    return false;
}

struct Placed {
    QuadLayout layout;
    std::vector<std::string> said;
};

Placed place(const QuadLayoutOptions& options, long long bound) {
    Placed p{staircase(), {}};
    place_layout_edges(plate(), &p.layout, options, bound,
                       [&](const std::string& m) { p.said.push_back(m); });
    return p;
}

void expect_same_corners(const QuadLayout& a, const QuadLayout& b) {
    ASSERT_EQ(a.cage.num_corners(), b.cage.num_corners());
    ASSERT_EQ(a.cage.num_quads(), b.cage.num_quads());
    for (int k = 0; k < a.cage.num_corners(); ++k) {
        EXPECT_EQ(a.cage.points[k].x, b.cage.points[k].x);
        EXPECT_EQ(a.cage.points[k].y, b.cage.points[k].y);
        EXPECT_EQ(a.cage.points[k].z, b.cage.points[k].z);
    }
}

TEST(LayoutPlaceEdges, TheEdgesAreEmbeddedOrSmoothedWithinTheBoundAndTheProgressSaysWhich) {
    const Placed p = place(QuadLayoutOptions{}, bound_of(staircase()));
    const bool embedded = said(p.said, "edge embedding: keeping the embedded edges");
    const bool smoothed = said(p.said, "smoothing: the map made harmonic");
    EXPECT_NE(embedded, smoothed);
    EXPECT_EQ(embedded, !said(p.said, "edge embedding: not kept"));
    EXPECT_TRUE(p.layout.edges_smoothed);
    EXPECT_EQ(verify_quad_layout(p.layout), "");
    expect_same_corners(p.layout, staircase());
    EXPECT_LE(p.layout.mesh.num_vertices() - p.layout.input_vertices, bound_of(staircase()));
    if (embedded) {
        EXPECT_LT(p.layout.quality.patch_area_max_over_min, staircase().quality.patch_area_max_over_min);
    }
}

TEST(LayoutPlaceEdges, AboveTheVertexLimitTheEmbeddingIsSkippedAndTheEdgesAreSmoothed) {
    QuadLayoutOptions o;
    o.edge_embedding_max_vertices = staircase().mesh.num_vertices() - 1;
    const Placed p = place(o, bound_of(staircase()));
    EXPECT_TRUE(said(p.said, "edge embedding: skipped: the layout mesh has " +
                                 std::to_string(staircase().mesh.num_vertices()) + " vertices"));
    EXPECT_FALSE(said(p.said, "embedding the layout edges"));
    EXPECT_TRUE(said(p.said, "smoothing: the map made harmonic"));
    EXPECT_TRUE(p.layout.edges_smoothed);
    EXPECT_EQ(verify_quad_layout(p.layout), "");
    expect_same_corners(p.layout, staircase());
}

TEST(LayoutPlaceEdges, EdgesThatWouldPassTheBoundStayAlongMeshEdges) {
    // Bound 0: every crossing of a mesh edge is a vertex too many, embedded or smoothed.
    const Placed p = place(QuadLayoutOptions{}, 0);
    EXPECT_TRUE(said(p.said, "edge embedding: not kept (they add "));
    EXPECT_TRUE(said(p.said, "smoothing: keeping the edges along mesh edges (smoothed, they add "));
    EXPECT_EQ(verify_quad_layout(p.layout), "");
    // The staircase as it came (its unused refinement was undone already), but over the bound, so
    // with the vertices of its straight stretches on flat ground taken out (the same corners), and
    // then, still over it, traced again on the input's triangles: its edges now cross them.
    EXPECT_TRUE(std::any_of(p.said.begin(), p.said.end(), [](const std::string& m) {
        return m.find(" vertices taken out of straight stretches of the layout edges removed") !=
               std::string::npos;
    }));
    EXPECT_TRUE(said(p.said, "refinement: the curves traced again on the input's triangles: "));
    EXPECT_TRUE(p.layout.edges_smoothed);
    EXPECT_LT(p.layout.mesh.num_vertices(), staircase().mesh.num_vertices());
    EXPECT_EQ(p.layout.corner_vertex.size(), staircase().corner_vertex.size());
    for (size_t c = 0; c < p.layout.corner_vertex.size(); ++c)
        EXPECT_EQ(p.layout.mesh.points[p.layout.corner_vertex[c]],
                  staircase().mesh.points[staircase().corner_vertex[c]]);
}

TEST(LayoutPlaceEdges, WithoutSmoothingTheEdgesStayAlongMeshEdges) {
    QuadLayoutOptions o;
    o.smooth_edges = false;
    const Placed p = place(o, bound_of(staircase()));
    EXPECT_FALSE(said(p.said, "edge embedding"));
    EXPECT_FALSE(said(p.said, "embedding the layout edges"));
    EXPECT_FALSE(said(p.said, "smoothing"));
    EXPECT_FALSE(p.layout.edges_smoothed);
    EXPECT_EQ(p.layout.triangle_patch, staircase().triangle_patch);
}

// A big smooth body with two small handles (the class whose corners crowd round the handles), its
// verified layout with the edges along mesh edges, and place_layout_edges() on it.
const Mesh& body() {
    static const Mesh m = shapes::body_with_handles();
    return m;
}

const QuadLayout& body_staircase() {
    static const QuadLayout L = [] {
        QuadLayoutOptions o;
        o.smooth_edges = false;
        return build_quad_layout(body(), o);
    }();
    return L;
}

Placed place_on_body(const QuadLayoutOptions& options) {
    Placed p{body_staircase(), {}};
    place_layout_edges(body(), &p.layout, options, bound_of(body_staircase()),
                       [&](const std::string& m) { p.said.push_back(m); });
    return p;
}

// Whether a progress line contains `part`.
bool says(const std::vector<std::string>& lines, const std::string& part) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& m) { return m.find(part) != std::string::npos; });
}

// The cone charts (issue #20's corner angles) pull the map round each corner towards the conformal
// map that spreads the corner's edges evenly in its tangent plane; on a big smooth body with two
// small handles (the class whose corners crowd round the handles) they lower the mean corner angle
// deviation check_layout.py --quality measures well below the held ends' (29.9 -> 16.0 deg through
// `quadcage layout --choose-s-cycles shape`), with the same corners and a verified layout.
TEST(LayoutPlaceEdges, ConeChartsSpreadTheEdgesEvenlyRoundTheCorners) {
    const QuadLayout& start = body_staircase();
    const long long bound = bound_of(start);
    auto placed = [](double charts) {
        QuadLayoutOptions o;
        o.edge_embedding_cone_charts = charts;
        return place_on_body(o);
    };
    const Placed held = placed(0), pulled = placed(1000);
    ASSERT_TRUE(said(pulled.said, "edge embedding: keeping the embedded edges"));
    EXPECT_TRUE(says(pulled.said, "pulled towards the cone charts"));
    EXPECT_EQ(verify_quad_layout(pulled.layout), "");
    expect_same_corners(pulled.layout, start);
    EXPECT_LE(pulled.layout.mesh.num_vertices() - pulled.layout.input_vertices, bound);
    std::cout << "  corner angle deviation: relaxed " << start.quality.corner_angle_mean_deviation_deg
              << ", ends held " << held.layout.quality.corner_angle_mean_deviation_deg << ", cone charts "
              << pulled.layout.quality.corner_angle_mean_deviation_deg << " deg\n";
    EXPECT_LT(pulled.layout.quality.corner_angle_mean_deviation_deg,
              held.layout.quality.corner_angle_mean_deviation_deg - 5);
    EXPECT_LE(pulled.layout.quality.corner_angle_mean_deviation_deg, 20.0);  // issue #20's target
}

// The area term (issue #20's balance): on the big smooth body with two small handles, the edge
// embedding with an area term spreads the surface more evenly over the patches than symmetric
// Dirichlet alone, through the same corners, verified and within the bound; the progress line says
// the weight.
TEST(LayoutPlaceEdges, AnAreaTermSpreadsTheSurfaceMoreEvenlyOverThePatches) {
    const QuadLayout& start = body_staircase();
    const long long bound = bound_of(start);
    auto placed = [](double weight) {
        QuadLayoutOptions o;
        o.edge_embedding_area_weight = weight;
        return place_on_body(o);
    };
    const Placed plain = placed(0), weighted = placed(10);
    ASSERT_TRUE(said(weighted.said, "edge embedding: keeping the embedded edges"));
    EXPECT_TRUE(says(weighted.said, "with an area term of weight 10"));
    EXPECT_FALSE(says(plain.said, "with an area term"));
    EXPECT_EQ(verify_quad_layout(weighted.layout), "");
    expect_same_corners(weighted.layout, start);
    EXPECT_LE(weighted.layout.mesh.num_vertices() - weighted.layout.input_vertices, bound);
    std::cout << "  patch area max/min: relaxed " << start.quality.patch_area_max_over_min
              << ", symmetric Dirichlet " << plain.layout.quality.patch_area_max_over_min
              << ", with the area term " << weighted.layout.quality.patch_area_max_over_min << "\n";
    EXPECT_LT(weighted.layout.quality.patch_area_max_over_min,
              0.9 * plain.layout.quality.patch_area_max_over_min);
}

TEST(LayoutPlaceEdges, AreaWeightMustBeFiniteAndNonNegative) {
    QuadLayoutOptions o;
    o.edge_embedding_area_weight = -1;
    EXPECT_NE(o.validate(), "");
    o.edge_embedding_area_weight = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(o.validate(), "");
    o.edge_embedding_area_weight = 10;
    EXPECT_EQ(o.validate(), "");
}

TEST(LayoutPlaceEdges, ConeChartStrengthMustBeFiniteAndNonNegative) {
    QuadLayoutOptions o;
    o.edge_embedding_cone_charts = -1;
    EXPECT_NE(o.validate(), "");
    o.edge_embedding_cone_charts = std::numeric_limits<double>::infinity();
    EXPECT_NE(o.validate(), "");
    o.edge_embedding_cone_charts = 1000;
    EXPECT_EQ(o.validate(), "");
}

}  // namespace
}  // namespace quadcage::layout::detail

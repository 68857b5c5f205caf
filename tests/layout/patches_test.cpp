// The cage, patches and patch maps of a curve network (extract_cage, parameterize_patches), and the
// cut-surface labelling under them, on hand-built networks.

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "detail/patches.h"
#include "detail/surface.h"
#include "quadcage/layout/quad_layout.h"
#include "support/torus_network.h"

namespace quadcage::layout::detail {
namespace {

// A genus-1 layout on `mesh` with nothing extracted yet.
QuadLayout empty_layout(const Mesh& mesh) {
    QuadLayout L;
    L.mesh = mesh;
    L.input_vertices = mesh.num_vertices();
    L.genus = 1;
    return L;
}

TEST(LayoutPatches, FaceComponentsCountTheCutsPieces) {
    const test::TorusNetwork t = test::torus_network(16, 8, {0, 8}, {0, 4});
    const Surface s(t.mesh);
    std::vector<int> label;
    // One meridian (two paths): the torus stays in one piece (an annulus).
    EXPECT_EQ(face_components(s, cut_half_edges(s, {t.paths[0], t.paths[1]}), &label), 1);
    // Both meridians: two annuli.
    EXPECT_EQ(face_components(s, cut_half_edges(s, {t.paths[0], t.paths[1], t.paths[2], t.paths[3]}), &label), 2);
    // The whole network: four patches, every triangle labelled.
    EXPECT_EQ(face_components(s, cut_half_edges(s, t.paths), &label), 4);
    EXPECT_EQ(static_cast<int>(label.size()), t.mesh.num_triangles());
    EXPECT_EQ(*std::min_element(label.begin(), label.end()), 0);
    EXPECT_EQ(*std::max_element(label.begin(), label.end()), 3);
}

TEST(LayoutPatches, TorusGridGivesFourQuadsWithMapsInTheUnitSquare) {
    const test::TorusNetwork t = test::torus_network(16, 8, {0, 8}, {0, 4});
    const Surface s(t.mesh);
    QuadLayout L = empty_layout(t.mesh);
    ASSERT_EQ(extract_cage(s, t.corners, t.paths, &L), "");
    EXPECT_EQ(L.cage.num_quads(), 4);
    EXPECT_EQ(L.cage.num_corners(), 4);
    EXPECT_EQ(L.cage.num_edges(), 8);
    EXPECT_EQ(subdiv::check_cage(L.cage), "");
    // Every quad has all four corners: each corner joins every quad once.
    for (const auto& q : L.cage.quads) EXPECT_EQ(std::set<int>(q.corners.begin(), q.corners.end()).size(), 4u);
    parameterize_patches(&L);
    ASSERT_EQ(L.corner_uv.size(), static_cast<size_t>(t.mesh.num_triangles()));
    for (const auto& tri : L.corner_uv)
        for (const auto& uv : tri)
            for (double x : uv) {
                EXPECT_GE(x, -1e-12);
                EXPECT_LE(x, 1 + 1e-12);
            }
    EXPECT_EQ(verify_quad_layout(L), "");
    // Equal patches on a regular grid: the area ratio is that of the torus' inner and outer halves.
    measure_quality(&L);
    EXPECT_LT(L.quality.patch_area_max_over_min, 3.0);
    EXPECT_EQ(L.quality.flipped_triangles, 0);
}

TEST(LayoutPatches, SidesRunCounterClockwiseRoundTheUnitSquare) {
    EXPECT_EQ(side_point(0, 0.25), (UV{0.25, 0.0}));
    EXPECT_EQ(side_point(1, 0.25), (UV{1.0, 0.25}));
    EXPECT_EQ(side_point(2, 0.25), (UV{0.75, 1.0}));
    EXPECT_EQ(side_point(3, 0.25), (UV{0.0, 0.75}));
    for (int k = 0; k < 4; ++k) EXPECT_EQ(side_point(k, 1.0), side_point((k + 1) % 4, 0.0));
}

TEST(LayoutPatches, ANetworkWithAMissingEdgeIsNoQuadLayout) {
    test::TorusNetwork t = test::torus_network(16, 8, {0, 8}, {0, 4});
    t.paths.pop_back();  // two patches merge into a hexagon-like face
    const Surface s(t.mesh);
    QuadLayout L = empty_layout(t.mesh);
    EXPECT_NE(extract_cage(s, t.corners, t.paths, &L), "");
}

}  // namespace
}  // namespace quadcage::layout::detail

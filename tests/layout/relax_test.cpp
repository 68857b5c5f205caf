// Relaxation of a layout's edges and corners (relax_layout_edges, relax_layout_corners) on a
// hand-built, deliberately unbalanced network: the combinatorics stay, the patches even out.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <set>

#include "detail/patches.h"
#include "detail/relax.h"
#include "detail/surface.h"
#include "quadcage/layout/quad_layout.h"
#include "support/torus_network.h"

namespace quadcage::layout::detail {
namespace {

using Corners = std::vector<std::array<double, 3>>;  // a quad's corner positions, sorted

struct Extracted {
    std::set<Corners> quads;  // every quad's corners
    double area_ratio = 0;    // largest / smallest patch
};

Extracted extract(const Surface& s, const std::vector<int>& corners, const std::vector<std::vector<int>>& paths) {
    QuadLayout L;
    L.mesh = s.mesh();
    L.input_vertices = s.num_vertices();
    L.genus = 1;
    const std::string problem = extract_cage(s, corners, paths, &L);
    EXPECT_EQ(problem, "");
    Extracted out;
    for (const auto& q : L.cage.quads) {
        Corners c;
        for (int k : q.corners) c.push_back({L.cage.points[k].x, L.cage.points[k].y, L.cage.points[k].z});
        std::sort(c.begin(), c.end());
        out.quads.insert(c);
    }
    std::vector<double> area(L.cage.num_quads(), 0);
    for (int t = 0; t < L.mesh.num_triangles(); ++t) area[L.triangle_patch[t]] += triangle_area(L.mesh, t);
    out.area_ratio = *std::max_element(area.begin(), area.end()) / *std::min_element(area.begin(), area.end());
    return out;
}

// A 4 x 4 grid on the torus whose longitudes crowd together (minor indices 0, 2, 4, 6 would be even;
// 0, 1, 2, 12 of 24 are not): neighbouring patches share one edge each, so every edge can move.
test::TorusNetwork crowded() { return test::torus_network(32, 24, {0, 8, 16, 24}, {0, 3, 6, 12}); }

TEST(LayoutRelax, EdgesMoveTowardsBalanceAndKeepTheCombinatorics) {
    const test::TorusNetwork t = crowded();
    const Surface s(t.mesh);
    const Extracted before = extract(s, t.corners, t.paths);
    std::vector<std::vector<int>> paths = t.paths;
    const int moves = relax_layout_edges(s, &paths);
    EXPECT_GT(moves, 0);
    const Extracted after = extract(s, t.corners, paths);
    EXPECT_EQ(after.quads, before.quads);  // the same corners bound the same quads
    for (size_t e = 0; e < paths.size(); ++e) {  // edges still join the same corners
        EXPECT_EQ(paths[e].front(), t.paths[e].front());
        EXPECT_EQ(paths[e].back(), t.paths[e].back());
    }
    std::cout << "  crowded torus grid: patch area max/min " << before.area_ratio << " -> " << after.area_ratio << "\n";
    EXPECT_LT(after.area_ratio, 0.8 * before.area_ratio);
}

TEST(LayoutRelax, CornersMoveInsideTheirStarsAndKeepTheCombinatorics) {
    const test::TorusNetwork t = crowded();
    const Surface s(t.mesh);
    const Extracted before = extract(s, t.corners, t.paths);
    std::vector<int> corners = t.corners;
    std::vector<std::vector<int>> paths = t.paths;
    const int moved = relax_layout_corners(s, &corners, &paths);
    EXPECT_GT(moved, 0);
    const Extracted after = extract(s, corners, paths);
    EXPECT_EQ(after.quads.size(), before.quads.size());
    std::cout << "  crowded torus grid: " << moved << " corners moved, patch area max/min " << before.area_ratio
              << " -> " << after.area_ratio << "\n";
    EXPECT_LT(after.area_ratio, before.area_ratio);
}

}  // namespace
}  // namespace quadcage::layout::detail

// Curves on a Surface (detail/curves.h): the sectors of a vertex on a curve, and the Builder every
// curve construction shares (obstacles, chord splitting for room, sector-to-sector paths).

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "detail/curves.h"
#include "support/torus_network.h"

namespace quadcage::layout::detail {
namespace {

TEST(LayoutCurves, SectorsSplitTheRingAtTheCurve) {
    const Surface s(shapes::icosphere(2));
    for (int x : {0, 5, 17}) {
        const std::vector<int> ring = s.ring(x);
        const int prev = ring[0], next = ring[ring.size() / 2];
        const auto sec = sectors(s, x, prev, next);
        // Both sectors together are the ring without prev and next, each vertex once.
        std::multiset<int> both(sec[0].begin(), sec[0].end());
        both.insert(sec[1].begin(), sec[1].end());
        std::multiset<int> rest(ring.begin(), ring.end());
        rest.erase(prev);
        rest.erase(next);
        EXPECT_EQ(both, rest) << "vertex " << x;
        EXPECT_FALSE(sec[0].empty());
        EXPECT_FALSE(sec[1].empty());
        // Sector 0 starts beside the triangle of half-edge x -> prev.
        const int h = s.find_half_edge(x, prev);
        const Triangle& t = s.mesh().triangles[h / 3];
        EXPECT_NE(std::find(t.begin(), t.end(), sec[0].front()), t.end());
    }
}

TEST(LayoutCurves, ObstaclesBlockAndPathsLeaveAndArriveThroughTheirSectors) {
    // A meridian of the torus as an obstacle: a path from one side of it to the other must go round
    // the torus the long way, and leaves and arrives through the sectors asked for.
    const test::TorusNetwork t = test::torus_network(24, 8, {0}, {0});
    Builder b(t.mesh, {});
    Cycle meridian;
    for (int j = 0; j < 8; ++j) meridian.push_back(j);  // vertices (0, j)
    const int id = b.add_curve(meridian);
    const std::vector<char> block = b.blocked();
    for (int v : meridian) EXPECT_TRUE(block[v]);
    EXPECT_EQ(std::count(block.begin(), block.end(), 1), 8);
    const int x = 0;  // on the meridian
    const auto [prev, next] = neighbours_on(b.curves_[id], x);
    const auto sec = sectors(b.s_, x, prev, next);
    // From x's one side round to its other side: the path has to go once round the major circle.
    const auto cost = b.cost_near(block);
    double total = 0;
    const std::vector<int> path = b.sector_path(x, sec[0], x, sec[1], block, cost, &total);
    ASSERT_FALSE(path.empty());
    for (int v : path) EXPECT_FALSE(block[v]) << v;
    EXPECT_NE(std::find(sec[0].begin(), sec[0].end(), path.front()), sec[0].end());
    EXPECT_NE(std::find(sec[1].begin(), sec[1].end(), path.back()), sec[1].end());
    EXPECT_GE(path.size(), 23u);  // at least once round the 24 meridians
}

TEST(LayoutCurves, SplitChordsMakesRoomBetweenCurvesSideBySide) {
    // Two neighbouring meridians: every edge between them joins two curve vertices without being
    // a curve edge, so no path can pass between them until those chords are split.
    const test::TorusNetwork t = test::torus_network(24, 8, {0}, {0});
    Builder b(t.mesh, {});
    Cycle m0, m1;
    for (int j = 0; j < 8; ++j) m0.push_back(j), m1.push_back(8 + j);  // (0, j) and (1, j)
    b.add_curve(m0);
    b.add_curve(m1);
    const int before = b.s_.num_vertices();
    const int split = b.split_chords();
    EXPECT_GE(split, 8);  // the rungs (0, j)-(1, j) at least, and the diagonals
    EXPECT_EQ(b.s_.num_vertices(), before + split);
    // The new vertices are free, and the curves kept their vertices (no curve edge was split).
    const std::vector<char> block = b.blocked();
    for (int v = before; v < b.s_.num_vertices(); ++v) EXPECT_FALSE(block[v]);
    EXPECT_EQ(b.curves_[0].size(), 8u);
    EXPECT_EQ(b.curves_[1].size(), 8u);
    EXPECT_EQ(b.split_chords(), 0);  // nothing left to split
}

}  // namespace
}  // namespace quadcage::layout::detail

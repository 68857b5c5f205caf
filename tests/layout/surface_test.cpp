// The half-edge Surface every layout stage works on: adjacency, edge splits, Dijkstra.

#include "detail/surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <stdexcept>

#include "detail/search.h"
#include "quadcage/core/shapes.h"

namespace quadcage::layout::detail {
namespace {

void expect_consistent(const Surface& s) {
    for (int h = 0; h < s.num_half_edges(); ++h) {
        const int t = s.twin(h);
        ASSERT_GE(t, 0) << "half-edge " << h << " has no twin on a closed surface";
        EXPECT_EQ(s.twin(t), h);
        EXPECT_EQ(s.from(t), s.to(h));
        EXPECT_EQ(s.to(t), s.from(h));
        EXPECT_EQ(s.from(s.rotate(h)), s.from(h));
    }
}

TEST(LayoutSurface, TwinsRingsAndHalfEdgesAgree) {
    const Surface s(shapes::icosphere(2));
    expect_consistent(s);
    int degree_sum = 0;
    for (int v = 0; v < s.num_vertices(); ++v) {
        const std::vector<int> ring = s.ring(v);
        degree_sum += static_cast<int>(ring.size());
        EXPECT_TRUE(ring.size() == 5 || ring.size() == 6) << v;  // an icosphere's valences
        for (int w : ring) {
            const int h = s.find_half_edge(v, w);
            ASSERT_GE(h, 0);
            EXPECT_EQ(s.from(h), v);
            EXPECT_EQ(s.to(h), w);
        }
        EXPECT_EQ(s.out_half_edges(v).size(), ring.size());
    }
    EXPECT_EQ(degree_sum, s.num_half_edges());  // every half-edge leaves exactly one vertex
    EXPECT_EQ(s.find_half_edge(0, 0), -1);
}

TEST(LayoutSurface, SplitEdgesKeepsVerticesAndAddsMidpoints) {
    const Mesh input = shapes::torus(12, 6);
    Surface s(input);
    const int h = s.find_half_edge(0, s.ring(0)[0]);
    const int a = s.from(h), b = s.to(h), c = s.ring(7)[2];
    const std::vector<int> added = s.split_edges({{a, b}, {7, c}});
    ASSERT_EQ(added.size(), 2u);
    EXPECT_EQ(s.num_vertices(), input.num_vertices() + 2);
    EXPECT_EQ(s.mesh().num_triangles(), input.num_triangles() + 4);  // each split edge: 2 triangles more
    for (int v = 0; v < input.num_vertices(); ++v) EXPECT_EQ(s.point(v), input.points[v]);
    EXPECT_LT(norm(s.point(added[0]) - (input.points[a] + input.points[b]) * 0.5), 1e-15);
    EXPECT_EQ(s.find_half_edge(a, b), -1);
    EXPECT_GE(s.find_half_edge(a, added[0]), 0);
    EXPECT_GE(s.find_half_edge(added[0], b), 0);
    expect_consistent(s);
}

// split_edges() updates the adjacency of the split triangles only: it must be the one a surface
// built from the split mesh has (the same twins and the same first outgoing half-edge per vertex,
// where rotations start), after splits of one, two and three edges of a triangle, of neighbouring
// triangles, and after several batches.
TEST(LayoutSurface, SplitEdgesGiveTheAdjacencyOfAFreshSurface) {
    Surface s(shapes::torus(12, 6));
    auto expect_as_fresh = [](const Surface& split) {
        const Surface fresh(split.mesh());
        for (int h = 0; h < split.num_half_edges(); ++h) ASSERT_EQ(split.twin(h), fresh.twin(h)) << h;
        for (int v = 0; v < split.num_vertices(); ++v)
            ASSERT_EQ(split.out_half_edge(v), fresh.out_half_edge(v)) << v;
    };
    const Triangle t = s.mesh().triangles[5];
    s.split_edges({{t[0], t[1]}, {t[1], t[2]}, {t[2], t[0]}});  // all three edges of one triangle
    expect_as_fresh(s);
    const Triangle u = s.mesh().triangles[20];
    s.split_edges({{u[0], u[1]}, {u[1], u[2]}});  // two edges of one triangle
    expect_as_fresh(s);
    std::vector<std::pair<int, int>> ring_edges;  // a vertex's star: every edge out of it
    for (int w : s.ring(30)) ring_edges.push_back({30, w});
    s.split_edges(ring_edges);
    expect_as_fresh(s);
    for (int batch = 0; batch < 4; ++batch) {
        std::vector<std::pair<int, int>> edges;
        for (int h = 7 * batch; h < s.num_half_edges(); h += 37)
            if (s.from(h) < s.to(h)) edges.push_back({s.from(h), s.to(h)});
        s.split_edges(edges);
        expect_as_fresh(s);
    }
}

TEST(LayoutSurface, InsertMidpointsFollowsTheSplitEdges) {
    std::vector<std::vector<int>> curves = {{0, 1, 2}, {5, 6}};
    insert_midpoints(curves, {{1, 2, 10}, {2, 0, 11}, {6, 5, 12}}, true);
    EXPECT_EQ(curves[0], (std::vector<int>{0, 1, 10, 2, 11}));  // closed: 2 -> 0 is walked too
    // Open: only the edges the curve walks count.
    std::vector<std::vector<int>> open = {{5, 6}};
    insert_midpoints(open, {{6, 5, 12}}, false);
    EXPECT_EQ(open[0], (std::vector<int>{5, 12, 6}));
}

TEST(LayoutSurface, DijkstraPathsHaveTheirDistanceAndAvoidBlockedVertices) {
    const Surface s(shapes::icosphere(3));
    PathSearch q;
    q.sources = {{0, 0.0}};
    const PathResult free = dijkstra(s, q);
    // The farthest vertex from 0 on the unit sphere is about pi away along edges (a bit more).
    int far = 0;
    for (int v = 0; v < s.num_vertices(); ++v)
        if (free.distance[v] > free.distance[far]) far = v;
    EXPECT_GT(free.distance[far], 3.14);
    EXPECT_LT(free.distance[far], 3.14 * 1.15);
    const std::vector<int> path = free.path_to(s, far);
    ASSERT_GE(path.size(), 2u);
    EXPECT_EQ(path.front(), 0);
    EXPECT_EQ(path.back(), far);
    double length = 0;
    for (size_t i = 1; i < path.size(); ++i) length += norm(s.point(path[i]) - s.point(path[i - 1]));
    EXPECT_NEAR(length, free.distance[far], 1e-12);
    // Block that path's interior: the path found then goes around it (antipodal points have many
    // shortest paths, so it need not be longer).
    std::vector<char> block(s.num_vertices(), 0);
    for (size_t i = 1; i + 1 < path.size(); ++i) block[path[i]] = 1;
    q.blocked = &block;
    const PathResult around = dijkstra(s, q);
    EXPECT_GE(around.distance[far], free.distance[far]);
    for (int v : around.path_to(s, far)) EXPECT_FALSE(block[v]) << v;
    // A wall round the sphere between the source and the target: nothing beyond it is reached.
    std::vector<char> wall(s.num_vertices(), 0);
    const double z0 = 0.5 * (s.point(0).z + s.point(far).z);
    for (int v = 0; v < s.num_vertices(); ++v) wall[v] = std::abs(s.point(v).z - z0) < 0.1;
    ASSERT_FALSE(wall[0]);
    q.blocked = &wall;
    EXPECT_TRUE(std::isinf(dijkstra(s, q).distance[far]));
}

// dijkstra() keeps per-thread scratch between searches: searches stopped early (at a target, a
// distance, the settled vertices wanted, a throwing cost), and on a larger surface, leave nothing
// behind that changes the next search.
TEST(LayoutSurface, DijkstraSearchesLeaveNoTraceOnTheNext) {
    const Surface s(shapes::icosphere(3));
    PathSearch full;
    full.sources = {{0, 0.0}, {5, 0.25}};
    const PathResult before = dijkstra(s, full);
    int far = 0;
    for (int v = 0; v < s.num_vertices(); ++v)
        if (before.distance[v] > before.distance[far]) far = v;
    PathSearch early = full;
    early.targets = {{far, 0.5}};
    EXPECT_EQ(dijkstra(s, early).target, far);
    early = full;
    early.max_distance = 1.0;
    const PathResult near = dijkstra(s, early);
    EXPECT_TRUE(std::isinf(near.distance[far]));
    EXPECT_EQ(near.distance[0], 0.0);
    early = full;
    early.settle = {far / 3, far / 4};
    EXPECT_LT(dijkstra(s, early).distance[far / 3], std::numeric_limits<double>::infinity());
    early = full;
    int calls = 0;
    early.cost = [&](int h) {
        if (++calls > 50) throw std::runtime_error("stop");
        return s.length(h);
    };
    EXPECT_THROW(dijkstra(s, early), std::runtime_error);
    const Surface large(shapes::icosphere(4));
    dijkstra(large, full);
    const PathResult after = dijkstra(s, full);
    EXPECT_EQ(after.distance, before.distance);
    EXPECT_EQ(after.parent_half_edge, before.parent_half_edge);
}

// The search's 4-ary heap gives its (distance, vertex) pairs in the order std::priority_queue does
// (smallest first), pushes and pops interleaved, ties in distance broken by the vertex.
TEST(LayoutSurface, SearchHeapPopsInPriorityQueueOrder) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> coin(0, 2), vertex(0, 999), level(0, 40);
    using Item = search::HeapItem;
    std::vector<Item> heap;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> reference;
    int pushes = 0, pops = 0;
    for (int step = 0; step < 20000; ++step) {
        if (reference.empty() || coin(rng) > 0) {
            const Item item{0.125 * level(rng), vertex(rng) + 1000 * step};  // distinct pairs
            search::heap_push(heap, item);
            reference.push(item);
            ++pushes;
        } else {
            ASSERT_EQ(search::heap_pop(heap), reference.top()) << "pop " << pops;
            reference.pop();
            ++pops;
        }
        ASSERT_EQ(heap.size(), reference.size());
    }
    while (!reference.empty()) {
        ASSERT_EQ(search::heap_pop(heap), reference.top());
        reference.pop();
    }
    EXPECT_TRUE(heap.empty());
    EXPECT_GT(pops, 1000);
    EXPECT_GT(pushes, pops);
}

// dijkstra_with() with a cost lambda is dijkstra() with the same cost as PathSearch::cost: the
// same distances and the same tree, to the last bit.
TEST(LayoutSurface, DijkstraWithACostLambdaIsDijkstraWithThatCost) {
    const Surface s(shapes::icosphere(4));
    const auto cost = [&s](int h) { return s.length(h) * (1.5 + s.point(s.to(h)).z); };
    PathSearch q;
    q.sources = {{0, 0.0}, {17, 0.1}};
    q.cost = cost;
    const PathResult a = dijkstra(s, q);
    const PathResult b = dijkstra_with(s, q, cost);
    EXPECT_EQ(a.distance, b.distance);
    EXPECT_EQ(a.parent_half_edge, b.parent_half_edge);
    q.targets = {{s.num_vertices() - 1, 0.0}};
    EXPECT_EQ(dijkstra(s, q).target, dijkstra_with(s, q, cost).target);
    EXPECT_EQ(dijkstra(s, q).target_cost, dijkstra_with(s, q, cost).target_cost);
}

// run_both_ways() finds the path run_dijkstra() finds between the same sources and targets, at the
// same cost up to rounding (summed from both ends), with blocked vertices and a cost of its own;
// nothing where a wall separates them; and its per-thread scratch, used on a larger surface in
// between, changes nothing.
TEST(LayoutSurface, SearchFromBothEndsFindsTheOneWayPath) {
    const Surface s(shapes::icosphere(4));
    const auto cost = [&s](int h) { return s.length(h) * (2.5 + s.point(s.to(h)).z + s.point(s.from(h)).z); };  // > 0
    std::vector<char> block(s.num_vertices(), 0);
    for (int v = 0; v < s.num_vertices(); ++v) block[v] = std::abs(s.point(v).x) < 0.04 && s.point(v).z > -0.6;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> vertex(0, s.num_vertices() - 1);
    std::uniform_real_distribution<double> start(0.0, 0.2);
    // Both searches on q: the same path (or none) at the same cost; counts the paths found.
    auto compare = [&](const PathSearch& q, int trial, int* found) {
        const PathResult one = dijkstra_with(s, q, cost);
        double total = -1;
        const std::vector<int> both = search::run_both_ways(s, q, cost, &total);
        if (one.target < 0) {
            EXPECT_TRUE(both.empty()) << "trial " << trial;
            return both;
        }
        ++*found;
        EXPECT_EQ(both, one.path_to(s, one.target)) << "trial " << trial;
        EXPECT_NEAR(total, one.target_cost, 1e-12 * one.target_cost) << "trial " << trial;
        return both;
    };
    std::vector<std::vector<int>> paths;
    int found = 0;
    for (int trial = 0; trial < 40; ++trial) {
        PathSearch q;
        q.blocked = &block;
        for (int k = 0; k < 3; ++k) {
            const int a = vertex(rng), b = vertex(rng);
            const double ca = start(rng), cb = start(rng);
            if (!block[a]) q.sources.push_back({a, ca});
            if (!block[b]) q.targets.push_back({b, cb});
        }
        paths.push_back(compare(q, trial, &found));
        for (int v : paths.back()) EXPECT_FALSE(block[v]) << "trial " << trial;
    }
    EXPECT_GT(found, 20);
    // Sources inside the wall (run_dijkstra() lets a path start there) at costs up to about the
    // paths' own: the path leaves them at once, and the cheapest start need not be the one settled
    // first.
    std::uniform_real_distribution<double> wall_start(0.0, 3.0);
    std::vector<int> walled;
    for (int v = 0; v < s.num_vertices(); ++v)
        if (block[v]) walled.push_back(v);
    ASSERT_GT(walled.size(), 10u);
    int from_wall = 0;
    for (int trial = 0; trial < 40; ++trial) {
        PathSearch q;
        q.blocked = &block;
        for (int k = 0; k < 3; ++k) {
            q.sources.push_back({walled[vertex(rng) % walled.size()], wall_start(rng)});
            const int b = vertex(rng);
            if (!block[b]) q.targets.push_back({b, start(rng)});
        }
        compare(q, trial, &from_wall);
    }
    EXPECT_GT(from_wall, 20);
    // A wall all round the sphere: nothing from one side to the other.
    std::vector<char> wall(s.num_vertices(), 0);
    for (int v = 0; v < s.num_vertices(); ++v) wall[v] = std::abs(s.point(v).z) < 0.1;
    PathSearch apart;
    apart.blocked = &wall;
    int top = 0, bottom = 0;
    for (int v = 0; v < s.num_vertices(); ++v) {
        if (s.point(v).z > s.point(top).z) top = v;
        if (s.point(v).z < s.point(bottom).z) bottom = v;
    }
    apart.sources = {{top, 0.0}};
    apart.targets = {{bottom, 0.0}};
    double total = -1;
    EXPECT_TRUE(search::run_both_ways(s, apart, cost, &total).empty());
    EXPECT_EQ(total, -1);
    constexpr double kInf = std::numeric_limits<double>::infinity();
    // Failing, it marks what the one-way search settles: the top's side of the wall, every vertex.
    std::vector<char> settled(s.num_vertices(), 0);
    EXPECT_TRUE(search::run_both_ways(s, apart, cost, &total, kInf, &settled).empty());
    const PathResult from_top = dijkstra_with(s, apart, cost);
    ASSERT_LT(from_top.target, 0);
    int above = 0;
    for (int v = 0; v < s.num_vertices(); ++v) {
        EXPECT_EQ(settled[v] != 0, from_top.distance[v] < kInf) << "vertex " << v;
        above += settled[v];
    }
    EXPECT_GT(above, s.num_vertices() / 3);
    // The scratch, grown on a larger surface, leaves the first searches' answers as they were.
    const Surface large(shapes::icosphere(5));
    search::run_both_ways(large, apart, [&large](int h) { return large.length(h); }, &total);
    std::mt19937 again(3);
    for (int trial = 0; trial < 40; ++trial) {
        PathSearch q;
        q.blocked = &block;
        for (int k = 0; k < 3; ++k) {
            const int a = vertex(again), b = vertex(again);
            const double ca = start(again), cb = start(again);
            if (!block[a]) q.sources.push_back({a, ca});
            if (!block[b]) q.targets.push_back({b, cb});
        }
        EXPECT_EQ(search::run_both_ways(s, q, cost, &total), paths[trial]) << "trial " << trial;
        // Bounded: the same path when it is cheaper than the bound, none when it is not.
        if (paths[trial].empty()) continue;
        const double cheapest = total;
        std::vector<char> unused(s.num_vertices(), 0);
        EXPECT_EQ(search::run_both_ways(s, q, cost, &total, 1.01 * cheapest, &unused), paths[trial])
            << "trial " << trial;
        EXPECT_TRUE(search::run_both_ways(s, q, cost, &total, 0.99 * cheapest).empty()) << "trial " << trial;
        EXPECT_EQ(std::count(unused.begin(), unused.end(), 1), 0) << "trial " << trial;
    }
}

// lower_distances() adds sources to a distance field: the result is the field of all the sources
// searched together, to the last bit, with blocked vertices and a distance limit.
TEST(LayoutSurface, LowerDistancesGivesTheFieldOfAllTheSources) {
    const Surface s(shapes::icosphere(4));
    std::vector<char> block(s.num_vertices(), 0);
    for (int v = 0; v < s.num_vertices(); ++v) block[v] = std::abs(s.point(v).z) < 0.05 && s.point(v).x > 0;
    for (const double limit : {std::numeric_limits<double>::infinity(), 0.7}) {
        PathSearch q;
        q.blocked = &block;
        q.max_distance = limit;
        std::vector<int> first, more;
        for (int v = 0; v < s.num_vertices(); v += 97)
            if (!block[v]) (v % 2 ? first : more).push_back(v);
        for (int v : first) q.sources.push_back({v, 0.0});
        std::vector<double> field = dijkstra(s, q).distance;
        for (int v : more) q.sources.push_back({v, 0.0});
        const std::vector<double> all = dijkstra(s, q).distance;
        lower_distances(s, more, &block, limit, &field);
        EXPECT_EQ(field, all);
    }
}

}  // namespace
}  // namespace quadcage::layout::detail

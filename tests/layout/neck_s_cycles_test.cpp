// S-cycles at the necks (neck_s_cycles.cpp): the matching that joins pairs of pants into T-shirts,
// on graphs where the answer is known; and on a wheel (input_wheel's class), S-cycles that cut the
// surface into T-shirts and annuli and stay shorter than the handle loops' body cut, which winds
// its S-cycles round the ring of holes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "detail/curves.h"
#include "detail/stages.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/orthogonal_system.h"

namespace quadcage::layout::detail {
namespace {

// A theta graph (2 pants, 3 loops between them): the longest loop is dropped.
TEST(NeckSCyclesMatching, DropsTheLongestLoopBetweenTwoPants) {
    const auto dropped = pants_matching({{0, 1}, {0, 1}, {1, 0}}, {2.0, 5.0, 3.0}, 2);
    ASSERT_TRUE(dropped);
    EXPECT_EQ(*dropped, (std::vector<char>{0, 1, 0}));
}

// A dumbbell (each pair of pants has a loop with both sides on it, one loop between them): that
// loop is the only one a matching can drop, however short.
TEST(NeckSCyclesMatching, NeverDropsALoopWithBothSidesOnOnePairOfPants) {
    const auto dropped = pants_matching({{0, 0}, {0, 1}, {1, 1}}, {9.0, 1.0, 9.0}, 2);
    ASSERT_TRUE(dropped);
    EXPECT_EQ(*dropped, (std::vector<char>{0, 1, 0}));
}

// Four pants in a cycle with a chord pattern: K4 (6 loops) has 3 perfect matchings; the one of
// greatest total length is dropped. Lengths: 0-1: 1, 2-3: 1 (total 2); 0-2: 4, 1-3: 4 (8);
// 0-3: 3, 1-2: 6 (9).
TEST(NeckSCyclesMatching, TakesThePerfectMatchingOfGreatestLength) {
    const std::vector<std::array<int, 2>> ends{{0, 1}, {2, 3}, {0, 2}, {1, 3}, {0, 3}, {1, 2}};
    const auto dropped = pants_matching(ends, {1, 1, 4, 4, 3, 6}, 4);
    ASSERT_TRUE(dropped);
    EXPECT_EQ(*dropped, (std::vector<char>{0, 0, 0, 0, 1, 1}));
}

// Two pants joined only through a third pair of pants (a path 0-1-2 plus self-loops): an odd
// number of pants, or no edge to pair one with, has no perfect matching.
TEST(NeckSCyclesMatching, SaysWhenThereIsNoPerfectMatching) {
    EXPECT_FALSE(pants_matching({{0, 0}, {0, 1}, {1, 2}, {2, 2}}, {1, 1, 1, 1}, 3));
    EXPECT_FALSE(pants_matching({{0, 0}, {1, 1}, {0, 0}, {1, 1}}, {1, 1, 1, 1}, 2));
}

// The greatest total length of a perfect matching, by trying every one (few pants only).
double best_by_enumeration(const std::vector<std::array<int, 2>>& ends, const std::vector<double>& lengths,
                           std::vector<char>* matched) {
    const auto first = std::find(matched->begin(), matched->end(), 0);
    if (first == matched->end()) return 0;
    const int a = static_cast<int>(first - matched->begin());
    double best = -1;
    for (size_t e = 0; e < ends.size(); ++e) {
        const int z = ends[e][0] == a ? ends[e][1] : ends[e][1] == a ? ends[e][0] : -1;
        if (z < 0 || z == a || (*matched)[z]) continue;
        (*matched)[a] = (*matched)[z] = 1;
        if (const double rest = best_by_enumeration(ends, lengths, matched); rest >= 0)
            best = std::max(best, rest + lengths[e]);
        (*matched)[a] = (*matched)[z] = 0;
    }
    return best;
}

// Pants graphs as a decomposition makes them (every pair of pants has three loop sides: a random
// cubic multigraph, self-loops included), numbered at random: the loops dropped form a perfect
// matching whose length is the greatest any has.
TEST(NeckSCyclesMatching, MatchesEnumerationOnRandomPantsGraphs) {
    std::mt19937 rng(7);
    int matched_graphs = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const int pants = 2 * (1 + trial % 6);  // 2 to 12
        std::vector<int> sides;
        for (int p = 0; p < pants; ++p) sides.insert(sides.end(), 3, p);
        std::shuffle(sides.begin(), sides.end(), rng);
        std::vector<std::array<int, 2>> ends;
        std::vector<double> lengths;
        std::uniform_real_distribution<double> length(1.0, 10.0);
        for (size_t i = 0; i < sides.size(); i += 2) ends.push_back({sides[i], sides[i + 1]}), lengths.push_back(length(rng));
        std::vector<char> matched(pants, 0);
        const double expected = best_by_enumeration(ends, lengths, &matched);
        const auto dropped = pants_matching(ends, lengths, pants);
        ASSERT_EQ(dropped.has_value(), expected >= 0) << "trial " << trial;
        if (!dropped) continue;
        ++matched_graphs;
        std::vector<int> degree(pants, 0);
        double total = 0;
        for (size_t e = 0; e < ends.size(); ++e)
            if ((*dropped)[e]) ++degree[ends[e][0]], ++degree[ends[e][1]], total += lengths[e];
        EXPECT_EQ(degree, std::vector<int>(pants, 1)) << "trial " << trial;
        EXPECT_NEAR(total, expected, 1e-9 * expected) << "trial " << trial;
    }
    EXPECT_GT(matched_graphs, 150);
}

// Genus 32's 62 pants (past the 22 an exact matching over all subsets of them could hold): a
// prism, two rings of 31 pants joined by rungs, each pair of pants on one rung. The rungs are the
// longest loops, and the matching drops all of them.
TEST(NeckSCyclesMatching, MatchesSixtyTwoPantsInAPrism) {
    const int n = 31;
    std::vector<std::array<int, 2>> ends;
    std::vector<double> lengths;
    for (int i = 0; i < n; ++i) {
        ends.push_back({i, (i + 1) % n}), lengths.push_back(2.0);
        ends.push_back({n + i, n + (i + 1) % n}), lengths.push_back(2.0);
        ends.push_back({i, n + i}), lengths.push_back(3.0);
    }
    bool too_many = true;
    const auto dropped = pants_matching(ends, lengths, 2 * n, &too_many);
    ASSERT_TRUE(dropped);
    EXPECT_FALSE(too_many);
    for (size_t e = 0; e < ends.size(); ++e) EXPECT_EQ((*dropped)[e], e % 3 == 2) << "loop " << e;
}

double total_length(const Builder& b, const std::vector<int>& ids) {
    double sum = 0;
    for (int id : ids) sum += cycle_length(b.s_.mesh(), b.curves_[id]);
    return sum;
}

double longest(const Builder& b, const std::vector<int>& ids) {
    double most = 0;
    for (int id : ids) most = std::max(most, cycle_length(b.s_.mesh(), b.curves_[id]));
    return most;
}

// The Builder the layout starts from: the orthogonal system's cycles as curves 0..2g-1, and the
// handle loops after them; none of them blocks a search (as in network_of_handles_and_tshirts()).
Builder builder_of(const OrthogonalSystem& system, std::vector<int>* handle_loops) {
    Builder b(system.mesh, {});
    for (const Cycle& c : system.cycles) b.add_curve(c, true, false);
    for (const Cycle& c : system.handle_loops) handle_loops->push_back(b.add_curve(c, true, false));
    return b;
}

// A wheel of genus 5 (4 holes in a ring round the axle): the necks cut it into 4 T-shirts and 8
// annuli, and their S-cycles are shorter, in total and the longest, than those of the handle
// loops, whose body annuli wind round the ring (the bundles of issue 20's renders).
TEST(NeckSCycles, AWheelIsCutIntoTshirtsByShorterSCyclesThanTheHandleLoops) {
    shapes::WheelOptions o;
    o.holes = 4;
    o.resolution = 2;
    const OrthogonalSystem system = build_orthogonal_system(shapes::wheel(o));
    const int g = system.genus;
    ASSERT_EQ(g, 5);
    const Say quiet = [](const std::string&) {};

    std::vector<int> loops;
    Builder necks = builder_of(system, &loops);
    const std::optional<std::vector<int>> at_necks = neck_s_cycles(necks, g, quiet);
    ASSERT_TRUE(at_necks);
    ASSERT_EQ(at_necks->size(), static_cast<size_t>(4 * g - 4));
    const Pieces pieces = find_pieces(necks, *at_necks, g);  // throws unless T-shirts and annuli
    EXPECT_EQ(pieces.holes.size(), static_cast<size_t>(3 * g - 3));

    loops.clear();
    Builder handles = builder_of(system, &loops);
    const std::optional<std::vector<int>> from_handle_loops = tube_s_cycles(handles, loops, g, quiet);
    ASSERT_TRUE(from_handle_loops);
    ASSERT_EQ(from_handle_loops->size(), static_cast<size_t>(4 * g - 4));

    const double necks_total = total_length(necks, *at_necks), handles_total = total_length(handles, *from_handle_loops);
    const double necks_longest = longest(necks, *at_necks), handles_longest = longest(handles, *from_handle_loops);
    RecordProperty("necks_total", std::to_string(necks_total));
    RecordProperty("handle_loops_total", std::to_string(handles_total));
    EXPECT_LT(necks_total, handles_total);
    EXPECT_LT(necks_longest, handles_longest);
}

// Small handles on a big body: the shortest loops go round each handle's feet, so a pair of pants
// gets two handles hanging off it and the pants have no perfect matching. The search starts again
// with loops that separate nothing (whose pants always have one) and cuts the surface into
// T-shirts and annuli.
TEST(NeckSCycles, HandlesOnABodyAreCutAgainWithLoopsThatSeparateNothing) {
    shapes::HandleBodyOptions o;
    o.handles = 4;
    o.resolution = 2;
    const OrthogonalSystem system = build_orthogonal_system(shapes::body_with_handles(o));
    const int g = system.genus;
    ASSERT_EQ(g, 4);
    std::vector<std::string> said;
    const Say record = [&said](const std::string& m) { said.push_back(m); };
    std::vector<int> loops;
    Builder b = builder_of(system, &loops);
    const std::optional<std::vector<int>> ids = neck_s_cycles(b, g, record);
    const bool again = std::any_of(said.begin(), said.end(), [](const std::string& m) {
        return m.find("again with loops that separate nothing") != std::string::npos;
    });
    EXPECT_TRUE(again) << "the first search's pants had a perfect matching: this shape no longer tests the retry";
    ASSERT_TRUE(ids);
    ASSERT_EQ(ids->size(), static_cast<size_t>(4 * g - 4));
    const Pieces pieces = find_pieces(b, *ids, g);  // throws unless T-shirts and annuli
    EXPECT_EQ(pieces.holes.size(), static_cast<size_t>(3 * g - 3));
}

// Deterministic: the same S-cycles twice.
TEST(NeckSCycles, TheSameSCyclesEveryRun) {
    shapes::WheelOptions o;
    o.holes = 3;
    o.resolution = 2;
    const OrthogonalSystem system = build_orthogonal_system(shapes::wheel(o));
    const Say quiet = [](const std::string&) {};
    std::vector<std::vector<Cycle>> runs;
    for (int run = 0; run < 2; ++run) {
        std::vector<int> loops;
        Builder b = builder_of(system, &loops);
        const auto ids = neck_s_cycles(b, system.genus, quiet);
        ASSERT_TRUE(ids);
        runs.emplace_back();
        for (int id : *ids) runs.back().push_back(b.curves_[id]);
    }
    EXPECT_EQ(runs[0], runs[1]);
}

}  // namespace
}  // namespace quadcage::layout::detail

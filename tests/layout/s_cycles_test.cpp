// How the handle-loop S-cycles cut the body into T-shirts (handle_loop_s_cycles.cpp): the chain
// (tshirt_plan()) and the tree (tshirt_tree()) over the holes, on distances between holes laid out
// on a line, where the right grouping is known; and the Euler characteristic that tells an annulus
// from a torus with two holes (pieces.cpp).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"

namespace quadcage::layout::detail {
namespace {

// Distances between holes at positions x on a line.
std::vector<std::vector<double>> gaps(const std::vector<double>& x) {
    std::vector<std::vector<double>> g(x.size(), std::vector<double>(x.size(), 0));
    for (size_t i = 0; i < x.size(); ++i)
        for (size_t j = 0; j < x.size(); ++j) g[i][j] = std::abs(x[i] - x[j]);
    return g;
}

// The separation penalty of an annulus round `set`, computed here from its definition.
double separation(const std::vector<std::vector<double>>& gap, const std::set<int>& set) {
    double p = 0;
    for (int a : set)
        for (int b = 0; b < static_cast<int>(gap.size()); ++b)
            if (!set.count(b)) p += 1 / (gap[a][b] * gap[a][b]);
    return p;
}

// Checks the tree's shape (g-2 merges of three distinct open nodes, four left) and returns, per
// merge, the holes under it.
std::vector<std::set<int>> holes_under(const std::vector<std::array<int, 3>>& merges, int n) {
    std::vector<std::set<int>> under;
    std::set<int> open;
    for (int i = 0; i < n; ++i) under.push_back({i}), open.insert(i);
    for (const auto& m : merges) {
        std::set<int> u;
        for (int x : m) {
            EXPECT_EQ(open.count(x), 1u) << "node " << x << " merged twice or not made yet";
            open.erase(x);
            u.insert(under.at(x).begin(), under.at(x).end());
        }
        open.insert(static_cast<int>(under.size()));
        under.push_back(u);
    }
    EXPECT_EQ(open.size(), 4u) << "the last T-shirt has four holes";
    return std::vector<std::set<int>>(under.begin() + n, under.end());
}

TEST(SCyclesTshirtTree, GroupsHolesCrowdedInThreesAndCostsWhatItsAnnuliCost) {
    // Four crowds of three holes each (genus 6), far apart: no annulus of the tree splits a crowd,
    // and its penalty is the sum of its annuli's.
    const std::vector<double> x = {0, 0.1, 0.2, 10, 10.1, 10.2, 20, 20.1, 20.2, 30, 30.1, 30.2};
    const auto gap = gaps(x);
    double penalty = -1;
    const auto merges = tshirt_tree(gap, &penalty);
    ASSERT_EQ(merges.size(), 4u);  // g - 2
    const auto under = holes_under(merges, 12);
    double sum = 0;
    for (const std::set<int>& u : under) {
        sum += separation(gap, u);
        for (int crowd = 0; crowd < 4; ++crowd) {
            const auto in = std::count_if(u.begin(), u.end(), [crowd](int h) { return h / 3 == crowd; });
            EXPECT_TRUE(in == 0 || in == 3) << "an annulus splits crowd " << crowd;
        }
    }
    EXPECT_NEAR(penalty, sum, 1e-9 * sum);
    // The chain must put a crowd's holes on both sides of some annulus (its groups after the first
    // are pairs), so it separates close holes where the tree does not.
    double chain_penalty = -1;
    const auto plan = tshirt_plan(gap, &chain_penalty);
    ASSERT_EQ(plan.size(), 5u);  // g - 1 groups
    EXPECT_EQ(plan.front().size(), 3u);
    EXPECT_EQ(plan.back().size(), 3u);
    EXPECT_LT(penalty, 0.5 * chain_penalty);
}

TEST(SCyclesTshirtTree, IsNoBetterThanTheChainWhenTheHolesAreEvenlySpread) {
    // Holes evenly spaced on a line (genus 4): a chain along the line separates neighbours only at
    // its two annuli; the tree cannot do markedly better, so the layout keeps the chain.
    std::vector<double> x;
    for (int i = 0; i < 8; ++i) x.push_back(i);
    const auto gap = gaps(x);
    double tree = -1, chain = -1;
    ASSERT_EQ(tshirt_tree(gap, &tree).size(), 2u);
    ASSERT_EQ(tshirt_plan(gap, &chain).size(), 3u);
    EXPECT_GT(tree, 0.9 * chain);
}

TEST(SCyclesPieceEuler, TellsAnAnnulusFromATorusWithTwoHoles) {
    // shapes::torus(32, 16) has two triangles per grid square, square (i, j) = triangles
    // 2 (16 i + j) and the next. Cut along two meridians: two annuli.
    const Mesh torus = shapes::torus(32, 16);
    const Surface s(torus);
    std::vector<int> label(torus.num_triangles());
    for (int t = 0; t < torus.num_triangles(); ++t) label[t] = t / 2 / 16 < 16 ? 0 : 1;
    EXPECT_EQ(piece_euler_characteristic(s, label, 0), 0);
    EXPECT_EQ(piece_euler_characteristic(s, label, 1), 0);
    // Two squares cut out as pieces of their own: disks, and the rest a torus with two holes (two
    // boundary loops, as an annulus has, but a handle in it).
    std::fill(label.begin(), label.end(), 0);
    for (int t : {0, 1}) label[t] = 1;
    for (int t : {2 * (16 * 16 + 8), 2 * (16 * 16 + 8) + 1}) label[t] = 2;
    EXPECT_EQ(piece_euler_characteristic(s, label, 1), 1);
    EXPECT_EQ(piece_euler_characteristic(s, label, 2), 1);
    EXPECT_EQ(piece_euler_characteristic(s, label, 0), -2);
    const Mesh sphere = shapes::icosphere(1);
    EXPECT_EQ(piece_euler_characteristic(Surface(sphere), std::vector<int>(sphere.num_triangles(), 0), 0), 2);
}

}  // namespace
}  // namespace quadcage::layout::detail

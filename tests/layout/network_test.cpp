// The layout network from its curves to a verified layout (network.cpp): the edges cut from the
// closed curves at their corners, hairpins taken out, the cage and patch maps built and checked,
// and the relaxation, on a hand-built 4-quad torus network.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/stages.h"
#include "quadcage/core/mesh.h"
#include "quadcage/core/shapes.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {
namespace {

constexpr int kMajor = 32, kMinor = 16;
int id(int i, int j) {
    return ((i + kMajor) % kMajor) * kMinor + (j + kMinor) % kMinor;
}

Cycle meridian(int i) {  // round the tube at major index i
    Cycle c;
    for (int j = 0; j < kMinor; ++j) c.push_back(id(i, j));
    return c;
}
Cycle longitude(int j) {  // round the hole at minor index j
    Cycle c;
    for (int i = 0; i < kMajor; ++i) c.push_back(id(i, j));
    return c;
}

// Two meridians (major 0 and m) and two longitudes (minor 0 and l) as a genus-1 network: its four
// crossings are the corners, each closed curve carries two. The first meridian and longitude stand
// for the orthogonal system (curves 0 and 1, as build_quad_layout() adds them).
struct TorusNet {
    Builder b;
    Network net;
};
TorusNet torus_net(int m, int l, const Cycle& second_meridian) {
    TorusNet t{Builder(shapes::torus(kMajor, kMinor), {}), {}};
    const int m0 = t.b.add_curve(meridian(0)), l0 = t.b.add_curve(longitude(0));
    const int m1 = t.b.add_curve(second_meridian), l1 = t.b.add_curve(longitude(l));
    t.net.corners = {id(0, 0), id(0, l), id(m, 0), id(m, l)};
    t.net.closed = {{m0, {id(0, 0), id(0, l)}},
                    {l0, {id(0, 0), id(m, 0)}},
                    {m1, {id(m, 0), id(m, l)}},
                    {l1, {id(0, l), id(m, l)}}};
    return t;
}

TEST(LayoutNetwork, TheEdgesAreTheClosedCurvesCutAtTheirCorners) {
    const TorusNet t = torus_net(16, 8, meridian(16));
    const std::vector<std::vector<int>> paths = layout_edge_paths(t.b, t.net);
    ASSERT_EQ(paths.size(), 8u);
    for (size_t k = 0; k < t.net.closed.size(); ++k) {
        const auto& [curve, corners] = t.net.closed[k];
        const std::vector<int>&first = paths[2 * k], &second = paths[2 * k + 1];
        EXPECT_EQ(first.front(), corners[0]);
        EXPECT_EQ(first.back(), corners[1]);
        EXPECT_EQ(second.front(), corners[1]);
        EXPECT_EQ(second.back(), corners[0]);
        // Together they walk the whole curve once, in its direction.
        std::vector<int> round(first.begin(), first.end() - 1);
        round.insert(round.end(), second.begin(), second.end() - 1);
        Cycle c = t.b.curves_[curve];
        std::rotate(c.begin(), std::find(c.begin(), c.end(), corners[0]), c.end());
        EXPECT_EQ(round, c);
    }
}

TEST(LayoutNetwork, TighteningTakesOutAHairpinAndLeavesStraightCurves) {
    // The second meridian makes a hairpin two grid steps long (out along major 17 and 18 at minor 3,
    // back at minor 4): it comes back next to itself round a disk that holds nothing else.
    Cycle hairpin = meridian(16);
    const auto at = std::find(hairpin.begin(), hairpin.end(), id(16, 3)) + 1;
    hairpin.insert(at, {id(17, 3), id(18, 3), id(18, 4), id(17, 4)});
    TorusNet t = torus_net(16, 8, hairpin);
    const int extra = t.b.add_curve(meridian(24), true, true);  // not a layout curve
    const std::vector<Cycle> before = t.b.curves_;
    tighten_layout_curves(t.b, t.net, 1);
    const Cycle& tight = t.b.curves_[2];
    EXPECT_LT(tight.size(), hairpin.size());
    for (int v : {id(18, 3), id(18, 4)}) EXPECT_EQ(std::count(tight.begin(), tight.end(), v), 0) << v;
    for (int corner : {id(16, 0), id(16, 8)}) EXPECT_EQ(std::count(tight.begin(), tight.end(), corner), 1);
    // Straight curves have no hairpin: they stay as they were, and so does a curve not in the
    // network.
    for (int c : {0, 1, 3, extra}) EXPECT_EQ(t.b.curves_[c], before[c]);
    // Only the network's curves stay obstacles.
    EXPECT_EQ(t.b.obstacle_, std::vector<char>({1, 1, 1, 1, 0}));
}

TEST(LayoutNetwork, FinishingBuildsTheFourQuadTorusAndSaysWhatFails) {
    TorusNet t = torus_net(16, 8, meridian(16));
    QuadLayout L;
    L.input_vertices = t.b.s_.num_vertices();
    L.genus = 1;
    NetworkSeconds seconds;
    EXPECT_EQ(finish_network(
                  t.b, t.net, &L, [](const std::string&) {}, &seconds),
              "");
    EXPECT_EQ(L.cage.num_quads(), 4);
    EXPECT_EQ(L.cage.num_corners(), 4);
    EXPECT_EQ(verify_quad_layout(L), "");
    EXPECT_GE(seconds.mapped, 0);
    EXPECT_GE(seconds.checked, 0);

    // Without the second longitude two corners have degree 3 and one patch is an annulus.
    t.net.closed.pop_back();
    QuadLayout broken;
    broken.input_vertices = L.input_vertices;
    broken.genus = 1;
    const std::string problem = finish_network(
        t.b, t.net, &broken, [](const std::string&) {}, &seconds);
    EXPECT_EQ(problem.rfind("the layout curves do not form a quad layout: ", 0), 0u) << problem;
}

TEST(LayoutNetwork, RelaxingACrowdedNetworkEvensOutItsPatches) {
    // The longitudes 3 of 16 minor steps apart, the meridians 4 of 32 major steps.
    TorusNet t = torus_net(4, 3, meridian(4));
    QuadLayout plain;
    plain.input_vertices = t.b.s_.num_vertices();
    plain.genus = 1;
    NetworkSeconds seconds;
    ASSERT_EQ(finish_network(
                  t.b, t.net, &plain, [](const std::string&) {}, &seconds),
              "");
    measure_quality(&plain);

    QuadLayout out;
    out.input_vertices = plain.input_vertices;
    out.genus = 1;
    std::vector<int> s_cycle_ids;
    bool measured = false;
    std::vector<std::string> said;
    ASSERT_TRUE(relax_network(
        &t.b, t.net, QuadLayoutOptions{}, 1, [&](const std::string& m) { said.push_back(m); }, &out,
        &s_cycle_ids, &seconds, &measured));
    EXPECT_EQ(said.front(), "relaxing the layout corners and edges");
    EXPECT_EQ(verify_quad_layout(out), "");
    EXPECT_EQ(out.cage.num_quads(), 4);
    if (!measured) measure_quality(&out);
    EXPECT_LT(out.quality.patch_area_max_over_min, 0.5 * plain.quality.patch_area_max_over_min)
        << plain.quality.patch_area_max_over_min << " -> " << out.quality.patch_area_max_over_min;
}

TEST(NetworkBalance, ExcessIsTheFartherOfTheTwoTargets) {
    LayoutQuality q;
    q.patch_area_max_over_min = 4.0;
    q.corner_angle_mean_deviation_deg = 10.0;
    EXPECT_NEAR(balance_excess(q), 1.0, 1e-12);
    q.patch_area_max_over_min = 16.0;
    EXPECT_NEAR(balance_excess(q), 2.0, 1e-12);
    q.corner_angle_mean_deviation_deg = 60.0;
    EXPECT_NEAR(balance_excess(q), 3.0, 1e-12);
    q.patch_area_max_over_min = 0.5;  // below 1 only by rounding: counts as 1
    q.corner_angle_mean_deviation_deg = 0.0;
    EXPECT_EQ(balance_excess(q), 0.0);
}

}  // namespace
}  // namespace quadcage::layout::detail

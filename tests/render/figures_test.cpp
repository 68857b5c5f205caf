// The figures: patch structure of a labelling, layout colours and corners, deviation colour bar.

#include <gtest/gtest.h>

#include <cmath>

#include "quadcage/core/errors.h"
#include "quadcage/core/shapes.h"
#include "quadcage/render/colour_map.h"
#include "quadcage/render/figures.h"

namespace {

using namespace quadcage;
using namespace quadcage::render;

// Octant of each triangle's centroid: 8 patches of a sphere; 6 points where 4 patches meet.
std::vector<int> octants(const Mesh& m) {
    std::vector<int> p;
    for (const Triangle& t : m.triangles) {
        const Vec3 c = (m.points[t[0]] + m.points[t[1]] + m.points[t[2]]) / 3.0;
        p.push_back((c.x > 0) + 2 * (c.y > 0) + 4 * (c.z > 0));
    }
    return p;
}

// Pixel p is a shade k * c (0.2 <= k <= 1) of colour c, up to rounding.
bool shade_of(Rgb p, Rgb c) {
    const double dot = p.r * c.r + p.g * c.g + p.b * c.b, cc = c.r * c.r + c.g * c.g + c.b * c.b;
    const double k = dot / cc;
    if (k < 0.2 || k > 1.01) return false;
    const double dr = p.r - k * c.r, dg = p.g - k * c.g, db = p.b - k * c.b;
    return std::sqrt(dr * dr + dg * dg + db * db) < 4.0;
}

TEST(PatchStructure, OctantsOfASphere) {
    // icosphere vertices at coordinate planes exist, so octant labels meet along the great circles.
    const Mesh sphere = shapes::icosphere(3);
    const PatchStructure s = patch_structure(sphere, octants(sphere));
    EXPECT_EQ(s.patches, 8);
    for (const auto& adj : s.adjacency) EXPECT_EQ(adj.size(), 3u);  // each octant touches 3 others
    EXPECT_GE(s.corners.size(), 6u);
    EXPECT_FALSE(s.boundary_edges.empty());
}

TEST(PatchStructure, NonContiguousLabelsAndBadInput) {
    const Mesh sphere = shapes::icosphere(1);
    std::vector<int> labels(sphere.triangles.size(), 7);
    labels[0] = 1000;
    const PatchStructure s = patch_structure(sphere, labels);
    EXPECT_EQ(s.patches, 2);
    EXPECT_EQ(s.boundary_edges.size(), 3u);
    EXPECT_TRUE(s.corners.empty());
    labels[1] = -1;
    EXPECT_THROW(patch_structure(sphere, labels), InvalidInput);
    labels.pop_back();
    EXPECT_THROW(patch_structure(sphere, labels), InvalidInput);
}

TEST(LayoutFigure, BothPatchColoursBoundaryAndCornersAppear) {
    const Mesh sphere = shapes::icosphere(4);
    std::vector<int> two;
    for (const Triangle& t : sphere.triangles)
        two.push_back(sphere.points[t[0]].y + sphere.points[t[1]].y + sphere.points[t[2]].y > 0 ? 1 : 0);
    FigureOptions fo;
    fo.width = 800;
    fo.height = 430;
    const Image img = layout_figure(sphere, two, fo);
    const std::vector<Rgb> colours = patch_colours({{1}, {0}});
    long long a = 0, b = 0;
    for (const Rgb& p : img.pixels()) a += shade_of(p, colours[0]), b += shade_of(p, colours[1]);
    EXPECT_GT(a, 10000);
    EXPECT_GT(b, 10000);
    EXPECT_GT(img.count({20, 20, 20}), 100);  // the boundary line (the equator)

    const Image oct = layout_figure(sphere, octants(sphere), fo);
    EXPECT_GT(oct.count({220, 20, 20}), 6 * 20);  // corner dots
}

TEST(PatchColours, NeighboursDiffer) {
    // Quads of a 7 x 6 torus grid, each touching its 4 edge neighbours and 4 corner neighbours
    // (those meet at layout corners and must differ too).
    const int nx = 7, ny = 6;
    std::vector<std::vector<int>> adj(nx * ny);
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int di = -1; di <= 1; ++di)
                for (int dj = -1; dj <= 1; ++dj)
                    if (di || dj) adj[i * ny + j].push_back(((i + di + nx) % nx) * ny + (j + dj + ny) % ny);
    const std::vector<Rgb> c = patch_colours(adj);
    for (int p = 0; p < nx * ny; ++p)
        for (int q : adj[p]) {
            const double d = std::sqrt(std::pow(c[p].r - c[q].r, 2) + std::pow(c[p].g - c[q].g, 2) +
                                       std::pow(c[p].b - c[q].b, 2));
            EXPECT_GE(d, 90.0) << p << " " << q;
        }
    EXPECT_EQ(patch_colours(adj), c);  // deterministic
}

TEST(DeviationFigure, ColourBarSpansTheMapAndBadDistancesAreRejected) {
    const Mesh sphere = shapes::icosphere(3);
    std::vector<float> d;
    for (const Vec3& p : sphere.points) d.push_back(static_cast<float>(0.05 * (p.x + 1)));
    FigureOptions fo;
    fo.width = 900;
    fo.height = 450;
    const Image img = deviation_figure(sphere, d, fo);
    // The bar (unshaded) holds the colours of both ends of the scale.
    const Rgb top = sequential_colour(1.0), bottom = sequential_colour(0.0);
    auto near = [](Rgb a, Rgb b) { return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) <= 6; };
    long long top_px = 0, bottom_px = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = img.width() - 210; x < img.width(); ++x)
            top_px += near(img.at(x, y), top), bottom_px += near(img.at(x, y), bottom);
    EXPECT_GT(top_px, 10);
    EXPECT_GT(bottom_px, 10);
    d[3] = -1;
    EXPECT_THROW(deviation_figure(sphere, d, fo), InvalidInput);
    d.pop_back();
    EXPECT_THROW(deviation_figure(sphere, d, fo), InvalidInput);
    EXPECT_NO_THROW(deviation_figure(sphere, std::vector<float>(sphere.points.size(), 0.0f), fo));
}

TEST(ColourMap, TicksAreNiceAndInsideTheRange) {
    EXPECT_EQ(nice_ticks(0, 1, 5), (std::vector<double>{0, 0.2, 0.4, 0.6000000000000001, 0.8, 1}));
    const auto t = nice_ticks(0, 0.0392, 5);
    EXPECT_EQ(t.front(), 0.0);
    EXPECT_LE(t.back(), 0.0392);
    EXPECT_GE(t.size(), 3u);
    EXPECT_EQ(format_tick(0.005), "0.005");
    EXPECT_EQ(format_tick(1e-5), "1e-05");
}

}  // namespace

// The software rasteriser: framing predicted by the projection, two views, face colours, and
// overlays that show in front of the surface but not through it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "quadcage/core/errors.h"
#include "quadcage/core/shapes.h"
#include "quadcage/render/rasterizer.h"

namespace {

using namespace quadcage;
using namespace quadcage::render;

const Rgb kWhite{255, 255, 255};

struct Extent {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
    long long count = 0;
};

Extent extent(const Image& img, int xa, int xb, Rgb background = kWhite) {
    Extent e;
    for (int y = 0; y < img.height(); ++y)
        for (int x = xa; x < xb; ++x)
            if (img.at(x, y) != background) {
                e.x0 = std::min(e.x0, x), e.x1 = std::max(e.x1, x);
                e.y0 = std::min(e.y0, y), e.y1 = std::max(e.y1, y);
                ++e.count;
            }
    return e;
}

RenderOptions unlabelled(int width, int height) {
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.margin = 0.1;
    for (View& v : o.views) v.label.clear();
    return o;
}

TEST(Rasterizer, SphereIsACircleOfThePredictedRadiusInBothViews) {
    const Mesh sphere = shapes::icosphere(4);  // radius 1, centred
    const RenderOptions o = unlabelled(800, 400);
    Scene scene;
    scene.mesh = &sphere;
    const Image img = render_scene(scene, o);
    ASSERT_EQ(img.width(), 800);
    ASSERT_EQ(img.height(), 400);
    // Panels of 400 x 400; the sphere's projected extent (2) scaled into 400 / (1 + 2 * 0.1) px.
    const double r = 400 / (1 + 2 * 0.1) / 2;
    for (int view = 0; view < 2; ++view) {
        const Extent e = extent(img, view * 400, view * 400 + 400);
        SCOPED_TRACE(view);
        EXPECT_NEAR(e.x1 - e.x0 + 1, 2 * r, 3.0);
        EXPECT_NEAR(e.y1 - e.y0 + 1, 2 * r, 3.0);
        EXPECT_NEAR((e.x0 + e.x1 + 1) / 2.0, view * 400 + 200, 2.0);
        EXPECT_NEAR((e.y0 + e.y1 + 1) / 2.0, 200, 2.0);
        EXPECT_NEAR(static_cast<double>(e.count), M_PI * r * r, 0.02 * M_PI * r * r);
    }
    // project() agrees: the centre lands at the panel centre, a point on the silhouette at distance r.
    const Vec3 c = project({0, 0, 0}, sphere, o, 1);
    EXPECT_NEAR(c.x, 600, 1.0);
    EXPECT_NEAR(c.y, 200, 1.0);
    const Vec3 up = project({0, 1, 0}, sphere, o, 0);
    EXPECT_NEAR(200 - up.y, r * std::sqrt(1 - std::pow(0.6 / std::sqrt(2.36), 2)), 2.0);
}

TEST(Rasterizer, FaceColoursAppearUnshadedWhenAmbientIsOne) {
    const Mesh sphere = shapes::icosphere(3);
    Scene scene;
    scene.mesh = &sphere;
    const Rgb red{200, 30, 30}, blue{30, 30, 200};
    for (const Triangle& t : sphere.triangles)
        scene.face_colours.push_back(sphere.points[t[0]].x + sphere.points[t[1]].x + sphere.points[t[2]].x > 0 ? red : blue);
    RenderOptions o = unlabelled(600, 300);
    o.ambient = 1.0;
    o.supersample = 1;  // no blending at the patch border
    const Image img = render_scene(scene, o);
    const long long disc = img.count_not(kWhite);
    EXPECT_GT(img.count(red), disc / 5);
    EXPECT_GT(img.count(blue), disc / 5);
    EXPECT_EQ(img.count(red) + img.count(blue), disc);
}

TEST(Rasterizer, OverlaysShowInFrontButNotThroughTheSurface) {
    const Mesh sphere = shapes::icosphere(3);
    RenderOptions o = unlabelled(400, 400);
    o.views = {View{{0, 0, 1}, {0, 1, 0}, ""}};
    o.supersample = 1;
    const Rgb line{0, 200, 0}, dot{250, 0, 250};
    Scene scene;
    scene.mesh = &sphere;
    scene.segment_colour = line;
    scene.point_colour = dot;
    scene.point_radius_px = 6;
    scene.segments = {{Vec3{-0.5, 0.5, -0.99}, Vec3{0.5, 0.5, -0.99}}};  // behind the sphere
    scene.points = {Vec3{0, -0.5, -0.95}};
    EXPECT_EQ(render_scene(scene, o).count(line), 0);
    EXPECT_EQ(render_scene(scene, o).count(dot), 0);
    // On the visible side, lying on the surface (a chord dips below it by less than the offset).
    scene.segments = {{Vec3{-0.1, 0.0, std::sqrt(1 - 0.01)}, Vec3{0.1, 0.0, std::sqrt(1 - 0.01)}}};
    scene.points = {Vec3{0, -0.5, std::sqrt(0.75)}};
    const Image img = render_scene(scene, o);
    const Vec3 a = project(scene.segments[0][0], sphere, o, 0), b = project(scene.segments[0][1], sphere, o, 0);
    EXPECT_NEAR(static_cast<double>(img.count(line)), (b.x - a.x) * 2, (b.x - a.x) * 0.5);  // 2 px wide
    EXPECT_GT(img.count(dot), 50);
}

TEST(Rasterizer, DeterministicAndValidatesItsInput) {
    const Mesh sphere = shapes::icosphere(2);
    Scene scene;
    scene.mesh = &sphere;
    RenderOptions o = unlabelled(300, 150);
    EXPECT_EQ(render_scene(scene, o).pixels(), render_scene(scene, o).pixels());
    scene.face_colours = {Rgb{1, 2, 3}};
    EXPECT_THROW(render_scene(scene, o), InvalidInput);
    scene.face_colours.clear();
    o.supersample = 0;
    EXPECT_THROW(render_scene(scene, o), InvalidInput);
    o.supersample = 2;
    o.views = {View{{0, 1, 0}, {0, 2, 0}, ""}};
    EXPECT_NE(o.validate(), "");
    Mesh broken = sphere;
    broken.triangles[0][1] = 99999;
    scene.mesh = &broken;
    EXPECT_THROW(render_scene(scene, unlabelled(300, 150)), InvalidInput);
}

}  // namespace

#pragma once
// Off-screen software rendering of a triangle mesh: orthographic, z-buffered, Lambert-shaded, with
// overlays of line segments and points drawn over the surface they lie on.

#include <array>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/render/image.h"

namespace quadcage::render {

/// One camera direction of a multi-view image.
struct View {
    Vec3 eye{1, 0.6, 1};  ///< Direction from the scene centre towards the camera (any length > 0).
    Vec3 up{0, 1, 0};     ///< Up direction on screen (must not be parallel to eye).
    std::string label;    ///< Drawn in the panel's top-left corner (empty: none).
};

/// Two isometric-like views from opposite sides ("front" and "back"), y up.
std::vector<View> two_views();

/// What to draw. Colours: per-vertex (interpolated) if given, else per-face, else `surface_colour`.
struct Scene {
    const Mesh* mesh = nullptr;           ///< Required; indices must be valid.
    std::vector<Rgb> vertex_colours;      ///< Empty or one per vertex.
    std::vector<Rgb> face_colours;        ///< Empty or one per triangle.
    Rgb surface_colour{200, 200, 205};    ///< Used when neither list is given.
    std::vector<std::array<Vec3, 2>> segments;  ///< Line segments on (or near) the surface.
    Rgb segment_colour{20, 20, 20};
    double segment_width_px = 2.0;        ///< Width in output pixels.
    std::vector<Vec3> points;             ///< Dots (e.g. layout corners).
    Rgb point_colour{220, 20, 20};
    double point_radius_px = 4.0;         ///< Radius in output pixels.
};

/// Options for render_scene().
struct RenderOptions {
    int width = 1200;                     ///< Output width in pixels; split into one panel per view.
    int height = 600;                     ///< Output height in pixels.
    int supersample = 3;                  ///< Samples per pixel along x and y (anti-aliasing), 1..8.
    Rgb background{255, 255, 255};
    std::vector<View> views = two_views();  ///< Panels side by side, left to right (at least one).
    double margin = 0.06;                 ///< Free border around the bounding sphere, fraction of its size.
    double depth_offset = 0.004;          ///< Overlays win depth ties by this fraction of the bbox diagonal.
    double ambient = 0.30;                ///< Shade = ambient + (1 - ambient) * |cos(normal, light)|.
    std::string validate() const;         ///< Empty if valid, else what is wrong.
};

/// Pixel position and depth of world point p in panel `view_index` of an image of `mesh` made with
/// `options`: x to the right and y down in output pixels (panel offset included), depth growing away
/// from the camera. Framing: orthographic; every view uses the same scale, the largest at which each
/// view's projected extent of the mesh's used points fits its panel (width / views x height) shrunk
/// by the factor 1 / (1 + 2 * margin); each view's extent is centred in its panel.
/// \throw InvalidInput if the options are invalid.
Vec3 project(const Vec3& p, const Mesh& mesh, const RenderOptions& options, int view_index);

/// Renders the scene from every view of `options` into one image.
/// \throw InvalidInput if the options are invalid, the colour lists have the wrong size, or the mesh
///        has no triangles or indices out of range.
Image render_scene(const Scene& scene, const RenderOptions& options = {});

}  // namespace quadcage::render

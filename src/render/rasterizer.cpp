#include "quadcage/render/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "quadcage/core/errors.h"
#include "quadcage/render/font.h"

namespace quadcage::render {
namespace {

Vec3 normalized(const Vec3& v) {
    const double n = norm(v);
    return n > 0 ? v / n : v;
}

// Orthographic camera of one panel, in output pixels.
struct Camera {
    Vec3 right, up, back;
    double mid_right = 0, mid_up = 0;  // centre of the projected extent (world units)
    double scale = 1;                  // pixels per world unit
    double cx = 0, cy = 0;             // panel centre in pixels
    int x0 = 0, x1 = 0;                // panel columns [x0, x1)

    Vec3 to_pixels(const Vec3& p) const {
        return {cx + scale * (dot(p, right) - mid_right), cy - scale * (dot(p, up) - mid_up), -dot(p, back)};
    }
};

// One camera per view, all with the same scale: the largest at which every view's projected extent
// of the used points fits its panel inside the margin.
std::vector<Camera> make_cameras(const Mesh& mesh, const RenderOptions& o) {
    std::vector<char> used(mesh.points.size(), 0);
    for (const Triangle& t : mesh.triangles)
        for (int v : t)
            if (v >= 0 && v < mesh.num_vertices()) used[v] = 1;
    const int n = static_cast<int>(o.views.size());
    const int panel_w = o.width / n;
    std::vector<Camera> cams(n);
    double scale = HUGE_VAL;
    for (int i = 0; i < n; ++i) {
        Camera& cam = cams[i];
        cam.back = normalized(o.views[i].eye);
        cam.right = normalized(cross(o.views[i].up, cam.back));
        cam.up = cross(cam.back, cam.right);
        double r0 = HUGE_VAL, r1 = -HUGE_VAL, u0 = HUGE_VAL, u1 = -HUGE_VAL;
        for (size_t v = 0; v < mesh.points.size(); ++v) {
            if (!used[v]) continue;
            const double r = dot(mesh.points[v], cam.right), u = dot(mesh.points[v], cam.up);
            r0 = std::min(r0, r);
            r1 = std::max(r1, r);
            u0 = std::min(u0, u);
            u1 = std::max(u1, u);
        }
        if (!(r0 <= r1)) r0 = r1 = u0 = u1 = 0;
        cam.mid_right = (r0 + r1) / 2;
        cam.mid_up = (u0 + u1) / 2;
        const double fit = std::min(panel_w / std::max(r1 - r0, 1e-300), o.height / std::max(u1 - u0, 1e-300));
        scale = std::min(scale, fit / (1 + 2 * o.margin));
        cam.x0 = i * panel_w;
        cam.x1 = i == n - 1 ? o.width : cam.x0 + panel_w;
        cam.cx = cam.x0 + panel_w / 2.0;
        cam.cy = o.height / 2.0;
    }
    if (!std::isfinite(scale) || !(scale > 0)) scale = 1;  // a single point: any scale
    for (Camera& cam : cams) cam.scale = scale;
    return cams;
}

Rgb shade(Rgb c, double intensity) {
    auto f = [intensity](std::uint8_t v) {
        return static_cast<std::uint8_t>(std::lround(std::clamp(v * intensity, 0.0, 255.0)));
    };
    return {f(c.r), f(c.g), f(c.b)};
}

Rgb lerp3(Rgb a, Rgb b, Rgb c, double wa, double wb, double wc) {
    auto f = [&](double x, double y, double z) {
        return static_cast<std::uint8_t>(std::lround(std::clamp(wa * x + wb * y + wc * z, 0.0, 255.0)));
    };
    return {f(a.r, b.r, c.r), f(a.g, b.g, c.g), f(a.b, b.b, c.b)};
}

void check_scene(const Scene& s) {
    if (!s.mesh) throw InvalidInput("render: no mesh given");
    const Mesh& m = *s.mesh;
    if (m.triangles.empty()) throw InvalidInput("render: the mesh has no triangles");
    for (size_t t = 0; t < m.triangles.size(); ++t)
        for (int v : m.triangles[t])
            if (v < 0 || v >= m.num_vertices())
                throw InvalidInput("render: triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) +
                                   " out of range (" + std::to_string(m.num_vertices()) + " vertices)");
    if (!s.vertex_colours.empty() && s.vertex_colours.size() != m.points.size())
        throw InvalidInput("render: " + std::to_string(s.vertex_colours.size()) + " vertex colours for " +
                           std::to_string(m.points.size()) + " vertices");
    if (!s.face_colours.empty() && s.face_colours.size() != m.triangles.size())
        throw InvalidInput("render: " + std::to_string(s.face_colours.size()) + " face colours for " +
                           std::to_string(m.triangles.size()) + " triangles");
}

}  // namespace

std::vector<View> two_views() {
    return {View{{1.0, 0.6, 1.0}, {0, 1, 0}, "front"}, View{{-1.0, 0.6, -1.0}, {0, 1, 0}, "back"}};
}

std::string RenderOptions::validate() const {
    if (width < 1 || height < 1 || width > 16384 || height > 16384) return "image size must be 1..16384 per side";
    if (supersample < 1 || supersample > 8) return "supersample must be 1..8";
    if (views.empty()) return "at least one view is needed";
    if (width < static_cast<int>(views.size())) return "image narrower than one pixel per view";
    for (const View& v : views) {
        if (!(norm(v.eye) > 0) || !is_finite(v.eye)) return "a view has a zero or non-finite eye direction";
        if (!(norm(cross(v.up, v.eye)) > 1e-9 * norm(v.up) * norm(v.eye))) return "a view's up is parallel to its eye";
    }
    if (!(margin >= 0 && margin < 10)) return "margin must be in [0, 10)";
    if (!(depth_offset >= 0 && depth_offset < 1)) return "depth_offset must be in [0, 1)";
    if (!(ambient >= 0 && ambient <= 1)) return "ambient must be in [0, 1]";
    return {};
}

Vec3 project(const Vec3& p, const Mesh& mesh, const RenderOptions& options, int view_index) {
    if (const std::string e = options.validate(); !e.empty()) throw InvalidInput("render options: " + e);
    QC_CHECK(view_index >= 0 && view_index < static_cast<int>(options.views.size()), "project: bad view index");
    return make_cameras(mesh, options)[view_index].to_pixels(p);
}

Image render_scene(const Scene& scene, const RenderOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("render options: " + e);
    check_scene(scene);
    const Mesh& mesh = *scene.mesh;
    const BoundingBox box = bounding_box(mesh);
    const int ss = o.supersample;
    const int W = o.width * ss, H = o.height * ss;
    Image big(W, H, o.background);
    std::vector<double> zbuf(static_cast<size_t>(W) * H, std::numeric_limits<double>::infinity());
    const double offset = o.depth_offset * std::max(box.diagonal(), 1e-300);

    // Area-weighted vertex normals for smooth shading; flat where a vertex normal vanishes.
    std::vector<Vec3> face_normal(mesh.triangles.size());
    std::vector<Vec3> vertex_normal(mesh.points.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        face_normal[t] = cross(mesh.points[tri[1]] - mesh.points[tri[0]], mesh.points[tri[2]] - mesh.points[tri[0]]);
        for (int v : tri) vertex_normal[v] += face_normal[t];
    }
    for (Vec3& n : vertex_normal) n = normalized(n);
    for (Vec3& n : face_normal) n = normalized(n);

    const std::vector<Camera> cams = make_cameras(mesh, o);
    std::vector<Vec3> screen(mesh.points.size());
    std::vector<double> light(mesh.points.size());
    for (int vi = 0; vi < static_cast<int>(o.views.size()); ++vi) {
        const Camera& cam = cams[vi];
        const Vec3 to_light = normalized(cam.back + cam.up * 0.35 + cam.right * -0.25);
        auto intensity = [&](const Vec3& n) { return o.ambient + (1 - o.ambient) * std::abs(dot(n, to_light)); };
        for (size_t v = 0; v < mesh.points.size(); ++v) {
            const Vec3 p = cam.to_pixels(mesh.points[v]);
            screen[v] = {p.x * ss, p.y * ss, p.z};
            light[v] = intensity(vertex_normal[v]);
        }
        const int col0 = cam.x0 * ss, col1 = cam.x1 * ss;
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Triangle& tri = mesh.triangles[t];
            const Vec3 &a = screen[tri[0]], &b = screen[tri[1]], &c = screen[tri[2]];
            const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            if (area == 0 || !std::isfinite(area)) continue;
            const int xa = std::max(col0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
            const int xb = std::min(col1 - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
            const int ya = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
            const int yb = std::min(H - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
            const bool flat = norm(vertex_normal[tri[0]]) == 0 || norm(vertex_normal[tri[1]]) == 0 ||
                              norm(vertex_normal[tri[2]]) == 0;
            const double flat_light = intensity(face_normal[t]);
            for (int y = ya; y <= yb; ++y) {
                const double py = y + 0.5;
                for (int x = xa; x <= xb; ++x) {
                    const double px = x + 0.5;
                    // Barycentric weights; both orientations accepted (back faces are drawn too).
                    const double w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
                    const double w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
                    const double w2 = 1 - w0 - w1;
                    if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                    const double depth = w0 * a.z + w1 * b.z + w2 * c.z;
                    double& z = zbuf[static_cast<size_t>(y) * W + x];
                    if (!(depth < z)) continue;
                    z = depth;
                    Rgb base = scene.surface_colour;
                    if (!scene.vertex_colours.empty())
                        base = lerp3(scene.vertex_colours[tri[0]], scene.vertex_colours[tri[1]],
                                     scene.vertex_colours[tri[2]], w0, w1, w2);
                    else if (!scene.face_colours.empty())
                        base = scene.face_colours[t];
                    const double li = flat ? flat_light : w0 * light[tri[0]] + w1 * light[tri[1]] + w2 * light[tri[2]];
                    big.set(x, y, shade(base, li));
                }
            }
        }

        // Overlays: drawn where they are not behind the surface by more than `offset`.
        const double half = scene.segment_width_px * ss / 2;
        for (const auto& seg : scene.segments) {
            Vec3 p = cam.to_pixels(seg[0]), q = cam.to_pixels(seg[1]);
            p.x *= ss, p.y *= ss, q.x *= ss, q.y *= ss;
            const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
            const int xa = std::max(col0, static_cast<int>(std::floor(std::min(p.x, q.x) - half)));
            const int xb = std::min(col1 - 1, static_cast<int>(std::ceil(std::max(p.x, q.x) + half)));
            const int ya = std::max(0, static_cast<int>(std::floor(std::min(p.y, q.y) - half)));
            const int yb = std::min(H - 1, static_cast<int>(std::ceil(std::max(p.y, q.y) + half)));
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    const double px = x + 0.5 - p.x, py = y + 0.5 - p.y;
                    const double s = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
                    const double ex = px - s * dx, ey = py - s * dy;
                    if (ex * ex + ey * ey > half * half) continue;
                    const double depth = p.z + s * (q.z - p.z);
                    if (depth - offset <= zbuf[static_cast<size_t>(y) * W + x]) big.set(x, y, scene.segment_colour);
                }
        }
        const double r = scene.point_radius_px * ss;
        const double point_offset = offset + scene.point_radius_px / cam.scale;
        for (const Vec3& pt : scene.points) {
            Vec3 p = cam.to_pixels(pt);
            p.x *= ss, p.y *= ss;
            const int xa = std::max(col0, static_cast<int>(std::floor(p.x - r)));
            const int xb = std::min(col1 - 1, static_cast<int>(std::ceil(p.x + r)));
            const int ya = std::max(0, static_cast<int>(std::floor(p.y - r)));
            const int yb = std::min(H - 1, static_cast<int>(std::ceil(p.y + r)));
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    const double ex = x + 0.5 - p.x, ey = y + 0.5 - p.y;
                    const double d2 = ex * ex + ey * ey;
                    if (d2 > r * r) continue;
                    if (p.z - point_offset > zbuf[static_cast<size_t>(y) * W + x]) continue;
                    // A dark rim makes dots readable on any patch colour.
                    big.set(x, y, d2 > (r - 1.2 * ss) * (r - 1.2 * ss) ? Rgb{15, 15, 15} : scene.point_colour);
                }
        }
    }
    Image out = downsample(big, ss);
    for (int vi = 0; vi < static_cast<int>(o.views.size()); ++vi) {
        const Camera& cam = cams[vi];
        if (!o.views[vi].label.empty()) draw_text(out, cam.x0 + 8, 8, o.views[vi].label, {90, 90, 90});
    }
    return out;
}

}  // namespace quadcage::render

#include "quadcage/render/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "quadcage/core/errors.h"
#include "quadcage/render/colour_map.h"
#include "quadcage/render/font.h"
#include "quadcage/render/rasterizer.h"

namespace quadcage::render {
namespace {

constexpr int kTitleHeight = 30;
constexpr int kColourBarWidth = 210;
const Rgb kInk{30, 30, 30};

void check_indices(const Mesh& mesh) {
    if (mesh.triangles.empty()) throw InvalidInput("figure: the mesh has no triangles");
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int v : mesh.triangles[t])
            if (v < 0 || v >= mesh.num_vertices())
                throw InvalidInput("figure: triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) +
                                   " out of range (" + std::to_string(mesh.num_vertices()) + " vertices)");
}

// The views go below the title strip; the title is drawn on the final image.
RenderOptions view_options(const FigureOptions& o, int width) {
    RenderOptions r;
    r.width = width;
    r.height = o.height - kTitleHeight;
    r.supersample = o.supersample;
    return r;
}

Image with_title(const Image& views, const FigureOptions& o, const std::string& subtitle) {
    Image out(o.width, o.height);
    out.paste(views, 0, kTitleHeight);
    std::string line = o.title;
    if (!subtitle.empty()) line += (line.empty() ? "" : "  -  ") + subtitle;
    draw_text(out, 10, 10, line, kInk);
    return out;
}

}  // namespace

std::string FigureOptions::validate() const {
    if (width < 300 || height < 150 || width > 16384 || height > 16384)
        return "figure size must be at least 300x150 and at most 16384 per side";
    if (supersample < 1 || supersample > 8) return "supersample must be 1..8";
    return {};
}

PatchStructure patch_structure(const Mesh& mesh, const std::vector<int>& patch) {
    check_indices(mesh);
    if (patch.size() != mesh.triangles.size())
        throw InvalidInput("patch labels: " + std::to_string(patch.size()) + " values for " +
                           std::to_string(mesh.triangles.size()) + " triangles");
    for (size_t t = 0; t < patch.size(); ++t)
        if (patch[t] < 0)
            throw InvalidInput("patch labels: triangle " + std::to_string(t) + " has negative label " +
                               std::to_string(patch[t]));
    // Labels -> ranks 0..n-1 (labels need not be contiguous).
    std::vector<int> labels(patch);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    auto rank = [&](int label) {
        return static_cast<int>(std::lower_bound(labels.begin(), labels.end(), label) - labels.begin());
    };
    PatchStructure s;
    s.patches = static_cast<int>(labels.size());
    s.adjacency.resize(labels.size());

    std::vector<std::tuple<int, int, int>> edges;  // (a, b, patch rank) per triangle side, a < b
    edges.reserve(mesh.triangles.size() * 3);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const int p = rank(patch[t]);
        for (int k = 0; k < 3; ++k) {
            const int a = tri[k], b = tri[(k + 1) % 3];
            edges.emplace_back(std::min(a, b), std::max(a, b), p);
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::vector<int>> vertex_patches(mesh.points.size());
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
               std::get<1>(edges[j]) == std::get<1>(edges[i]))
            ++j;
        const int first = std::get<2>(edges[i]);
        bool boundary = false;
        for (size_t k = i; k < j; ++k) {
            const int p = std::get<2>(edges[k]);
            vertex_patches[std::get<0>(edges[k])].push_back(p);
            vertex_patches[std::get<1>(edges[k])].push_back(p);
            if (p != first) {
                boundary = true;
                s.adjacency[first].push_back(p);
                s.adjacency[p].push_back(first);
            }
        }
        if (boundary) s.boundary_edges.push_back({std::get<0>(edges[i]), std::get<1>(edges[i])});
        i = j;
    }
    for (auto& adj : s.adjacency) {
        std::sort(adj.begin(), adj.end());
        adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
    }
    for (size_t v = 0; v < vertex_patches.size(); ++v) {
        auto& ps = vertex_patches[v];
        std::sort(ps.begin(), ps.end());
        ps.erase(std::unique(ps.begin(), ps.end()), ps.end());
        if (ps.size() >= 3) {
            s.corners.push_back(static_cast<int>(v));
            s.corner_patches.push_back(ps);
        }
    }
    return s;
}

Image layout_figure(const Mesh& mesh, const std::vector<int>& patch, const FigureOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("figure options: " + e);
    const PatchStructure s = patch_structure(mesh, patch);
    // Patches meeting at a corner count as neighbours for colouring (diagonal quads of a grid).
    std::vector<std::vector<int>> near = s.adjacency;
    for (const auto& ps : s.corner_patches)
        for (int p : ps)
            for (int q : ps)
                if (p != q) near[p].push_back(q);
    const std::vector<Rgb> colours = patch_colours(near);
    std::vector<int> labels(patch);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());

    Scene scene;
    scene.mesh = &mesh;
    scene.face_colours.reserve(patch.size());
    for (int label : patch)
        scene.face_colours.push_back(
            colours[std::lower_bound(labels.begin(), labels.end(), label) - labels.begin()]);
    for (const auto& e : s.boundary_edges) scene.segments.push_back({mesh.points[e[0]], mesh.points[e[1]]});
    for (int v : s.corners) scene.points.push_back(mesh.points[v]);
    scene.segment_width_px = 2.0;
    scene.point_radius_px = 4.5;
    const Image views = render_scene(scene, view_options(o, o.width));
    return with_title(views, o,
                      std::to_string(s.patches) + " patches, " + std::to_string(s.corners.size()) +
                          " corners (red), patch boundaries dark");
}

Image deviation_figure(const Mesh& mesh, const std::vector<float>& distance, const FigureOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("figure options: " + e);
    check_indices(mesh);
    if (distance.size() != mesh.points.size())
        throw InvalidInput("deviation: " + std::to_string(distance.size()) + " distances for " +
                           std::to_string(mesh.points.size()) + " vertices");
    double max_d = 0;
    for (size_t v = 0; v < distance.size(); ++v) {
        if (distance[v] < 0)
            throw InvalidInput("deviation: vertex " + std::to_string(v) + " has negative distance " +
                               std::to_string(distance[v]));
        if (std::isfinite(distance[v])) max_d = std::max(max_d, static_cast<double>(distance[v]));
    }
    const double scale = max_d > 0 ? max_d : 1.0;  // all zero: everything at the bottom colour
    Scene scene;
    scene.mesh = &mesh;
    scene.vertex_colours.reserve(distance.size());
    for (float d : distance) scene.vertex_colours.push_back(sequential_colour(std::isfinite(d) ? d / scale : 1.0));
    const Image views = render_scene(scene, view_options(o, o.width - kColourBarWidth));
    const double diag = bounding_box(mesh).diagonal();
    char buf[120];
    std::snprintf(buf, sizeof buf, ": max %.3g = %.3g%% of the bbox diagonal %.3g", max_d, diag > 0 ? 100 * max_d / diag : 0.0,
                  diag);
    Image out = with_title(views, o, o.distance_meaning + buf);
    ColourBarOptions bar;
    bar.max_value = scale;
    bar.title = "distance   % of diag";
    bar.secondary_scale = diag > 0 ? 100.0 / diag : 0.0;
    bar.secondary_suffix = "%";
    bar.secondary_title = "0 = on the surface";
    draw_colour_bar(out, o.width - kColourBarWidth + 20, kTitleHeight + 20, kColourBarWidth - 30,
                    o.height - kTitleHeight - 40, bar);
    return out;
}

Image plain_figure(const Mesh& mesh, const FigureOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("figure options: " + e);
    check_indices(mesh);
    Scene scene;
    scene.mesh = &mesh;
    const Image views = render_scene(scene, view_options(o, o.width));
    return with_title(views, o,
                      std::to_string(mesh.num_vertices()) + " vertices, " + std::to_string(mesh.num_triangles()) +
                          " triangles");
}

}  // namespace quadcage::render

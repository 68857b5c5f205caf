#pragma once
// The pictures quadcage draws: a quad layout (patches, their boundaries and corners), a deviation
// map (distance to the fitted surface with a colour bar) and a plain shaded mesh. Used by
// `quadcage render` and `quadcage bench`.

#include <array>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/render/image.h"

namespace quadcage::render {

/// Options shared by the figures.
struct FigureOptions {
    int width = 1200;        ///< Output pixels (two views side by side; deviation adds a colour bar).
    int height = 600;
    int supersample = 3;     ///< Anti-aliasing samples per pixel along each axis (1..8).
    std::string title;       ///< Drawn at the top (empty: none).
    /// What the deviation figure's 'distance' measures, as its caption says it.
    std::string distance_meaning = "distance to the fitted surface";
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// Boundaries and corners of a patch labelling of a triangle mesh.
struct PatchStructure {
    std::vector<std::array<int, 2>> boundary_edges;  ///< Vertex pairs (a < b) of edges whose two sides differ in patch.
    std::vector<int> corners;                        ///< Vertices where at least 3 patches meet (ascending).
    std::vector<std::vector<int>> corner_patches;    ///< Per corner, the patches meeting there (ascending).
    std::vector<std::vector<int>> adjacency;         ///< Per patch: the patches sharing an edge with it (ascending).
    int patches = 0;                                 ///< Number of distinct labels.
};

/// Boundary edges, corners and patch adjacency of the labelling `patch` (one label >= 0 per
/// triangle; labels need not be contiguous: patch i is the i-th smallest label).
/// \throw InvalidInput if `patch` has the wrong size, a negative label or the mesh bad indices.
PatchStructure patch_structure(const Mesh& mesh, const std::vector<int>& patch);

/// Two views of a quad layout: every patch in its own colour (patches sharing an edge or a corner
/// get clearly different colours, see patch_colours()), patch
/// boundaries as dark lines and corners (>= 3 patches) as red dots. The title line also states the
/// patch and corner counts.
/// \throw InvalidInput as patch_structure() and render_scene().
Image layout_figure(const Mesh& mesh, const std::vector<int>& patch, const FigureOptions& options = {});

/// Two views of `mesh` coloured by `distance` (one value >= 0 per vertex; non-finite values are shown
/// as the top colour) with a colour bar from 0 to the maximum, labelled in absolute units and in
/// percent of the bounding-box diagonal; the caption calls it options.distance_meaning.
/// \throw InvalidInput if `distance` has the wrong size or a negative value, or as render_scene().
Image deviation_figure(const Mesh& mesh, const std::vector<float>& distance, const FigureOptions& options = {});

/// Two shaded views of `mesh` in one neutral colour.
/// \throw InvalidInput as render_scene().
Image plain_figure(const Mesh& mesh, const FigureOptions& options = {});

}  // namespace quadcage::render

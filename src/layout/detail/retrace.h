#pragma once
// The layout's curves traced again on the input's own triangles (issue #20: "layout edges run as
// smooth curves across triangles, split where they cross ... no refinement cascade"). The curve
// constructions refine the mesh densely where curves crowd (a genus-20 plate of 834 vertices grows
// to 80k), and the curves keep a vertex wherever they cross that refinement. Traced again, a curve
// keeps only the points where it passes from one input triangle to the next (and its corners and
// the points where it meets other curves), and runs straight between them inside each triangle.

#include <functional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

/// The input triangles round each vertex and each edge of an input (which must outlive it).
struct InputAdjacency {
    explicit InputAdjacency(const Mesh& input);
    /// The triangles of edge ab (either order), in increasing order; none if it is not an edge.
    std::vector<int> edge(int a, int b) const;
    /// Per vertex, the triangles round it, in increasing order.
    std::vector<std::vector<int>> vertex_faces;
    const Mesh& mesh;
};

/// Layout curves located on an input's triangles, for cut_input_along().
struct CurvesOnInput {
    std::vector<Vec3> points;  ///< The input's points first, in order, then the curves' own.
    /// Per point: the input triangles it lies in (all round an input vertex, the two of the input
    /// edge it lies on, else the one it lies inside).
    std::vector<std::vector<int>> place;
    /// Point paths as in QuadLayout (closed cycles without the first point repeated); two points in
    /// a row lie in one input triangle.
    std::vector<std::vector<int>> edge_paths, orthogonal_system, s_cycles;
    std::vector<int> corners;  ///< The point of each cage corner.
};

/// The patch that a point inside input triangle `input_triangle` lies in, or -1 if it cannot say.
using PatchAt = std::function<int(int input_triangle, const Vec3& point)>;

/// The layout on `input` whose curves are `curves`: the input with only the curves' points that
/// they need, each input triangle cut by the straight pieces of the curves that cross it and
/// triangulated (retrace_on_input() says which points are kept). Each region between the layout
/// edges takes the patch that patch_at() gives most of its area (at its triangles' centroids);
/// everything else (the cage's topology, genus, flags) is `like`'s, with the cage's points at the
/// new corners. Points below written.size() are written as written[] gives them (the geometry
/// uses curves.points). Mapped again and verified. Returns "" and sets *out, or says why not.
std::string cut_input_along(const Mesh& input, const InputAdjacency& adjacency, const CurvesOnInput& curves,
                            const std::vector<Vec3>& written, const PatchAt& patch_at, const QuadLayout& like,
                            QuadLayout* out);

/// A layout equivalent to `layout` on the triangles of `input` alone: its mesh is `input` with only
/// the vertices its curves (layout edges, orthogonal system, S-cycles) keep, each input triangle
/// cut by the straight pieces of the curves that cross it and triangulated (new vertices on input
/// edges, and inside input triangles where curves meet, turn at a corner, or must keep a point to
/// stay apart). A curve keeps, along each stretch between points where curves meet, the fewest of
/// its points such that each piece between two kept points lies in one input triangle; where two
/// pieces would cross or touch in a triangle, both keep their points there. The patches follow the
/// curves (each region between layout edges takes the patch most of its area had), are mapped again
/// and verified. Returns "" and sets *out, or says why not (*out then unspecified).
/// \pre layout is a verified layout of `input` (its first input_vertices points are input's).
std::string retrace_on_input(const Mesh& input, const QuadLayout& layout, QuadLayout* out);

/// The layout `proxy` (built on a coarser copy of `input`, such as decimated() makes) carried onto
/// `input`. Each point of its curves is carried to its closest point on the input; where the curves
/// so carried fail, the whole is tried again with each point carried along the proxy's normal there
/// (area-weighted at its vertices, interpolated along its edges) to the nearest input point on that
/// line, within twice the proxy's median edge, whose triangle faces the same way (else its closest
/// point). A point that lands on an input vertex or edge is moved off it into the triangle its
/// offset points into. The proxy's edges are sampled about a median input edge apart and each
/// sample walked to the next across the input's triangles, straight on across a crease where the
/// next lies behind it (midpoints carried too where a walk is lost; a jump joined along input
/// edges, up to twice the proxy's median edge). Then cut_input_along(), each region taking the
/// patch of the proxy triangles nearest it. The layout has the proxy's cage topology, genus and
/// S-cycles, on the input's own triangles. Fails (returns why, for both ways) where the carried
/// curves cross or lose their way, or the result does not verify; returns "" and sets *out (and
/// *how, if given: which way carried it) otherwise.
/// \pre proxy is a verified layout; input is closed and manifold.
std::string trace_from_proxy(const Mesh& input, const QuadLayout& proxy, QuadLayout* out, std::string* how = nullptr);

}  // namespace quadcage::layout::detail

#pragma once
// The layout's curves traced again on the input's own triangles (issue #20: "layout edges run as
// smooth curves across triangles, split where they cross ... no refinement cascade"). The curve
// constructions refine the mesh densely where curves crowd (a genus-20 plate of 834 vertices grows
// to 80k), and the curves keep a vertex wherever they cross that refinement. Traced again, a curve
// keeps only the points where it passes from one input triangle to the next (and its corners and
// the points where it meets other curves), and runs straight between them inside each triangle.

#include <string>

#include "quadcage/core/mesh.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

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

}  // namespace quadcage::layout::detail

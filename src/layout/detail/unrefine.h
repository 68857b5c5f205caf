#pragma once
// Undoing the refinement no curve needs (issue #20: "the layout mesh grows by at most 25% of the
// input's vertices plus 200 per corner"). The curve constructions split mesh edges for room while
// they search (Builder::split_chords and its kin); most of those splits end up under a curve, but
// many are left inside patches once the curves that needed them were rerouted or relaxed.

#include <functional>
#include <string>

#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

/// Removes the vertices the layout added (index >= input_vertices) that lie on no layout edge,
/// cycle of the orthogonal system or S-cycle, by collapsing each into a neighbour where that keeps
/// the surface exactly: every triangle that changes keeps its plane (so a vertex on an input edge
/// between two faces that are not coplanar only slides along that edge) and its orientation, the
/// collapse keeps the mesh a manifold (link condition), and no new edge joins two vertices of one
/// layout edge without being part of it (the dividing chords parameterize_patches() cannot map).
/// Of the neighbours that qualify, the one whose new triangles have the largest smallest angle is
/// taken. With `straighten`, a vertex inside one layout edge (on no other edge, cycle or S-cycle)
/// is taken out of it the same way too, into one of its two neighbours along the edge, where the
/// edge turns there by at most 10 degrees, and edges inside a plane are flipped where the
/// Delaunay condition asks (never an edge between two input vertices or along a curve, nor into a
/// dividing chord): on flat
/// stretches the edges lose the points where they crossed splits (a straight edge across a flat
/// input face keeps only its crossings of the input's edges). That moves the layout edges a little,
/// so it is only for a layout over the bound (undo_unused_refinement()). Later vertices go first (a split
/// made inside another split's triangles is undone before it), over passes until one removes nothing. Every
/// kept vertex stays where it is; vertices are renumbered in their order (the input's first, unchanged), and
/// the mesh, triangle_patch, corner_vertex, edge_paths (without the vertices taken out), the cycles and the
/// corner_uv of the triangles kept as they were follow. Returns the number of vertices removed. Only if that
/// is not 0, *out is set to the layout without them (nothing is copied otherwise), and the patches where a
/// vertex was removed are marked in *changed (one flag per cage quad): map them again (parameterize_patches()
/// with `only`) and verify the result. quality is not recomputed. \pre layout is a verified layout
/// (verify_quad_layout() returns "").
int remove_unused_refinement(const QuadLayout& layout, QuadLayout* out, std::vector<char>* changed,
                             bool straighten = false);

/// remove_unused_refinement() on *L, the changed patches mapped again, kept if the result verifies
/// (its quality then measured again); one progress line says which. Then, if bound >= 0 and the
/// layout still adds more vertices than that, the same with `straighten`; and if it still does and
/// `input` is given, the layout traced again on the input's triangles (retrace_on_input()), kept if
/// it verifies and adds fewer vertices. Its time is added to L->seconds.parameterization.
/// \pre *L is a verified layout (of *input, if given).
void undo_unused_refinement(QuadLayout* L, const std::function<void(const std::string&)>& say,
                            long long bound = -1, const Mesh* input = nullptr);

}  // namespace quadcage::layout::detail

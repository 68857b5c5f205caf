#pragma once
// From a network of layout curves on a surface to the cage, the patches and their maps onto the
// unit square (design.md §3, §5).

#include <array>
#include <string>
#include <vector>

#include "detail/surface.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout::detail {

/// Sets both half-edges of every mesh edge that `path` walks to `value` in `cut`.
void mark_path(const Surface& s, const std::vector<int>& path, std::vector<char>* cut, char value);

/// Half the cotangent of the angle at o of triangle (i, j, o): the weight that triangle gives edge
/// i-j in the cotangent Laplacian, clamped to [-500, 500] (500 for a degenerate triangle).
double half_cotangent(const Mesh& mesh, int i, int j, int o);

/// Floods from the triangles on `stack` across half-edges not marked in `cut`: every neighbour o
/// for which claim(o) returns true (claim marks it) is flooded from in turn. Empties `stack`.
template <class Claim>
void flood_triangles(const Surface& s, const std::vector<char>& cut, std::vector<int>& stack, Claim claim) {
    while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        for (int k = 0; k < 3; ++k)
            if (const int h = 3 * f + k; !cut[h])
                if (const int o = s.twin(h) / 3; claim(o)) stack.push_back(o);
    }
}

/// Marks both half-edges of every edge walked by the given vertex paths (open paths).
std::vector<char> cut_half_edges(const Surface& s, const std::vector<std::vector<int>>& paths);

/// Labels triangles by the components of the surface cut along `cut` half-edges; components are
/// numbered in the order of their lowest triangle. Returns the number of components.
int face_components(const Surface& s, const std::vector<char>& cut, std::vector<int>* label);

/// The next boundary half-edge of a region after h: around to(h), inside the region of h's
/// triangle, the first half-edge that is cut.
int next_cut_half_edge(const Surface& s, const std::vector<char>& cut, int h);

/// The cage of a curve network: `corners` are mesh vertices, `paths` the layout edges (vertex paths
/// from a corner to a corner through no other corner). Patches are the faces of the network.
/// Fills layout->cage (positions of the corner vertices), corner_vertex, triangle_patch and
/// edge_paths. Patch i is cage quad i, corner 0 of each quad is its lowest-numbered corner.
/// Returns "" or what makes the network no quad layout (a face without 4 corners, ...).
std::string extract_cage(const Surface& s, const std::vector<int>& corners,
                         const std::vector<std::vector<int>>& paths, QuadLayout* layout);

/// Maps every patch onto [0,1]^2: sides by arc length, interior by a Tutte embedding with positive
/// weights, which cannot fold on a convex boundary (Floater 2003): clamped cotangent weights (or
/// uniform ones where those squeeze a triangle below rounding), then reweighted by the local L2
/// stretch for up to 8 rounds (Yoshizawa, Belyaev & Seidel 2004), keeping the least stretched map.
/// With `only` (one flag per cage quad), maps only the patches it marks and keeps the corner_uv of
/// the others' triangles, which must be their maps already.
/// \pre extract_cage() succeeded and no mesh edge joins two boundary vertices of a patch without
///      being a layout edge (split such chords first).
void parameterize_patches(QuadLayout* layout, const std::vector<char>* only = nullptr);

/// The boundary of cage quad q as a closed loop of mesh vertices starting at its corner 0, with
/// the side (0..3) of each loop edge: loop[i] -> loop[i+1] lies on side side[i].
void quad_boundary(const QuadLayout& layout, int q, std::vector<int>* loop, std::vector<int>* side);

/// (u, v) of the point at fraction t along side k of the unit square, the sides running
/// counter-clockwise from (0,0): (t,0), (1,t), (1-t,1), (0,1-t).
UV side_point(int k, double t);

/// The (u, v) of each vertex of a quad_boundary() loop: on side k at its arc-length fraction t along
/// the side, side_point(k, t). Both patches of a layout edge so agree on its vertices.
std::vector<UV> boundary_positions(const Mesh& mesh, const std::vector<int>& loop, const std::vector<int>& side);

/// Fills layout->quality.
void measure_quality(QuadLayout* layout);

}  // namespace quadcage::layout::detail

#pragma once
// Relaxation of a quad layout (design.md §4's "tight and smooth, corners spread"): each corner is
// moved towards where it shares its patches' area evenly, each layout edge to the middle of the two
// patches it separates.

#include <vector>

#include "detail/surface.h"

namespace quadcage::layout::detail {

struct RelaxOptions {
    int sweeps = 3;         ///< Passes over all edges (each pass moves every edge once, in order).
    double middle = 10.0;   ///< Path cost factor 1 + middle * (2h - 1)^2 at harmonic value h.
    double ray = 50.0;      ///< A moved corner's edges: path cost factor 1 + ray * d^2 at distance d
                            ///< from the straight ray in the star's map (radius 1).
    double balance = 0.5;   ///< A moved corner's target: this fraction of the way from the centre of
                            ///< its star's map to the point that shares its area evenly.
    int corner_candidates = 4;  ///< Vertices tried as a moved corner, nearest the target first.
};

/// Moves every layout edge (vertex path from a corner to a corner along mesh edges; `paths` as
/// for extract_cage) to the middle of the region its two patches make: there the harmonic function
/// that is 0 on one patch's other three sides and 1 on the other's is 1/2, so each edge ends up
/// balancing the shapes of its two patches, and edges that a construction packed side by side
/// spread out. The new edge is a mesh-edge path through the interior of that region, so the network
/// keeps its combinatorics: the same corners, edges and patches. An edge whose region is not a
/// disk (its two patches share another edge) or offers no interior path is left as it is.
/// Returns the number of edge moves made.
int relax_layout_edges(const Surface& s, std::vector<std::vector<int>>* paths, const RelaxOptions& options = {});

/// One pass over the corners (`corners` and `paths` as for extract_cage): each corner moves inside
/// its star, the union of its patches, towards where it would share the star's area evenly among
/// them. The star is cut open where its boundary meets itself (the level-0 cage's multi-edges) and
/// mapped onto a regular polygon: its corners and the corners diagonal to it alternate at the
/// polygon's vertices, sides by arc length, the inside by a Tutte embedding. The target is the point
/// `balance` of the way from the polygon's centre (the corner of a conformal split) to the point
/// whose fan of quads splits the star's area most evenly; the new corner is the first vertex near
/// it from which every edge can be rerouted along the map's rays to the same neighbour corners.
/// Large patches so give area to small ones, and corners that a construction clustered spread out.
/// The network keeps its combinatorics (the same corner order, edges and patches; a moved corner's
/// edges keep their direction). A corner whose star is not a disk, or whose edges cannot all be
/// rerouted, stays. Returns the number of corners moved.
int relax_layout_corners(const Surface& s, std::vector<int>* corners, std::vector<std::vector<int>>* paths,
                         const RelaxOptions& options = {});

}  // namespace quadcage::layout::detail

#pragma once
// Relaxation of a quad layout's edges (design.md §4's "tight and smooth, corners spread"): each
// layout edge is moved to the middle of the two patches it separates.

#include <vector>

#include "detail/surface.h"

namespace quadcage::layout::detail {

struct RelaxOptions {
    int sweeps = 3;         ///< Passes over all edges (each pass moves every edge once, in order).
    double middle = 10.0;   ///< Path cost factor 1 + middle * (2h - 1)^2 at harmonic value h.
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

}  // namespace quadcage::layout::detail

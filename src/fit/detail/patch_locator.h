#pragma once
// The inverse of a layout's patch parameterisation: (patch, u, v) -> point on the mesh
// (private to src/fit).

#include <vector>

#include "detail/sampling.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::fit::detail {

/// Finds the mesh point with given patch coordinates, through a uniform grid over each patch's
/// unit square that lists the triangles whose (u, v) bounding box overlaps each cell.
class PatchLocator {
public:
    /// \pre layout sizes are consistent (checked by the caller).
    explicit PatchLocator(const layout::QuadLayout& layout);

    /// The point of patch q at (u, v): the triangle of q whose (u, v) image contains it, or, if
    /// none does (round-off on a side), the one it is closest to, with clamped barycentrics.
    MeshSample locate(int q, double u, double v) const;

private:
    struct Patch {
        int grid = 1;
        std::vector<std::vector<int>> cells;  ///< grid * grid lists of triangles.
    };
    const layout::QuadLayout& layout_;
    std::vector<Patch> patches_;
};

}  // namespace quadcage::fit::detail

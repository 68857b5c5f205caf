#pragma once
// Checks of a user's control mesh against the mesh it is to be fitted to (private to src/fit).

#include <string>

#include "quadcage/accel/closest_point.h"
#include "quadcage/core/mesh.h"

namespace quadcage::fit::detail {

/// check_control_mesh() with a ready index of `mesh`.
std::string check_control_mesh(const Mesh& mesh, const accel::ClosestPointIndex& index, const PolygonMesh& cage,
                               double max_mean_distance);

}  // namespace quadcage::fit::detail

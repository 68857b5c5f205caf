#pragma once
// OpenSubdiv topology shared by the subdiv sources (never included outside src/subdiv).

#include <opensubdiv/far/topologyRefiner.h>

#include <memory>

#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::subdiv::detail {

/// Throws InvalidInput (prefixed with `who`) unless `mesh` is a simple quad mesh with finite points
/// and `levels` is in [0, kMaxRefinementLevel].
void validate_quad_mesh(const QuadMesh& mesh, int levels, const char* who);

/// A Catmull-Clark refiner for `mesh` (CATMARK, boundary EDGE_ONLY), refined uniformly `levels`
/// times; `for_limit` keeps the full topology of the last level. \pre validate_quad_mesh() passed.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> make_refiner(const QuadMesh& mesh, int levels, bool for_limit);

}  // namespace quadcage::subdiv::detail

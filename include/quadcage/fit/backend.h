#pragma once
// The least-squares backend of the fit module (Ceres Solver).

#include <string>

namespace quadcage::fit {

/// Ceres' version, with the result of a one-residual solve run through the linked library
/// (proves the library links and its solver runs; used by `quadcage version`).
std::string ceres_version();

}  // namespace quadcage::fit

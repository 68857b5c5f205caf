#pragma once
// The least-squares backend of the fit module (Ceres Solver).

#include <string>

namespace quadcage::fit {

/// Ceres' version, with the result of a one-residual solve run through the linked library
/// (proves the library links and its solver runs; used by `quadcage version`).
std::string ceres_version();

/// Eigen's version, with the residual of a small dense solve run through it.
std::string eigen_version();

}  // namespace quadcage::fit

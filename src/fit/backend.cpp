#include "quadcage/fit/backend.h"

#include <ceres/ceres.h>
#include <ceres/version.h>

#include <Eigen/Dense>
#include <cstdio>

namespace quadcage::fit {
namespace {
// r(x) = x - 3: the solve must land on x = 3.
struct Offset {
    template <class T>
    bool operator()(const T* x, T* r) const {
        r[0] = x[0] - T(3.0);
        return true;
    }
};
}  // namespace

std::string ceres_version() {
    double x = 0.0;
    ceres::Problem problem;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Offset, 1, 1>(new Offset), nullptr, &x);
    ceres::Solver::Options options;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    char buf[128];
    std::snprintf(buf, sizeof buf, "Ceres %s (test solve: %s, x=%.6g)", CERES_VERSION_STRING,
                  summary.IsSolutionUsable() ? "ok" : "FAILED", x);
    return buf;
}

std::string eigen_version() {
    Eigen::Matrix3d a;
    a << 4, 1, 0, 1, 3, 1, 0, 1, 2;
    const Eigen::Vector3d b(1, 2, 3);
    const Eigen::Vector3d x = a.ldlt().solve(b);
    char buf[128];
    std::snprintf(buf, sizeof buf, "Eigen %d.%d.%d (test solve residual %.1e)", EIGEN_WORLD_VERSION,
                  EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, (a * x - b).norm());
    return buf;
}

}  // namespace quadcage::fit

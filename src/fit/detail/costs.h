#pragma once
// The residuals of the fit as Ceres cost functions with analytic Jacobians (private to src/fit).
//
// Every residual here is affine in a weighted sum of control points y = sum_i w_i x_i (a limit
// stencil, possibly composed with the level-0 -> level-1 map): r = A y - b with A a 3x3 or 1x3
// matrix, so dr/dx_i = w_i A exactly.

#include <ceres/cost_function.h>

#include <array>
#include <memory>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::fit::detail {

/// One affine residual r = A (sum_i w_i x_i) - b (A: `rows` x 3, row-major; rows 1 or 3).
struct StencilRows {
    std::vector<double> weights;
    int rows = 3;
    std::array<double, 9> a{};
    std::array<double, 3> b{};
};

/// Several StencilRows over the same parameter blocks (one per weight, the same in every member),
/// stacked into one residual block (the factories below make blocks of one). Data points and
/// surface samples on the same control face share their stencil's control points; as one block
/// each, Ceres builds the structure of J^T J from (faces x stencil size^2) products instead of
/// (points x stencil size^2).
class StencilGroupCost final : public ceres::CostFunction {
public:
    explicit StencilGroupCost(std::vector<StencilRows> members);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

private:
    std::vector<StencilRows> members_;
};

/// The least-squares equivalent of StencilGroupCost(members) in fewer rows, for a group with more
/// residuals than unknowns: r = R x - d with R (3n x 3n, upper triangular) the Cholesky factor of
/// J^T J and d = R^-T J^T b, where the group's residuals are J x - b. The sum of squares differs
/// from the group's by a constant (|b|^2 - |d|^2); the gradient and the Gauss-Newton matrix J^T J
/// are the same, so a Gauss-Newton or Levenberg-Marquardt step is the same. Ceres forms J^T J of
/// a block in (rows x columns^2): a face's 60 data rows over its 16 control points become 48.
/// Null when J^T J is not positive definite (the group is then kept as it is).
std::unique_ptr<ceres::CostFunction> compressed_group_cost(const std::vector<StencilRows>& members);

/// The residuals of the factories below, as StencilRows (for StencilGroupCost).
StencilRows point_to_point_rows(std::vector<double> weights, const Vec3& p, double scale);
StencilRows tangent_weighted_rows(std::vector<double> weights, const Vec3& p, const Vec3& n, double mu, double scale);
StencilRows point_to_plane_rows(std::vector<double> weights, const Vec3& q, const Vec3& n, double scale);

/// scale * (S - p): point-to-point distance of the limit point S = sum w_i x_i to a data point p.
ceres::CostFunction* point_to_point_cost(std::vector<double> weights, const Vec3& p, double scale);

/// scale * A (S - p) with A = n n^T + sqrt(mu) (I - n n^T): the distance of S to p along the unit
/// normal n counted fully, its tangential part with weight mu (squared). With mu = 1 this is
/// point_to_point_cost; small mu lets the surface slide along itself, as in squared-distance
/// minimisation (Pottmann et al.), which converges much faster than point-to-point fitting.
ceres::CostFunction* tangent_weighted_cost(std::vector<double> weights, const Vec3& p, const Vec3& n, double mu,
                                           double scale);

/// scale * n . (S - q): signed distance of S to the plane through q with unit normal n.
ceres::CostFunction* point_to_plane_cost(std::vector<double> weights, const Vec3& q, const Vec3& n, double scale);

/// One residual sum_i c_i . x_i - b with a 3-vector c_i per control point: a linearised scalar
/// function of the control points that is not of one weighted sum (the fit's turned-over term,
/// which reads the surface's two derivatives at a point).
ceres::CostFunction* linear_row_cost(std::vector<Vec3> coefficients, double b);

/// scale * sum w_i x_i with weights summing to 0: a Laplacian of the control net (x_i minus the mean
/// of its neighbours) or any other linear smoothness measure.
ceres::CostFunction* smoothness_cost(std::vector<double> weights, double scale);

}  // namespace quadcage::fit::detail

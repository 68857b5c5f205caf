#include "detail/costs.h"

#include <Eigen/Dense>

#include <cmath>

#include "quadcage/core/errors.h"

namespace quadcage::fit::detail {

StencilGroupCost::StencilGroupCost(std::vector<StencilRows> members) : members_(std::move(members)) {
    QC_CHECK(!members_.empty(), "StencilGroupCost: no members");
    const size_t blocks = members_.front().weights.size();
    QC_CHECK(blocks > 0, "StencilGroupCost: empty stencil");
    int rows = 0;
    for (const StencilRows& m : members_) {
        QC_CHECK(m.rows == 1 || m.rows == 3, "StencilGroupCost: rows must be 1 or 3");
        QC_CHECK(m.weights.size() == blocks, "StencilGroupCost: members differ in their number of blocks");
        rows += m.rows;
    }
    set_num_residuals(rows);
    mutable_parameter_block_sizes()->assign(blocks, 3);
}

bool StencilGroupCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
    const size_t blocks = members_.front().weights.size();
    int row = 0;
    for (const StencilRows& m : members_) {
        double y[3] = {0, 0, 0};
        for (size_t i = 0; i < blocks; ++i)
            for (int d = 0; d < 3; ++d) y[d] += m.weights[i] * parameters[i][d];
        for (int r = 0; r < m.rows; ++r)
            residuals[row + r] = m.a[3 * r] * y[0] + m.a[3 * r + 1] * y[1] + m.a[3 * r + 2] * y[2] - m.b[r];
        if (jacobians)
            for (size_t i = 0; i < blocks; ++i) {
                if (!jacobians[i]) continue;
                double* out = jacobians[i] + 3 * row;  // rows x 3, row-major, this member's rows
                for (int k = 0; k < 3 * m.rows; ++k) out[k] = m.weights[i] * m.a[k];
            }
        row += m.rows;
    }
    return true;
}

namespace {

/// r = M x - d over parameter blocks of size 3 (M: rows x 3 blocks, column-major).
class DenseAffineCost final : public ceres::CostFunction {
public:
    DenseAffineCost(Eigen::MatrixXd m, Eigen::VectorXd d) : m_(std::move(m)), d_(std::move(d)) {
        set_num_residuals(static_cast<int>(m_.rows()));
        mutable_parameter_block_sizes()->assign(m_.cols() / 3, 3);
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        const Eigen::Index blocks = m_.cols() / 3;
        Eigen::Map<Eigen::VectorXd> r(residuals, m_.rows());
        r = -d_;
        for (Eigen::Index i = 0; i < blocks; ++i)
            r.noalias() += m_.middleCols<3>(3 * i) * Eigen::Map<const Eigen::Vector3d>(parameters[i]);
        if (jacobians)
            for (Eigen::Index i = 0; i < blocks; ++i)
                if (jacobians[i])
                    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(jacobians[i], m_.rows(), 3) =
                        m_.middleCols<3>(3 * i);
        return true;
    }

private:
    Eigen::MatrixXd m_;
    Eigen::VectorXd d_;
};

}  // namespace

std::unique_ptr<ceres::CostFunction> compressed_group_cost(const std::vector<StencilRows>& members) {
    QC_CHECK(!members.empty(), "compressed_group_cost: no members");
    const Eigen::Index blocks = static_cast<Eigen::Index>(members.front().weights.size()), cols = 3 * blocks;
    Eigen::Index rows = 0;
    for (const StencilRows& m : members) {
        QC_CHECK(m.weights.size() == members.front().weights.size(), "compressed_group_cost: members differ");
        rows += m.rows;
    }
    // J: row r of a member is a_r (1 x 3) times the stencil weight of each block.
    Eigen::MatrixXd j(rows, cols);
    Eigen::VectorXd b(rows);
    Eigen::Index row = 0;
    for (const StencilRows& m : members)
        for (int r = 0; r < m.rows; ++r, ++row) {
            for (Eigen::Index i = 0; i < blocks; ++i)
                for (int d = 0; d < 3; ++d) j(row, 3 * i + d) = m.weights[i] * m.a[3 * r + d];
            b(row) = m.b[r];
        }
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(cols, cols);
    normal.selfadjointView<Eigen::Lower>().rankUpdate(j.transpose());
    const Eigen::LLT<Eigen::MatrixXd> llt(normal);
    if (llt.info() != Eigen::Success) return nullptr;
    Eigen::MatrixXd r = llt.matrixU();
    // Positive definite in floating point is not enough: a tiny pivot would make d huge.
    const double largest = r.diagonal().cwiseAbs().maxCoeff(), smallest = r.diagonal().cwiseAbs().minCoeff();
    if (!(smallest > 1e-7 * largest)) return nullptr;
    Eigen::VectorXd d = llt.matrixL().solve(j.transpose() * b);
    return std::make_unique<DenseAffineCost>(std::move(r), std::move(d));
}

StencilRows point_to_point_rows(std::vector<double> weights, const Vec3& p, double scale) {
    return {std::move(weights), 3, {scale, 0, 0, 0, scale, 0, 0, 0, scale}, {scale * p.x, scale * p.y, scale * p.z}};
}

StencilRows tangent_weighted_rows(std::vector<double> weights, const Vec3& p, const Vec3& n, double mu, double scale) {
    QC_CHECK(mu >= 0, "tangent_weighted_cost: mu must be >= 0");
    const double t = std::sqrt(mu);
    const double nv[3] = {n.x, n.y, n.z};
    StencilRows out{std::move(weights), 3, {}, {}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out.a[3 * r + c] = scale * ((1 - t) * nv[r] * nv[c] + (r == c ? t : 0.0));
    for (int r = 0; r < 3; ++r) out.b[r] = out.a[3 * r] * p.x + out.a[3 * r + 1] * p.y + out.a[3 * r + 2] * p.z;
    return out;
}

StencilRows point_to_plane_rows(std::vector<double> weights, const Vec3& q, const Vec3& n, double scale) {
    return {std::move(weights), 1, {scale * n.x, scale * n.y, scale * n.z, 0, 0, 0, 0, 0, 0}, {scale * dot(n, q), 0, 0}};
}

namespace {
ceres::CostFunction* single(StencilRows r) { return new StencilGroupCost({std::move(r)}); }
}  // namespace

ceres::CostFunction* point_to_point_cost(std::vector<double> weights, const Vec3& p, double scale) {
    return single(point_to_point_rows(std::move(weights), p, scale));
}

ceres::CostFunction* tangent_weighted_cost(std::vector<double> weights, const Vec3& p, const Vec3& n, double mu,
                                           double scale) {
    return single(tangent_weighted_rows(std::move(weights), p, n, mu, scale));
}

ceres::CostFunction* point_to_plane_cost(std::vector<double> weights, const Vec3& q, const Vec3& n, double scale) {
    return single(point_to_plane_rows(std::move(weights), q, n, scale));
}

namespace {
class LinearRowCost final : public ceres::CostFunction {
public:
    LinearRowCost(std::vector<Vec3> c, double b) : c_(std::move(c)), b_(b) {
        set_num_residuals(1);
        for (size_t i = 0; i < c_.size(); ++i) mutable_parameter_block_sizes()->push_back(3);
    }
    bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
        double r = -b_;
        for (size_t i = 0; i < c_.size(); ++i) r += c_[i].x * x[i][0] + c_[i].y * x[i][1] + c_[i].z * x[i][2];
        residuals[0] = r;
        if (jacobians)
            for (size_t i = 0; i < c_.size(); ++i)
                if (jacobians[i]) jacobians[i][0] = c_[i].x, jacobians[i][1] = c_[i].y, jacobians[i][2] = c_[i].z;
        return true;
    }

private:
    std::vector<Vec3> c_;
    double b_;
};
}  // namespace

ceres::CostFunction* linear_row_cost(std::vector<Vec3> coefficients, double b) {
    return new LinearRowCost(std::move(coefficients), b);
}

ceres::CostFunction* smoothness_cost(std::vector<double> weights, double scale) {
    const std::array<double, 9> a = {scale, 0, 0, 0, scale, 0, 0, 0, scale};
    return single({std::move(weights), 3, a, {0, 0, 0}});
}

}  // namespace quadcage::fit::detail

// Ceres gradient checks of every cost function of the fit (src/fit/detail/costs.h).

#include "detail/costs.h"

#include <Eigen/Dense>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace quadcage::fit::detail {
namespace {

struct Probe {
    std::vector<double> weights;
    std::vector<std::array<double, 3>> points;
};

Probe random_probe(int blocks, unsigned seed, bool sum_to_zero) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    Probe p;
    double sum = 0;
    for (int i = 0; i < blocks; ++i) {
        p.weights.push_back(uni(rng));
        sum += p.weights.back();
        p.points.push_back({uni(rng), uni(rng), uni(rng)});
    }
    if (sum_to_zero) p.weights.back() -= sum;
    return p;
}

// True if Ceres' numeric differentiation agrees with the analytic Jacobian.
bool gradient_ok(const ceres::CostFunction& cost, const Probe& probe, std::string* log) {
    ceres::NumericDiffOptions numeric;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(&cost, no_manifolds, numeric);
    std::vector<const double*> params;
    for (const auto& p : probe.points) params.push_back(p.data());
    ceres::GradientChecker::ProbeResults results;
    const bool ok = checker.Probe(params.data(), 1e-7, &results);
    *log = results.error_log;
    return ok;
}

TEST(FitCosts, PointToPointGradient) {
    for (int blocks : {1, 4, 16}) {
        const Probe p = random_probe(blocks, 10 + blocks, false);
        std::unique_ptr<ceres::CostFunction> cost(point_to_point_cost(p.weights, {0.3, -0.2, 0.9}, 2.5));
        std::string log;
        EXPECT_TRUE(gradient_ok(*cost, p, &log)) << log;
    }
}

TEST(FitCosts, PointToPlaneGradient) {
    for (int blocks : {1, 5, 20}) {
        const Probe p = random_probe(blocks, 20 + blocks, false);
        const Vec3 n = Vec3{1, 2, -2} / 3.0;
        std::unique_ptr<ceres::CostFunction> cost(point_to_plane_cost(p.weights, {0.1, 0.2, 0.3}, n, 0.7));
        std::string log;
        EXPECT_TRUE(gradient_ok(*cost, p, &log)) << log;
    }
}

TEST(FitCosts, TangentWeightedGradient) {
    for (int blocks : {1, 6, 16}) {
        const Probe p = random_probe(blocks, 40 + blocks, false);
        const Vec3 n = Vec3{2, -1, 2} / 3.0;
        std::unique_ptr<ceres::CostFunction> cost(tangent_weighted_cost(p.weights, {0.4, -0.1, 0.2}, n, 0.05, 1.5));
        std::string log;
        EXPECT_TRUE(gradient_ok(*cost, p, &log)) << log;
    }
}

TEST(FitCosts, TangentWeightedSplitsNormalAndTangentialParts) {
    // S = 0.25 a + 0.75 b = (3, 0, 0); p = (3, 1, 2); n = z: normal part -2, tangential part (0, -1, 0).
    const std::array<double, 3> a{0, 0, 0}, b{4, 0, 0};
    const double* params[] = {a.data(), b.data()};
    double r[3], q[3];
    for (const double mu : {0.0, 0.04, 1.0}) {
        std::unique_ptr<ceres::CostFunction> c(tangent_weighted_cost({0.25, 0.75}, {3, 1, 2}, {0, 0, 1}, mu, 2.0));
        ASSERT_TRUE(c->Evaluate(params, r, nullptr));
        EXPECT_NEAR(r[2], 2.0 * -2.0, 1e-12) << "mu " << mu;                 // normal part in full
        EXPECT_NEAR(r[1], 2.0 * std::sqrt(mu) * -1.0, 1e-12) << "mu " << mu;  // tangential part scaled
        EXPECT_NEAR(r[0], 0.0, 1e-12);
    }
    // mu = 1 is point-to-point.
    std::unique_ptr<ceres::CostFunction> t(tangent_weighted_cost({0.25, 0.75}, {3, 1, 2}, {0, 0, 1}, 1.0, 2.0));
    std::unique_ptr<ceres::CostFunction> p2p(point_to_point_cost({0.25, 0.75}, {3, 1, 2}, 2.0));
    ASSERT_TRUE(t->Evaluate(params, r, nullptr));
    ASSERT_TRUE(p2p->Evaluate(params, q, nullptr));
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(r[d], q[d], 1e-12);
}

TEST(FitCosts, SmoothnessGradient) {
    for (int blocks : {2, 6}) {
        const Probe p = random_probe(blocks, 30 + blocks, true);
        std::unique_ptr<ceres::CostFunction> cost(smoothness_cost(p.weights, 0.05));
        std::string log;
        EXPECT_TRUE(gradient_ok(*cost, p, &log)) << log;
    }
}

TEST(FitCosts, StencilGroupGradient) {
    for (int blocks : {1, 4, 16}) {
        const Probe p = random_probe(blocks, 40 + blocks, false);
        const Probe q = random_probe(blocks, 50 + blocks, false);  // other weights, same blocks
        const Vec3 n = Vec3{2, -1, 2} / 3.0;
        std::vector<StencilRows> members;
        members.push_back(point_to_point_rows(p.weights, {0.3, -0.2, 0.9}, 2.5));
        members.push_back(tangent_weighted_rows(q.weights, {0.4, -0.1, 0.2}, n, 0.05, 1.5));
        members.push_back(point_to_plane_rows(p.weights, {0.1, 0.2, 0.3}, n, 0.7));
        const StencilGroupCost cost(members);
        EXPECT_EQ(cost.num_residuals(), 7);
        std::string log;
        EXPECT_TRUE(gradient_ok(cost, p, &log)) << log;
    }
}

TEST(FitCosts, StencilGroupStacksItsMembers) {
    // The group's residuals are its members' residuals, in order, each as its own cost gives it.
    const Probe p = random_probe(5, 61, false), q = random_probe(5, 62, false);
    const Vec3 n = Vec3{0, 0.6, 0.8};
    std::vector<std::unique_ptr<ceres::CostFunction>> singles;
    singles.emplace_back(tangent_weighted_cost(p.weights, {1, 2, 3}, n, 0.1, 0.5));
    singles.emplace_back(point_to_plane_cost(q.weights, {-1, 0, 2}, n, 3.0));
    const StencilGroupCost group({tangent_weighted_rows(p.weights, {1, 2, 3}, n, 0.1, 0.5),
                                  point_to_plane_rows(q.weights, {-1, 0, 2}, n, 3.0)});
    std::vector<const double*> params;
    for (const auto& x : p.points) params.push_back(x.data());
    double all[4], one[3];
    ASSERT_TRUE(group.Evaluate(params.data(), all, nullptr));
    ASSERT_TRUE(singles[0]->Evaluate(params.data(), one, nullptr));
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(all[k], one[k]);
    ASSERT_TRUE(singles[1]->Evaluate(params.data(), one, nullptr));
    EXPECT_DOUBLE_EQ(all[3], one[0]);
    EXPECT_THROW(StencilGroupCost({point_to_point_rows({1.0}, {0, 0, 0}, 1.0), point_to_point_rows({0.5, 0.5}, {0, 0, 0}, 1.0)}),
                 std::exception);
}

TEST(FitCosts, ResidualsHaveTheirMeaning) {
    // A stencil (0.25, 0.75) on points a, b is the point 0.25 a + 0.75 b.
    const std::array<double, 3> a{0, 0, 0}, b{4, 0, 0};
    const double* params[] = {a.data(), b.data()};
    double r[3];
    std::unique_ptr<ceres::CostFunction> p2p(point_to_point_cost({0.25, 0.75}, {3, 1, 0}, 1.0));
    ASSERT_TRUE(p2p->Evaluate(params, r, nullptr));
    EXPECT_DOUBLE_EQ(r[0], 0.0);
    EXPECT_DOUBLE_EQ(r[1], -1.0);
    std::unique_ptr<ceres::CostFunction> p2l(point_to_plane_cost({0.25, 0.75}, {0, 5, 0}, {1, 0, 0}, 2.0));
    ASSERT_TRUE(p2l->Evaluate(params, r, nullptr));
    EXPECT_DOUBLE_EQ(r[0], 6.0);  // 2 * (3 - 0)
    EXPECT_EQ(p2l->num_residuals(), 1);
}

// A tall group: `count` members (all three kinds) over the blocks of `probe`.
std::vector<StencilRows> tall_group(const Probe& probe, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::vector<StencilRows> members;
    for (int k = 0; k < count; ++k) {
        std::vector<double> w(probe.weights.size());
        for (double& x : w) x = uni(rng);
        const Vec3 p{uni(rng), uni(rng), uni(rng)};
        const Vec3 n = Vec3{uni(rng), uni(rng), 1.0} / norm(Vec3{uni(rng), uni(rng), 1.0});
        if (k % 3 == 0) members.push_back(point_to_point_rows(w, p, 1.5));
        else if (k % 3 == 1) members.push_back(tangent_weighted_rows(w, p, n / norm(n), 0.02, 0.7));
        else members.push_back(point_to_plane_rows(w, p, n / norm(n), 2.0));
    }
    return members;
}

// Residuals r and Jacobian J (rows x 3 blocks, dense) of a cost at the probe's points.
void evaluate_dense(const ceres::CostFunction& cost, const Probe& probe, Eigen::VectorXd* r, Eigen::MatrixXd* j) {
    const int rows = cost.num_residuals(), blocks = static_cast<int>(probe.points.size());
    std::vector<const double*> params;
    for (const auto& p : probe.points) params.push_back(p.data());
    std::vector<std::vector<double>> jac(blocks, std::vector<double>(3 * rows));
    std::vector<double*> jac_ptr;
    for (auto& b : jac) jac_ptr.push_back(b.data());
    r->resize(rows);
    ASSERT_TRUE(cost.Evaluate(params.data(), r->data(), jac_ptr.data()));
    j->resize(rows, 3 * blocks);
    for (int b = 0; b < blocks; ++b)
        for (int row = 0; row < rows; ++row)
            for (int d = 0; d < 3; ++d) (*j)(row, 3 * b + d) = jac[b][3 * row + d];
}

TEST(FitCosts, CompressedGroupGradient) {
    const Probe p = random_probe(16, 71, false);
    const std::vector<StencilRows> members = tall_group(p, 40, 72);
    EXPECT_EQ(StencilGroupCost(members).num_residuals(), 94);
    const std::unique_ptr<ceres::CostFunction> cost = compressed_group_cost(members);
    ASSERT_NE(cost, nullptr);
    EXPECT_EQ(cost->num_residuals(), 48);  // 16 blocks of 3
    std::string log;
    EXPECT_TRUE(gradient_ok(*cost, p, &log)) << log;
}

TEST(FitCosts, CompressedGroupTakesTheSameSteps) {
    // Same J^T J and J^T r at any point, so the same Gauss-Newton / Levenberg-Marquardt step; the
    // sums of squares differ by the same constant everywhere.
    const Probe at = random_probe(6, 81, false), elsewhere = random_probe(6, 82, false);
    const std::vector<StencilRows> members = tall_group(at, 30, 83);
    const StencilGroupCost full(members);
    const std::unique_ptr<ceres::CostFunction> small = compressed_group_cost(members);
    ASSERT_NE(small, nullptr);
    EXPECT_LT(small->num_residuals(), full.num_residuals());
    double offset[2];
    int k = 0;
    for (const Probe* probe : {&at, &elsewhere}) {
        Eigen::VectorXd rf, rs;
        Eigen::MatrixXd jf, js;
        evaluate_dense(full, *probe, &rf, &jf);
        evaluate_dense(*small, *probe, &rs, &js);
        const Eigen::MatrixXd nf = jf.transpose() * jf, ns = js.transpose() * js;
        EXPECT_LT((nf - ns).cwiseAbs().maxCoeff(), 1e-10 * nf.cwiseAbs().maxCoeff());
        const Eigen::VectorXd gf = jf.transpose() * rf, gs = js.transpose() * rs;
        EXPECT_LT((gf - gs).cwiseAbs().maxCoeff(), 1e-10 * (1 + gf.cwiseAbs().maxCoeff()));
        offset[k++] = rf.squaredNorm() - rs.squaredNorm();
    }
    EXPECT_GT(offset[0], 0);
    EXPECT_NEAR(offset[0], offset[1], 1e-9 * offset[0]);
}

TEST(FitCosts, CompressedGroupRefusesASingularGroup) {
    // Block 2 has weight 0 in every member: J^T J is singular and the group stays as it is.
    const Probe p = random_probe(3, 91, false);
    std::vector<StencilRows> members = tall_group(p, 10, 92);
    for (StencilRows& m : members) m.weights[2] = 0;
    EXPECT_EQ(compressed_group_cost(members), nullptr);
}

// The checker itself must catch a wrong Jacobian, or the tests above prove nothing.
class WrongJacobian final : public ceres::CostFunction {
public:
    WrongJacobian() {
        set_num_residuals(3);
        mutable_parameter_block_sizes()->push_back(3);
    }
    bool Evaluate(double const* const* x, double* r, double** j) const override {
        for (int d = 0; d < 3; ++d) r[d] = 2 * x[0][d];
        if (j && j[0])
            for (int k = 0; k < 9; ++k) j[0][k] = (k % 4 == 0) ? 1.0 : 0.0;  // should be 2
        return true;
    }
};

TEST(FitCosts, GradientCheckerRejectsAWrongJacobian) {
    const Probe p = random_probe(1, 5, false);
    std::string log;
    EXPECT_FALSE(gradient_ok(WrongJacobian(), p, &log));
}

}  // namespace
}  // namespace quadcage::fit::detail

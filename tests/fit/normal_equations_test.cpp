// The normal-equation solver of the fit's rounds (src/fit/detail/normal_equations.h) against a
// dense least-squares solve of the same problem.

#include "detail/normal_equations.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "common/blas_threads.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit::detail {
namespace {

// A random sparse least-squares problem: groups over random cliques of 3-vector variables (some
// cliques repeat variables of others, as neighbouring faces share control points), each with its
// own dense rows J_k (rows x 3m) and right-hand side b_k.
struct Problem {
    int num_vars;
    std::vector<std::vector<int>> cliques;
    std::vector<Eigen::MatrixXd> j;
    std::vector<Eigen::VectorXd> b;
};

Problem random_problem(int num_vars, int groups, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    Problem p{num_vars, {}, {}, {}};
    for (int g = 0; g < groups; ++g) {
        // A window of neighbouring variables, so the pattern is banded like a surface's.
        const int m = 2 + static_cast<int>(rng() % 5);
        const int start = static_cast<int>(rng() % (num_vars - m + 1));
        std::vector<int> c;
        for (int k = 0; k < m; ++k) c.push_back(start + k);
        std::shuffle(c.begin(), c.end(), rng);
        std::sort(c.begin(), c.end());
        const int rows = 3 * m + static_cast<int>(rng() % 4);
        Eigen::MatrixXd jk(rows, 3 * m);
        Eigen::VectorXd bk(rows);
        for (int r = 0; r < rows; ++r) {
            for (int q = 0; q < 3 * m; ++q) jk(r, q) = uni(rng);
            bk(r) = uni(rng);
        }
        p.cliques.push_back(c);
        p.j.push_back(jk);
        p.b.push_back(bk);
    }
    // Every variable in some group: one group per variable window of 2 at the end.
    for (int v = 0; v + 1 < num_vars; v += 2) {
        p.cliques.push_back({v, v + 1});
        p.j.push_back(Eigen::MatrixXd::Identity(6, 6));
        p.b.push_back(Eigen::VectorXd::Constant(6, 0.5));
    }
    return p;
}

NormalEquations::GroupNormal group_normal(const Problem& p) {
    return [&p](int k, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtb) {
        jtj.selfadjointView<Eigen::Upper>().rankUpdate(p.j[k].transpose());
        jtb = p.j[k].transpose() * p.b[k];
    };
}

// The dense minimiser of sum |J_k x_k - b_k|^2 (+ damping |D^(1/2) (x - x0)|^2, D = diag(J^T J)).
Eigen::VectorXd dense_solution(const Problem& p, const Eigen::VectorXd& x0, double damping) {
    const int n3 = 3 * p.num_vars;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n3, n3);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n3);
    for (size_t k = 0; k < p.cliques.size(); ++k) {
        // The group's rows spread over all columns, block by block (its other columns are zero).
        const auto& c = p.cliques[k];
        for (size_t a = 0; a < c.size(); ++a) {
            for (size_t b = 0; b < c.size(); ++b)
                h.block(3 * c[a], 3 * c[b], 3, 3) +=
                    p.j[k].middleCols(3 * a, 3).transpose() * p.j[k].middleCols(3 * b, 3);
            g.segment(3 * c[a], 3) += p.j[k].middleCols(3 * a, 3).transpose() * p.b[k];
        }
    }
    Eigen::MatrixXd damped = h;
    damped.diagonal() += damping * h.diagonal();
    return x0 + damped.ldlt().solve(g - h * x0);
}

TEST(NormalEquations, MatchesADenseLeastSquaresSolve) {
    const Problem p = random_problem(40, 60, 1);
    NormalEquations eq(p.num_vars, p.cliques);
    eq.assemble(group_normal(p), 2);
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::vector<double> x0(3 * p.num_vars);
    for (double& v : x0) v = uni(rng);
    const Eigen::VectorXd x0v = Eigen::Map<const Eigen::VectorXd>(x0.data(), x0.size());
    for (double damping : {0.0, 1e-4, 1.0}) {
        std::vector<double> x;
        ASSERT_TRUE(eq.solve(x0, damping, &x));
        const Eigen::VectorXd expected = dense_solution(p, x0v, damping);
        ASSERT_EQ(x.size(), static_cast<size_t>(expected.size()));
        for (size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], expected[i], 1e-9 * (1 + std::abs(expected[i]))) << i;
    }
}

TEST(NormalEquations, RoundsReuseThePatternWithNewValues) {
    // The same pattern, other values: the second assembly replaces the first (the analysis is reused).
    Problem p = random_problem(30, 40, 3);
    NormalEquations eq(p.num_vars, p.cliques);
    std::vector<double> x0(3 * p.num_vars, 0.0), x;
    eq.assemble(group_normal(p), 1);
    ASSERT_TRUE(eq.solve(x0, 0.0, &x));
    for (auto& jk : p.j) jk *= 2.0;
    for (auto& bk : p.b) bk *= 3.0;
    eq.assemble(group_normal(p), 1);
    ASSERT_TRUE(eq.solve(x0, 0.0, &x));
    const Eigen::VectorXd expected = dense_solution(p, Eigen::VectorXd::Zero(x0.size()), 0.0);
    for (size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], expected[i], 1e-9 * (1 + std::abs(expected[i])));
}

TEST(NormalEquations, TheResultDoesNotDependOnTheThreadCount) {
    const Problem p = random_problem(200, 400, 4);
    std::vector<double> x0(3 * p.num_vars, 0.25);
    std::vector<std::vector<double>> out;
    for (int threads : {1, 2, 3, 8}) {
        NormalEquations eq(p.num_vars, p.cliques);
        eq.assemble(group_normal(p), threads);
        out.emplace_back();
        ASSERT_TRUE(eq.solve(x0, 1e-4, &out.back()));
    }
    for (size_t k = 1; k < out.size(); ++k) EXPECT_EQ(out[k], out[0]);
}

TEST(NormalEquations, ManyBatchesSumInGroupOrderOnAnyThreadCount) {
    // More groups than one batch of 512 (the batches are summed by a helper thread while the next
    // is computed): the same bits on 1, 2 and 3 threads, and the dense solution.
    const Problem p = random_problem(300, 1400, 5);
    std::vector<double> x0(3 * p.num_vars, -0.5);
    std::vector<std::vector<double>> out;
    for (int threads : {1, 2, 3}) {
        NormalEquations eq(p.num_vars, p.cliques);
        eq.assemble(group_normal(p), threads);
        out.emplace_back();
        ASSERT_TRUE(eq.solve(x0, 1e-4, &out.back()));
    }
    for (size_t k = 1; k < out.size(); ++k) EXPECT_EQ(out[k], out[0]);
    const Eigen::VectorXd expected =
        dense_solution(p, Eigen::Map<const Eigen::VectorXd>(x0.data(), x0.size()), 1e-4);
    for (size_t i = 0; i < out[0].size(); ++i)
        EXPECT_NEAR(out[0][i], expected[i], 1e-8 * (1 + std::abs(expected[i]))) << i;
}

TEST(NormalEquations, AGroupThatThrowsInALaterBatchIsRethrown) {
    const Problem p = random_problem(300, 1400, 6);
    NormalEquations eq(p.num_vars, p.cliques);
    const NormalEquations::GroupNormal good = group_normal(p);
    for (int threads : {1, 2}) {
        EXPECT_THROW(eq.assemble(
                         [&](int k, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtb) {
                             if (k == 1200) throw quadcage::InvalidInput("group 1200");
                             good(k, jtj, jtb);
                         },
                         threads),
                     quadcage::InvalidInput);
    }
}

TEST(NormalEquations, ASingularSystemIsReportedNotSolved) {
    // Variable 2 appears in a clique whose rows never touch it: H has a zero 3 x 3 block there.
    Problem p{3, {{0, 1}, {1, 2}}, {}, {}};
    p.j.push_back(Eigen::MatrixXd::Identity(6, 6));
    Eigen::MatrixXd j2 = Eigen::MatrixXd::Zero(3, 6);
    j2.leftCols(3) = Eigen::Matrix3d::Identity();
    p.j.push_back(j2);
    p.b = {Eigen::VectorXd::Ones(6), Eigen::VectorXd::Ones(3)};
    NormalEquations eq(p.num_vars, p.cliques);
    eq.assemble(group_normal(p), 1);
    std::vector<double> x;
    EXPECT_FALSE(eq.solve(std::vector<double>(9, 0.0), 1e-4, &x));
}

// OpenBLAS's thread count as the process has it (OPENBLAS_NUM_THREADS, the core count, or a caller's
// openblas_set_num_threads); null when the BLAS is not OpenBLAS.
using SetThreads = void (*)(int);
using GetThreads = int (*)();
SetThreads openblas_set() { return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")); }
GetThreads openblas_get() { return reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")); }

TEST(ScopedBlasThreads, SetsTheCountAndRestoresIt) {
    const SetThreads set = openblas_set();
    const GetThreads get = openblas_get();
    if (!set || !get) GTEST_SKIP() << "the BLAS of this process is not OpenBLAS: there is no thread count to pin";
    set(3);
    {
        const quadcage::detail::ScopedBlasThreads blas(1);
        EXPECT_EQ(get(), 1);
    }
    EXPECT_EQ(get(), 3);
    set(1);
    {
        const quadcage::detail::ScopedBlasThreads blas(2);
        EXPECT_EQ(get(), 2);
    }
    EXPECT_EQ(get(), 1);
}

TEST(ScopedBlasThreads, ScopesOnTwoThreadsTakeTurns) {
    // The layout builds its constructions in threads of their own and scores them with fits
    // meanwhile: a scope asking for 1 thread and one asking for 2 must not see each other's count;
    // two asking for the same count may run together.
    const SetThreads set = openblas_set();
    const GetThreads get = openblas_get();
    if (!set || !get) GTEST_SKIP() << "the BLAS of this process is not OpenBLAS: there is no thread count to pin";
    set(3);
    std::atomic<bool> inside{false};
    std::atomic<int> seen_by_second{-1}, seen_by_third{-1};
    std::thread second, third;
    {
        const quadcage::detail::ScopedBlasThreads one(1);
        second = std::thread([&] {
            inside.store(true);
            const quadcage::detail::ScopedBlasThreads two(2);  // waits for `one` to end
            seen_by_second.store(get());
        });
        third = std::thread([&] {
            const quadcage::detail::ScopedBlasThreads also_one(1);  // runs beside `one`
            seen_by_third.store(get());
        });
        third.join();
        EXPECT_EQ(seen_by_third.load(), 1);
        while (!inside.load()) std::this_thread::yield();
        // The second thread is blocked in its constructor, so the count stays 1 here.
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        EXPECT_EQ(get(), 1);
        EXPECT_EQ(seen_by_second.load(), -1) << "the second scope began inside the first";
        {
            const quadcage::detail::ScopedBlasThreads nested(1);  // a thread may nest its own count
            EXPECT_EQ(get(), 1);
        }
        EXPECT_THROW(quadcage::detail::ScopedBlasThreads other(2), InternalError);  // would wait for itself
    }
    second.join();
    EXPECT_EQ(seen_by_second.load(), 2);
    EXPECT_EQ(get(), 3);
}

TEST(ScopedBlasThreads, TheFitEndsInTheSameBitsWhateverBlasThreadsTheProcessHas) {
    // Before the pin, eight.off fitted at level 3 ended in other bits with OPENBLAS_NUM_THREADS=1
    // than with 2: CHOLMOD's dense kernels round differently on one thread. Here the process's count
    // is 1, 2 or 3 before each fit of the bundled QuadriFlow cage of eight.off (2,000 unknowns).
    const SetThreads set = openblas_set();
    const GetThreads get = openblas_get();
    if (!set || !get) GTEST_SKIP() << "the BLAS of this process is not OpenBLAS: there is no thread count to pin";
    const std::string data = QUADCAGE_DATA_DIR;
    const Mesh mesh = read_mesh(data + "/eight.off");
    const PolygonMesh cage = read_polygon_mesh(data + "/eight_quadriflow.obj");
    FitOptions o;
    o.level = 0;
    o.area_samples = 3000;
    o.error_samples = 20000;
    std::vector<std::vector<Vec3>> points;
    for (int threads : {1, 2, 3}) {
        set(threads);
        points.push_back(fit_control_mesh(mesh, cage, o).fitted_cage.points);
        EXPECT_EQ(get(), threads) << "the fit left OpenBLAS on another thread count";
    }
    for (size_t k = 1; k < points.size(); ++k) {
        ASSERT_EQ(points[k].size(), points[0].size());
        for (size_t i = 0; i < points[0].size(); ++i)
            for (int d = 0; d < 3; ++d) ASSERT_EQ(points[k][i][d], points[0][i][d]) << "control point " << i;
    }
}

}  // namespace
}  // namespace quadcage::fit::detail

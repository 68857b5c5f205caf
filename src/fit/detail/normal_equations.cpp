#include "detail/normal_equations.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <algorithm>
#include <future>
#include <string>

#include "common/blas_threads.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::fit::detail {

namespace {

/// Factorisations of fewer flops (CHOLMOD's count after the analysis) run their BLAS on one thread.
constexpr double kThreadedBlasFlops = 1e9;

}  // namespace

struct NormalEquations::Factor {
    Eigen::SparseMatrix<double> h;  ///< Upper triangle of H (the pattern; values per round).
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt;
    bool analysed = false;
};

NormalEquations::NormalEquations(int num_vars, std::vector<std::vector<int>> cliques)
    : num_vars_(num_vars), cliques_(std::move(cliques)), factor_(std::make_unique<Factor>()) {
    QC_CHECK(num_vars_ > 0, "NormalEquations: no variables");
    // A matrix that is not positive definite is an expected outcome (solve() returns false and the
    // caller raises the damping): no CHOLMOD warning on stderr.
    factor_->llt.cholmod().print = 0;
    // Block rows I <= J of every block column J.
    std::vector<std::vector<int>> rows_of(num_vars_);
    for (auto& c : cliques_) {
        QC_CHECK(!c.empty(), "NormalEquations: empty clique");
        std::sort(c.begin(), c.end());
        QC_CHECK(c.front() >= 0 && c.back() < num_vars_, "NormalEquations: variable out of range");
        QC_CHECK(std::adjacent_find(c.begin(), c.end()) == c.end(), "NormalEquations: repeated variable");
        for (size_t b = 0; b < c.size(); ++b)
            for (size_t a = 0; a <= b; ++a) rows_of[c[b]].push_back(c[a]);
    }
    for (int j = 0; j < num_vars_; ++j) {
        auto& r = rows_of[j];
        r.push_back(j);  // a variable no group uses still gets its diagonal (the solve then fails)
        std::sort(r.begin(), r.end());
        r.erase(std::unique(r.begin(), r.end()), r.end());
    }
    const int n3 = 3 * num_vars_;
    Eigen::SparseMatrix<double>& h = factor_->h;
    h.resize(n3, n3);
    std::vector<int> nnz_per_column(n3);
    for (int j = 0; j < num_vars_; ++j)
        for (int e = 0; e < 3; ++e) nnz_per_column[3 * j + e] = 3 * (static_cast<int>(rows_of[j].size()) - 1) + e + 1;
    h.reserve(nnz_per_column);
    for (int j = 0; j < num_vars_; ++j)
        for (int e = 0; e < 3; ++e) {
            const int col = 3 * j + e;
            for (int i : rows_of[j])
                for (int d = 0; d < 3 && (i < j || d <= e); ++d) h.insert(3 * i + d, col) = 0.0;
        }
    h.makeCompressed();
    const int* outer = h.outerIndexPtr();
    diagonal_.resize(n3);
    for (int j = 0; j < num_vars_; ++j)
        for (int e = 0; e < 3; ++e) diagonal_[3 * j + e] = outer[3 * j + e] + 3 * (static_cast<int>(rows_of[j].size()) - 1) + e;
    // Where each pair of a clique's variables lies in its block column.
    block_offset_.resize(cliques_.size());
    for (size_t k = 0; k < cliques_.size(); ++k) {
        const auto& c = cliques_[k];
        auto& off = block_offset_[k];
        off.reserve(c.size() * (c.size() + 1) / 2);
        for (size_t b = 0; b < c.size(); ++b)
            for (size_t a = 0; a <= b; ++a) {
                const auto& r = rows_of[c[b]];
                off.push_back(static_cast<int>(std::lower_bound(r.begin(), r.end(), c[a]) - r.begin()));
            }
    }
    rhs_.assign(n3, 0.0);
}

NormalEquations::~NormalEquations() = default;

void NormalEquations::assemble(const GroupNormal& group, int threads) {
    Eigen::SparseMatrix<double>& h = factor_->h;
    double* values = h.valuePtr();
    const int* outer = h.outerIndexPtr();
    std::fill(values, values + h.nonZeros(), 0.0);
    std::fill(rhs_.begin(), rhs_.end(), 0.0);
    // Batches: the dense blocks in parallel, then summed in group order, by a helper thread while
    // the next batch's blocks are computed (two sets of blocks in turn). The sums are the same
    // whatever the thread count: one thread adds every batch, in order.
    const int num_groups = static_cast<int>(cliques_.size());
    constexpr int kBatch = 512;
    std::vector<Eigen::MatrixXd> jtj[2] = {std::vector<Eigen::MatrixXd>(kBatch),
                                           std::vector<Eigen::MatrixXd>(kBatch)};
    std::vector<Eigen::VectorXd> jtb[2] = {std::vector<Eigen::VectorXd>(kBatch),
                                           std::vector<Eigen::VectorXd>(kBatch)};
    auto sum = [&](int begin, int count, int set) {
        for (int i = 0; i < count; ++i) {
            const auto& c = cliques_[begin + i];
            const auto& off = block_offset_[begin + i];
            const Eigen::MatrixXd& a = jtj[set][i];
            size_t p = 0;
            for (size_t b = 0; b < c.size(); ++b)
                for (size_t q = 0; q <= b; ++q, ++p) {
                    const int col0 = 3 * c[b], base = 3 * off[p];
                    for (int e = 0; e < 3; ++e) {
                        double* out = values + outer[col0 + e] + base;
                        const int dmax = q < b ? 3 : e + 1;
                        for (int d = 0; d < dmax; ++d) out[d] += a(3 * q + d, 3 * b + e);
                    }
                }
            for (size_t v = 0; v < c.size(); ++v)
                for (int d = 0; d < 3; ++d) rhs_[3 * c[v] + d] += jtb[set][i](3 * v + d);
        }
    };
    const bool helper = resolve_threads(threads) > 1;
    std::future<void> summing;  // joins in its destructor if a group throws
    for (int begin = 0, set = 0; begin < num_groups; begin += kBatch, set ^= 1) {
        const int count = std::min(kBatch, num_groups - begin);
        parallel_for(count, threads, [&](int i) {
            const int m3 = 3 * static_cast<int>(cliques_[begin + i].size());
            jtj[set][i].setZero(m3, m3);
            jtb[set][i].setZero(m3);
            group(begin + i, jtj[set][i], jtb[set][i]);
        });
        if (summing.valid()) summing.get();  // the previous batch, from the other set
        if (helper)
            summing = std::async(std::launch::async, sum, begin, count, set);
        else
            sum(begin, count, set);
    }
    if (summing.valid()) summing.get();
}

bool NormalEquations::solve(const std::vector<double>& x, double damping, std::vector<double>* out) {
    const int n3 = 3 * num_vars_;
    QC_CHECK(static_cast<int>(x.size()) == n3, "NormalEquations::solve: wrong size");
    Factor& f = *factor_;
    const Eigen::Map<const Eigen::VectorXd> x0(x.data(), n3);
    Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(rhs_.data(), n3);
    r.noalias() -= f.h.selfadjointView<Eigen::Upper>() * x0;
    double* values = f.h.valuePtr();
    std::vector<double> diag(n3);
    for (int i = 0; i < n3; ++i) {
        diag[i] = values[diagonal_[i]];
        values[diagonal_[i]] += damping * diag[i];
    }
    if (!f.analysed) {
        f.llt.analyzePattern(f.h);  // the ordering only: no BLAS
        f.analysed = true;
    }
    // A small factorisation runs its BLAS on one thread: a second thread saves it little, and
    // OpenBLAS's worker then spins for a while after every call, on a core the fit's own threads need
    // next (on botijo, a level-1 factorisation is 1e7 flops and its level 3's 2e9).
    const quadcage::detail::ScopedBlasThreads blas(
        f.llt.cholmod().fl < kThreadedBlasFlops ? 1 : quadcage::detail::kBlasThreads);
    f.llt.factorize(f.h);
    bool ok = f.llt.info() == Eigen::Success;
    Eigen::VectorXd step;
    if (ok) {
        step = f.llt.solve(r);
        ok = f.llt.info() == Eigen::Success && step.allFinite();
    }
    for (int i = 0; i < n3; ++i) values[diagonal_[i]] = diag[i];
    if (!ok) return false;
    out->resize(n3);
    for (int i = 0; i < n3; ++i) (*out)[i] = x[i] + step[i];
    return true;
}

}  // namespace quadcage::fit::detail

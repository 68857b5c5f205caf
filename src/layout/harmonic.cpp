#include "detail/harmonic.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/blas_threads.h"
#include "detail/patches.h"

namespace quadcage::layout::detail {

CotangentWeights::CotangentWeights(const Mesh& mesh)
    : mesh_(mesh),
      w_(3 * static_cast<size_t>(mesh.num_triangles()), std::numeric_limits<double>::quiet_NaN()) {}

double CotangentWeights::operator()(int t, int k) {
    double& w = w_[3 * static_cast<size_t>(t) + k];
    if (std::isnan(w)) {
        const Triangle& tri = mesh_.triangles[t];
        w = std::max(half_cotangent(mesh_, tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]), 0.025);
    }
    return w;
}

bool harmonic_extension(CotangentWeights& weight, const std::vector<int>& tris, const std::vector<int>& slot,
                        int m, int cols, const std::function<double(int, int)>& fixed, Eigen::MatrixXd* x,
                        HarmonicSolver solver) {
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, cols);
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(m);
    for (size_t f = 0; f < tris.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const double w = weight(tris[f], k);
            const int li = slot[3 * f + k], lj = slot[3 * f + (k + 1) % 3];
            const bool fi = li < m, fj = lj < m;
            if (fi) diagonal[li] += w;
            if (fj) diagonal[lj] += w;
            if (fi && fj) {
                entries.emplace_back(li, lj, -w);
                entries.emplace_back(lj, li, -w);
            } else if (fi) {
                for (int c = 0; c < cols; ++c) rhs(li, c) += w * fixed(lj - m, c);
            } else if (fj) {
                for (int c = 0; c < cols; ++c) rhs(lj, c) += w * fixed(li - m, c);
            }
        }
    }
    for (int i = 0; i < m; ++i) entries.emplace_back(i, i, diagonal[i]);
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(entries.begin(), entries.end());
    if (solver == HarmonicSolver::Simplicial) {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
        if (ldlt.info() != Eigen::Success) return false;
        *x = ldlt.solve(rhs);
        return true;
    }
    // AMD's ordering alone: trying METIS's as well, as the embedding's Newton steps do, made each
    // solve of a 40k-vertex genus-1 body 0.33 s instead of 0.15 s. One BLAS thread, so the bits do
    // not depend on the machine's core count (blas_threads.h).
    const quadcage::detail::ScopedBlasThreads blas(1);
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
    llt.cholmod().print = 0;
    llt.cholmod().nmethods = 1;
    llt.cholmod().method[0].ordering = CHOLMOD_AMD;
    llt.compute(A);
    if (llt.info() != Eigen::Success) return false;
    *x = llt.solve(rhs);
    return llt.info() == Eigen::Success;
}

}  // namespace quadcage::layout::detail

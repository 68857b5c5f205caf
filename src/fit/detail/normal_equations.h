#pragma once
// The fit's rounds as linear least-squares problems solved through their normal equations
// (private to src/fit).
//
// With the feet of the data points fixed, a round's residuals are affine in the control points:
// one Gauss-Newton step solves it. Ceres took that step as one Levenberg-Marquardt iteration and,
// since every round was a new ceres::Problem, redid the whole preprocessing each time: the block
// structure of J^T J and CHOLMOD's symbolic analysis (fill-reducing ordering, supernodes). The
// sparsity of a level's rounds never changes (a face's residuals always use the control points of
// that face's stencil), so here the analysis is done once per level and a round only assembles
// the values, factorises and solves.

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <vector>

namespace quadcage::fit::detail {

/// Normal equations H x = g of min sum_k |J_k x_k - b_k|^2 over n 3-vectors x_v, where residual
/// group k uses the variables cliques[k] only. H is block-sparse with 3 x 3 blocks; its pattern is
/// the union of the cliques' blocks and is fixed at construction.
class NormalEquations {
public:
    /// cliques[k]: the variables of group k, distinct, each in [0, num_vars).
    /// \throw InvalidInput (internal misuse) if a clique is empty or out of range.
    NormalEquations(int num_vars, std::vector<std::vector<int>> cliques);
    ~NormalEquations();
    NormalEquations(const NormalEquations&) = delete;
    NormalEquations& operator=(const NormalEquations&) = delete;

    int num_vars() const { return num_vars_; }
    const std::vector<int>& clique(int k) const { return cliques_[k]; }

    /// The dense J_k^T J_k (3m x 3m, m = |cliques[k]|, variables in the clique's sorted order,
    /// coordinates innermost) and J_k^T b_k of group k, written into jtj / jtb (already sized and
    /// zeroed). A group without residuals leaves them zero.
    using GroupNormal = std::function<void(int k, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtb)>;

    /// H and g from every group: the dense blocks computed in parallel on `threads` threads, summed
    /// in group order (the result does not depend on the thread count).
    void assemble(const GroupNormal& group, int threads);

    /// The Levenberg-Marquardt step from x: solves (H + damping diag(H)) d = g - H x and returns
    /// x + d (3n values, variable-major). False if the damped H is not positive definite.
    /// The first call analyses the pattern (CHOLMOD: ordering, supernodes); later calls reuse it.
    bool solve(const std::vector<double>& x, double damping, std::vector<double>* out);

private:
    struct Factor;
    int num_vars_;
    std::vector<std::vector<int>> cliques_;  ///< Sorted.
    // H's upper triangle, compressed sparse columns (3n x 3n): block column J holds the blocks
    // (I, J), I <= J in the pattern, in increasing I; the diagonal block keeps its upper part.
    std::vector<int> outer_, inner_;
    std::vector<double> values_, rhs_;
    std::vector<int> diagonal_;                     ///< Position of H(i, i) in values_.
    std::vector<std::vector<int>> block_offset_;    ///< Per clique, per pair a <= b: k of block row in column.
    std::unique_ptr<Factor> factor_;
};

}  // namespace quadcage::fit::detail

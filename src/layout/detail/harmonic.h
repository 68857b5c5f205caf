#pragma once
// Harmonic extension over a set of triangles with clamped cotangent weights: the solve the
// relaxation (relax.cpp) and the torus's level fields (pieces.cpp) share. Private to src/layout.

#include <Eigen/Dense>
#include <functional>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::layout::detail {

/// The clamped cotangent weight of each half-edge, computed when first asked for: a relaxation pass
/// solves on overlapping regions of one surface (each patch in several), which share them.
class CotangentWeights {
public:
    explicit CotangentWeights(const Mesh& mesh);
    /// max(half_cotangent(corner k, corner k+1, corner k+2 of triangle t), 0.025).
    double operator()(int t, int k);

private:
    const Mesh& mesh_;
    std::vector<double> w_;
};

/// How harmonic_extension() factorises: Eigen's simplicial LDLT (the relaxation's smaller regions) or
/// CHOLMOD's supernodal LLT (the relaxation's regions of 20k unknowns or more, harmonic_across()'s
/// whole surface).
enum class HarmonicSolver { Simplicial, Supernodal };

/// The harmonic extension over the triangles `tris`, whose corners have ids slot[3 i + k] (corner k
/// of tris[i]): ids below m are the free unknowns (row id of *x), an id m + b is fixed at
/// fixed(b, col) in each of the `cols` columns. A vertex may so have several ids (a star whose
/// boundary meets itself, or a curve the triangles lie on both sides of). Clamped cotangent weights:
/// positive, so the system is SPD, the extension obeys the maximum principle, and on a convex
/// boundary it is a Tutte embedding. False if the factorisation fails.
bool harmonic_extension(CotangentWeights& weight, const std::vector<int>& tris, const std::vector<int>& slot,
                        int m, int cols, const std::function<double(int, int)>& fixed, Eigen::MatrixXd* x,
                        HarmonicSolver solver = HarmonicSolver::Simplicial);

}  // namespace quadcage::layout::detail

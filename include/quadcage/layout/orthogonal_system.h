#pragma once
// Orthogonal system of cycles (paper §2: Definition 6, Lemma 3, Theorem 1; Corollary 1).

#include <functional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::layout {

/// A closed walk along mesh edges: vertex indices, first vertex not repeated at the end.
using Cycle = std::vector<int>;

/// Options for build_orthogonal_system().
struct OrthogonalSystemOptions {
    int root_samples = 24;        ///< Roots (farthest-point samples) tried for each shortest non-separating loop.
    int crossing_candidates = 8;  ///< Crossing vertices tried on a curve for each new crossing curve.
    double repulsion = 8.0;       ///< Path cost multiplier near existing curves: len*(1 + repulsion*exp(-d/sigma)); 0 = plain shortest paths.
    double repulsion_radius = 0.05;  ///< sigma, as a fraction of sqrt(surface area).
    int max_genus = 64;           ///< Larger genus is rejected (homology classes are 128-bit).
    std::function<void(const std::string&)> progress;  ///< Called with a short message per stage; may be empty.
    std::string validate() const; ///< Empty if valid, else what is wrong.
};

/// The result: the refined surface and the 2g cycles on it, in chain order
/// (a1, b1, c1, b2, c2, ..., c(g-1), bg: consecutive cycles cross once, the others are disjoint).
struct OrthogonalSystem {
    Mesh mesh;                    ///< Refined copy of the input: its first input_vertices points are the input's.
    int input_vertices = 0;
    int genus = 0;
    std::vector<Cycle> cycles;    ///< 2g cycles of `mesh` vertex indices.
    /// Length of the shortest non-separating loop of each handle (the greedy homology basis
    /// a1..ag before the chain is built), ascending: a tiny value flags a tunnel from scan noise.
    std::vector<double> handle_lengths;
    /// The g disjoint handle loops a1..ag the chain was built from (a1 is cycles[0]), in chain order,
    /// on `mesh`: short loops round the handles' tubes, independent in homology.
    std::vector<Cycle> handle_loops;
    int refinement_splits = 0;    ///< Edges split to make room for curves.
};

/// Builds an orthogonal system of 2g cycles on a closed, connected, orientable manifold triangle
/// mesh of genus g (no cycles for g = 0). Route of design.md §4: greedy shortest non-separating
/// loops a1..ag (tree-cotree homology masks), ordered along a shortest Hamiltonian path; b_i
/// crossing a_i once; c_i joining b_i and b(i+1); chords split for room. The chain is built in
/// both directions (two threads) and the shorter system kept. Deterministic.
/// \pre mesh is closed, connected, manifold, consistently oriented (core::validate(), orient_outward()).
/// \throw InvalidInput if the precondition fails or the genus exceeds options.max_genus.
OrthogonalSystem build_orthogonal_system(const Mesh& mesh, const OrthogonalSystemOptions& options = {});

/// Checks Definition 6 and Corollary 1 combinatorially: 2g simple closed walks along edges;
/// consecutive cycles share exactly one vertex where they cross (edges alternate around it);
/// others are disjoint; each cycle alone and all together leave the surface connected; the union
/// is a cutting graph (chi = 1 - 2g). For genus 0 only the empty system passes.
/// Returns "" if all hold, else what fails.
/// \pre mesh is closed, connected, manifold and consistently oriented.
std::string verify_orthogonal_system(const Mesh& mesh, const std::vector<Cycle>& cycles);

/// Total length of a cycle.
double cycle_length(const Mesh& mesh, const Cycle& cycle);

}  // namespace quadcage::layout

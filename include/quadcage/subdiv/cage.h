#pragma once
// The level-0 quad cage of a layout, with explicit edges, and its first Catmull-Clark step
// (design.md §3).

#include <array>
#include <utility>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::subdiv {

/// A closed quad cage that may have multi-edges (two edges joining the same two corners) and quads
/// with the same corner set, as the 10g-10 layout of the paper has (design.md §3). A face-vertex
/// list cannot describe it; edges are explicit here.
///
/// Conventions: side k of quad q runs from corners[k] to corners[k+1 mod 4] and lies on edge
/// edges[k]; quads are counter-clockwise seen from outside, so each edge is walked once in each
/// direction by its two (quad, side) uses.
struct Cage {
    struct Edge {
        std::array<int, 2> corners{};  ///< Its two end corners (distinct).
        std::array<int, 2> quads{};    ///< The two quads it borders (may be the same quad only if
                                       ///< sides differ; never the case in a valid layout).
        std::array<int, 2> sides{};    ///< Which side (0..3) of quads[i] it is.
    };
    struct Quad {
        std::array<int, 4> corners{};  ///< Counter-clockwise seen from outside.
        std::array<int, 4> edges{};    ///< edges[k] joins corners[k] and corners[k+1 mod 4].
    };
    std::vector<Vec3> points;  ///< One position per corner.
    std::vector<Edge> edges;   ///< Explicit edges (a multi-edge is two entries with the same corners).
    std::vector<Quad> quads;   ///< One per layout patch, in patch order.

    int num_corners() const { return static_cast<int>(points.size()); }
    int num_edges() const { return static_cast<int>(edges.size()); }
    int num_quads() const { return static_cast<int>(quads.size()); }
};

/// Checks that `cage` is a closed oriented quad surface: indices in range; each quad's 4 corners
/// distinct; edges[k] of a quad joins corners[k] and corners[k+1]; every edge is used by exactly its
/// two recorded (quad, side) pairs, once in each direction; around every corner the quads form one
/// cycle (a disk, not a pinch); every corner is used. Returns an empty string if valid, else what is
/// wrong (the first problem found, naming the index).
std::string check_cage(const Cage& cage);

/// A sparse linear combination: sum of weight * point[index].
using Stencil = std::vector<std::pair<int, double>>;

/// The result of one Catmull-Clark step on a Cage.
struct CageRefinement {
    /// Level-1 control mesh: a simple closed quad mesh (no multi-edges) with the same limit surface.
    /// Points: cage corners first (same order), then one per cage edge (same order), then one per
    /// cage quad (same order): V + E + F points. Quads: 4 per cage quad, quad 4q+k is the child of
    /// cage quad q at its corner k, listed in the parent's orientation (the child at corner 0 is
    /// corner0, edge point of side 0, face point, edge point of side 3; see to_child()), the same
    /// convention as refine_uniform().
    QuadMesh level1;
    /// level1.points[i] = sum over stencils[i] of weight * cage.points[index]. Weights sum to 1.
    std::vector<Stencil> stencils;
};

/// One Catmull-Clark step (Catmull & Clark 1978) on the explicit-edge cage.
/// \throw InvalidInput if check_cage() reports a problem.
CageRefinement refine_cage(const Cage& cage);

/// Checks that `cage` is a closed, oriented 2-manifold polygon mesh: finite points; every face has
/// >= 3 distinct corners in range; every vertex is used; every edge has exactly two faces that walk
/// it in opposite directions; the faces around every vertex form one fan. Returns an empty string
/// if so, else the first problem found as a phrase, counting vertices and faces from 1 in file order
/// ("it is open: the edge between the 4th vertex and 8th vertex has one face ...").
std::string check_polygon_cage(const PolygonMesh& cage);

/// One Catmull-Clark step on a closed polygon mesh (any face sizes): a simple closed quad mesh with
/// the same limit surface. level1 points: the cage's vertices first (same order), then one per edge
/// (in order of first use walking the faces), then one per face. A face with n corners has n
/// consecutive children; a quad's children follow refine_cage()'s quadrant convention (child 4q+k,
/// so to_child() holds for all-quad cages), child k of any other face is (corner k, edge point of
/// side k, face point, edge point of side k-1). stencils as in refine_cage().
/// \throw InvalidInput if check_polygon_cage() reports a problem.
CageRefinement refine_polygon_cage(const PolygonMesh& cage);

/// A point on a face of a quad control mesh: face index and its (u, v) in [0,1]^2, corner k of the
/// face at (0,0), (1,0), (1,1), (0,1) for k = 0..3 (OpenSubdiv's quad parameterisation).
struct FacePoint {
    int face = -1;  ///< Face index (-1: none).
    double u = 0;   ///< In [0, 1].
    double v = 0;   ///< In [0, 1].
};

/// The same surface point on the next refinement level (refine_cage() or refine_uniform() with one
/// more level): face 4f+k where k is the quadrant of (u, v), coordinates scaled by 2.
FacePoint to_child(const FacePoint& p);

/// to_child() applied `levels` times.
FacePoint descend(FacePoint p, int levels);

}  // namespace quadcage::subdiv

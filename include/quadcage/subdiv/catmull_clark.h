#pragma once
// Catmull-Clark refinement and limit positions of simple quad cages, through OpenSubdiv's Far API
// (design.md §3, §5).

#include <array>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::subdiv {

/// A polygon mesh whose faces are all quads, counter-clockwise seen from outside.
///
/// The functions here accept only *simple* quad meshes: every quad has 4 distinct vertices, no
/// edge is used twice in the same direction (so an edge has at most 2 quads, consistently oriented)
/// and every point is used by a quad.
/// The level-0 cage of a 10g-10 layout has multi-edges and cannot be written this way; refine it
/// once on its own half-edge structure first (design.md §3) and hand the level-1 cage here.
/// Open boundaries are allowed (their edges stay sharp, see refine_uniform()).
struct QuadMesh {
    std::vector<Vec3> points;
    std::vector<std::array<int, 4>> quads;

    int num_vertices() const { return static_cast<int>(points.size()); }
    int num_quads() const { return static_cast<int>(quads.size()); }
};

/// Largest number of uniform refinement levels the functions below accept.
constexpr int kMaxRefinementLevel = 8;

/// Uniform Catmull-Clark refinement, `levels` times (Catmull & Clark 1978; OpenSubdiv `Far`,
/// scheme CATMARK, smooth, boundary interpolation EDGE_ONLY). Returns the level-`levels` control
/// mesh: 4^levels * cage.num_quads() quads, in OpenSubdiv's order (children of quad f are
/// consecutive, the same corner order as f), and its points. levels = 0 returns a copy of the cage.
/// \pre cage is a simple quad mesh (see QuadMesh) with finite points.
/// \throw InvalidInput if levels is outside [0, kMaxRefinementLevel], the cage is empty, an index is
///        out of range, a quad repeats a vertex, an edge is used twice in the same direction
///        (multi-edge, non-manifold edge or inconsistent orientation), a point is unused or not
///        finite, or the result would have more than 2^28 quads.
QuadMesh refine_uniform(const QuadMesh& cage, int levels);

/// The limit-surface positions of the vertices of refine_uniform(cage, levels), in the same order
/// (OpenSubdiv `PrimvarRefiner::Limit`). Vertex i of the refined mesh converges to element i as
/// refinement continues; vertices that are children of a cage vertex come first, so element i of
/// limit_positions(cage, 0) equals element i of limit_positions(cage, k) for every k.
/// \pre and \throw as refine_uniform().
std::vector<Vec3> limit_positions(const QuadMesh& cage, int levels);

/// OBJ text of a quad mesh: a `# comment` line, `v` lines with 17 significant digits (coordinates
/// read back bit-identical), `f` lines with 4 one-based indices. No checks: the level-0 cage of a
/// layout (multi-edges) is written this way too, for people and checkers.
std::string quad_obj_text(const QuadMesh& mesh, const std::string& comment);

/// The same for a polygon mesh (`f` lines with each face's one-based indices).
std::string polygon_obj_text(const PolygonMesh& mesh, const std::string& comment);

/// Run-time proof that OpenSubdiv links and works: "OpenSubdiv v3_5_0 (cube refined: 24 faces)",
/// where the face count comes from refining a cube at run time.
std::string opensubdiv_version();

}  // namespace quadcage::subdiv

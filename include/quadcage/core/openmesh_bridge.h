#pragma once
// Reading polygon meshes through OpenMesh, to cross-check what quadcage writes with an independent
// half-edge library (e.g. that a level-1 cage is a closed manifold quad mesh).

#include <string>

#include "quadcage/core/mesh.h"

namespace quadcage {

/// What OpenMesh made of a polygon mesh file.
struct PolygonMeshSummary {
    int vertices = 0;
    int faces = 0;
    int edges = 0;
    int boundary_edges = 0;
    int min_face_valence = 0;
    int max_face_valence = 0;
    int isolated_vertices = 0;
    /// Has faces and no boundary edge.
    bool closed() const { return faces > 0 && boundary_edges == 0; }
    /// Has faces, all of them quads.
    bool all_quads() const { return faces > 0 && min_face_valence == 4 && max_face_valence == 4; }
    /// V - E + F.
    int euler_characteristic() const { return vertices - edges + faces; }
};

/// Reads `path` with OpenMesh's own reader (OBJ, OFF, PLY, STL). OpenMesh's half-edge kernel
/// refuses faces that would make the mesh non-manifold, so a file whose face count differs from
/// `faces` was not a manifold polygon mesh.
/// \throw InvalidInput if OpenMesh cannot read the file.
PolygonMeshSummary read_with_openmesh(const std::string& path);

/// `mesh` decimated to `vertices` vertices, or as near as its collapses go, for a coarser copy of
/// the same surface to build on (QuadLayoutOptions::proxy_vertices). In rounds, its edges shortest
/// first are collapsed to their midpoints through OpenMesh's half-edge kernel, skipping a collapse
/// that breaks the link condition (is_collapse_ok: a closed manifold keeps its genus), turns a
/// triangle by more than 60 degrees or takes its area, or touches a vertex that a collapse of the
/// same round moved. Deterministic. (OpenMesh's own quadric decimater took 1.5 s on botijo's 41k
/// vertices and 34 s on 658k: it updates a heap at every collapse.)
/// \pre mesh is a closed, oriented manifold triangle mesh.
/// \throw InvalidInput if vertices < 4 or OpenMesh refuses a triangle of mesh.
Mesh decimated(const Mesh& mesh, int vertices);

/// OpenMesh's version, read from the linked library's headers, with a run-time round trip through
/// its half-edge kernel (proves the library links).
std::string openmesh_version();

}  // namespace quadcage

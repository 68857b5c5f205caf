#pragma once
// The peer of `quadcage bench`: QuadriFlow (through Blender) remeshes the same input, and the
// polygon mesh it returns is checked here before our fitter fits it as a control mesh.

#include <optional>
#include <string>

namespace quadcage::bench {

/// Counts of a polygon mesh (faces kept as polygons, not triangulated).
struct PolygonMeshStats {
    int vertices = 0;            ///< Vertices used by at least one face.
    int edges = 0;               ///< Distinct undirected edges.
    int faces = 0;
    int quads = 0;               ///< Faces with 4 corners.
    int components = 0;          ///< Connected components (through shared vertices).
    int euler_characteristic = 0;  ///< V - E + F.
    std::optional<int> genus;    ///< (2 * components - chi) / 2 when that is a whole number >= 0.
    int irregular_vertices = 0;  ///< Used vertices whose number of distinct edge neighbours is not 4.
    int boundary_edges = 0;      ///< Edges used by exactly one face (an open surface).
    int nonmanifold_edges = 0;   ///< Edges used by three or more faces.
    int misoriented_edges = 0;   ///< Edges of two faces that run along them in the same direction.
    int degenerate_faces = 0;    ///< Faces with a repeated vertex.
    /// Every edge used by exactly two faces, in opposite directions, and no face degenerate.
    bool closed_manifold() const {
        return faces > 0 && boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 &&
               degenerate_faces == 0;
    }
};

/// Reads the `v` and `f` statements of an OBJ file (faces as polygons; `v/vt/vn` and negative
/// indices accepted) and counts. An OBJ without faces gives all zeros (faces == 0).
/// \throw InvalidInput if the file cannot be read or a face index is out of range or malformed.
PolygonMeshStats polygon_obj_stats(const std::string& path);

/// Why a remesh with statistics `st` cannot be the peer's control mesh of an input with `genus`
/// (summed over its components) and `components` components; "" if it can: at least one face, all
/// quads, closed, manifold and consistently oriented (see closed_manifold()), of that genus and
/// component count. The reasons read "empty output (no faces)", "not all quads (12 of 600 faces are
/// not)", "open (8 boundary edges)", "wrong genus 1 (input 2)", ...
std::string peer_cage_problem(const PolygonMeshStats& st, int genus, int components);

}  // namespace quadcage::bench

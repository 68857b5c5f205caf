#pragma once
// The peer column of `quadcage bench`: QuadriFlow (through Blender) remeshing the same input, and
// the statistics of the polygon mesh it returns.

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
};

/// Reads the `v` and `f` statements of an OBJ file (faces as polygons; `v/vt/vn` and negative
/// indices accepted) and counts. An OBJ without faces gives all zeros (faces == 0).
/// \throw InvalidInput if the file cannot be read or a face index is out of range or malformed.
PolygonMeshStats polygon_obj_stats(const std::string& path);

}  // namespace quadcage::bench

#pragma once
// What `quadcage info` reports about a mesh file.

#include <string>

#include "quadcage/core/io.h"
#include "quadcage/core/validate.h"

namespace quadcage {

/// A mesh file as read and validated: the report of `quadcage info`.
struct MeshInfo {
    std::string file;             ///< The file as the user named it.
    LoadInfo load;                ///< What read_mesh() found (format, polygons split, ...).
    ValidationReport validation;  ///< validate() of the mesh read.

    /// The report as pretty-printed JSON (2-space indent, keys in alphabetical order, a final
    /// newline): file, format, vertices, vertices_in_file, unused_vertices, triangles,
    /// polygons_split, welded_vertices, bbox_diagonal, quaddable, counts {...}, components [{index,
    /// vertices, triangles, edges, closed, manifold, orientable, consistently_oriented,
    /// boundary_loops, boundary_edges, non_manifold_edges, non_manifold_vertices,
    /// euler_characteristic, area, volume, degenerate, genus, minimal_quads}], minimal_quads (the
    /// sum, null unless every component has one), issues [{severity, code, count, message}].
    /// Undefined figures (genus, minimal_quads) and non-finite numbers (a mesh with NaN
    /// coordinates) are null. Deterministic. Never throws but std::bad_alloc.
    std::string to_json() const;
};

}  // namespace quadcage

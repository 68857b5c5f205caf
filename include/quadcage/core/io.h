#pragma once
// Reading and writing triangle meshes.

#include <string>

#include "quadcage/core/mesh.h"

namespace quadcage {

/// What a reader found besides the mesh (for reports and validation).
struct LoadInfo {
    std::string format;          ///< "obj", "ply-ascii", "ply-binary-le", "ply-binary-be", "off", "stl-ascii", "stl-binary".
    int polygons_split = 0;      ///< Faces with more than 3 corners that were fan-triangulated.
    int welded_vertices = 0;     ///< STL: corners merged into an earlier vertex with bit-identical coordinates (-0 = +0).
    int dropped_faces = 0;       ///< Faces with fewer than 3 corners (ignored).
};

/// Reads an OBJ (`v`, `f` with `v`, `v/vt`, `v//vn`, `v/vt/vn`, negative indices), PLY (ascii and
/// binary of either endianness; `face` or `tristrips` connectivity, unknown elements skipped), OFF
/// (also COFF/NOFF) or STL (ascii and binary; corners with identical coordinates welded) file.
/// The format is recognised by the file's content (PLY magic, binary STL size, `solid`, `OFF`, OBJ
/// statements); the extension only decides when the content does not. Polygons are
/// fan-triangulated and faces with fewer than 3 corners dropped (both counted in `info`). OFF, PLY
/// and STL indices are kept as written (0-based) even when out of range: validate() reports them;
/// an OBJ index that names no vertex is an error reported in the file's own numbering (1-based or
/// negative, with its line). Only regular files are read (not directories, devices or FIFOs), and
/// the work is bounded by the file's size whatever counts its header declares.
/// \throw InvalidInput if the path is not a regular file, cannot be opened, is empty, has no
///        triangles, is truncated or malformed (including a count larger than the rest of the file
///        can hold), or has an unknown format; the message names the file and the line or element.
Mesh read_mesh(const std::string& path, LoadInfo* info = nullptr);

/// Reads a mesh file like read_mesh() but keeps its polygons (a control cage of quads or any
/// polygons: `quadcage fit --cage`). Triangle strips and STL facets come out as triangles. Indices
/// are kept as written, even when out of range (except OBJ, as read_mesh()): the caller checks them.
/// \throw InvalidInput as read_mesh().
PolygonMesh read_polygon_mesh(const std::string& path, LoadInfo* info = nullptr);

/// Optional per-element properties for write_ply().
struct PlyExtras {
    std::string face_int_name;         ///< Name of an int face property (e.g. "patch"); empty: none.
    std::vector<int> face_ints;        ///< One value per triangle.
    std::string vertex_float_name;     ///< Name of a float vertex property (e.g. "distance"); empty: none.
    std::vector<float> vertex_floats;  ///< One value per vertex.
};

/// Reads a PLY file like read_mesh() and also the scalar properties named in `extras`:
/// `face_int_name` on the `face` element and `vertex_float_name` on the `vertex` element (either may be
/// empty: not read). Values are converted to int and float; a polygon's value is repeated on
/// every triangle of its fan, so `face_ints` has one value per triangle of the result. A property the
/// file lacks leaves its vector empty (callers decide whether that is an error). read_mesh() itself
/// ignores such properties.
/// \throw InvalidInput as read_mesh(), if the file is not a PLY, and (naming the file and element) if
///        a value read is NaN, infinite or out of the range of its int or float.
Mesh read_ply_with_extras(const std::string& path, PlyExtras& extras, LoadInfo* info = nullptr);

/// Writes a PLY file (binary little-endian unless `ascii`) with the optional properties of `extras`:
/// vertices as `double` x, y, z (coordinates read back bit-identical), faces as
/// `list uchar int vertex_indices`. Writes to `path + ".tmp"` and renames it, so a failure never
/// leaves a half-written file.
/// \throw InvalidInput (naming `path`) if the file cannot be written, an extras array has the wrong
///        size, or an extras name is empty-with-values, contains spaces or clashes with a standard one.
void write_ply(const std::string& path, const Mesh& mesh, const PlyExtras& extras = {}, bool ascii = false);

/// Writes an OBJ file (`v` with 17 significant digits, so coordinates read back bit-identical; `f`
/// 1-based) atomically (temporary file + rename).
/// \throw InvalidInput (naming `path`) if the file cannot be written.
void write_obj(const std::string& path, const Mesh& mesh);

/// Writes `text` to `path` atomically (temporary file + rename).
/// \throw InvalidInput if the file cannot be written.
void write_text_file(const std::string& path, const std::string& text);

}  // namespace quadcage

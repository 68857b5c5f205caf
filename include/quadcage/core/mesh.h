#pragma once
// The triangle mesh every module works on, and the small vector type of the public API.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace quadcage {

/// A point or vector in R^3 (double precision).
struct Vec3 {
    double x = 0, y = 0, z = 0;

    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
    bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
    bool operator!=(const Vec3& o) const { return !(*this == o); }
};

/// Dot product.
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// Cross product (right-handed).
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Euclidean length.
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
/// True if no coordinate is NaN or infinite.
inline bool is_finite(const Vec3& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// Vertex indices of one triangle, counter-clockwise seen from outside.
using Triangle = std::array<int, 3>;

/// An indexed triangle mesh. Nothing is assumed about it: indices may be out of range and the
/// surface may be open or non-manifold until core::validate() says otherwise.
struct Mesh {
    std::vector<Vec3> points;         ///< Vertex positions, in the mesh's own units.
    std::vector<Triangle> triangles;  ///< Indices into `points`.

    int num_vertices() const { return static_cast<int>(points.size()); }
    int num_triangles() const { return static_cast<int>(triangles.size()); }
};

/// A polygon mesh: faces with any number of corners (a control cage, as a file holds it). Nothing
/// is assumed about it until checked (subdiv::check_polygon_cage()).
struct PolygonMesh {
    std::vector<Vec3> points;
    std::vector<std::vector<int>> faces;  ///< Corner indices into points, counter-clockwise seen from outside.

    int num_vertices() const { return static_cast<int>(points.size()); }
    int num_faces() const { return static_cast<int>(faces.size()); }
};

/// Area of triangle t (indices must be valid).
double triangle_area(const Mesh& mesh, int t);

/// Sum of triangle areas (indices must be valid).
double surface_area(const Mesh& mesh);

/// Axis-aligned bounding box of the points that at least one triangle uses (all points if none).
struct BoundingBox {
    Vec3 min, max;
    double diagonal() const { return norm(max - min); }  ///< Length of the box diagonal (mesh units).
};
/// The bounding box of `mesh` (see BoundingBox); out-of-range indices are ignored, a mesh without
/// points gives the zero box.
BoundingBox bounding_box(const Mesh& mesh);

/// Share of the surface area on folds: triangles that meet a neighbour across an edge where the
/// surface turns by more than 90 degrees (their normals point apart: dot < 0). On a fine
/// tessellation of a smooth surface that is a place where the surface folds back on itself (a
/// pleat); on a coarse mesh it is also a sharp crease of its own (a tetrahedron's edges). Edges not
/// used by exactly two triangles, and degenerate triangles, count as no fold. 0 for an empty mesh.
/// Indices must be valid.
double folded_area_fraction(const Mesh& mesh);

/// One 1-to-4 midpoint split of every triangle: the same surface (points stay in place, new points at
/// edge midpoints), 4x the triangles. Used to make large inputs for benchmarks. Indices must be valid.
Mesh subdivide_midpoint(const Mesh& mesh);

}  // namespace quadcage

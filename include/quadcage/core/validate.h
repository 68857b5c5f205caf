#pragma once
// Validation of a triangle mesh: everything the later stages need to know before they start.

#include <string>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage {

/// One finding of validate(): an error stops the quad pipeline, a warning does not.
struct ValidationIssue {
    enum class Severity { warning, error };
    Severity severity = Severity::error;
    std::string code;     ///< Stable identifier, e.g. "boundary", "non_manifold_edge".
    long count = 0;       ///< How many elements are affected.
    std::string message;  ///< One sentence a user can act on, with an example element and position.
};

/// Facts about one connected component (connected through shared vertices).
struct ComponentReport {
    int vertices = 0;
    int triangles = 0;
    int edges = 0;
    int boundary_edges = 0;
    int boundary_loops = 0;
    int non_manifold_edges = 0;
    int non_manifold_vertices = 0;
    bool closed = false;      ///< Every edge has exactly two triangles.
    bool manifold = false;    ///< Edge- and vertex-manifold.
    bool orientable = false;  ///< An orientation exists (only meaningful when manifold).
    bool consistently_oriented = false;  ///< The triangles as given already agree on it.
    int euler_characteristic = 0;        ///< V - E + F.
    int genus = -1;           ///< (2 - chi - boundary loops) / 2; -1 when not manifold or not orientable.
    int minimal_quads = -1;   ///< Quads of the minimal cage (10g-10, 4 for g=1, 6 for g=0); -1 if none.
    double area = 0;
    double volume = 0;        ///< Enclosed volume (absolute value) when closed and orientable, else 0.
    bool degenerate = false;  ///< Closed but of zero area or enclosing no volume (flat): not quaddable.
    int first_triangle = 0;   ///< Lowest triangle index in the component (identifies it).

    /// Closed, manifold and orientable: the quad pipeline accepts it.
    bool quaddable() const { return closed && manifold && orientable && genus >= 0 && !degenerate; }
};

/// Everything validate() found.
struct ValidationReport {
    int vertices_in_file = 0;
    int vertices_used = 0;
    int triangles = 0;
    int unused_vertices = 0;
    int non_finite_vertices = 0;
    int out_of_range_triangles = 0;
    int repeated_index_triangles = 0;  ///< A triangle that names one vertex twice.
    int zero_area_triangles = 0;
    int duplicate_triangles = 0;
    int non_manifold_edges = 0;
    int non_manifold_vertices = 0;
    int boundary_edges = 0;
    int boundary_loops = 0;
    int inconsistently_oriented_edges = 0;
    double bbox_diagonal = 0;
    std::vector<ComponentReport> components;  ///< Ordered by first triangle index.
    std::vector<ValidationIssue> issues;      ///< Errors first, then warnings.

    /// True when there is no error and every component is quaddable.
    bool quaddable() const;
    /// The errors, joined into one line ("" if none).
    std::string error_summary() const;
};

/// Checks a mesh as loaded: finite coordinates, a scale whose bounding-box diagonal is in
/// [1e-30, 1e30], indices in range, unused vertices (counted, ignored), repeated-index, zero-area
/// and duplicate triangles, non-manifold edges and vertices, boundary loops (with a hint to weld
/// when vertices coincide: an unwelded triangle soup), orientation and orientability, connected
/// components with the genus of each, and degenerate components (zero area or no enclosed volume).
/// Never throws on a bad mesh: it describes it. Runs in O(n log n).
ValidationReport validate(const Mesh& mesh);

/// validate() and throw InvalidInput("<what>: <errors>") unless the mesh is quaddable.
/// `what` names the input (usually the file path).
ValidationReport require_quaddable(const Mesh& mesh, const std::string& what);

/// The minimal quad count for a closed orientable surface of genus g (10g-10, 4, 6).
int minimal_quad_count(int genus);

/// Flips triangles so that every component is consistently oriented, keeping the orientation of
/// each component's first triangle; outward if the component's signed volume was negative after
/// that, all its triangles are flipped. Returns the number of flipped triangles.
/// \pre manifold and orientable (validate()); otherwise throws InvalidInput.
int orient_outward(Mesh& mesh);

/// Removes vertices no triangle uses; returns old -> new index (-1 for removed).
std::vector<int> remove_unused_vertices(Mesh& mesh);

/// Splits a mesh into its connected components (through shared vertices), in the order of
/// ValidationReport::components. `vertex_maps[c][i]` is the original index of vertex i of component c.
std::vector<Mesh> split_components(const Mesh& mesh, std::vector<std::vector<int>>* vertex_maps = nullptr);

}  // namespace quadcage

namespace quadcage {

/// A mesh made ready for the quad pipeline: validated, unused vertices dropped, triangles
/// consistently oriented, split into connected components.
struct PreparedMesh {
    ValidationReport report;                   ///< Of the mesh as given.
    std::vector<Mesh> components;              ///< One closed orientable manifold mesh each.
    std::vector<std::vector<int>> vertex_maps; ///< Per component: local vertex -> index in the mesh as given.
    int flipped_triangles = 0;                 ///< Triangles re-oriented to agree with their neighbours.
};

/// Validates `mesh` and prepares it for the quad pipeline (cycles, layout, fit).
/// Triangles keep the input's orientation where it is consistent.
/// \throw InvalidInput("<what>: cannot be quadded: ...") if any component is open, non-manifold
///        or non-orientable, or the mesh has bad coordinates or indices.
PreparedMesh prepare_for_quadding(const Mesh& mesh, const std::string& what);

}  // namespace quadcage

#pragma once
// The layout stage over a whole mesh (every component of core::prepare_for_quadding()), its reports
// and its files: what `quadcage layout` and `quadcage cycles` compute and write, as library calls
// (fit/outputs.h and fit/mesh_fit.h are the same for `quadcage fit`).

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/validate.h"
#include "quadcage/layout/orthogonal_system.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout {

/// The report of one component's layout: report.json of `quadcage layout` (with the run fields),
/// and the `layout` object of `quadcage fit`'s report.json (without them).
struct LayoutReport {
    int genus = 0;
    int input_vertices = 0;             ///< Vertices of the component as given.
    int vertices = 0;                   ///< Of QuadLayout::mesh (input vertices + points added on edges).
    int triangles = 0;                  ///< Of QuadLayout::mesh.
    long long vertices_added_bound = 0; ///< vertices_added_bound() of the input and the cage's corners.
    int quads = 0;                      ///< Cage quads (10g-10, 4 or 6).
    int corners = 0;                    ///< Cage corners.
    int edges = 0;                      ///< Cage edges.
    std::map<int, int> degree_histogram;  ///< Corner degree -> number of corners of that degree.
    int s_cycles = 0;                   ///< QuadLayout::s_cycles.size().
    int level1_quads = 0;               ///< Quads of the cage after one Catmull-Clark step.
    int level1_vertices = 0;            ///< Vertices of that level-1 cage.
    LayoutQuality quality;
    QuadLayout::Seconds seconds;        ///< Wall-clock seconds by stage; the JSON adds their total.
    /// The sum of `seconds` over the stages (the JSON's seconds.total).
    double seconds_total() const;

    /// Run fields: written only when `run` is true (`quadcage layout`'s report.json).
    bool run = false;
    std::string input;                  ///< The mesh file as the user named it.
    int component = 0;                  ///< Index of the component (0-based).
    int components = 1;                 ///< Components of the input mesh.
    double peak_memory_mib = 0;         ///< Peak resident memory of the process after this layout, MiB.

    /// The report as pretty-printed JSON (2-space indent, keys in alphabetical order, a final
    /// newline): command, genus, input_vertices, vertices, triangles, vertices_added,
    /// vertices_added_bound, vertices_added_within_bound, quads,
    /// corners, edges, degree_histogram, s_cycles, level1 {quads, vertices}, verified (always true:
    /// build_quad_layout() verifies), quality {...}, seconds {cycles, curves, parameterization,
    /// verification, total}; with `run` also input, component, components, peak_memory_mib.
    /// Deterministic: equal reports give equal text.
    /// \throw InternalError if a number is not finite (it would be written as null).
    std::string to_json() const;
};

/// The report of a layout: counts, degrees, quality and seconds of `layout` (run fields unset).
LayoutReport layout_report(const QuadLayout& layout);

/// The top report.json of `quadcage layout` on a mesh of several components.
struct MeshLayoutReport {
    std::string input;                      ///< The mesh file as the user named it.
    std::vector<LayoutReport> components;   ///< One per component, in order (with run fields).
    double seconds = 0;                     ///< Wall-clock seconds of build_mesh_layout() (all components).
    double peak_memory_mib = 0;             ///< Peak resident memory of the process, MiB.

    /// Pretty-printed JSON as LayoutReport::to_json(): command, input, components (count), quads,
    /// corners, edges and degree_histogram summed over the components, component_reports (the
    /// components' reports), verified, seconds {total}, peak_memory_mib.
    /// \throw InternalError if a number is not finite.
    std::string to_json() const;
};

/// The layouts of every component of a mesh, with their reports.
struct MeshLayout {
    std::vector<QuadLayout> layouts;  ///< layouts[i] of prepared.components[i].
    MeshLayoutReport report;          ///< report.components[i] of layouts[i].
};

/// build_quad_layout() on each component of `prepared`, in order, with the reports `quadcage
/// layout` writes. `input` names the mesh in the reports. options.progress, if set, gets each
/// component's messages prefixed "component i: " when there are several.
/// \pre prepared comes from core::prepare_for_quadding() (its components are closed, connected,
///      orientable manifolds, oriented outward).
/// \throw InvalidInput as build_quad_layout() (options invalid, genus too high).
MeshLayout build_mesh_layout(const PreparedMesh& prepared, const std::string& input,
                             const QuadLayoutOptions& options = {});

/// The files of one component's layout: layout.ply (binary; the layout's mesh with an int face
/// property `patch`, the cage quad of each triangle), cage.obj (the level-0 cage), cage_level1.obj
/// (its first Catmull-Clark step), cage.json (corners, edges with their sides and vertex paths,
/// quads) and cycles.json (the orthogonal system and S-cycles, as vertex indices of layout.ply).
const std::vector<std::string>& layout_file_names();

/// Writes the files of layout_file_names() for `layout` into directory `dir` (created if missing),
/// and report.json from `report` unless it is null.
/// \throw InvalidInput (naming the path) if a file cannot be written; InternalError if the report
///        holds a non-finite number.
void write_layout_files(const std::string& dir, const QuadLayout& layout, const LayoutReport* report);

/// The outputs of write_layout_outputs() for a mesh of `components` components, relative to the
/// output directory (for OutputDir::expect()): each component's files and report.json, in
/// component_i/ when there are several, plus the top report.json then.
std::vector<std::string> layout_output_names(size_t components);

/// Stages every file of `quadcage layout` in `out` (the caller commits): each component's files
/// and report.json (in component_i/ when there are several), and the top report.json then.
/// \throw as write_layout_files().
void write_layout_outputs(OutputDir& out, const MeshLayout& layout);

/// The report of one component's orthogonal system: report.json of `quadcage cycles`.
struct CyclesReport {
    std::string input;                  ///< The mesh file as the user named it.
    int component = 0;
    int genus = 0;
    int input_vertices = 0;
    int input_triangles = 0;
    int vertices = 0;                   ///< Of OrthogonalSystem::mesh (refined).
    int triangles = 0;
    int edges_split = 0;                ///< OrthogonalSystem::refinement_splits.
    double area = 0;                    ///< Surface area, in the mesh's units squared.
    std::vector<double> cycle_lengths;  ///< Of the 2g cycles, in the mesh's units.
    std::vector<double> handle_lengths; ///< OrthogonalSystem::handle_lengths, in the mesh's units.
    int flipped_triangles = 0;          ///< PreparedMesh::flipped_triangles (of the whole mesh).
    double seconds = 0;                 ///< Wall-clock seconds of build_orthogonal_system().
    double peak_memory_mib = 0;         ///< Peak resident memory of the process after it, MiB.

    /// Handles shorter than this fraction of sqrt(area) are flagged as likely topological noise.
    static constexpr double kTinyHandle = 0.02;
    /// Handles shorter than kTinyHandle * sqrt(area).
    int tiny_handles() const;
    /// Sum of the cycle lengths over sqrt(area).
    double total_length_over_sqrt_area() const;

    /// Pretty-printed JSON (keys in alphabetical order): input, component, genus, input_vertices,
    /// input_triangles, vertices, triangles, refinement {edges_split, vertices_added}, area,
    /// cycle_lengths, cycle_lengths_over_sqrt_area, total_length_over_sqrt_area, shortest_handles
    /// [{length, over_sqrt_area}], tiny_handles, tiny_handle_threshold_over_sqrt_area,
    /// flipped_triangles, seconds, peak_memory_mib.
    /// \throw InternalError if a number is not finite.
    std::string to_json() const;
};

/// The orthogonal systems of every component of a mesh, with their reports.
struct MeshCycles {
    std::string input;                     ///< The mesh file as the user named it.
    std::vector<OrthogonalSystem> systems; ///< systems[i] of prepared.components[i].
    std::vector<CyclesReport> reports;     ///< reports[i] of systems[i].

    /// The top report.json for several components: input, components (the reports).
    /// \throw InternalError if a number is not finite.
    std::string to_json() const;
};

/// build_orthogonal_system() on each component of `prepared`, with the reports `quadcage cycles`
/// writes; progress prefixed as in build_mesh_layout().
/// \pre as build_mesh_layout(). \throw InvalidInput as build_orthogonal_system().
MeshCycles build_mesh_cycles(const PreparedMesh& prepared, const std::string& input,
                             const OrthogonalSystemOptions& options = {});

/// The outputs of write_cycles_outputs() (layout.ply, cycles.json, report.json per component, in
/// component_i/ when there are several, plus the top report.json then).
std::vector<std::string> cycles_output_names(size_t components);

/// Stages every file of `quadcage cycles` in `out` (the caller commits): per component layout.ply
/// (the refined mesh), cycles.json {genus, orthogonal_system} and report.json; the top report.json
/// when there are several.
/// \throw InvalidInput (naming the path) if a file cannot be written; InternalError if a report
///        holds a non-finite number.
void write_cycles_outputs(OutputDir& out, const MeshCycles& cycles);

/// Output folder of component `c` of `components`, relative to the output directory: "" for a
/// single component, else "component_c".
std::string component_dir(size_t c, size_t components);

/// Prefix of component `c`'s messages: "" for a single component, else "component c: ".
std::string component_tag(size_t c, size_t components);

/// Names `per_component` in each component's folder (component_dir()), plus the top report.json
/// when there are several components.
std::vector<std::string> component_output_names(size_t components, const std::vector<std::string>& per_component);

}  // namespace quadcage::layout

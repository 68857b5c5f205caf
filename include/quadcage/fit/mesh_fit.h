#pragma once
// The fit over a whole mesh (every component of core::prepare_for_quadding()), its reports and its
// files: what `quadcage fit` computes and writes, as library calls (layout/outputs.h is the same
// for `quadcage layout`).

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/validate.h"
#include "quadcage/fit/fit.h"
#include "quadcage/fit/outputs.h"
#include "quadcage/layout/outputs.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::fit {

/// report.json of one component of `quadcage fit`: the fit's report (FitReport) with the run's
/// fields beside it.
struct ComponentFitReport {
    std::string input;     ///< The mesh file as the user named it.
    std::string cage;      ///< The control mesh file of a control-mesh fit (`--cage`); empty for a layout fit.
    int component = 0;     ///< Index of the component (0-based).
    int components = 1;    ///< Components of the input mesh.
    std::optional<layout::LayoutReport> layout;  ///< Layout fit: the layout's report (run fields unset).
    int control_mesh_faces = 0;     ///< Control-mesh fit: faces of this component's control mesh.
    int control_mesh_vertices = 0;  ///< Control-mesh fit: its vertices.
    double layout_seconds = 0;      ///< Wall-clock seconds of build_quad_layout() (layout fit).
    double fit_seconds = 0;         ///< Wall-clock seconds of the fit.
    double peak_memory_mib = 0;     ///< Peak resident memory of the process once the files were written, MiB.
    FitReport fit;                  ///< With limit_tessellation once the files were written.
    /// Further top-level objects of the report by key, each as the JSON text of another module's
    /// report (`quadcage fit --step` puts the CAD export's under "cad"). Written as objects.
    std::map<std::string, std::string> sections;

    /// The report as pretty-printed JSON (2-space indent, keys in alphabetical order, a final
    /// newline): FitReport's fields, command ("fit"), input, component, components, seconds
    /// {layout, fit, total} and peak_memory_mib; a layout fit adds genus, quads and layout (its
    /// LayoutReport); a control-mesh fit adds cage and control_mesh {faces, vertices} and has no
    /// seconds.layout. Deterministic: equal reports give equal text.
    /// \throw InternalError if a number is not finite (it would be written as null).
    std::string to_json() const;
};

/// The top report.json of `quadcage fit` on a mesh of several components.
struct MeshFitReport {
    std::string input;                          ///< The mesh file as the user named it.
    std::string cage;                           ///< The control mesh file (`--cage`); empty for layout fits.
    std::vector<ComponentFitReport> components; ///< One per component, in order.
    double peak_memory_mib = 0;                 ///< Peak resident memory of the process, MiB.

    /// Pretty-printed JSON as ComponentFitReport::to_json(): command, input, cage (control-mesh
    /// fits), components (count), component_reports, peak_memory_mib.
    /// \throw InternalError if a number is not finite.
    std::string to_json() const;
};

/// The fits of every component of a mesh, with their reports.
struct MeshFit {
    std::vector<layout::QuadLayout> layouts;  ///< Layout fits: layouts[i] of component i; empty for control-mesh fits.
    std::vector<FitResult> fits;              ///< fits[i] of component i (evaluate fits[i].surface).
    MeshFitReport report;                     ///< report.components[i] of fits[i], without the
                                              ///< tessellation and final peak memory (write_mesh_fit_outputs() adds them).
};

/// fit_cage() on each component of `prepared` (layout, then fit), in order, with the reports
/// `quadcage fit MESH` writes; `input` names the mesh in them. Each options' progress, if set, gets
/// the component's messages prefixed "component i: " when there are several. `choice` as fit_cage()'s.
/// \pre prepared comes from core::prepare_for_quadding().
/// \throw InvalidInput if the options are invalid or a component cannot be laid out (as fit_cage()).
MeshFit fit_mesh(const PreparedMesh& prepared, const std::string& input,
                 const layout::QuadLayoutOptions& layout_options = {}, const FitOptions& fit_options = {},
                 SCycleChoice choice = SCycleChoice::Fit);

/// fit_control_mesh() on each component of `prepared` with its component of `cage`
/// (match_control_mesh()), with the reports `quadcage fit MESH --cage CAGE` writes; `input` and
/// `cage_name` name the files in the reports and messages.
/// \pre prepared comes from core::prepare_for_quadding().
/// \throw InvalidInput, naming cage_name and input, if the cage is not a closed oriented manifold
///        (subdiv::check_polygon_cage()), does not match the components, or a component's control
///        mesh cannot be fitted (check_control_mesh()); also if the options are invalid.
MeshFit fit_mesh_to_control_mesh(const PreparedMesh& prepared, const std::string& input, const PolygonMesh& cage,
                                 const std::string& cage_name, const FitOptions& fit_options = {});

/// The outputs of write_mesh_fit_outputs() for `components` components, relative to the output
/// directory (for OutputDir::expect()): with_layout adds layout::layout_file_names().
std::vector<std::string> fit_output_names(size_t components, bool with_layout);

/// Stages every file of `quadcage fit` in `out` (the caller commits): per component (in
/// component_i/ when there are several) the layout's files (layout fits), fitted_cage.obj,
/// limit.ply, deviation.ply (write_fit_files() against the component) and report.json; the top
/// report.json when there are several. `progress`, if set, gets a line per component.
/// Returns the reports as written (with the tessellations and peak memory).
/// \pre fit comes from fit_mesh() or fit_mesh_to_control_mesh() on `prepared`.
/// \throw InvalidInput (naming the path) if a file cannot be written or fit does not match
///        prepared; InternalError if a report holds a non-finite number.
/// `ply_options` chooses limit.ply's tessellation (write_fit_files()).
MeshFitReport write_mesh_fit_outputs(OutputDir& out, const PreparedMesh& prepared, const MeshFit& fit,
                                     const std::function<void(const std::string&)>& progress = {},
                                     const LimitPlyOptions& ply_options = {});

}  // namespace quadcage::fit

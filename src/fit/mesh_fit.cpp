#include "quadcage/fit/mesh_fit.h"

#include <chrono>
#include <filesystem>

#include "common/json_text.h"
#include "layout/report_json.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/process.h"
#include "quadcage/subdiv/cage.h"
#include "report_json.h"

namespace quadcage::fit {

namespace {

// Keys sorted (nlohmann::json is a std::map): the order `quadcage fit`'s report.json has always had.
using json = nlohmann::json;

std::function<void(const std::string&)> tagged(const std::function<void(const std::string&)>& progress,
                                               const std::string& tag) {
    if (!progress) return {};
    return [progress, tag](const std::string& m) { progress(tag + m); };
}

json component_object(const ComponentFitReport& r) {
    json report;
    detail::put_fit_report(r.fit, report);
    report["command"] = "fit";
    report["input"] = r.input;
    if (!r.cage.empty()) report["cage"] = r.cage;
    report["component"] = r.component;
    report["components"] = r.components;
    if (r.layout) {
        report["genus"] = r.layout->genus;
        report["quads"] = r.layout->quads;
        report["layout"] = layout::detail::layout_report_object(*r.layout);
        report["seconds"] = {{"layout", r.layout_seconds}, {"fit", r.fit_seconds}, {"total", r.layout_seconds + r.fit_seconds}};
    } else {
        report["control_mesh"] = {{"faces", r.control_mesh_faces}, {"vertices", r.control_mesh_vertices}};
        report["seconds"] = {{"fit", r.fit_seconds}, {"total", r.fit_seconds}};
    }
    for (const auto& [key, text] : r.sections) report[key] = json::parse(text);
    report["peak_memory_mib"] = r.peak_memory_mib;
    return report;
}

// The run fields every component's report has.
ComponentFitReport component_report(const std::string& input, size_t c, size_t nc) {
    ComponentFitReport r;
    r.input = input;
    r.component = static_cast<int>(c);
    r.components = static_cast<int>(nc);
    return r;
}

}  // namespace

std::string ComponentFitReport::to_json() const { return quadcage::detail::report_text(component_object(*this), 2); }

std::string MeshFitReport::to_json() const {
    json top = {{"command", "fit"}, {"input", input}, {"components", components.size()}};
    if (!cage.empty()) top["cage"] = cage;
    json parts = json::array();
    for (const ComponentFitReport& r : components) parts.push_back(component_object(r));
    top["component_reports"] = parts;
    top["peak_memory_mib"] = peak_memory_mib;
    return quadcage::detail::report_text(top, 2);
}

MeshFit fit_mesh(const PreparedMesh& prepared, const std::string& input, const layout::QuadLayoutOptions& layout_options,
                 const FitOptions& fit_options, SCycleChoice choice) {
    const size_t nc = prepared.components.size();
    MeshFit out;
    out.report.input = input;
    for (size_t c = 0; c < nc; ++c) {
        const std::string tag = layout::component_tag(c, nc);
        layout::QuadLayoutOptions lo = layout_options;
        lo.progress = tagged(layout_options.progress, tag);
        FitOptions fo = fit_options;
        fo.progress = tagged(fit_options.progress, tag);
        CageFit f = fit_cage(prepared.components[c], lo, fo, choice);
        ComponentFitReport r = component_report(input, c, nc);
        r.layout = layout::layout_report(f.layout);
        r.layout_seconds = f.layout_seconds;
        r.fit_seconds = f.fit_seconds;
        r.fit = fit_report(f.fit, fit_options);
        out.layouts.push_back(std::move(f.layout));
        out.fits.push_back(std::move(f.fit));
        out.report.components.push_back(std::move(r));
    }
    return out;
}

MeshFit fit_mesh_to_control_mesh(const PreparedMesh& prepared, const std::string& input, const PolygonMesh& cage,
                                 const std::string& cage_name, const FitOptions& fit_options) {
    if (const std::string e = fit_options.validate(); !e.empty()) throw InvalidInput("fit options: " + e);
    if (const std::string why = subdiv::check_polygon_cage(cage); !why.empty())
        throw InvalidInput(cage_name + ": cannot be fitted as a control mesh: " + why);
    std::vector<PolygonMesh> pieces;
    try {
        pieces = match_control_mesh(prepared.components, cage);
    } catch (const InvalidInput& e) {
        throw InvalidInput(cage_name + ": " + e.what() + " (" + input + ")");
    }
    const size_t nc = prepared.components.size();
    MeshFit out;
    out.report.input = input;
    out.report.cage = cage_name;
    for (size_t c = 0; c < nc; ++c) {
        FitOptions fo = fit_options;
        fo.progress = tagged(fit_options.progress, layout::component_tag(c, nc));
        const auto t0 = std::chrono::steady_clock::now();
        ComponentFitReport r = component_report(input, c, nc);
        try {
            out.fits.push_back(fit_control_mesh(prepared.components[c], pieces[c], fo));
        } catch (const InvalidInput& e) {
            throw InvalidInput(cage_name + ": " + e.what() + " (" + input + ")");
        }
        r.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r.cage = cage_name;
        r.control_mesh_faces = pieces[c].num_faces();
        r.control_mesh_vertices = pieces[c].num_vertices();
        r.fit = fit_report(out.fits.back(), fit_options);
        out.report.components.push_back(std::move(r));
    }
    return out;
}

std::vector<std::string> fit_output_names(size_t components, bool with_layout) {
    if (!with_layout) return layout::component_output_names(components, {"fitted_cage.obj", "limit.ply", "deviation.ply", "report.json"});
    std::vector<std::string> files = layout::layout_file_names();
    for (const char* f : {"report.json", "fitted_cage.obj", "limit.ply", "deviation.ply"}) files.push_back(f);
    return layout::component_output_names(components, files);
}

MeshFitReport write_mesh_fit_outputs(OutputDir& out, const PreparedMesh& prepared, const MeshFit& fit,
                                     const std::function<void(const std::string&)>& progress,
                                     const LimitPlyOptions& ply_options) {
    const size_t nc = prepared.components.size();
    if (fit.fits.size() != nc || fit.report.components.size() != nc || (!fit.layouts.empty() && fit.layouts.size() != nc))
        throw InvalidInput("write_mesh_fit_outputs: the fit has " + std::to_string(fit.fits.size()) +
                           " components, the mesh " + std::to_string(nc));
    MeshFitReport written = fit.report;
    for (size_t c = 0; c < nc; ++c) {
        const std::string dir = out.folder(layout::component_dir(c, nc));
        if (!fit.layouts.empty()) layout::write_layout_files(dir, fit.layouts[c], nullptr);
        if (progress) progress(layout::component_tag(c, nc) + "writing the fitted surface");
        const FitOutputs files = write_fit_files(dir, prepared.components[c], fit.fits[c], ply_options);
        ComponentFitReport& r = written.components[c];
        r.fit.limit_tessellation = files.tessellation;
        r.peak_memory_mib = peak_memory_mib();
        write_text_file((std::filesystem::path(dir) / "report.json").string(), r.to_json());
    }
    if (nc > 1) {
        written.peak_memory_mib = peak_memory_mib();
        write_text_file(out.path("report.json"), written.to_json());
    }
    return written;
}

}  // namespace quadcage::fit

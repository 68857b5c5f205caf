#include "commands.h"

#include "cad_stage.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include "quadcage/accel/closest_point.h"
#include "quadcage/cad/cad_export.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/openmesh_bridge.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "quadcage/fit/backend.h"
#include "quadcage/fit/fit.h"
#include "quadcage/fit/outputs.h"
#include "quadcage/layout/orthogonal_system.h"
#include "quadcage/layout/quad_layout.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::cli {
namespace {

using nlohmann::json;

const char* severity_name(ValidationIssue::Severity s) {
    return s == ValidationIssue::Severity::error ? "error" : "warning";
}

json info_json(const std::string& path, const LoadInfo& load, const ValidationReport& r) {
    json j;
    j["file"] = path;
    j["format"] = load.format;
    j["vertices"] = r.vertices_used;
    j["vertices_in_file"] = r.vertices_in_file;
    j["unused_vertices"] = r.unused_vertices;
    j["triangles"] = r.triangles;
    j["polygons_split"] = load.polygons_split;
    j["welded_vertices"] = load.welded_vertices;
    j["bbox_diagonal"] = r.bbox_diagonal;
    j["quaddable"] = r.quaddable();
    j["counts"] = {{"non_finite_vertices", r.non_finite_vertices},
                   {"out_of_range_triangles", r.out_of_range_triangles},
                   {"repeated_index_triangles", r.repeated_index_triangles},
                   {"zero_area_triangles", r.zero_area_triangles},
                   {"duplicate_triangles", r.duplicate_triangles},
                   {"non_manifold_edges", r.non_manifold_edges},
                   {"non_manifold_vertices", r.non_manifold_vertices},
                   {"boundary_edges", r.boundary_edges},
                   {"boundary_loops", r.boundary_loops},
                   {"inconsistently_oriented_edges", r.inconsistently_oriented_edges}};
    json comps = json::array();
    int total_quads = 0;
    bool all_quads = true;
    for (size_t i = 0; i < r.components.size(); ++i) {
        const ComponentReport& c = r.components[i];
        json jc{{"index", i},
                {"vertices", c.vertices},
                {"triangles", c.triangles},
                {"edges", c.edges},
                {"closed", c.closed},
                {"manifold", c.manifold},
                {"orientable", c.orientable},
                {"consistently_oriented", c.consistently_oriented},
                {"boundary_loops", c.boundary_loops},
                {"boundary_edges", c.boundary_edges},
                {"non_manifold_edges", c.non_manifold_edges},
                {"non_manifold_vertices", c.non_manifold_vertices},
                {"euler_characteristic", c.euler_characteristic},
                {"area", c.area},
                {"volume", c.volume},
                {"degenerate", c.degenerate}};
        jc["genus"] = c.genus >= 0 ? json(c.genus) : json(nullptr);
        jc["minimal_quads"] = c.minimal_quads >= 0 ? json(c.minimal_quads) : json(nullptr);
        if (c.minimal_quads >= 0) total_quads += c.minimal_quads;
        else all_quads = false;
        comps.push_back(jc);
    }
    j["components"] = comps;
    j["minimal_quads"] = all_quads && !r.components.empty() ? json(total_quads) : json(nullptr);
    json issues = json::array();
    for (const ValidationIssue& i : r.issues)
        issues.push_back({{"severity", severity_name(i.severity)}, {"code", i.code}, {"count", i.count},
                          {"message", i.message}});
    j["issues"] = issues;
    return j;
}

void print_info_text(const std::string& path, const LoadInfo& load, const ValidationReport& r) {
    std::printf("%s: %s, %d vertices", path.c_str(), load.format.c_str(), r.vertices_used);
    if (r.unused_vertices) std::printf(" (+%d unused)", r.unused_vertices);
    std::printf(", %d triangles, %zu component%s, bounding-box diagonal %.6g\n", r.triangles,
                r.components.size(), r.components.size() == 1 ? "" : "s", r.bbox_diagonal);
    const size_t shown = std::min<size_t>(r.components.size(), 20);
    for (size_t i = 0; i < shown; ++i) {
        const ComponentReport& c = r.components[i];
        std::printf("  component %zu: %d vertices, %d triangles, %s, %s, %s", i, c.vertices, c.triangles,
                    c.closed ? "closed" : "open", c.manifold ? "manifold" : "non-manifold",
                    !c.manifold ? "orientability n/a" : (c.orientable ? "orientable" : "non-orientable"));
        if (c.boundary_loops) std::printf(", %d boundary loop%s", c.boundary_loops, c.boundary_loops == 1 ? "" : "s");
        if (c.genus >= 0) std::printf(", genus %d", c.genus);
        if (c.minimal_quads >= 0) std::printf(" -> minimal cage: %d quads", c.minimal_quads);
        std::printf("\n");
    }
    if (shown < r.components.size()) std::printf("  ... %zu more components\n", r.components.size() - shown);
    for (const ValidationIssue& i : r.issues) std::printf("  %s: %s\n", severity_name(i.severity), i.message.c_str());
    std::printf("%s\n", r.quaddable() ? "ok: the mesh can be quadded" : "cannot be quadded (see errors above)");
}

// Progress lines on stderr: "quadcage: [12.3 s] message".
class Progress {
public:
    explicit Progress(bool quiet) : quiet_(quiet), start_(std::chrono::steady_clock::now()) {}
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    void say(const std::string& m) const {
        if (!quiet_) std::fprintf(stderr, "quadcage: [%6.1f s] %s\n", seconds(), m.c_str());
    }
    std::function<void(const std::string&)> callback(const std::string& prefix) const {
        return [this, prefix](const std::string& m) { say(prefix + m); };
    }

private:
    bool quiet_;
    std::chrono::steady_clock::time_point start_;
};

// `name` inside the relative folder `dir` of an output directory ("" is the directory itself).
std::string output_path(const std::string& dir, const std::string& name) {
    return (std::filesystem::path(dir) / name).string();
}

// The output files of a command: `per_component` in each component's folder, plus report.json at the
// top when there are several components.
std::vector<std::string> output_names(size_t components, const std::vector<std::string>& per_component);

// A report as text. A non-finite number would be written as null and hide a bug: refuse it.
std::string report_text(const json& j, int indent, const std::string& where = "") {
    if (j.is_number_float() && !std::isfinite(j.get<double>()))
        throw InternalError("a report would hold a non-finite number at " + (where.empty() ? "/" : where));
    if (j.is_object())
        for (const auto& [k, v] : j.items()) report_text(v, indent, where + "/" + k);
    if (j.is_array())
        for (size_t i = 0; i < j.size(); ++i) report_text(j[i], indent, where + "/" + std::to_string(i));
    return where.empty() ? j.dump(indent) + "\n" : std::string();
}

json cycles_json(const std::vector<layout::Cycle>& cycles) {
    json j = json::array();
    for (const layout::Cycle& c : cycles) j.push_back(c);
    return j;
}

// Peak resident memory of this process so far, in MiB.
double peak_memory_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// Handles shorter than this fraction of sqrt(area) are flagged as likely topological noise.
constexpr double kTinyHandle = 0.02;


// Everything `layout` writes for one component, rendered in memory before any file is written.
struct LayoutFiles {
    std::string dir;
    Mesh mesh;
    PlyExtras extras;
    std::string cage_obj, cage_level1_obj;
    json cage, cycles, report;
};

LayoutFiles layout_files(const layout::QuadLayout& L, const std::string& dir) {
    LayoutFiles f;
    f.dir = dir;
    f.mesh = L.mesh;
    f.extras.face_int_name = "patch";
    f.extras.face_ints = L.triangle_patch;
    subdiv::QuadMesh level0;
    level0.points = L.cage.points;
    for (const auto& q : L.cage.quads) level0.quads.push_back(q.corners);
    f.cage_obj = subdiv::quad_obj_text(level0, "quadcage level-0 cage: " + std::to_string(level0.num_quads()) +
                                                   " quads; OBJ cannot tell multi-edges apart, cage.json has the exact topology");
    const subdiv::CageRefinement r1 = subdiv::refine_cage(L.cage);
    f.cage_level1_obj = subdiv::quad_obj_text(
        r1.level1, "quadcage level-1 cage: one Catmull-Clark step of the level-0 cage (same limit surface)");
    json corners = json::array(), edges = json::array(), jquads = json::array();
    for (int c = 0; c < L.cage.num_corners(); ++c) {
        const Vec3& p = L.cage.points[c];
        corners.push_back({{"position", {p.x, p.y, p.z}}, {"vertex", L.corner_vertex[c]}});
    }
    for (size_t e = 0; e < L.cage.edges.size(); ++e) {
        const auto& E = L.cage.edges[e];
        edges.push_back({{"corners", {E.corners[0], E.corners[1]}},
                         {"sides", {{{"quad", E.quads[0]}, {"side", E.sides[0]}}, {{"quad", E.quads[1]}, {"side", E.sides[1]}}}},
                         {"path", L.edge_paths[e]}});
    }
    for (const auto& q : L.cage.quads) jquads.push_back({{"corners", q.corners}, {"edges", q.edges}});
    f.cage = {{"genus", L.genus},
              {"note", "side k of a quad runs from corners[k] to corners[k+1] along edges[k]; quads are "
                       "counter-clockwise seen from outside; path: layout.ply vertices from corners[0] to corners[1]"},
              {"corners", corners},
              {"edges", edges},
              {"quads", jquads}};
    f.cycles = {{"genus", L.genus}, {"orthogonal_system", cycles_json(L.orthogonal_system)}, {"s_cycles", cycles_json(L.s_cycles)}};
    std::map<int, int> histogram;
    {
        std::vector<int> degree(L.cage.num_corners(), 0);
        for (const auto& e : L.cage.edges)
            for (int c : e.corners) ++degree[c];
        for (int d : degree) ++histogram[d];
    }
    json hist = json::object();
    for (const auto& [d, count] : histogram) hist[std::to_string(d)] = count;
    const auto& q = L.quality;
    f.report = {{"command", "layout"},
                {"genus", L.genus},
                {"input_vertices", L.input_vertices},
                {"vertices", L.mesh.num_vertices()},
                {"triangles", L.mesh.num_triangles()},
                {"vertices_added", L.mesh.num_vertices() - L.input_vertices},
                {"quads", L.cage.num_quads()},
                {"corners", L.cage.num_corners()},
                {"edges", L.cage.num_edges()},
                {"degree_histogram", hist},
                {"s_cycles", L.s_cycles.size()},
                {"level1", {{"quads", r1.level1.num_quads()}, {"vertices", r1.level1.num_vertices()}}},
                {"verified", true},
                {"quality",
                 {{"patch_area_max_over_min", q.patch_area_max_over_min},
                  {"corner_angle_mean_deviation_deg", q.corner_angle_mean_deviation_deg},
                  {"corner_angle_max_deviation_deg", q.corner_angle_max_deviation_deg},
                  {"distortion_mean", q.distortion_mean},
                  {"distortion_max", q.distortion_max},
                  {"edge_length_over_sqrt_area", q.edge_length_over_sqrt_area},
                  {"flipped_triangles", q.flipped_triangles}}}};
    const double total = L.seconds.cycles + L.seconds.curves + L.seconds.parameterization + L.seconds.verification;
    f.report["seconds"] = {{"cycles", L.seconds.cycles},
                           {"curves", L.seconds.curves},
                           {"parameterization", L.seconds.parameterization},
                           {"verification", L.seconds.verification},
                           {"total", total}};
    return f;
}

// Output folder (relative to DIR) and message prefix of component c of nc: DIR itself and nothing
// for a single component.
std::string component_dir(size_t c, size_t nc) { return nc == 1 ? "" : "component_" + std::to_string(c); }
std::string component_tag(size_t c, size_t nc) { return nc == 1 ? "" : "component " + std::to_string(c) + ": "; }

std::vector<std::string> output_names(size_t components, const std::vector<std::string>& per_component) {
    std::vector<std::string> names;
    for (size_t c = 0; c < components; ++c)
        for (const std::string& n : per_component) names.push_back(output_path(component_dir(c, components), n));
    if (components > 1) names.push_back("report.json");
    return names;
}

const std::vector<std::string> kLayoutFiles = {"layout.ply", "cage.obj", "cage_level1.obj", "cage.json", "cycles.json", "report.json"};

// Stages the files; OutputDir::commit() moves them into DIR.
void write_layout_files(OutputDir& out, const LayoutFiles& f) {
    write_ply(out.path(output_path(f.dir, "layout.ply")), f.mesh, f.extras);
    write_text_file(out.path(output_path(f.dir, "cage.obj")), f.cage_obj);
    write_text_file(out.path(output_path(f.dir, "cage_level1.obj")), f.cage_level1_obj);
    write_text_file(out.path(output_path(f.dir, "cage.json")), report_text(f.cage, -1));
    write_text_file(out.path(output_path(f.dir, "cycles.json")), report_text(f.cycles, -1));
    write_text_file(out.path(output_path(f.dir, "report.json")), report_text(f.report, 2));
}

}  // namespace

int run_layout(const LayoutOptions& o) {
    Progress progress(o.quiet);
    OutputDir out(o.output_dir);  // usable, checked before any work
    progress.say("loading " + o.mesh);
    const Mesh input = read_mesh(o.mesh);
    const PreparedMesh prepared = prepare_for_quadding(input, o.mesh);
    const size_t nc = prepared.components.size();
    out.expect(output_names(nc, kLayoutFiles), {o.mesh});
    std::vector<LayoutFiles> pending;
    std::string summary;  // printed once the files are in place
    json top = {{"command", "layout"}, {"input", o.mesh}, {"components", nc}, {"quads", 0}, {"corners", 0}, {"edges", 0}};
    json parts = json::array();
    std::map<std::string, int> histogram;
    for (size_t c = 0; c < nc; ++c) {
        const std::string dir = component_dir(c, nc);
        const std::string tag = component_tag(c, nc);
        layout::QuadLayoutOptions options;
        options.progress = progress.callback(tag);
        const layout::QuadLayout L = layout::build_quad_layout(prepared.components[c], options);
        LayoutFiles f = layout_files(L, dir);
        f.report["input"] = o.mesh;
        f.report["component"] = c;
        f.report["components"] = nc;
        f.report["peak_memory_mib"] = peak_memory_mib();
        for (const auto& [d, count] : f.report["degree_histogram"].items()) histogram[d] += count.get<int>();
        top["quads"] = top["quads"].get<int>() + L.cage.num_quads();
        top["corners"] = top["corners"].get<int>() + L.cage.num_corners();
        top["edges"] = top["edges"].get<int>() + L.cage.num_edges();
        parts.push_back(f.report);
        const auto& q = L.quality;
        char line[512];
        std::snprintf(line, sizeof line,
                      "%sgenus %d: %d quads, %d corners (all of degree %d), verified; patch area max/min %.3g, "
                      "corner angle deviation %.1f deg, distortion mean %.2f max %.3g; %.2f s\n",
                      tag.c_str(), L.genus, L.cage.num_quads(), L.cage.num_corners(),
                      L.genus >= 2 ? 5 : (L.genus == 1 ? 4 : 3), q.patch_area_max_over_min,
                      q.corner_angle_mean_deviation_deg, q.distortion_mean, q.distortion_max,
                      f.report["seconds"]["total"].get<double>());
        summary += line;
        pending.push_back(std::move(f));
    }
    for (const LayoutFiles& f : pending) write_layout_files(out, f);
    if (nc > 1) {
        top["degree_histogram"] = histogram;
        top["component_reports"] = parts;
        top["verified"] = true;
        top["seconds"] = {{"total", progress.seconds()}};
        top["peak_memory_mib"] = peak_memory_mib();
        write_text_file(out.path("report.json"), report_text(top, 2));
    }
    out.commit();
    std::fputs(summary.c_str(), stdout);
    progress.say("wrote " + o.output_dir);
    return kOk;
}

namespace {

fit::FitOptions fit_options_of(const FitCommandOptions& o) {
    fit::FitOptions fit_options;
    if (o.tolerance > 0) {
        fit_options.mode = fit::FitMode::Tolerance;
        fit_options.tolerance = o.tolerance;
        fit_options.max_level = o.max_level;
    } else {
        fit_options.level = o.level;
    }
    if (const std::string e = fit_options.validate(); !e.empty()) throw InvalidInput("fit: " + e);
    return fit_options;
}

// The per-level lines of `fit`'s summary.
void print_fit_summary(const std::string& tag, const fit::FitResult& fit, const fit::FitOptions& options,
                       const fit::FitOutputs& written) {
    for (const fit::LevelReport& l : fit.levels)
        std::printf("%s  level %d: %d control points, relative RMS %.3g, Hausdorff %.3g, %.0f%% of the input within %.3g (%s)\n",
                    tag.c_str(), l.level, l.control_points, l.relative.rms, l.relative.hausdorff,
                    100 * l.within_tolerance, options.tolerance, l.stop_reason.c_str());
    std::printf("%s  %s\n", tag.c_str(), fit.message.c_str());
    std::printf("%s  limit.ply: %lld triangles (tessellation error %.2g of the RMS)\n", tag.c_str(),
                written.tessellation.triangles,
                fit.levels.back().absolute.rms > 0 ? written.tessellation.rms_error / fit.levels.back().absolute.rms : 0.0);
}

// The end of `fit`: the top report of several components, the outputs moved in at once, the JSON
// asked for.
int finish_fit(const FitCommandOptions& o, const Progress& progress, OutputDir& out, json& top, const json& parts,
               CadStage* cad) {
    if (parts.size() > 1) {
        top["component_reports"] = parts;
        top["peak_memory_mib"] = peak_memory_mib();
        write_text_file(out.path("report.json"), report_text(top, 2));
    }
    out.commit();
    if (cad) cad->commit();
    if (o.json) std::cout << (parts.size() == 1 ? parts[0] : top).dump(2) << "\n";
    progress.say("wrote " + o.output_dir);
    return kOk;
}

// The STEP/IGES files of `fit --step/--iges`: one component only (checked before any work).
std::unique_ptr<CadStage> fit_cad_stage(const FitCommandOptions& o, OutputDir& out, size_t components,
                                        const std::vector<std::string>& inputs) {
    CadFileOptions files;
    files.step = o.step;
    files.iges = o.iges;
    files.tolerance = o.cad_tolerance;
    if (!files.any()) return nullptr;
    if (components != 1)
        throw InvalidInput(o.mesh + ": has " + std::to_string(components) +
                           " components; --step/--iges export one solid: fit, then `quadcage export DIR/component_<i>`");
    return std::make_unique<CadStage>(files, &out, o.output_dir, inputs);
}

// `fit MESH --cage CAGE`: the user's control mesh, matched to MESH's components, fitted to each.
int run_fit_cage(const FitCommandOptions& o) {
    Progress progress(o.quiet);
    const fit::FitOptions fit_options = fit_options_of(o);
    OutputDir out(o.output_dir);  // usable, checked before any work
    progress.say("loading " + o.mesh);
    const Mesh input = read_mesh(o.mesh);
    const PreparedMesh prepared = prepare_for_quadding(input, o.mesh);
    const size_t nc = prepared.components.size();
    progress.say("loading " + o.cage);
    const PolygonMesh cage = read_polygon_mesh(o.cage);
    if (const std::string why = subdiv::check_polygon_cage(cage); !why.empty())
        throw InvalidInput(o.cage + ": cannot be fitted as a control mesh: " + why);
    std::vector<PolygonMesh> pieces;
    try {
        pieces = fit::match_control_mesh(prepared.components, cage);
    } catch (const InvalidInput& e) {
        throw InvalidInput(o.cage + ": " + e.what() + " (" + o.mesh + ")");
    }
    out.expect(output_names(nc, {"fitted_cage.obj", "limit.ply", "deviation.ply", "report.json"}), {o.mesh, o.cage});
    const std::unique_ptr<CadStage> cad = fit_cad_stage(o, out, nc, {o.mesh, o.cage});
    struct Pending {
        fit::FitResult fit;
        double seconds = 0;
    };
    std::vector<Pending> pending;
    for (size_t c = 0; c < nc; ++c) {
        fit::FitOptions options = fit_options;
        options.progress = progress.callback(component_tag(c, nc));
        const double t0 = progress.seconds();
        Pending p;
        try {
            p.fit = fit::fit_control_mesh(prepared.components[c], pieces[c], options);
        } catch (const InvalidInput& e) {
            throw InvalidInput(o.cage + ": " + e.what() + " (" + o.mesh + ")");
        }
        p.seconds = progress.seconds() - t0;
        pending.push_back(std::move(p));
    }
    json top = {{"command", "fit"}, {"input", o.mesh}, {"cage", o.cage}, {"components", nc}};
    json parts = json::array();
    for (size_t c = 0; c < nc; ++c) {
        const Pending& p = pending[c];
        const std::string dir = component_dir(c, nc), tag = component_tag(c, nc);
        json cad_report;
        if (cad) cad_report = cad->write(p.fit.surface, p.fit.levels.back().diagonal, fit_options.irregular_level,
                                           progress.callback(tag));
        progress.say(tag + "writing the fitted surface");
        const fit::FitOutputs written = fit::write_fit_outputs(out.folder(dir), prepared.components[c], p.fit, fit_options);
        json report = json::parse(fit::fit_report_json(p.fit, fit_options, &written.tessellation));
        report["command"] = "fit";
        report["input"] = o.mesh;
        report["cage"] = o.cage;
        report["component"] = c;
        report["components"] = nc;
        report["control_mesh"] = {{"faces", pieces[c].num_faces()}, {"vertices", pieces[c].num_vertices()}};
        report["seconds"] = {{"fit", p.seconds}, {"total", p.seconds}};
        if (cad) report["cad"] = cad_report;
        report["peak_memory_mib"] = peak_memory_mib();
        write_text_file(out.path(output_path(dir, "report.json")), report_text(report, 2));
        parts.push_back(report);
        if (o.json) continue;
        std::printf("%scontrol mesh of %d faces, %d vertices, fit %.2f s\n", tag.c_str(), pieces[c].num_faces(),
                    pieces[c].num_vertices(), p.seconds);
        print_fit_summary(tag, p.fit, fit_options, written);
        if (cad) print_cad_summary(tag + "  ", cad_report);
    }
    return finish_fit(o, progress, out, top, parts, cad.get());
}

}  // namespace

int run_fit(const FitCommandOptions& o) {
    if (!o.cage.empty()) return run_fit_cage(o);
    Progress progress(o.quiet);
    const fit::FitOptions fit_options = fit_options_of(o);
    OutputDir out(o.output_dir);  // usable, checked before any work
    progress.say("loading " + o.mesh);
    const Mesh input = read_mesh(o.mesh);
    const PreparedMesh prepared = prepare_for_quadding(input, o.mesh);
    const size_t nc = prepared.components.size();
    {
        std::vector<std::string> files = kLayoutFiles;
        for (const char* f : {"fitted_cage.obj", "limit.ply", "deviation.ply"}) files.push_back(f);
        out.expect(output_names(nc, files), {o.mesh});
    }
    const std::unique_ptr<CadStage> cad = fit_cad_stage(o, out, nc, {o.mesh});
    struct Pending {
        LayoutFiles layout;
        fit::FitResult fit;
        double layout_seconds = 0, fit_seconds = 0;
        const Mesh* mesh = nullptr;
    };
    std::vector<Pending> pending;
    for (size_t c = 0; c < nc; ++c) {
        const std::string dir = component_dir(c, nc);
        const std::string tag = component_tag(c, nc);
        layout::QuadLayoutOptions layout_options;
        layout_options.progress = progress.callback(tag + "layout: ");
        const double t0 = progress.seconds();
        const layout::QuadLayout L = layout::build_quad_layout(prepared.components[c], layout_options);
        const double t1 = progress.seconds();
        fit::FitOptions options = fit_options;
        options.progress = progress.callback(tag);
        Pending p;
        p.fit = fit::fit_surface(L, options);
        p.fit_seconds = progress.seconds() - t1;
        p.layout_seconds = t1 - t0;
        p.layout = layout_files(L, dir);
        p.mesh = &prepared.components[c];
        pending.push_back(std::move(p));
    }
    json top = {{"command", "fit"}, {"input", o.mesh}, {"components", nc}};
    json parts = json::array();
    for (size_t c = 0; c < pending.size(); ++c) {
        Pending& p = pending[c];
        const std::string tag = component_tag(c, nc);
        json cad_report;
        if (cad) cad_report = cad->write(p.fit.surface, p.fit.levels.back().diagonal, fit_options.irregular_level,
                                           progress.callback(tag));
        write_layout_files(out, p.layout);
        progress.say(tag + "writing the fitted surface");
        const fit::FitOutputs written = fit::write_fit_outputs(out.folder(p.layout.dir), *p.mesh, p.fit, fit_options);
        // report.json: the fit's report, with the layout's beside it.
        json report = json::parse(fit::fit_report_json(p.fit, fit_options, &written.tessellation));
        report["command"] = "fit";
        report["input"] = o.mesh;
        report["component"] = c;
        report["components"] = nc;
        report["genus"] = p.layout.report["genus"];
        report["quads"] = p.layout.report["quads"];
        report["layout"] = p.layout.report;
        report["seconds"] = {{"layout", p.layout_seconds}, {"fit", p.fit_seconds}, {"total", p.layout_seconds + p.fit_seconds}};
        if (cad) report["cad"] = cad_report;
        report["peak_memory_mib"] = peak_memory_mib();
        write_text_file(out.path(output_path(p.layout.dir, "report.json")), report_text(report, 2));
        parts.push_back(report);
        if (o.json) continue;
        std::printf("%sgenus %d: %d-quad cage, layout %.2f s, fit %.2f s\n", tag.c_str(), p.layout.report["genus"].get<int>(),
                    p.layout.report["quads"].get<int>(), p.layout_seconds, p.fit_seconds);
        print_fit_summary(tag, p.fit, fit_options, written);
        if (cad) print_cad_summary(tag + "  ", cad_report);
    }
    return finish_fit(o, progress, out, top, parts, cad.get());  // a tolerance not met is reported, not an error
}

int run_cycles(const CyclesOptions& o) {
    Progress progress(o.quiet);
    progress.say("loading " + o.mesh);
    OutputDir out(o.output_dir);  // usable, checked before any work
    LoadInfo load;
    const Mesh input = read_mesh(o.mesh, &load);
    const PreparedMesh prepared = prepare_for_quadding(input, o.mesh);
    const size_t nc = prepared.components.size();
    out.expect(output_names(nc, {"layout.ply", "cycles.json", "report.json"}), {o.mesh});
    // Everything is computed before anything is written: a failure leaves no partial output.
    struct Pending {
        std::string dir;
        Mesh mesh;
        json cycles, report;
    };
    std::vector<Pending> pending;
    json top;
    top["input"] = o.mesh;
    top["components"] = json::array();
    for (size_t c = 0; c < nc; ++c) {
        const std::string dir = component_dir(c, nc);
        const std::string tag = component_tag(c, nc);
        const Mesh& mesh = prepared.components[c];
        const double t0 = progress.seconds();
        layout::OrthogonalSystemOptions options;
        options.progress = progress.callback(tag);
        const layout::OrthogonalSystem sys = layout::build_orthogonal_system(mesh, options);
        const double seconds = progress.seconds() - t0;
        const double area = surface_area(mesh);
        const double root_area = std::sqrt(area);

        json report;
        report["input"] = o.mesh;
        report["component"] = c;
        report["genus"] = sys.genus;
        report["input_vertices"] = sys.input_vertices;
        report["input_triangles"] = mesh.num_triangles();
        report["vertices"] = sys.mesh.num_vertices();
        report["triangles"] = sys.mesh.num_triangles();
        report["refinement"] = {{"edges_split", sys.refinement_splits},
                                {"vertices_added", sys.mesh.num_vertices() - sys.input_vertices}};
        report["area"] = area;
        json lengths = json::array(), relative = json::array();
        double total = 0;
        for (const layout::Cycle& cy : sys.cycles) {
            const double len = layout::cycle_length(sys.mesh, cy);
            total += len;
            lengths.push_back(len);
            relative.push_back(len / root_area);
        }
        report["cycle_lengths"] = lengths;
        report["cycle_lengths_over_sqrt_area"] = relative;
        report["total_length_over_sqrt_area"] = total / root_area;
        json handles = json::array();
        int tiny = 0;
        for (double len : sys.handle_lengths) {
            handles.push_back({{"length", len}, {"over_sqrt_area", len / root_area}});
            if (len / root_area < kTinyHandle) ++tiny;
        }
        report["shortest_handles"] = handles;
        report["tiny_handles"] = tiny;
        report["tiny_handle_threshold_over_sqrt_area"] = kTinyHandle;
        report["flipped_triangles"] = prepared.flipped_triangles;
        report["seconds"] = seconds;
        report["peak_memory_mib"] = peak_memory_mib();

        json cj;
        cj["genus"] = sys.genus;
        cj["orthogonal_system"] = cycles_json(sys.cycles);
        top["components"].push_back(report);
        pending.push_back({dir, sys.mesh, cj, report});

        std::printf("%sgenus %d: %zu cycles, total length %.3g sqrt(area), %d vertices added, %.2f s\n",
                    tag.c_str(), sys.genus, sys.cycles.size(), total / root_area,
                    sys.mesh.num_vertices() - sys.input_vertices, seconds);
        if (tiny > 0)
            std::printf("%swarning: %d handle%s shorter than %.2g sqrt(area): possibly tunnels from scan noise\n",
                        tag.c_str(), tiny, tiny == 1 ? " is" : "s are", kTinyHandle);
    }
    for (const Pending& p : pending) {
        write_ply(out.path(output_path(p.dir, "layout.ply")), p.mesh);
        write_text_file(out.path(output_path(p.dir, "cycles.json")), report_text(p.cycles, -1));
        write_text_file(out.path(output_path(p.dir, "report.json")), report_text(p.report, 2));
    }
    if (nc > 1) write_text_file(out.path("report.json"), report_text(top, 2));
    out.commit();
    progress.say("wrote " + o.output_dir);
    return kOk;
}

int run_info(const InfoOptions& o) {
    LoadInfo load;
    const Mesh mesh = read_mesh(o.mesh, &load);
    const ValidationReport r = validate(mesh);
    if (o.json) std::cout << info_json(o.mesh, load, r).dump(2) << "\n";
    else print_info_text(o.mesh, load, r);
    if (!r.quaddable()) {
        std::fprintf(stderr, "quadcage: error: %s: cannot be quadded: %s\n", o.mesh.c_str(), r.error_summary().c_str());
        return kInvalidInput;
    }
    return kOk;
}

int run_version() {
    // Every line is produced by a call into the linked library, not by a header constant alone.
    std::printf("quadcage %s\n", QUADCAGE_VERSION);
    std::printf("  %s\n", openmesh_version().c_str());
    std::printf("  %s\n", subdiv::opensubdiv_version().c_str());
    std::printf("  %s\n", accel::embree_version().c_str());
    std::printf("  %s\n", fit::ceres_version().c_str());
    std::printf("  %s\n", fit::eigen_version().c_str());
    std::printf("  %s\n", cad::occt_version().c_str());
    return kOk;
}

// Writes .ply or .obj by the output's extension.
void write_mesh_by_extension(const std::string& out, const Mesh& mesh) {
    if (out.size() >= 4 && out.compare(out.size() - 4, 4, ".ply") == 0) write_ply(out, mesh);
    else write_obj(out, mesh);
}

// A single output file must not be (the same file as) the input.
void refuse_to_replace(const std::string& input, const std::string& output) {
    std::error_code ec;
    if (std::filesystem::exists(output, ec) && std::filesystem::equivalent(input, output, ec))
        throw OutputConflict(output + ": this output would replace the input " + input + "; choose another output file (-o)");
}

int run_subdivide(const SubdivideOptions& o) {
    refuse_to_replace(o.mesh, o.output);
    Mesh mesh = read_mesh(o.mesh);
    require_quaddable(mesh, o.mesh);
    for (int i = 0; i < o.times; ++i) mesh = subdivide_midpoint(mesh);
    write_mesh_by_extension(o.output, mesh);
    std::printf("%s: %d vertices, %d triangles\n", o.output.c_str(), mesh.num_vertices(), mesh.num_triangles());
    return kOk;
}

int run_generate(const GenerateOptions& o) {
    Mesh mesh;
    if (o.shape == "sphere") mesh = shapes::icosphere(o.resolution);
    else if (o.shape == "torus") mesh = shapes::torus(8 * o.resolution, 4 * o.resolution);
    else if (o.shape == "plate") {
        shapes::PlateOptions p;
        p.resolution = o.resolution;
        mesh = shapes::plate_with_holes(o.genus, p);
    } else if (o.shape == "limbs") {
        shapes::LimbOptions l;
        l.limbs = o.limbs;
        l.subdivisions = o.resolution;
        l.seed = o.seed;
        mesh = shapes::body_with_limbs(l);
    } else {
        throw InvalidInput("unknown shape '" + o.shape + "' (use sphere, torus, plate or limbs)");
    }
    write_mesh_by_extension(o.output, mesh);
    std::printf("%s: %d vertices, %d triangles\n", o.output.c_str(), mesh.num_vertices(), mesh.num_triangles());
    return kOk;
}

}  // namespace quadcage::cli

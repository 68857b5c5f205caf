#include "quadcage/layout/outputs.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "common/json_text.h"
#include "layout/report_json.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/process.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::layout {

namespace {

// Keys are sorted (nlohmann::json is a std::map): the order report.json has always had.
using json = nlohmann::json;
namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string output_path(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

// options.progress with each message prefixed by the component's tag; empty if it is.
std::function<void(const std::string&)> tagged(const std::function<void(const std::string&)>& progress,
                                               const std::string& tag) {
    if (!progress) return {};
    return [progress, tag](const std::string& m) { progress(tag + m); };
}

json cycles_json(const std::vector<Cycle>& cycles) {
    json j = json::array();
    for (const Cycle& c : cycles) j.push_back(c);
    return j;
}

// cage.json: the exact cage topology (OBJ cannot tell multi-edges apart) and the edges' vertex paths.
json cage_json(const QuadLayout& L) {
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
    return {{"genus", L.genus},
            {"note", "side k of a quad runs from corners[k] to corners[k+1] along edges[k]; quads are "
                     "counter-clockwise seen from outside; path: layout.ply vertices from corners[0] to corners[1]"},
            {"corners", corners},
            {"edges", edges},
            {"quads", jquads}};
}

json histogram_json(const std::map<int, int>& histogram) {
    json hist = json::object();
    for (const auto& [d, count] : histogram) hist[std::to_string(d)] = count;
    return hist;
}

}  // namespace

namespace detail {

json layout_report_object(const LayoutReport& r) {
    const LayoutQuality& q = r.quality;
    json j = {{"command", "layout"},
              {"genus", r.genus},
              {"input_vertices", r.input_vertices},
              {"vertices", r.vertices},
              {"triangles", r.triangles},
              {"vertices_added", r.vertices - r.input_vertices},
              {"vertices_added_bound", r.vertices_added_bound},
              {"vertices_added_within_bound", r.vertices - r.input_vertices <= r.vertices_added_bound},
              {"quads", r.quads},
              {"corners", r.corners},
              {"edges", r.edges},
              {"degree_histogram", histogram_json(r.degree_histogram)},
              {"s_cycles", r.s_cycles},
              {"level1", {{"quads", r.level1_quads}, {"vertices", r.level1_vertices}}},
              {"verified", true},
              {"quality",
               {{"patch_area_max_over_min", q.patch_area_max_over_min},
                {"corner_angle_mean_deviation_deg", q.corner_angle_mean_deviation_deg},
                {"corner_angle_max_deviation_deg", q.corner_angle_max_deviation_deg},
                {"distortion_mean", q.distortion_mean},
                {"distortion_max", q.distortion_max},
                {"edge_length_over_sqrt_area", q.edge_length_over_sqrt_area},
                {"flipped_triangles", q.flipped_triangles}}}};
    j["seconds"] = {{"cycles", r.seconds.cycles},
                    {"curves", r.seconds.curves},
                    {"parameterization", r.seconds.parameterization},
                    {"verification", r.seconds.verification},
                    {"total", r.seconds_total()}};
    if (r.run) {
        j["input"] = r.input;
        j["component"] = r.component;
        j["components"] = r.components;
        j["peak_memory_mib"] = r.peak_memory_mib;
    }
    return j;
}

}  // namespace detail

double LayoutReport::seconds_total() const {
    return seconds.cycles + seconds.curves + seconds.parameterization + seconds.verification;
}

std::string LayoutReport::to_json() const { return quadcage::detail::report_text(detail::layout_report_object(*this), 2); }

LayoutReport layout_report(const QuadLayout& L) {
    LayoutReport r;
    r.genus = L.genus;
    r.input_vertices = L.input_vertices;
    r.vertices = L.mesh.num_vertices();
    r.triangles = L.mesh.num_triangles();
    r.quads = L.cage.num_quads();
    r.corners = L.cage.num_corners();
    r.vertices_added_bound = vertices_added_bound(L.input_vertices, r.corners);
    r.edges = L.cage.num_edges();
    std::vector<int> degree(L.cage.num_corners(), 0);
    for (const auto& e : L.cage.edges)
        for (int c : e.corners) ++degree[c];
    for (int d : degree) ++r.degree_histogram[d];
    r.s_cycles = static_cast<int>(L.s_cycles.size());
    const subdiv::CageRefinement r1 = subdiv::refine_cage(L.cage);
    r.level1_quads = r1.level1.num_quads();
    r.level1_vertices = r1.level1.num_vertices();
    r.quality = L.quality;
    r.seconds = L.seconds;
    return r;
}

std::string MeshLayoutReport::to_json() const {
    json top = {{"command", "layout"}, {"input", input}, {"components", components.size()}};
    int quads = 0, corners = 0, edges = 0;
    std::map<std::string, int> histogram;  // by the degree's text, as the components' histograms
    json parts = json::array();
    for (const LayoutReport& r : components) {
        quads += r.quads;
        corners += r.corners;
        edges += r.edges;
        for (const auto& [d, count] : r.degree_histogram) histogram[std::to_string(d)] += count;
        parts.push_back(detail::layout_report_object(r));
    }
    top["quads"] = quads;
    top["corners"] = corners;
    top["edges"] = edges;
    top["degree_histogram"] = histogram;
    top["component_reports"] = parts;
    top["verified"] = true;
    top["seconds"] = {{"total", seconds}};
    top["peak_memory_mib"] = peak_memory_mib;
    return quadcage::detail::report_text(top, 2);
}

MeshLayout build_mesh_layout(const PreparedMesh& prepared, const std::string& input, const QuadLayoutOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const size_t nc = prepared.components.size();
    MeshLayout out;
    out.report.input = input;
    for (size_t c = 0; c < nc; ++c) {
        QuadLayoutOptions o = options;
        o.progress = tagged(options.progress, component_tag(c, nc));
        out.layouts.push_back(build_quad_layout(prepared.components[c], o));
        LayoutReport r = layout_report(out.layouts.back());
        r.run = true;
        r.input = input;
        r.component = static_cast<int>(c);
        r.components = static_cast<int>(nc);
        r.peak_memory_mib = peak_memory_mib();
        out.report.components.push_back(std::move(r));
    }
    out.report.seconds = seconds_since(t0);
    out.report.peak_memory_mib = peak_memory_mib();
    return out;
}

const std::vector<std::string>& layout_file_names() {
    static const std::vector<std::string> names = {"layout.ply", "cage.obj", "cage_level1.obj", "cage.json", "cycles.json"};
    return names;
}

void write_layout_files(const std::string& dir, const QuadLayout& L, const LayoutReport* report) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw InvalidInput("cannot create output directory " + dir + ": " + ec.message());
    // Everything is rendered before the first file is written.
    PlyExtras extras;
    extras.face_int_name = "patch";
    extras.face_ints = L.triangle_patch;
    subdiv::QuadMesh level0;
    level0.points = L.cage.points;
    for (const auto& q : L.cage.quads) level0.quads.push_back(q.corners);
    const std::string cage_obj = subdiv::quad_obj_text(
        level0, "quadcage level-0 cage: " + std::to_string(level0.num_quads()) +
                    " quads; OBJ cannot tell multi-edges apart, cage.json has the exact topology");
    const std::string cage_level1_obj = subdiv::quad_obj_text(
        subdiv::refine_cage(L.cage).level1,
        "quadcage level-1 cage: one Catmull-Clark step of the level-0 cage (same limit surface)");
    const std::string cage = quadcage::detail::report_text(cage_json(L), -1);
    const std::string cycles = quadcage::detail::report_text(
        json{{"genus", L.genus}, {"orthogonal_system", cycles_json(L.orthogonal_system)}, {"s_cycles", cycles_json(L.s_cycles)}},
        -1);
    const std::string text = report ? report->to_json() : std::string();
    write_ply(output_path(dir, "layout.ply"), L.mesh, extras);
    write_text_file(output_path(dir, "cage.obj"), cage_obj);
    write_text_file(output_path(dir, "cage_level1.obj"), cage_level1_obj);
    write_text_file(output_path(dir, "cage.json"), cage);
    write_text_file(output_path(dir, "cycles.json"), cycles);
    if (report) write_text_file(output_path(dir, "report.json"), text);
}

std::vector<std::string> layout_output_names(size_t components) {
    std::vector<std::string> per_component = layout_file_names();
    per_component.push_back("report.json");
    return component_output_names(components, per_component);
}

void write_layout_outputs(OutputDir& out, const MeshLayout& layout) {
    const size_t nc = layout.layouts.size();
    if (layout.report.components.size() != nc)
        throw InvalidInput("write_layout_outputs: " + std::to_string(nc) + " layouts but " +
                           std::to_string(layout.report.components.size()) + " reports");
    for (size_t c = 0; c < nc; ++c)
        write_layout_files(out.folder(component_dir(c, nc)), layout.layouts[c], &layout.report.components[c]);
    if (nc > 1) write_text_file(out.path("report.json"), layout.report.to_json());
}

int CyclesReport::tiny_handles() const {
    const double root_area = std::sqrt(area);
    int tiny = 0;
    for (double len : handle_lengths)
        if (len / root_area < kTinyHandle) ++tiny;
    return tiny;
}

double CyclesReport::total_length_over_sqrt_area() const {
    double total = 0;
    for (double len : cycle_lengths) total += len;
    return total / std::sqrt(area);
}

namespace {

json cycles_report_object(const CyclesReport& r) {
    const double root_area = std::sqrt(r.area);
    json report;
    report["input"] = r.input;
    report["component"] = r.component;
    report["genus"] = r.genus;
    report["input_vertices"] = r.input_vertices;
    report["input_triangles"] = r.input_triangles;
    report["vertices"] = r.vertices;
    report["triangles"] = r.triangles;
    report["refinement"] = {{"edges_split", r.edges_split}, {"vertices_added", r.vertices - r.input_vertices}};
    report["area"] = r.area;
    json lengths = json::array(), relative = json::array();
    for (double len : r.cycle_lengths) {
        lengths.push_back(len);
        relative.push_back(len / root_area);
    }
    report["cycle_lengths"] = lengths;
    report["cycle_lengths_over_sqrt_area"] = relative;
    report["total_length_over_sqrt_area"] = r.total_length_over_sqrt_area();
    json handles = json::array();
    for (double len : r.handle_lengths) handles.push_back({{"length", len}, {"over_sqrt_area", len / root_area}});
    report["shortest_handles"] = handles;
    report["tiny_handles"] = r.tiny_handles();
    report["tiny_handle_threshold_over_sqrt_area"] = CyclesReport::kTinyHandle;
    report["flipped_triangles"] = r.flipped_triangles;
    report["seconds"] = r.seconds;
    report["peak_memory_mib"] = r.peak_memory_mib;
    return report;
}

}  // namespace

std::string CyclesReport::to_json() const { return quadcage::detail::report_text(cycles_report_object(*this), 2); }

std::string MeshCycles::to_json() const {
    json top;
    top["input"] = input;
    top["components"] = json::array();
    for (const CyclesReport& r : reports) top["components"].push_back(cycles_report_object(r));
    return quadcage::detail::report_text(top, 2);
}

MeshCycles build_mesh_cycles(const PreparedMesh& prepared, const std::string& input,
                             const OrthogonalSystemOptions& options) {
    const size_t nc = prepared.components.size();
    MeshCycles out;
    out.input = input;
    for (size_t c = 0; c < nc; ++c) {
        const Mesh& mesh = prepared.components[c];
        const auto t0 = std::chrono::steady_clock::now();
        OrthogonalSystemOptions o = options;
        o.progress = tagged(options.progress, component_tag(c, nc));
        OrthogonalSystem sys = build_orthogonal_system(mesh, o);
        CyclesReport r;
        r.seconds = seconds_since(t0);
        r.input = input;
        r.component = static_cast<int>(c);
        r.genus = sys.genus;
        r.input_vertices = sys.input_vertices;
        r.input_triangles = mesh.num_triangles();
        r.vertices = sys.mesh.num_vertices();
        r.triangles = sys.mesh.num_triangles();
        r.edges_split = sys.refinement_splits;
        r.area = surface_area(mesh);
        for (const Cycle& cy : sys.cycles) r.cycle_lengths.push_back(cycle_length(sys.mesh, cy));
        r.handle_lengths = sys.handle_lengths;
        r.flipped_triangles = prepared.flipped_triangles;
        r.peak_memory_mib = peak_memory_mib();
        out.systems.push_back(std::move(sys));
        out.reports.push_back(std::move(r));
    }
    return out;
}

std::vector<std::string> cycles_output_names(size_t components) {
    return component_output_names(components, {"layout.ply", "cycles.json", "report.json"});
}

void write_cycles_outputs(OutputDir& out, const MeshCycles& cycles) {
    const size_t nc = cycles.systems.size();
    if (cycles.reports.size() != nc)
        throw InvalidInput("write_cycles_outputs: " + std::to_string(nc) + " systems but " +
                           std::to_string(cycles.reports.size()) + " reports");
    for (size_t c = 0; c < nc; ++c) {
        const OrthogonalSystem& sys = cycles.systems[c];
        const std::string dir = component_dir(c, nc);
        const std::string cj = quadcage::detail::report_text(
            json{{"genus", sys.genus}, {"orthogonal_system", cycles_json(sys.cycles)}}, -1);
        const std::string report = cycles.reports[c].to_json();
        write_ply(out.path(output_path(dir, "layout.ply")), sys.mesh);
        write_text_file(out.path(output_path(dir, "cycles.json")), cj);
        write_text_file(out.path(output_path(dir, "report.json")), report);
    }
    if (nc > 1) write_text_file(out.path("report.json"), cycles.to_json());
}

std::string component_dir(size_t c, size_t components) {
    return components == 1 ? "" : "component_" + std::to_string(c);
}

std::string component_tag(size_t c, size_t components) {
    return components == 1 ? "" : "component " + std::to_string(c) + ": ";
}

std::vector<std::string> component_output_names(size_t components, const std::vector<std::string>& per_component) {
    std::vector<std::string> names;
    for (size_t c = 0; c < components; ++c)
        for (const std::string& n : per_component) names.push_back(output_path(component_dir(c, components), n));
    if (components > 1) names.push_back("report.json");
    return names;
}

}  // namespace quadcage::layout

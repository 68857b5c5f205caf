#include "quadcage/core/mesh_info.h"

#include <nlohmann/json.hpp>

namespace quadcage {

namespace {

using json = nlohmann::json;

const char* severity_name(ValidationIssue::Severity s) {
    return s == ValidationIssue::Severity::error ? "error" : "warning";
}

}  // namespace

std::string MeshInfo::to_json() const {
    const std::string& path = file;
    const ValidationReport& r = validation;
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
    return j.dump(2) + "\n";
}

}  // namespace quadcage

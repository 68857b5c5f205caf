// layout/outputs.h: the layout's and the cycles' reports (to_json) and writers, as `quadcage layout`
// and `quadcage cycles` use them.

#include "quadcage/layout/outputs.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "support/files.h"

namespace quadcage::layout {
namespace {

namespace fs = std::filesystem;
using test::slurp;

const std::string kEight = std::string(QUADCAGE_DATA_DIR) + "/eight.off";

// eight.off (genus 2) and a torus beside it: one mesh of two components.
Mesh eight_and_torus() {
    Mesh m = read_mesh(kEight);
    const Mesh torus = shapes::torus(24, 12);
    const int base = m.num_vertices();
    for (const Vec3& p : torus.points) m.points.push_back(p + Vec3{5, 0, 0});
    for (const Triangle& t : torus.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return m;
}

const QuadLayout& eight_layout() {
    static const QuadLayout layout = [] {
        const PreparedMesh p = prepare_for_quadding(read_mesh(kEight), kEight);
        return build_quad_layout(p.components[0]);
    }();
    return layout;
}

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("quadcage_layout_outputs_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

TEST(LayoutReport, HasEveryFieldWithTheLayoutsValues) {
    const QuadLayout& L = eight_layout();
    const LayoutReport r = layout_report(L);
    const nlohmann::json j = nlohmann::json::parse(r.to_json());
    EXPECT_EQ(j["command"], "layout");
    EXPECT_EQ(j["genus"], 2);
    EXPECT_EQ(j["quads"], 10);
    EXPECT_EQ(j["corners"], 8);
    EXPECT_EQ(j["edges"], L.cage.num_edges());
    EXPECT_EQ(j["degree_histogram"], nlohmann::json({{"5", 8}}));
    EXPECT_EQ(j["input_vertices"], L.input_vertices);
    EXPECT_EQ(j["vertices"], L.mesh.num_vertices());
    EXPECT_EQ(j["triangles"], L.mesh.num_triangles());
    EXPECT_EQ(j["vertices_added"], L.mesh.num_vertices() - L.input_vertices);
    EXPECT_EQ(j["vertices_added_bound"], L.input_vertices / 4 + 200 * 8);
    EXPECT_EQ(j["vertices_added_within_bound"], j["vertices_added"] <= j["vertices_added_bound"]);
    EXPECT_EQ(j["s_cycles"], L.s_cycles.size());
    EXPECT_EQ(j["level1"]["quads"], 40);
    EXPECT_EQ(j["verified"], true);
    EXPECT_EQ(j["quality"]["flipped_triangles"], L.quality.flipped_triangles);
    EXPECT_DOUBLE_EQ(j["quality"]["distortion_max"].get<double>(), L.quality.distortion_max);
    EXPECT_DOUBLE_EQ(j["seconds"]["total"].get<double>(), r.seconds_total());
    EXPECT_DOUBLE_EQ(j["seconds"]["cycles"].get<double>(), L.seconds.cycles);
    // No run fields unless asked for.
    for (const char* k : {"input", "component", "components", "peak_memory_mib"}) EXPECT_FALSE(j.contains(k)) << k;
    EXPECT_EQ(j.size(), 17u) << j.dump();
}

TEST(LayoutReport, RunFieldsAndDeterministicText) {
    LayoutReport r = layout_report(eight_layout());
    r.run = true;
    r.input = "some/dir/eight.off";
    r.component = 1;
    r.components = 3;
    r.peak_memory_mib = 12.5;
    const std::string text = r.to_json();
    EXPECT_EQ(text, r.to_json());                          // the same text every time
    EXPECT_EQ(text, LayoutReport(r).to_json());            // a copy prints the same
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    const nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_EQ(j["input"], "some/dir/eight.off");
    EXPECT_EQ(j["component"], 1);
    EXPECT_EQ(j["components"], 3);
    EXPECT_EQ(j["peak_memory_mib"], 12.5);
    // Pretty-printed with sorted keys: reading and printing it again gives the same text.
    EXPECT_EQ(j.dump(2) + "\n", text);
}

TEST(LayoutReport, RefusesANonFiniteNumber) {
    LayoutReport r = layout_report(eight_layout());
    r.quality.distortion_max = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(r.to_json(), InternalError);
    MeshLayoutReport top;
    top.components.push_back(r);
    EXPECT_THROW(top.to_json(), InternalError);
}

TEST(LayoutFiles, WritesEveryFileAndTheReportOnlyWhenGiven) {
    const QuadLayout& L = eight_layout();
    const fs::path dir = scratch("files");
    write_layout_files((dir / "a").string(), L, nullptr);
    for (const std::string& f : layout_file_names()) EXPECT_TRUE(fs::exists(dir / "a" / f)) << f;
    EXPECT_FALSE(fs::exists(dir / "a" / "report.json"));
    const LayoutReport r = layout_report(L);
    write_layout_files((dir / "b").string(), L, &r);
    EXPECT_EQ(slurp(dir / "b" / "report.json"), r.to_json());
    // The files do not depend on the report.
    for (const std::string& f : layout_file_names()) EXPECT_EQ(slurp(dir / "a" / f), slurp(dir / "b" / f)) << f;

    const Mesh back = read_mesh((dir / "a" / "layout.ply").string());
    EXPECT_EQ(back.num_triangles(), L.mesh.num_triangles());
    const auto cage = nlohmann::json::parse(slurp(dir / "a" / "cage.json"));
    EXPECT_EQ(cage["genus"], 2);
    EXPECT_EQ(cage["quads"].size(), 10u);
    EXPECT_EQ(cage["corners"].size(), 8u);
    EXPECT_EQ(cage["edges"].size(), static_cast<size_t>(L.cage.num_edges()));
    const auto cycles = nlohmann::json::parse(slurp(dir / "a" / "cycles.json"));
    EXPECT_EQ(cycles["orthogonal_system"].size(), L.orthogonal_system.size());
    EXPECT_EQ(cycles["s_cycles"].size(), L.s_cycles.size());
    const Mesh cage0 = read_mesh((dir / "a" / "cage.obj").string());  // triangulated on reading
    EXPECT_EQ(cage0.num_vertices(), 8);
    fs::remove_all(dir);
}

TEST(LayoutOutputs, SeveralComponentsGetAFolderEachAndATopReport) {
    const Mesh mesh = eight_and_torus();
    const PreparedMesh prepared = prepare_for_quadding(mesh, "two");
    ASSERT_EQ(prepared.components.size(), 2u);
    std::vector<std::string> messages;
    QuadLayoutOptions options;
    options.progress = [&](const std::string& m) { messages.push_back(m); };
    const MeshLayout result = build_mesh_layout(prepared, "two.obj", options);
    ASSERT_EQ(result.layouts.size(), 2u);
    ASSERT_EQ(result.report.components.size(), 2u);
    ASSERT_FALSE(messages.empty());
    for (const std::string& m : messages) EXPECT_EQ(m.rfind("component ", 0), 0u) << m;

    const fs::path dir = scratch("mesh");
    {
        OutputDir out((dir / "out").string());
        out.expect(layout_output_names(2), {});
        write_layout_outputs(out, result);
        out.commit();
    }
    for (const std::string& f : layout_output_names(2)) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    EXPECT_EQ(layout_output_names(2).size(), 2 * 6 + 1u);
    const auto top = nlohmann::json::parse(slurp(dir / "out" / "report.json"));
    EXPECT_EQ(top["command"], "layout");
    EXPECT_EQ(top["input"], "two.obj");
    EXPECT_EQ(top["components"], 2);
    EXPECT_EQ(top["quads"], 10 + 4);
    EXPECT_EQ(top["degree_histogram"], nlohmann::json({{"4", 4}, {"5", 8}}));
    ASSERT_EQ(top["component_reports"].size(), 2u);
    for (int c = 0; c < 2; ++c) {
        const auto part = nlohmann::json::parse(slurp(dir / "out" / ("component_" + std::to_string(c)) / "report.json"));
        EXPECT_EQ(part, top["component_reports"][c]);
        EXPECT_EQ(part["component"], c);
        EXPECT_EQ(part["input"], "two.obj");
    }
    EXPECT_EQ(slurp(dir / "out" / "report.json"), result.report.to_json());
    fs::remove_all(dir);
}

TEST(CyclesOutputs, ReportAndFiles) {
    const PreparedMesh prepared = prepare_for_quadding(read_mesh(kEight), kEight);
    const MeshCycles result = build_mesh_cycles(prepared, "eight.off");
    ASSERT_EQ(result.reports.size(), 1u);
    const CyclesReport& r = result.reports[0];
    EXPECT_EQ(r.genus, 2);
    EXPECT_EQ(r.cycle_lengths.size(), 4u);
    const std::string text = r.to_json();
    EXPECT_EQ(text, CyclesReport(r).to_json());
    const auto j = nlohmann::json::parse(text);
    for (const char* k : {"input", "component", "genus", "input_vertices", "input_triangles", "vertices", "triangles",
                          "refinement", "area", "cycle_lengths", "cycle_lengths_over_sqrt_area",
                          "total_length_over_sqrt_area", "shortest_handles", "tiny_handles",
                          "tiny_handle_threshold_over_sqrt_area", "flipped_triangles", "seconds", "peak_memory_mib"})
        EXPECT_TRUE(j.contains(k)) << k;
    EXPECT_EQ(j.size(), 18u);
    double total = 0;
    for (double l : r.cycle_lengths) total += l;
    EXPECT_DOUBLE_EQ(j["total_length_over_sqrt_area"].get<double>(), total / std::sqrt(r.area));
    EXPECT_EQ(j["tiny_handles"], r.tiny_handles());
    EXPECT_EQ(j["input"], "eight.off");

    const fs::path dir = scratch("cycles");
    {
        OutputDir out((dir / "out").string());
        out.expect(cycles_output_names(1), {});
        write_cycles_outputs(out, result);
        out.commit();
    }
    EXPECT_EQ(slurp(dir / "out" / "report.json"), text);
    const auto cj = nlohmann::json::parse(slurp(dir / "out" / "cycles.json"));
    EXPECT_EQ(cj["genus"], 2);
    EXPECT_EQ(cj["orthogonal_system"].size(), 4u);
    EXPECT_FALSE(fs::exists(dir / "out" / "component_0"));
    fs::remove_all(dir);
}

TEST(ComponentOutputNames, OneComponentAtTheTopSeveralInFolders) {
    EXPECT_EQ(component_output_names(1, {"a", "b"}), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(component_output_names(2, {"a"}),
              (std::vector<std::string>{"component_0/a", "component_1/a", "report.json"}));
    EXPECT_EQ(component_tag(0, 1), "");
    EXPECT_EQ(component_tag(1, 2), "component 1: ");
}

}  // namespace
}  // namespace quadcage::layout

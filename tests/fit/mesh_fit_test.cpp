// The fit's reports (FitReport, ComponentFitReport, MeshFitReport: to_json) and fit/mesh_fit.h's
// whole-mesh call and writer, as `quadcage fit` uses them.

#include "quadcage/fit/mesh_fit.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "quadcage/fit/outputs.h"
#include "support/files.h"

namespace quadcage::fit {
namespace {

namespace fs = std::filesystem;
using test::slurp;

LevelReport level_report(int level) {
    LevelReport l;
    l.level = level;
    l.control_points = 40 * (level + 1);
    l.absolute.input_to_surface = {0.01, 0.008, 0.05};
    l.absolute.surface_to_input = {0.02, 0.01, 0.06};
    l.absolute.rms = 0.015;
    l.absolute.hausdorff = 0.06;
    l.relative = l.absolute;
    l.relative.rms = 0.0015;
    l.diagonal = 10;
    l.within_tolerance = 0.75;
    l.iterations = 3;
    l.solver_iterations = 4;
    l.stop_reason = "converged";
    l.seconds = {0.1, 0.2, 0.3, 0.4, 1.0};
    return l;
}

FitReport sample_report() {
    FitReport r;
    r.mode = FitMode::Level;
    r.requested_level = 1;
    r.max_level = 5;
    r.tolerance = 1e-3;
    r.tolerance_met = false;
    r.level = 1;
    r.message = "level 1 fitted";
    r.diagonal = 10;
    r.levels = {level_report(0), level_report(1)};
    r.fitted_cage = FitReport::ControlMesh{42, 40};
    r.weights = {1.0, 0.002, 0.01};
    TessellationChoice t;
    t.segments = 4;
    t.triangles = 1280;
    t.rms_error = 1e-4;
    t.max_error = 3e-4;
    t.target = 1.5e-3;
    t.met = true;
    r.limit_tessellation = t;
    return r;
}

std::vector<std::string> keys(const nlohmann::ordered_json& j) {
    std::vector<std::string> k;
    for (const auto& item : j.items()) k.push_back(item.key());
    return k;
}

TEST(FitReport, FieldsInTheirDocumentedOrder) {
    const FitReport r = sample_report();
    const std::string text = r.to_json();
    const auto j = nlohmann::ordered_json::parse(text);
    EXPECT_EQ(keys(j), (std::vector<std::string>{"mode", "requested_level", "tolerance", "tolerance_met", "level",
                                                 "message", "diagonal", "levels", "fitted_cage", "irregular_level",
                                                 "weights", "limit_tessellation"}));
    EXPECT_EQ(j["mode"], "level");
    EXPECT_EQ(j["requested_level"], 1);
    ASSERT_EQ(j["levels"].size(), 2u);
    EXPECT_EQ(keys(j["levels"][1]),
              (std::vector<std::string>{"level", "control_points", "absolute", "relative", "within_tolerance", "iterations",
                                        "solver_iterations", "stop_reason", "seconds"}));
    EXPECT_EQ(keys(j["levels"][1]["absolute"]),
              (std::vector<std::string>{"input_to_surface", "surface_to_input", "rms", "hausdorff"}));
    EXPECT_EQ(keys(j["levels"][1]["seconds"]),
              (std::vector<std::string>{"parameterization", "evaluation", "closest_points", "solve", "total"}));
    EXPECT_EQ(j["levels"][1]["relative"]["rms"], 0.0015);
    EXPECT_EQ(j["fitted_cage"]["vertices"], 42);
    EXPECT_EQ(j["limit_tessellation"]["segments_per_face"], 4);
    EXPECT_EQ(j["limit_tessellation"]["met"], true);
    EXPECT_EQ(keys(j["weights"]), (std::vector<std::string>{"surface_to_input", "tangential", "turned_over"}));
    EXPECT_EQ(j["weights"]["turned_over"], 0.01);
    // Round trip: the text is what printing the parsed report gives, and it does not change.
    EXPECT_EQ(j.dump(2) + "\n", text);
    EXPECT_EQ(FitReport(r).to_json(), text);
}

TEST(FitReport, ToleranceModeAndOptionalParts) {
    FitReport r = sample_report();
    r.mode = FitMode::Tolerance;
    r.fitted_cage.reset();
    r.limit_tessellation.reset();
    r.rejected_level = level_report(2);
    r.levels[0].unfitted_relative_rms = 0.1;
    r.levels[0].unfitted_relative_hausdorff = 0.2;
    const auto j = nlohmann::ordered_json::parse(r.to_json());
    EXPECT_EQ(j["mode"], "tolerance");
    EXPECT_FALSE(j.contains("requested_level"));
    EXPECT_EQ(j["max_level"], 5);
    EXPECT_EQ(j["rejected_level"]["level"], 2);
    EXPECT_FALSE(j.contains("fitted_cage"));
    EXPECT_FALSE(j.contains("limit_tessellation"));
    EXPECT_EQ(j["levels"][0]["unfitted_relative"]["hausdorff"], 0.2);
    EXPECT_FALSE(j["levels"][1].contains("unfitted_relative"));
}

TEST(FitReport, RefusesANonFiniteNumber) {
    FitReport r = sample_report();
    r.levels[1].relative.hausdorff = std::numeric_limits<double>::infinity();
    EXPECT_THROW(r.to_json(), InternalError);
}

TEST(ComponentFitReport, LayoutFitAndControlMeshFitFields) {
    ComponentFitReport c;
    c.input = "in.off";
    c.component = 0;
    c.components = 1;
    c.layout = layout::LayoutReport{};
    c.layout->genus = 2;
    c.layout->quads = 10;
    c.layout_seconds = 0.5;
    c.fit_seconds = 1.5;
    c.peak_memory_mib = 100;
    c.fit = sample_report();
    const std::string text = c.to_json();
    EXPECT_EQ(text, ComponentFitReport(c).to_json());
    const auto j = nlohmann::json::parse(text);
    EXPECT_EQ(j.dump(2) + "\n", text);  // sorted keys, as `quadcage fit` has always written them
    EXPECT_EQ(j["command"], "fit");
    EXPECT_EQ(j["input"], "in.off");
    EXPECT_EQ(j["genus"], 2);
    EXPECT_EQ(j["quads"], 10);
    EXPECT_EQ(j["layout"]["command"], "layout");
    EXPECT_FALSE(j["layout"].contains("input"));
    EXPECT_EQ(j["seconds"], nlohmann::json({{"layout", 0.5}, {"fit", 1.5}, {"total", 2.0}}));
    EXPECT_EQ(j["levels"].size(), 2u);          // the FitReport's fields beside the run's
    EXPECT_EQ(j["limit_tessellation"]["triangles"], 1280);
    EXPECT_FALSE(j.contains("cage"));
    EXPECT_FALSE(j.contains("control_mesh"));
    EXPECT_FALSE(j.contains("cad"));
    // Another module's report (the CAD export's) goes in as an object under its key.
    c.sections["cad"] = R"({"faces": 10, "valid": true})";
    const auto with_cad = nlohmann::json::parse(c.to_json());
    EXPECT_EQ(with_cad["cad"], nlohmann::json({{"faces", 10}, {"valid", true}}));
    c.sections.clear();

    c.layout.reset();
    c.cage = "cage.obj";
    c.control_mesh_faces = 6;
    c.control_mesh_vertices = 8;
    const auto k = nlohmann::json::parse(c.to_json());
    EXPECT_EQ(k["cage"], "cage.obj");
    EXPECT_EQ(k["control_mesh"], nlohmann::json({{"faces", 6}, {"vertices", 8}}));
    EXPECT_EQ(k["seconds"], nlohmann::json({{"fit", 1.5}, {"total", 1.5}}));
    for (const char* key : {"genus", "quads", "layout"}) EXPECT_FALSE(k.contains(key)) << key;

    MeshFitReport top;
    top.input = "in.off";
    top.components = {c, c};
    top.peak_memory_mib = 200;
    const auto t = nlohmann::json::parse(top.to_json());
    EXPECT_EQ(t["components"], 2);
    EXPECT_EQ(t["component_reports"][1], k);
    EXPECT_FALSE(t.contains("cage"));
}

TEST(MeshFit, FitsAndWritesEveryComponent) {
    // Two tori side by side: one mesh of two genus-1 components.
    Mesh mesh = shapes::torus(24, 12);
    const Mesh second = shapes::torus(24, 12);
    const int base = mesh.num_vertices();
    for (const Vec3& p : second.points) mesh.points.push_back(p + Vec3{4, 0, 0});
    for (const Triangle& t : second.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    const PreparedMesh prepared = prepare_for_quadding(mesh, "tori");
    ASSERT_EQ(prepared.components.size(), 2u);
    FitOptions options;
    options.level = 1;
    options.area_samples = 2000;
    options.error_samples = 5000;
    const MeshFit result = fit_mesh(prepared, "tori.obj", {}, options);
    ASSERT_EQ(result.fits.size(), 2u);
    ASSERT_EQ(result.layouts.size(), 2u);
    EXPECT_FALSE(result.report.components[0].fit.limit_tessellation);  // added by the writer

    const fs::path dir = test::scratch_dir("quadcage_mesh_fit_");
    MeshFitReport written;
    {
        OutputDir out((dir / "out").string());
        out.expect(fit_output_names(2, true), {});
        written = write_mesh_fit_outputs(out, prepared, result);
        out.commit();
    }
    for (const std::string& f : fit_output_names(2, true)) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    EXPECT_EQ(slurp(dir / "out" / "report.json"), written.to_json());
    for (int c = 0; c < 2; ++c) {
        const ComponentFitReport& r = written.components[c];
        ASSERT_TRUE(r.fit.limit_tessellation);
        ASSERT_TRUE(r.layout);
        EXPECT_EQ(r.layout->genus, 1);
        EXPECT_EQ(r.fit.level, 1);
        EXPECT_EQ(r.component, c);
        EXPECT_EQ(slurp(dir / "out" / ("component_" + std::to_string(c)) / "report.json"), r.to_json());
    }
    fs::remove_all(dir);
}

TEST(MeshFit, ABadControlMeshNamesBothFiles) {
    const PreparedMesh prepared = prepare_for_quadding(shapes::torus(24, 12), "torus");
    PolygonMesh open;
    open.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    open.faces = {{0, 1, 2}};
    try {
        fit_mesh_to_control_mesh(prepared, "torus.obj", open, "cage.obj");
        FAIL() << "an open cage was accepted";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("cage.obj"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace quadcage::fit

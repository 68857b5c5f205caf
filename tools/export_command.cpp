// `quadcage export DIR` and the CAD files of `fit --step/--iges` (issue 22).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cad_stage.h"
#include "commands.h"
#include "quadcage/cad/cad_export.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/fit/bspline_patches.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/limit_surface.h"

namespace quadcage::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string canonical_dir(const std::string& dir) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(dir.empty() ? "." : dir), ec);
    return ec ? fs::absolute(dir).lexically_normal().string() : p.string();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The surface `fit` wrote into `dir` (fitted_cage.obj + report.json), with its diagonal.
/// \throw InvalidInput naming the file and the problem.
fit::FittedSurface load_fit(const std::string& dir, double& diagonal, int& irregular_level) {
    const fs::path base(dir);
    std::error_code ec;
    if (!fs::is_directory(base, ec)) throw InvalidInput(dir + ": not a directory written by `quadcage fit`");
    const std::string report_path = (base / "report.json").string(),
                      cage_path = (base / "fitted_cage.obj").string();
    if (!fs::exists(report_path, ec))
        throw InvalidInput(report_path + ": missing, so " + dir +
                           " holds no fit (run `quadcage fit MESH -o " + dir + "` first)");
    json r;
    {
        std::ifstream in(report_path);
        std::stringstream text;
        text << in.rdbuf();
        try {
            r = json::parse(text.str());
        } catch (const json::exception& e) {
            throw InvalidInput(report_path + ": not JSON (" + std::string(e.what()) + ")");
        }
    }
    try {
        if (r.value("command", std::string()) != "fit")
            throw InvalidInput(report_path + ": not written by `quadcage fit` (command: " +
                               r.value("command", std::string("none")) + ")");
        if (!r.contains("level") && r.value("components", 1) > 1)
            throw InvalidInput(report_path + ": the fit has " + std::to_string(r["components"].get<int>()) +
                               " components; export " + (base / "component_<i>").string() + " one at a time");
        if (!fs::exists(cage_path, ec))
            throw InvalidInput(cage_path + ": missing (the fit in " + dir + " is incomplete)");
        const int level = r.at("level").get<int>();
        diagonal = r.at("diagonal").get<double>();
        if (level < 0 || level > fit::kMaxFitLevel || !(diagonal > 0) || !std::isfinite(diagonal))
            throw InvalidInput(report_path + ": level " + std::to_string(level) +
                               " or diagonal out of range");
        const int want_vertices = r.at("fitted_cage").at("vertices").get<int>();
        const int want_quads = r.at("fitted_cage").at("quads").get<int>();
        const int irregular = r.value("irregular_level", fit::FitOptions{}.irregular_level);
        if (irregular < 1 || irregular > 10) throw InvalidInput(report_path + ": irregular_level must be in [1, 10]");
        irregular_level = irregular;
        const int lc = std::max(level, 1);
        const PolygonMesh cage = read_polygon_mesh(cage_path);
        auto disagree = [&](const std::string& what, long long got, long long want) {
            if (got != want)
                throw InvalidInput(cage_path + ": " + std::to_string(got) + " " + what + ", but " +
                                   report_path + " says " + std::to_string(want) +
                                   " (files from different fits?)");
        };
        subdiv::LimitSurfaceOptions lso;
        lso.irregular_level = irregular;
        auto as_quads = [&](const PolygonMesh& m) {
            subdiv::QuadMesh q;
            q.points = m.points;
            for (size_t f = 0; f < m.faces.size(); ++f) {
                if (m.faces[f].size() != 4)
                    throw InvalidInput(cage_path + ": face " + std::to_string(f + 1) + " has " +
                                       std::to_string(m.faces[f].size()) + " corners; a fit at level " +
                                       std::to_string(level) + " writes quads only");
                q.quads.push_back({m.faces[f][0], m.faces[f][1], m.faces[f][2], m.faces[f][3]});
            }
            return q;
        };
        if (r.contains("cage")) {  // fit --cage: the user's control mesh
            const int cage_faces = r.at("control_mesh").at("faces").get<int>();
            if (level == 0) {
                disagree("faces", cage.num_faces(), cage_faces);
                disagree("vertices", cage.num_vertices(), r.at("control_mesh").at("vertices").get<int>());
                if (const std::string why = subdiv::check_polygon_cage(cage); !why.empty())
                    throw InvalidInput(cage_path + ": " + why);
                const subdiv::QuadMesh level1 = subdiv::refine_polygon_cage(cage).level1;
                disagree("quads after one refinement", level1.num_quads(), want_quads);
                return fit::FittedSurface(std::make_shared<const subdiv::LimitSurface>(level1, lso), 0,
                                          cage_faces, level1.num_quads());
            }
            disagree("vertices", cage.num_vertices(), want_vertices);
            disagree("faces", cage.num_faces(), want_quads);
            const subdiv::QuadMesh q = as_quads(cage);
            const int level1_quads = want_quads >> (2 * (lc - 1));
            disagree("faces (not a whole number of level-1 quads)",
                     static_cast<long long>(level1_quads) << (2 * (lc - 1)), want_quads);
            return fit::FittedSurface(std::make_shared<const subdiv::LimitSurface>(q, lso), level, cage_faces,
                                      level1_quads);
        }
        const int cage_quads = r.at("quads").get<int>();
        disagree("vertices", cage.num_vertices(), want_vertices);
        disagree("faces", cage.num_faces(), want_quads);
        disagree("faces (the cage's quads x 4^level)", cage.num_faces(),
                 static_cast<long long>(cage_quads) << (2 * lc));
        return fit::FittedSurface(as_quads(cage), level, cage_quads, irregular);
    } catch (const json::exception& e) {
        throw InvalidInput(report_path + ": missing or malformed field (" + std::string(e.what()) + ")");
    }
}

}  // namespace

CadStage::CadStage(const CadFileOptions& files, OutputDir* primary, const std::string& primary_dir,
                   const std::vector<std::string>& inputs)
    : files_(files),
      primary_(primary),
      primary_dir_(primary_dir.empty() ? "" : canonical_dir(primary_dir)),
      inputs_(inputs) {
    if (!files_.step.empty() && files_.step == files_.iges)
        throw OutputConflict(files_.step + ": given as both the STEP and the IGES file");
    for (const std::string* f : {&files_.step, &files_.iges}) {
        if (f->empty()) continue;
        const fs::path p(*f);
        if (p.filename().empty() || fs::is_directory(p))
            throw InvalidInput(*f + ": is a directory, not a file name");
        const std::string dir = canonical_dir(p.parent_path().string());
        const std::string name = p.filename().string();
        if (primary_ && dir == primary_dir_) {
            primary_->expect({name}, inputs_);
            continue;
        }
        bool found = false;
        for (auto& [d, out] : others_)
            if (d == dir) out->expect({name}, inputs_), found = true;
        if (!found) {
            others_.emplace_back(
                dir, std::make_unique<OutputDir>(p.parent_path().empty() ? "." : p.parent_path().string()));
            others_.back().second->expect({name}, inputs_);
        }
    }
}

std::string CadStage::staged(const std::string& file) {
    const fs::path p(file);
    const std::string dir = canonical_dir(p.parent_path().string());
    if (primary_ && dir == primary_dir_) return primary_->path(p.filename().string());
    for (auto& [d, out] : others_)
        if (d == dir) return out->path(p.filename().string());
    throw InternalError("CAD file " + file + " was not expected");
}

cad::ExportReport CadStage::write(const fit::FittedSurface& surface, double diagonal, int irregular_level,
                                  const std::function<void(const std::string&)>& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    fit::BSplinePatchOptions po;
    po.tolerance = files_.tolerance;
    po.diagonal = diagonal;
    po.polynomial_depth = irregular_level;
    if (progress) progress("CAD: B-spline patches of the limit surface");
    const fit::BSplinePatches patches = fit::bspline_patches(surface, po);
    cad::ExportReport report;
    report.patch_seconds = seconds_since(t0);
    if (!patches.tolerance_met) {
        char t[32];
        std::snprintf(t, sizeof t, "%g", files_.tolerance);
        throw InvalidInput(std::string("--cad-tolerance ") + t + " cannot be reached: " + patches.message);
    }
    if (progress) progress("CAD: sewing " + std::to_string(patches.patches.size()) + " faces into a solid");
    const cad::Solid solid = cad::make_solid(patches);
    report.solid = solid.report();
    if (!report.solid.closed || !report.solid.valid) throw InternalError("CAD export: " + report.solid.message);
    report.exactness = patches.measurement.exactness;
    report.deviation_samples = patches.measurement.samples;
    for (const auto& [file, kind] : {std::pair{files_.step, "step"}, std::pair{files_.iges, "iges"}}) {
        if (file.empty()) continue;
        if (progress) progress(std::string("CAD: writing ") + file);
        const std::string at = staged(file);
        if (std::string(kind) == "step")
            cad::write_step(solid, at);
        else
            cad::write_iges(solid, at);
        std::error_code ec;
        report.files.push_back({kind, file, static_cast<long long>(fs::file_size(at, ec))});
    }
    report.total_seconds = seconds_since(t0);
    return report;
}

void CadStage::commit() {
    for (auto& [d, out] : others_) out->commit();
}

void print_cad_summary(const std::string& tag, const cad::ExportReport& report) {
    const cad::SolidReport& r = report.solid;
    const double d = r.diagonal > 0 ? r.diagonal : 1;
    std::printf("%sCAD: %s, %d faces, %d edges, %d vertices (%s); area %.9g, volume %.9g\n", tag.c_str(), r.verdict(),
                r.faces, r.edges, r.vertices, r.valid ? "BRepCheck: valid" : "BRepCheck: invalid", r.area, r.volume);
    std::printf(
        "%sCAD: max deviation from the limit surface %.3g (%.3g of the diagonal; polynomial cells %.3g, "
        "corner cells %.3g), "
        "knot depth %d\n",
        tag.c_str(), r.max_deviation, r.max_deviation / d, r.max_deviation_regular / d, r.max_deviation_corner / d,
        r.depth);
    std::printf(
        "%sCAD: max normal jump %.3g deg away from corners, %.3g deg in corner cells; sewing tolerance %.3g; "
        "%.2f s\n",
        tag.c_str(), r.max_normal_jump_regular_deg, r.max_normal_jump_corner_deg, r.sewing_tolerance,
        report.total_seconds);
    // export.json lists the files by kind (sorted keys): the same order here.
    std::vector<cad::ExportReport::File> files = report.files;
    std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.kind < b.kind; });
    for (const auto& f : files)
        std::printf("%sCAD: wrote %s (%lld bytes)\n", tag.c_str(), f.path.c_str(), f.bytes);
}

int run_export(const ExportOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    auto say = [&](const std::string& m) {
        if (!o.quiet) std::fprintf(stderr, "quadcage: [%6.1f s] %s\n", seconds_since(t0), m.c_str());
    };
    CadFileOptions files;
    files.step = o.step;
    files.iges = o.iges;
    files.tolerance = o.cad_tolerance;
    if (!files.any()) files.step = (fs::path(o.dir) / "surface.step").string();
    say("loading the fit in " + o.dir);
    double diagonal = 0;
    int irregular_level = 0;
    const fit::FittedSurface surface = load_fit(o.dir, diagonal, irregular_level);
    const std::vector<std::string> inputs = {(fs::path(o.dir) / "report.json").string(),
                                             (fs::path(o.dir) / "fitted_cage.obj").string()};
    OutputDir out(o.dir);
    out.expect({"export.json"}, inputs);
    CadStage stage(files, &out, o.dir, inputs);
    cad::ExportReport report = stage.write(surface, diagonal, irregular_level, say);
    report.fit_dir = o.dir;
    report.level = surface.level();
    const std::string text = report.to_json(2) + "\n";
    write_text_file(out.path("export.json"), text);
    out.commit();
    stage.commit();
    if (o.json)
        std::cout << text;
    else
        print_cad_summary("", report);
    return kOk;
}

}  // namespace quadcage::cli

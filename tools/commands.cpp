#include "commands.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>

#include "cad_stage.h"
#include "quadcage/accel/closest_point.h"
#include "quadcage/cad/cad_export.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/mesh_info.h"
#include "quadcage/core/openmesh_bridge.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/core/shapes.h"
#include "quadcage/core/validate.h"
#include "quadcage/fit/backend.h"
#include "quadcage/fit/fit.h"
#include "quadcage/fit/mesh_fit.h"
#include "quadcage/fit/outputs.h"
#include "quadcage/layout/outputs.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::cli {
namespace {

const char* severity_name(ValidationIssue::Severity s) {
    return s == ValidationIssue::Severity::error ? "error" : "warning";
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

// Reads and prepares the mesh of a command that works per component.
PreparedMesh load_for_quadding(const std::string& path, const Progress& progress) {
    progress.say("loading " + path);
    return prepare_for_quadding(read_mesh(path), path);
}

void print_layout_summary(const layout::MeshLayoutReport& report) {
    const size_t nc = report.components.size();
    for (size_t c = 0; c < nc; ++c) {
        const layout::LayoutReport& r = report.components[c];
        const layout::LayoutQuality& q = r.quality;
        std::printf("%sgenus %d: %d quads, %d corners (all of degree %d), verified; patch area max/min %.3g, "
                    "corner angle deviation %.1f deg, distortion mean %.2f max %.3g; %.2f s\n",
                    layout::component_tag(c, nc).c_str(), r.genus, r.quads, r.corners,
                    r.genus >= 2 ? 5 : (r.genus == 1 ? 4 : 3), q.patch_area_max_over_min,
                    q.corner_angle_mean_deviation_deg, q.distortion_mean, q.distortion_max, r.seconds_total());
    }
}

void print_cycles_summary(const layout::MeshCycles& cycles) {
    const size_t nc = cycles.reports.size();
    for (size_t c = 0; c < nc; ++c) {
        const layout::CyclesReport& r = cycles.reports[c];
        const std::string tag = layout::component_tag(c, nc);
        std::printf("%sgenus %d: %zu cycles, total length %.3g sqrt(area), %d vertices added, %.2f s\n", tag.c_str(),
                    r.genus, r.cycle_lengths.size(), r.total_length_over_sqrt_area(), r.vertices - r.input_vertices,
                    r.seconds);
        if (const int tiny = r.tiny_handles(); tiny > 0)
            std::printf("%swarning: %d handle%s shorter than %.2g sqrt(area): possibly tunnels from scan noise\n",
                        tag.c_str(), tiny, tiny == 1 ? " is" : "s are", layout::CyclesReport::kTinyHandle);
    }
}

fit::FitOptions fit_options_of(const FitCommandOptions& o) {
    fit::FitOptions fit_options;
    if (o.tolerance > 0) {
        fit_options.mode = fit::FitMode::Tolerance;
        fit_options.tolerance = o.tolerance;
        fit_options.max_level = o.max_level;
    } else {
        fit_options.level = o.level;
    }
    fit_options.solver = o.solver == "ceres" ? fit::FitSolver::Ceres : fit::FitSolver::Direct;
    fit_options.outer_iterations = o.rounds;
    fit_options.extra_rounds = o.extra_rounds;
    fit_options.tangential_weight = o.tangential_weight;
    fit_options.turned_over_weight = o.turned_over_weight;
    fit_options.surface_feature_feet = !o.plane_feet_only;
    if (const std::string e = fit_options.validate(); !e.empty()) throw InvalidInput("fit: " + e);
    return fit_options;
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

// `fit`'s summary: per component its layout or control mesh, then a line per level.
void print_fit_summary(const fit::MeshFit& result, const fit::MeshFitReport& written, double tolerance) {
    const size_t nc = written.components.size();
    for (size_t c = 0; c < nc; ++c) {
        const fit::ComponentFitReport& r = written.components[c];
        const fit::FitResult& fit = result.fits[c];
        const std::string tag = layout::component_tag(c, nc);
        if (r.layout)
            std::printf("%sgenus %d: %d-quad cage, layout %.2f s, fit %.2f s\n", tag.c_str(), r.layout->genus,
                        r.layout->quads, r.layout_seconds, r.fit_seconds);
        else
            std::printf("%scontrol mesh of %d faces, %d vertices, fit %.2f s\n", tag.c_str(), r.control_mesh_faces,
                        r.control_mesh_vertices, r.fit_seconds);
        for (const fit::LevelReport& l : fit.levels)
            std::printf("%s  level %d: %d control points, relative RMS %.3g, Hausdorff %.3g, %.0f%% of the input within %.3g (%s)\n",
                        tag.c_str(), l.level, l.control_points, l.relative.rms, l.relative.hausdorff,
                        100 * l.within_tolerance, tolerance, l.stop_reason.c_str());
        std::printf("%s  %s\n", tag.c_str(), fit.message.c_str());
        const fit::TessellationChoice& t = *r.fit.limit_tessellation;
        const double rms = fit.levels.back().absolute.rms;
        std::printf("%s  limit.ply: %lld triangles (tessellation error %.2g of the RMS)", tag.c_str(), t.triangles,
                    rms > 0 ? t.rms_error / rms : 0.0);
        if (t.folded_area_fraction >= 0)
            std::printf("; %.2f%% of its area on folds (the input: %.2f%%), %.2f%% turned over against the input",
                        100 * t.folded_area_fraction, 100 * t.input_folded_area_fraction, 100 * t.inverted_area_fraction);
        std::printf("\n");
    }
}

}  // namespace

namespace {

void apply(const EmbeddingFlags& flags, layout::QuadLayoutOptions* options) {
    options->embedding_iterations = flags.iterations;
    options->embedding_extract = flags.extract;
    options->embedding_area_weight = flags.area_weight;
    options->embedding_conformal_weight = flags.conformal_weight;
    options->embedding_cone_conformal_weight = flags.cone_conformal_weight;
    options->embedding_cone_sweeps = flags.cone_sweeps;
    options->smooth_edges = !flags.staircase_edges;
    options->s_cycles_from_necks = !flags.no_necks;
    options->split_long_edges = !flags.no_long_edge_splits;
    if (!flags.choose_by_shape) {
        options->score = fit::level1_fit_score();
        options->tie_score = fit::level2_fit_score();
    }
    options->edge_embedding_iterations = flags.edge_embedding;
    options->edge_embedding_max_vertices = flags.edge_embedding_max_vertices;
    options->edge_embedding_cone_charts = flags.edge_embedding_cone_charts;
    options->edge_embedding_area_weight = flags.edge_embedding_area_weight;
    options->proxy_vertices = flags.proxy_vertices;
    options->proxy_above = flags.proxy_above;
}

// The shortest of %.15g and %.17g that reads back as x.
std::string exact_number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.15g", x);
    if (std::strtod(text, nullptr) != x) std::snprintf(text, sizeof text, "%.17g", x);
    return text;
}

}  // namespace

std::vector<std::string> embedding_arguments(const EmbeddingFlags& flags) {
    const EmbeddingFlags defaults;
    std::vector<std::string> args;
    if (flags.iterations != defaults.iterations)
        args.insert(args.end(), {"--embedding-iterations", std::to_string(flags.iterations)});
    if (flags.extract) args.push_back("--embedding-extract");
    if (flags.area_weight != defaults.area_weight)
        args.insert(args.end(), {"--embedding-area-weight", exact_number(flags.area_weight)});
    if (flags.conformal_weight != defaults.conformal_weight)
        args.insert(args.end(), {"--embedding-conformal-weight", exact_number(flags.conformal_weight)});
    if (flags.cone_conformal_weight != defaults.cone_conformal_weight)
        args.insert(args.end(), {"--embedding-cone-conformal-weight", exact_number(flags.cone_conformal_weight)});
    if (flags.cone_sweeps != defaults.cone_sweeps)
        args.insert(args.end(), {"--embedding-cone-sweeps", std::to_string(flags.cone_sweeps)});
    if (flags.staircase_edges) args.push_back("--staircase-edges");
    if (flags.no_necks) args.push_back("--no-necks");
    if (flags.no_long_edge_splits) args.push_back("--no-long-edge-splits");
    if (flags.choose_by_shape) args.insert(args.end(), {"--choose-s-cycles", "shape"});
    if (flags.edge_embedding != defaults.edge_embedding)
        args.insert(args.end(), {"--edge-embedding", std::to_string(flags.edge_embedding)});
    if (flags.edge_embedding_max_vertices != defaults.edge_embedding_max_vertices)
        args.insert(args.end(),
                    {"--edge-embedding-max-vertices", std::to_string(flags.edge_embedding_max_vertices)});
    if (flags.edge_embedding_cone_charts != defaults.edge_embedding_cone_charts)
        args.insert(args.end(),
                    {"--edge-embedding-cone-charts", exact_number(flags.edge_embedding_cone_charts)});
    if (flags.edge_embedding_area_weight != defaults.edge_embedding_area_weight)
        args.insert(args.end(),
                    {"--edge-embedding-area-weight", exact_number(flags.edge_embedding_area_weight)});
    if (flags.proxy_vertices != defaults.proxy_vertices)
        args.insert(args.end(), {"--proxy-vertices", std::to_string(flags.proxy_vertices)});
    if (flags.proxy_above != defaults.proxy_above)
        args.insert(args.end(), {"--proxy-above", std::to_string(flags.proxy_above)});
    return args;
}

int run_layout(const LayoutOptions& o) {
    Progress progress(o.quiet);
    OutputDir out(o.output_dir);  // usable, checked before any work
    const PreparedMesh prepared = load_for_quadding(o.mesh, progress);
    out.expect(layout::layout_output_names(prepared.components.size()), {o.mesh});
    layout::QuadLayoutOptions options;
    options.progress = progress.callback("");
    apply(o.embedding, &options);
    const layout::MeshLayout result = layout::build_mesh_layout(prepared, o.mesh, options);
    layout::write_layout_outputs(out, result);
    out.commit();
    print_layout_summary(result.report);
    progress.say("wrote " + o.output_dir);
    return kOk;
}

int run_fit(const FitCommandOptions& o) {
    Progress progress(o.quiet);
    fit::FitOptions options = fit_options_of(o);
    OutputDir out(o.output_dir);  // usable, checked before any work
    const PreparedMesh prepared = load_for_quadding(o.mesh, progress);
    const size_t nc = prepared.components.size();
    options.progress = progress.callback("");
    fit::MeshFit result;
    std::unique_ptr<CadStage> cad;
    if (o.cage.empty()) {
        out.expect(fit::fit_output_names(nc, true), {o.mesh});
        cad = fit_cad_stage(o, out, nc, {o.mesh});
        layout::QuadLayoutOptions layout_options;
        layout_options.progress = progress.callback("layout: ");
        apply(o.embedding, &layout_options);
        // apply() leaves the scores empty for `--choose-s-cycles shape`, where fit_mesh() would fill them.
        result = fit::fit_mesh(prepared, o.mesh, layout_options, options,
                               o.embedding.choose_by_shape ? fit::SCycleChoice::Shape : fit::SCycleChoice::Fit);
    } else {
        progress.say("loading " + o.cage);
        const PolygonMesh cage = read_polygon_mesh(o.cage);
        out.expect(fit::fit_output_names(nc, false), {o.mesh, o.cage});
        cad = fit_cad_stage(o, out, nc, {o.mesh, o.cage});
        result = fit::fit_mesh_to_control_mesh(prepared, o.mesh, cage, o.cage, options);
    }
    // fit --step/--iges: the solid is built, checked and staged before anything is committed.
    cad::ExportReport cad_report;
    if (cad) {
        const fit::FitResult& f = result.fits[0];
        cad_report = cad->write(f.surface, f.levels.back().diagonal, options.irregular_level, progress.callback(""));
        result.report.components[0].sections["cad"] = cad_report.to_json();
    }
    fit::LimitPlyOptions ply;
    ply.max_error_relative = o.limit_max_error;
    const fit::MeshFitReport written = fit::write_mesh_fit_outputs(out, prepared, result, progress.callback(""), ply);
    out.commit();  // a tolerance not met is reported, not an error
    if (cad) cad->commit();
    if (o.json) std::cout << (nc == 1 ? written.components[0].to_json() : written.to_json());
    else {
        print_fit_summary(result, written, options.tolerance);
        if (cad) print_cad_summary("  ", cad_report);
    }
    progress.say("wrote " + o.output_dir);
    return kOk;
}

int run_cycles(const CyclesOptions& o) {
    Progress progress(o.quiet);
    OutputDir out(o.output_dir);  // usable, checked before any work
    const PreparedMesh prepared = load_for_quadding(o.mesh, progress);
    out.expect(layout::cycles_output_names(prepared.components.size()), {o.mesh});
    layout::OrthogonalSystemOptions options;
    options.progress = progress.callback("");
    const layout::MeshCycles result = layout::build_mesh_cycles(prepared, o.mesh, options);
    print_cycles_summary(result);
    layout::write_cycles_outputs(out, result);
    out.commit();
    progress.say("wrote " + o.output_dir);
    return kOk;
}

int run_info(const InfoOptions& o) {
    LoadInfo load;
    const Mesh mesh = read_mesh(o.mesh, &load);
    const ValidationReport r = validate(mesh);
    if (o.json) std::cout << MeshInfo{o.mesh, load, r}.to_json();
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

std::string output_extension(const std::string& path, const std::vector<std::string>& allowed) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (std::find(allowed.begin(), allowed.end(), ext) != allowed.end()) return ext;
    std::string names;
    for (const std::string& a : allowed) names += (names.empty() ? "" : " or ") + a;
    throw InvalidInput(path + ": cannot write this format here; name the output file " + names + " (-o)");
}

// The mesh file `generate` and `subdivide` write: PLY or OBJ by its name.
std::string mesh_output_extension(const std::string& out) {
    return output_extension(out, {".obj", ".ply"});
}

// Writes .ply or .obj by the output's extension.
void write_mesh_by_extension(const std::string& out, const Mesh& mesh) {
    const bool ply = mesh_output_extension(out) == ".ply";
    if (ply)
        write_ply(out, mesh);
    else write_obj(out, mesh);
}

// A single output file must not be (the same file as) the input.
void refuse_to_replace(const std::string& input, const std::string& output) {
    std::error_code ec;
    if (std::filesystem::exists(output, ec) && std::filesystem::equivalent(input, output, ec))
        throw OutputConflict(output + ": this output would replace the input " + input + "; choose another output file (-o)");
}

int run_subdivide(const SubdivideOptions& o) {
    mesh_output_extension(o.output);  // refuses other formats before any work
    refuse_to_replace(o.mesh, o.output);
    Mesh mesh = read_mesh(o.mesh);
    require_quaddable(mesh, o.mesh);
    for (int i = 0; i < o.times; ++i) mesh = subdivide_midpoint(mesh);
    write_mesh_by_extension(o.output, mesh);
    std::printf("%s: %d vertices, %d triangles\n", o.output.c_str(), mesh.num_vertices(), mesh.num_triangles());
    return kOk;
}

int run_generate(const GenerateOptions& o) {
    mesh_output_extension(o.output);  // refuses other formats before any work
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
        l.fins = o.fins;
        mesh = shapes::body_with_limbs(l);
    } else if (o.shape == "handles") {
        shapes::HandleBodyOptions h;
        h.handles = o.genus;
        h.resolution = std::max(2, o.resolution);
        h.in_a_row = o.in_a_row;
        h.bumps = o.bumps;
        h.fins = o.fins;
        h.seed = o.seed;
        mesh = shapes::body_with_handles(h);
    } else if (o.shape == "wheel") {
        if (o.genus < 1 || o.genus > 65)
            throw InvalidInput("generate wheel: --genus must be in 1..65 (the axle's hole and up to 64 more), got " +
                               std::to_string(o.genus));
        shapes::WheelOptions w;
        w.holes = o.genus - 1;
        w.resolution = std::max(2, o.resolution);
        w.ribs = o.ribs;
        w.cad = o.cad;
        mesh = shapes::wheel(w);
    } else {
        throw InvalidInput("unknown shape '" + o.shape + "' (use sphere, torus, plate, limbs, handles or wheel)");
    }
    write_mesh_by_extension(o.output, mesh);
    std::printf("%s: %d vertices, %d triangles\n", o.output.c_str(), mesh.num_vertices(), mesh.num_triangles());
    return kOk;
}

}  // namespace quadcage::cli

#include "quadcage/fit/outputs.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>

#include "common/json_text.h"
#include "detail/sampling.h"
#include "quadcage/accel/closest_point.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/parallel.h"
#include "report_json.h"

namespace quadcage::fit {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

long long max_segments(const FittedSurface& surface, long long max_triangles) {
    const long long faces = surface.limit().num_faces();
    return std::max(1LL, static_cast<long long>(std::floor(std::sqrt(double(max_triangles) / (2.0 * faces)))));
}

}  // namespace

std::string LimitPlyOptions::validate() const {
    if (!(error_fraction > 0 && error_fraction <= 1)) return "error_fraction must be in (0, 1]";
    if (!(max_error_relative >= 0) || !std::isfinite(max_error_relative)) return "max_error_relative must be finite and >= 0";
    if (max_triangles < 2) return "max_triangles must be >= 2";
    if (min_segments < 1) return "min_segments must be >= 1";
    if (estimate_faces < 1 || estimate_points_per_face < 1) return "estimate_faces and estimate_points_per_face must be >= 1";
    if (threads < 0) return "threads must be >= 0";
    return {};
}

TessellationChoice tessellation_error(const FittedSurface& surface, int segments, const LimitPlyOptions& options) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("tessellation_error: " + why);
    if (segments < 1) throw InvalidInput("tessellation_error: segments must be >= 1");
    const subdiv::LimitSurface& limit = surface.limit();
    const int nf = limit.num_faces();
    const int faces = std::min(nf, options.estimate_faces);
    const int per_face = options.estimate_points_per_face;
    std::vector<double> err(static_cast<size_t>(faces) * per_face);
    parallel_for(faces, options.threads, [&](int k) {
        const int f = static_cast<int>(static_cast<long long>(k) * nf / faces);
        detail::Rng rng(options.seed * 1000003ULL + f);
        const double n = segments;
        for (int s = 0; s < per_face; ++s) {
            const double u = rng.uniform(), v = rng.uniform();
            const int i = std::min(segments - 1, static_cast<int>(u * n));
            const int j = std::min(segments - 1, static_cast<int>(v * n));
            const double a = u * n - i, b = v * n - j;  // position in the cell
            auto at = [&](int di, int dj) { return limit.evaluate({f, (i + di) / n, (j + dj) / n}).position; };
            // The cell's two triangles: (00, 10, 11) below the diagonal a >= b, (00, 11, 01) above it.
            Vec3 flat;
            if (a >= b) flat = at(0, 0) * (1 - a) + at(1, 0) * (a - b) + at(1, 1) * b;
            else flat = at(0, 0) * (1 - b) + at(1, 1) * a + at(0, 1) * (b - a);
            err[static_cast<size_t>(k) * per_face + s] = norm(flat - limit.evaluate({f, u, v}).position);
        }
    });
    TessellationChoice c;
    c.segments = segments;
    c.triangles = 2LL * segments * segments * nf;
    double sum2 = 0;
    for (double e : err) sum2 += e * e, c.max_error = std::max(c.max_error, e);
    c.rms_error = std::sqrt(sum2 / err.size());
    return c;
}

TessellationChoice choose_tessellation(const FittedSurface& surface, double fit_rms, const LimitPlyOptions& options,
                                       double diagonal) {
    if (!(fit_rms > 0) || !std::isfinite(fit_rms))
        throw InvalidInput("choose_tessellation: the fit RMS must be positive and finite");
    if (options.max_error_relative > 0 && !(diagonal > 0 && std::isfinite(diagonal)))
        throw InvalidInput("choose_tessellation: max_error_relative needs the diagonal");
    const double target = options.error_fraction * fit_rms;
    const double max_target = options.max_error_relative > 0 ? options.max_error_relative * diagonal
                                                             : std::numeric_limits<double>::infinity();
    auto ok = [&](const TessellationChoice& c) { return c.rms_error <= target && c.max_error <= max_target; };
    const int cap = static_cast<int>(std::min<long long>(max_segments(surface, options.max_triangles), 1 << 14));
    int n = std::min(cap, std::max(options.min_segments, 4));
    TessellationChoice c = tessellation_error(surface, n, options);
    // Chord error falls like 1/n^2: jump to the predicted n, then re-measure (a few times at most).
    for (int attempt = 0; attempt < 6 && !ok(c) && n < cap; ++attempt) {
        const double factor = std::sqrt(std::max(c.rms_error / target, c.max_error / max_target)) * 1.05;
        n = std::min(cap, std::max(n + 1, static_cast<int>(std::ceil(n * factor))));
        c = tessellation_error(surface, n, options);
    }
    // The prediction may overshoot by one step.
    if (ok(c) && n > options.min_segments) {
        const TessellationChoice coarser = tessellation_error(surface, n - 1, options);
        if (ok(coarser)) c = coarser;
    }
    c.target = target;
    c.met = ok(c);
    return c;
}

void write_quad_obj(const std::string& path, const subdiv::QuadMesh& mesh) {
    write_text_file(path, subdiv::quad_obj_text(mesh, "quadcage fitted control mesh: " + std::to_string(mesh.num_vertices()) +
                                                          " vertices, " + std::to_string(mesh.num_quads()) + " quads"));
}

void write_polygon_obj(const std::string& path, const PolygonMesh& mesh) {
    write_text_file(path, subdiv::polygon_obj_text(mesh, "quadcage fitted control mesh: " + std::to_string(mesh.num_vertices()) +
                                                             " vertices, " + std::to_string(mesh.num_faces()) + " faces"));
}

TessellationChoice write_limit_ply(const std::string& path, const Mesh& input, const FittedSurface& surface,
                                   const TessellationChoice& choice, int threads) {
    const subdiv::LimitTessellation tess = surface.limit().tessellate(std::max(1, choice.segments));
    const accel::ClosestPointIndex index(input);
    const std::vector<accel::ClosestHit> hits = index.query_all(tess.mesh.points, threads);
    PlyExtras extras;
    extras.vertex_float_name = "distance";
    extras.vertex_floats.resize(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) extras.vertex_floats[i] = static_cast<float>(hits[i].distance);
    write_ply(path, tess.mesh, extras);
    TessellationChoice out = choice;
    out.folded_area_fraction = folded_area_fraction(tess.mesh);
    out.input_folded_area_fraction = folded_area_fraction(input);
    const Mesh& m = tess.mesh;
    std::vector<Vec3> input_normal(input.num_triangles());  // not unit: only signs are read
    for (int t = 0; t < input.num_triangles(); ++t) {
        const Triangle& tri = input.triangles[t];
        input_normal[t] = cross(input.points[tri[1]] - input.points[tri[0]], input.points[tri[2]] - input.points[tri[0]]);
    }
    double total = 0, inverted = 0;
    for (const Triangle& tri : m.triangles) {
        const Vec3 n = cross(m.points[tri[1]] - m.points[tri[0]], m.points[tri[2]] - m.points[tri[0]]);
        const double area = norm(n) / 2;
        total += area;
        bool against = true;
        for (int v : tri) against = against && dot(n, input_normal[hits[v].triangle]) < 0;
        if (against) inverted += area;
    }
    out.inverted_area_fraction = total > 0 ? inverted / total : 0;
    return out;
}

void write_deviation_ply(const std::string& path, const Mesh& input, const FittedSurface& surface, int threads) {
    const std::vector<double> d = distances_to_surface(surface, input.points, 32, threads);
    PlyExtras extras;
    extras.vertex_float_name = "distance";
    extras.vertex_floats.assign(d.begin(), d.end());
    write_ply(path, input, extras);
}

FitReport fit_report(const FitResult& result, const FitOptions& options, const TessellationChoice* tessellation) {
    FitReport r;
    r.mode = options.mode;
    r.requested_level = options.level;
    r.max_level = options.max_level;
    r.tolerance = options.tolerance;
    r.tolerance_met = result.tolerance_met;
    r.level = result.levels.empty() ? -1 : result.levels.back().level;
    r.message = result.message;
    r.diagonal = result.levels.empty() ? 0.0 : result.levels.back().diagonal;
    r.levels = result.levels;
    r.rejected_level = result.rejected_level;
    if (!result.surface.empty())
        r.fitted_cage = FitReport::ControlMesh{result.surface.control_mesh().num_vertices(),
                                               result.surface.control_mesh().num_quads(), result.surface.cage_faces()};
    r.irregular_level = options.irregular_level;
    r.weights = {options.surface_to_input_weight, options.tangential_weight, options.turned_over_weight};
    if (tessellation) r.limit_tessellation = *tessellation;
    return r;
}

std::string FitReport::to_json() const {
    Json report;
    detail::put_fit_report(*this, report);
    return quadcage::detail::report_text(report, 2);
}

FitOutputs write_fit_files(const std::string& dir, const Mesh& input, const FitResult& result,
                           const LimitPlyOptions& ply_options) {
    if (result.surface.empty() || result.levels.empty()) throw InvalidInput("write_fit_outputs: the fit result is empty");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw InvalidInput("cannot create output directory " + dir + ": " + ec.message());
    FitOutputs out;
    const fs::path base(dir);
    const std::string cage = (base / "fitted_cage.obj").string(), limit = (base / "limit.ply").string();
    const std::string deviation = (base / "deviation.ply").string();
    if (result.fitted_cage.faces.empty()) write_quad_obj(cage, result.surface.control_mesh());
    else write_polygon_obj(cage, result.fitted_cage);
    out.files.push_back(cage);
    out.tessellation = choose_tessellation(result.surface, result.levels.back().absolute.rms, ply_options,
                                           result.levels.back().diagonal);
    out.tessellation = write_limit_ply(limit, input, result.surface, out.tessellation, ply_options.threads);
    out.files.push_back(limit);
    write_deviation_ply(deviation, input, result.surface, ply_options.threads);
    out.files.push_back(deviation);
    return out;
}

FitOutputs write_fit_outputs(const std::string& dir, const Mesh& input, const FitResult& result,
                             const FitOptions& options, const LimitPlyOptions& ply_options) {
    FitOutputs out = write_fit_files(dir, input, result, ply_options);
    const std::string report = (fs::path(dir) / "report.json").string();
    write_text_file(report, fit_report(result, options, &out.tessellation).to_json());
    out.files.push_back(report);
    return out;
}

}  // namespace quadcage::fit

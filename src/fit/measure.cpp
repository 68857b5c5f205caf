#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "detail/measure.h"
#include "detail/sampling.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::fit {

namespace detail {

double seconds_since(const std::chrono::steady_clock::time_point& start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SurfaceProjector::SurfaceProjector(const subdiv::LimitSurface& surface, int segments, int threads)
    : surface_(surface),
      tessellation_(surface.tessellate(segments)),
      index_(tessellation_.mesh, accel::BuildQuality::Fast),
      threads_(threads) {}

subdiv::FacePoint SurfaceProjector::param_of(int triangle, const std::array<double, 3>& bary) const {
    // Triangles are emitted per face, per cell (i outer, j inner), two per cell: (a,b,c), (a,c,d)
    // with a = (i,j), b = (i+1,j), c = (i+1,j+1), d = (i,j+1) (LimitSurface::tessellate()).
    const int n = tessellation_.n, per_face = 2 * n * n;
    const int f = triangle / per_face, local = triangle % per_face, cell = local / 2;
    const int i = cell / n, j = cell % n;
    const double g[4][2] = {{double(i), double(j)}, {i + 1.0, double(j)}, {i + 1.0, j + 1.0}, {double(i), j + 1.0}};
    const int corners[2][3] = {{0, 1, 2}, {0, 2, 3}};
    const int* c = corners[local % 2];
    double u = 0, v = 0;
    for (int k = 0; k < 3; ++k) u += bary[k] * g[c[k]][0], v += bary[k] * g[c[k]][1];
    return {f, std::clamp(u / n, 0.0, 1.0), std::clamp(v / n, 0.0, 1.0)};
}

std::vector<subdiv::FacePoint> SurfaceProjector::project(const std::vector<Vec3>& points,
                                                         std::vector<double>* distances) const {
    const std::vector<accel::ClosestHit> hits = index_.query_all(points, threads_);
    std::vector<subdiv::FacePoint> out(points.size());
    if (distances) distances->assign(points.size(), 0.0);
    parallel_for(static_cast<int>(points.size()), threads_, [&](int i) {
        const subdiv::LimitSurface::Projection p =
            surface_.project_with_distance(points[i], param_of(hits[i].triangle, hits[i].barycentric));
        out[i] = p.foot;
        if (distances) (*distances)[i] = std::sqrt(p.distance2);
    });
    return out;
}

DistanceStats stats_of(const std::vector<double>& d) {
    DistanceStats s;
    if (d.empty()) return s;
    double sum = 0, sum2 = 0;
    for (double x : d) sum += x, sum2 += x * x, s.max = std::max(s.max, x);
    s.mean = sum / d.size();
    s.rms = std::sqrt(sum2 / d.size());
    return s;
}

int search_level(int faces) {
    return std::max(1, static_cast<int>(std::lround(0.5 * std::log2(std::max(faces, 1) / 40.0))));
}

int face_segments(int cage_segments, int level) {
    const int shift = std::min(30, std::max(level, 1));
    return std::max(1, (cage_segments + (1 << shift) - 1) >> shift);
}

std::vector<Vec3> input_points(const Mesh& mesh, const MeasureOptions& options) {
    std::vector<MeshSample> input = sample_by_area(mesh, options.samples, options.seed, options.threads);
    const std::vector<MeshSample> vertices = sample_vertices(mesh);
    input.insert(input.end(), vertices.begin(), vertices.end());
    std::vector<Vec3> out(input.size());
    for (size_t i = 0; i < input.size(); ++i) out[i] = input[i].point;
    return out;
}

ErrorMeasurement measure(const Mesh& mesh, const accel::ClosestPointIndex& mesh_index, const subdiv::LimitSurface& surface,
                         int level, const MeasureOptions& options, MeasureTimes* times) {
    MeasureTimes local;
    MeasureTimes& t = times ? *times : local;
    const auto clock = std::chrono::steady_clock::now();
    const MeasuredMesh input{mesh, mesh_index, input_points(mesh, options)};
    t.evaluation += seconds_since(clock);
    return measure(input, surface, level, options, &t);
}

ErrorMeasurement measure(const MeasuredMesh& input, const subdiv::LimitSurface& surface, int level,
                         const MeasureOptions& options, MeasureTimes* times) {
    MeasureTimes local;
    MeasureTimes& t = times ? *times : local;
    const Mesh& mesh = input.mesh;
    auto clock = std::chrono::steady_clock::now();
    const int segments = face_segments(options.search_segments, level);
    const SurfaceProjector projector(surface, segments, options.threads);
    // The input's projections are seeded from at least kSeedSegments a face (level 4 and finer);
    // the surface's samples stay on `projector`'s parameter points, the same at every level.
    std::optional<SurfaceProjector> finer;
    if (segments < kSeedSegments) finer.emplace(surface, kSeedSegments, options.threads);
    const SurfaceProjector& seeds = finer ? *finer : projector;
    t.evaluation += seconds_since(clock);

    // Input -> surface: area samples and every used vertex.
    clock = std::chrono::steady_clock::now();
    std::vector<double> d_in;  // the projection's own distances: no second evaluation of each foot
    seeds.project(input.points, &d_in);
    t.closest_points += seconds_since(clock);
    clock = std::chrono::steady_clock::now();

    // Surface -> input: area samples of the tessellation evaluated on the exact surface, and the
    // tessellation's vertices.
    const subdiv::LimitTessellation& tess = projector.tessellation();
    const std::vector<MeshSample> on_tess =
        sample_by_area(tess.mesh, options.samples, options.seed + 1, options.threads);
    std::vector<Vec3> surface_points(on_tess.size() + tess.mesh.points.size());
    parallel_for(static_cast<int>(on_tess.size()), options.threads, [&](int i) {
        surface_points[i] = surface.evaluate(projector.param_of(on_tess[i].triangle, on_tess[i].bary)).position;
    });
    std::copy(tess.mesh.points.begin(), tess.mesh.points.end(), surface_points.begin() + on_tess.size());
    t.evaluation += seconds_since(clock);
    clock = std::chrono::steady_clock::now();
    const std::vector<accel::ClosestHit> hits = input.index.query_all(surface_points, options.threads);
    std::vector<double> d_out(hits.size());
    for (size_t i = 0; i < hits.size(); ++i) d_out[i] = hits[i].distance;
    t.closest_points += seconds_since(clock);

    ErrorMeasurement m;
    m.diagonal = bounding_box(mesh).diagonal();
    m.absolute.input_to_surface = stats_of(d_in);
    m.absolute.surface_to_input = stats_of(d_out);
    std::vector<double> both = d_in;
    both.insert(both.end(), d_out.begin(), d_out.end());
    const DistanceStats all = stats_of(both);
    m.absolute.rms = all.rms;
    m.absolute.hausdorff = all.max;
    const double inv = m.diagonal > 0 ? 1.0 / m.diagonal : 0.0;
    auto scaled = [inv](DistanceStats s) { return DistanceStats{s.rms * inv, s.mean * inv, s.max * inv}; };
    m.relative.input_to_surface = scaled(m.absolute.input_to_surface);
    m.relative.surface_to_input = scaled(m.absolute.surface_to_input);
    m.relative.rms = m.absolute.rms * inv;
    m.relative.hausdorff = m.absolute.hausdorff * inv;
    const double threshold = options.tolerance * m.diagonal;
    size_t within = 0;
    for (double x : d_in) within += x <= threshold;
    m.within_tolerance = d_in.empty() ? 0.0 : double(within) / d_in.size();
    return m;
}

}  // namespace detail

std::string MeasureOptions::validate() const {
    if (samples < 1) return "samples must be >= 1, got " + std::to_string(samples);
    if (search_segments < 1) return "search_segments must be >= 1, got " + std::to_string(search_segments);
    if (!(tolerance > 0) || !std::isfinite(tolerance)) return "tolerance must be positive and finite";
    if (threads < 0) return "threads must be >= 0, got " + std::to_string(threads);
    return {};
}

ErrorMeasurement measure_fit_error(const Mesh& mesh, const FittedSurface& surface, const MeasureOptions& options) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("measure_fit_error: " + why);
    if (surface.empty()) throw InvalidInput("measure_fit_error: the fitted surface is empty");
    const accel::ClosestPointIndex index(mesh);  // validates the mesh
    return detail::measure(mesh, index, surface.limit(), surface.search_level(), options);
}

std::vector<double> distances_to_surface(const FittedSurface& surface, const std::vector<Vec3>& points,
                                         int search_segments, int threads) {
    if (surface.empty()) throw InvalidInput("distances_to_surface: the fitted surface is empty");
    if (search_segments < 1) throw InvalidInput("distances_to_surface: search_segments must be >= 1");
    const detail::SurfaceProjector projector(surface.limit(),
                                             std::max(detail::kSeedSegments,
                                                      detail::face_segments(search_segments, surface.search_level())),
                                             threads);
    std::vector<double> out;
    projector.project(points, &out);  // throws on non-finite points
    return out;
}

}  // namespace quadcage::fit

#include "quadcage/fit/fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>

#include "common/blas_threads.h"
#include "detail/control_mesh.h"
#include "detail/costs.h"
#include "detail/measure.h"
#include "detail/normal_equations.h"
#include "detail/patch_locator.h"
#include "detail/sampling.h"
#include "quadcage/accel/closest_point.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::fit {

// ---------------------------------------------------------------------------------------------
// FittedSurface

FittedSurface::FittedSurface(const subdiv::QuadMesh& control_mesh, int level, int cage_quads, int irregular_level) {
    subdiv::LimitSurfaceOptions o;
    o.irregular_level = irregular_level;
    *this = FittedSurface(std::make_shared<const subdiv::LimitSurface>(control_mesh, o), level, cage_quads);
}

FittedSurface::FittedSurface(std::shared_ptr<const subdiv::LimitSurface> surface, int level, int cage_quads)
    : FittedSurface(std::move(surface), level, cage_quads, 4 * cage_quads) {
    search_level_ = std::max(level, 1);
}

FittedSurface::FittedSurface(std::shared_ptr<const subdiv::LimitSurface> surface, int level, int cage_faces,
                             int level1_quads)
    : surface_(std::move(surface)), level_(level), cage_faces_(cage_faces), level1_quads_(level1_quads) {
    if (!surface_) throw InvalidInput("FittedSurface: no surface");
    if (level < 0 || level > kMaxFitLevel || cage_faces < 1 || level1_quads < 3 * cage_faces)
        throw InvalidInput("FittedSurface: level must be in [0, " + std::to_string(kMaxFitLevel) +
                           "], cage_faces >= 1 and level1_quads >= 3 * cage_faces");
    const long long expected = static_cast<long long>(level1_quads) << (2 * (std::max(level, 1) - 1));
    if (surface_->num_faces() != expected)
        throw InvalidInput("FittedSurface: the control mesh has " + std::to_string(surface_->num_faces()) +
                           " quads, expected " + std::to_string(expected) + " for level " + std::to_string(level) +
                           " of a " + std::to_string(cage_faces) + "-face cage");
    search_level_ = detail::search_level(static_cast<int>(expected));
}

const subdiv::LimitSurface& FittedSurface::limit() const {
    if (!surface_) throw InvalidInput("FittedSurface: the surface is empty");
    return *surface_;
}

const subdiv::QuadMesh& FittedSurface::control_mesh() const { return limit().control_mesh(); }

subdiv::LimitPoint FittedSurface::evaluate(const subdiv::FacePoint& p) const { return limit().evaluate(p); }

subdiv::FacePoint FittedSurface::from_cage(const subdiv::FacePoint& cage_point) const {
    if (cage_point.face < 0 || cage_point.face >= cage_quads())
        throw InvalidInput("FittedSurface: cage quad " + std::to_string(cage_point.face) + " is out of range" +
                           (cage_quads() == 0 ? " (the cage has faces other than quads)" : ""));
    return subdiv::descend(cage_point, std::max(level_, 1));
}

subdiv::LimitPoint FittedSurface::evaluate_on_cage(const subdiv::FacePoint& cage_point) const {
    return limit().evaluate(from_cage(cage_point));
}

// ---------------------------------------------------------------------------------------------
// Options

std::string FitOptions::validate() const {
    auto finite_nonneg = [](double x) { return std::isfinite(x) && x >= 0; };
    if (level < 0 || level > kMaxFitLevel)
        return "level must be in [0, " + std::to_string(kMaxFitLevel) + "], got " + std::to_string(level);
    if (max_level < 0 || max_level > kMaxFitLevel)
        return "max_level must be in [0, " + std::to_string(kMaxFitLevel) + "], got " + std::to_string(max_level);
    if (!(tolerance > 0) || !std::isfinite(tolerance)) return "tolerance must be positive and finite";
    if (outer_iterations < 1) return "outer_iterations must be >= 1";
    if (extra_rounds < 0) return "extra_rounds must be >= 0";
    if (solver_iterations < 1) return "solver_iterations must be >= 1";
    if (!(min_improvement >= 0 && min_improvement < 1)) return "min_improvement must be in [0, 1)";
    if (!finite_nonneg(smoothness_start) || !finite_nonneg(smoothness_end))
        return "smoothness weights must be finite and >= 0";
    if (!(tangential_weight >= 0 && tangential_weight <= 1)) return "tangential_weight must be in [0, 1]";
    if (!finite_nonneg(surface_to_input_weight)) return "surface_to_input_weight must be finite and >= 0";
    if (!finite_nonneg(turned_over_weight)) return "turned_over_weight must be finite and >= 0";
    if (!(huber_scale > 0) || !std::isfinite(huber_scale)) return "huber_scale must be positive and finite";
    if (area_samples < 0) return "area_samples must be >= 0";
    if (max_data_points < 1) return "max_data_points must be >= 1";
    if (data_points_per_face < 0) return "data_points_per_face must be >= 0";
    if (surface_samples_per_face < 1) return "surface_samples_per_face must be >= 1";
    if (error_samples < 1) return "error_samples must be >= 1";
    if (irregular_level < 1 || irregular_level > 10) return "irregular_level must be in [1, 10]";
    if (threads < 0) return "threads must be >= 0";
    return {};
}

namespace {

using Clock = std::chrono::steady_clock;
using detail::seconds_since;
/// Data points farther than this from their foot (relative to the diagonal) are fitted point to point.
constexpr double kNearDistance = 1e-2;
/// A level's fit from the parametric start counts as no worse than the previous level only when its
/// Hausdorff distance is this much (relatively) smaller, else the refined previous fit is tried as
/// well. The distance is a maximum over samples: another sampling of the same surfaces (that of
/// ../shared/tools/check_fit.py) measures it a few percent apart, enough to reorder two levels
/// measured within a percent of each other.
constexpr double kHausdorffMargin = 0.05;
/// A sparse linear combination of the free variables.
using Combo = std::vector<std::pair<int, double>>;

void validate_layout(const layout::QuadLayout& layout) {
    const Mesh& mesh = layout.mesh;
    const int nt = mesh.num_triangles(), nq = layout.cage.num_quads();
    if (nt == 0) throw InvalidInput("fit: the layout mesh has no triangles");
    if (static_cast<int>(layout.triangle_patch.size()) != nt || static_cast<int>(layout.corner_uv.size()) != nt)
        throw InvalidInput("fit: the layout has " + std::to_string(layout.triangle_patch.size()) + " patch labels and " +
                           std::to_string(layout.corner_uv.size()) + " uv triples for " + std::to_string(nt) + " triangles");
    if (const std::string why = subdiv::check_cage(layout.cage); !why.empty())
        throw InvalidInput("fit: invalid layout cage: " + why);
    std::vector<int> per_patch(nq, 0);
    for (int t = 0; t < nt; ++t) {
        const int q = layout.triangle_patch[t];
        if (q < 0 || q >= nq)
            throw InvalidInput("fit: triangle " + std::to_string(t) + " is in patch " + std::to_string(q) + " of " +
                               std::to_string(nq));
        ++per_patch[q];
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles[t][k];
            if (v < 0 || v >= mesh.num_vertices() || !is_finite(mesh.points[v]))
                throw InvalidInput("fit: triangle " + std::to_string(t) + " has an invalid or non-finite vertex");
            for (double x : layout.corner_uv[t][k])
                if (!(x >= -1e-9 && x <= 1 + 1e-9))
                    throw InvalidInput("fit: triangle " + std::to_string(t) + " has patch coordinates outside [0,1]");
        }
    }
    for (int q = 0; q < nq; ++q)
        if (per_patch[q] == 0) throw InvalidInput("fit: patch " + std::to_string(q) + " has no triangles");
}

/// The control mesh of one level and how its points depend on the free variables.
struct LevelTopology {
    int level = 0;
    int mesh_level = 1;                 ///< max(level, 1): the level OpenSubdiv sees.
    subdiv::QuadMesh mesh;              ///< Level mesh_level control mesh (points: parametric or fitted).
    std::vector<subdiv::Stencil> map;   ///< Level 0: level-1 point -> cage corners. Empty otherwise.
    int num_vars = 0;

    std::vector<Vec3> expand(const std::vector<Vec3>& vars) const {
        if (map.empty()) return vars;
        std::vector<Vec3> out(map.size());
        for (size_t i = 0; i < map.size(); ++i)
            for (const auto& [c, w] : map[i]) out[i] += vars[c] * w;
        return out;
    }

    /// sum_k weights[k] * point[indices[k]] as a combination of the variables.
    Combo compose(const std::vector<int>& indices, const std::vector<double>& weights) const {
        Combo out;
        if (map.empty()) {
            out.reserve(indices.size());
            for (size_t k = 0; k < indices.size(); ++k) out.push_back({indices[k], weights[k]});
            return out;
        }
        std::map<int, double> acc;
        for (size_t k = 0; k < indices.size(); ++k)
            for (const auto& [c, w] : map[indices[k]]) acc[c] += weights[k] * w;
        out.assign(acc.begin(), acc.end());
        return out;
    }
};

LevelTopology make_topology(const subdiv::CageRefinement& level1, int level) {
    LevelTopology t;
    t.level = level;
    t.mesh_level = std::max(level, 1);
    if (level == 0) {
        t.mesh = level1.level1;
        t.map = level1.stencils;
        int corners = 0;
        for (const auto& s : level1.stencils)
            for (const auto& [c, w] : s) corners = std::max(corners, c + 1);
        t.num_vars = corners;
    } else {
        t.mesh = subdiv::refine_uniform(level1.level1, level - 1);
        t.num_vars = t.mesh.num_vertices();
    }
    return t;
}

/// The cage-level (quad, u, v) of every vertex of the level-L mesh (children keep their parent's
/// orientation, so the base-4 digits of a face index give its cell in the quad's 2^L grid).
std::vector<subdiv::FacePoint> vertex_params(const subdiv::QuadMesh& mesh, int L) {
    std::vector<subdiv::FacePoint> out(mesh.points.size());
    std::vector<char> seen(mesh.points.size(), 0);
    const int cells = 1 << L;
    for (int f = 0; f < mesh.num_quads(); ++f) {
        const int q = f >> (2 * L);
        int i = 0, j = 0;
        for (int d = L - 1; d >= 0; --d) {
            const int k = (f >> (2 * d)) & 3;
            i = 2 * i + (k == 1 || k == 2);
            j = 2 * j + (k == 2 || k == 3);
        }
        const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
        for (int k = 0; k < 4; ++k) {
            const int v = mesh.quads[f][k];
            if (seen[v]) continue;
            seen[v] = 1;
            out[v] = {q, double(i + di[k]) / cells, double(j + dj[k]) / cells};
        }
    }
    return out;
}

/// Initial variables: control points at their parametric positions on the mesh.
std::vector<Vec3> parametric_vars(const layout::QuadLayout& layout, const detail::PatchLocator& locator,
                                  const LevelTopology& topo, int threads) {
    if (topo.level == 0) return layout.cage.points;
    const std::vector<subdiv::FacePoint> params = vertex_params(topo.mesh, topo.mesh_level);
    std::vector<Vec3> out(params.size());
    parallel_for(static_cast<int>(params.size()), threads,
                 [&](int v) { out[v] = locator.locate(params[v].face, params[v].u, params[v].v).point; });
    return out;
}

/// Control-net Laplacian rows (point minus the mean of its edge neighbours) as variable combinations.
std::vector<Combo> laplacian_rows(const LevelTopology& topo) {
    const int n = topo.mesh.num_vertices();
    std::vector<std::set<int>> nbr(n);
    for (const auto& q : topo.mesh.quads)
        for (int k = 0; k < 4; ++k) nbr[q[k]].insert(q[(k + 1) % 4]), nbr[q[(k + 1) % 4]].insert(q[k]);
    std::vector<Combo> rows(n);
    for (int i = 0; i < n; ++i) {
        std::vector<int> idx{i};
        std::vector<double> w{1.0};
        for (int j : nbr[i]) idx.push_back(j), w.push_back(-1.0 / nbr[i].size());
        rows[i] = topo.compose(idx, w);
    }
    return rows;
}

/// An input point of the data term and its current foot point on the surface (level-L face).
struct DataPoint {
    Vec3 p;
    subdiv::FacePoint c;
};

/// The data points of `mesh`; their feet come from the layout's patch coordinates, or (no layout)
/// are left unset (face -1) for a projection onto the surface.
std::vector<DataPoint> make_data_points(const Mesh& mesh, const layout::QuadLayout* layout, const FitOptions& options) {
    std::vector<detail::MeshSample> vertices = detail::sample_vertices(mesh);
    // Not the vertices a smoothed layout added on its edges: one wherever an edge crosses a mesh
    // edge, thousands along the patch boundaries, where they would weigh the fit. The input's
    // vertices stay, and so do added ones off the edges (a coarse input's 1-to-4 splits). Layouts
    // along mesh edges keep every vertex: dropping theirs moved the genus-3 plate's fit enough that
    // its CAD export's read-back check failed (tests/cad; see the README).
    if (layout && layout->edges_smoothed) {
        std::vector<char> on_edge(mesh.num_vertices(), 0);
        for (const auto& path : layout->edge_paths)
            for (int v : path) on_edge[v] = v >= layout->input_vertices;
        vertices.erase(std::remove_if(vertices.begin(), vertices.end(),
                                      [&](const detail::MeshSample& s) {
                                          const int k = s.bary[0] == 1 ? 0 : s.bary[1] == 1 ? 1 : 2;
                                          return on_edge[mesh.triangles[s.triangle][k]] != 0;
                                      }),
                       vertices.end());
    }
    const std::vector<detail::MeshSample> area = detail::sample_by_area(mesh, options.area_samples, options.seed);
    const size_t cap = static_cast<size_t>(options.max_data_points);
    if (area.size() >= cap) vertices.clear();
    else if (vertices.size() + area.size() > cap) {
        // Keep an evenly spread, deterministic subset of the vertices.
        const size_t keep = cap - area.size();
        std::vector<detail::MeshSample> kept;
        kept.reserve(keep);
        for (size_t k = 0; k < keep; ++k) kept.push_back(vertices[k * vertices.size() / keep]);
        vertices.swap(kept);
    }
    std::vector<DataPoint> out;
    out.reserve(vertices.size() + std::min(area.size(), cap));
    auto add = [&](const detail::MeshSample& s) {
        if (!layout) return out.push_back({s.point, {}});
        const auto& uv = layout->corner_uv[s.triangle];
        double u = 0, v = 0;
        for (int k = 0; k < 3; ++k) u += s.bary[k] * uv[k][0], v += s.bary[k] * uv[k][1];
        out.push_back({s.point, {layout->triangle_patch[s.triangle], std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)}});
    };
    for (const auto& s : vertices) add(s);
    for (size_t k = 0; k < area.size() && out.size() < cap; ++k) add(area[k]);
    // A fixed shuffle, so that every prefix is spread over the whole mesh: a coarse level fits a
    // prefix (level_data_count()).
    std::mt19937 rng(options.seed + 11);
    for (size_t i = out.size(); i > 1; --i) std::swap(out[i - 1], out[rng() % i]);
    return out;
}

/// How many of the (shuffled) data points a level with `faces` limit-surface faces fits.
size_t level_data_count(size_t available, int faces, const FitOptions& o) {
    if (o.data_points_per_face <= 0) return available;
    return std::min(available, static_cast<size_t>(o.data_points_per_face) * static_cast<size_t>(faces));
}

/// The fixed limit-surface sample grid of the surface-to-input term.
std::vector<subdiv::FacePoint> surface_samples(int faces, int per_face) {
    const int k = static_cast<int>(std::ceil(std::sqrt(double(per_face)) - 1e-9));
    std::vector<subdiv::FacePoint> out;
    out.reserve(static_cast<size_t>(faces) * k * k);
    for (int f = 0; f < faces; ++f)
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < k; ++j) out.push_back({f, (i + 0.5) / k, (j + 0.5) / k});
    return out;
}

/// Stencil weights of points grouped by control face, each face's points together in memory and
/// in their index order (the normal equations read them face by face; scattered, reading them
/// took most of the assembly). Slot s (of point slot_of[i]) holds size[face] weights from at[s].
struct FaceOrderedWeights {
    std::vector<int> begin;    ///< Per face, its first slot; begin[nf] = number of points.
    std::vector<int> slot_of;  ///< Per point, its slot.
    std::vector<size_t> at;    ///< Per slot, where its weights start.
    std::vector<double> weights;

    FaceOrderedWeights(const std::vector<int>& face_of, const std::vector<int>& face_size) {
        const int nf = static_cast<int>(face_size.size()), n = static_cast<int>(face_of.size());
        begin.assign(nf + 1, 0);
        for (int f : face_of) ++begin[f + 1];
        for (int f = 0; f < nf; ++f) begin[f + 1] += begin[f];
        std::vector<int> next(begin.begin(), begin.end() - 1);
        slot_of.resize(n);
        for (int i = 0; i < n; ++i) slot_of[i] = next[face_of[i]]++;
        at.resize(n);
        size_t total = 0;
        for (int f = 0; f < nf; ++f)
            for (int s = begin[f]; s < begin[f + 1]; ++s) at[s] = total, total += face_size[f];
        weights.resize(total);
    }
    double* of_point(int i) { return weights.data() + at[slot_of[i]]; }
};

struct LevelState {
    std::vector<Vec3> vars;
    std::vector<DataPoint> data;
};

struct Context {
    const Mesh& mesh;  ///< The surface fitted.
    const FitOptions& options;
    const accel::ClosestPointIndex& index;
    double diagonal;
    int threads;

    void progress(const std::string& line) const {
        if (options.progress) options.progress(line);
    }
    MeasureOptions measure_options() const {
        MeasureOptions m;
        m.samples = options.error_samples;
        m.tolerance = options.tolerance;
        m.seed = options.seed + 101;
        m.threads = options.threads;
        return m;
    }
};

double data_rms(const subdiv::LimitSurface& surface, const std::vector<DataPoint>& data, int threads) {
    std::vector<double> d2(data.size());
    parallel_for(static_cast<int>(data.size()), threads, [&](int i) {
        const Vec3 r = surface.evaluate(data[i].c).position - data[i].p;
        d2[i] = dot(r, r);
    });
    double sum = 0;
    for (double x : d2) sum += x;
    return data.empty() ? 0.0 : std::sqrt(sum / data.size());
}

/// The limit point a stencil describes, with the surface's current control points (the same as
/// LimitSurface::evaluate() at the stencil's point, without evaluating the patch again).
subdiv::LimitPoint limit_point(const subdiv::LimitSurface& surface, const subdiv::LimitStencil& s) {
    const std::vector<Vec3>& points = surface.control_mesh().points;
    subdiv::LimitPoint out;
    for (size_t k = 0; k < s.indices.size(); ++k) {
        const Vec3& x = points[s.indices[k]];
        out.position += x * s.position_weights[k];
        out.du += x * s.du_weights[k];
        out.dv += x * s.dv_weights[k];
    }
    const Vec3 n = cross(out.du, out.dv);
    const double len = norm(n);
    if (len > 0) out.normal = n / len;
    return out;
}

/// New feet of the data points on the (moved) surface: the better of a local projection from the
/// old foot (if set: face >= 0) and one from the closest point of a tessellation of the whole surface. The local walk
/// alone stays in the basin of its old foot: where a distorted patch map put a foot on the wrong
/// side of a thin part, the fit pulls the surface there into a fin and never lets go. Returns the
/// RMS distance of the data points to their new feet.
double update_correspondences(const subdiv::LimitSurface& surface, std::vector<DataPoint>* data, int threads) {
    const int n = static_cast<int>(data->size());
    std::vector<Vec3> points(n);
    for (int i = 0; i < n; ++i) points[i] = (*data)[i].p;
    // kSeedSegments (4) per face side: 32 triangles per face. Its index is built (in part on one
    // thread: the triangles, Embree's build) while the local walks run.
    auto building = std::async(
        resolve_threads(threads) > 1 ? std::launch::async : std::launch::deferred,
        [&] { return std::make_unique<const detail::SurfaceProjector>(surface, detail::kSeedSegments, threads); });
    // The local walks first: their distances bound the global search.
    std::vector<double> d2(n, std::numeric_limits<double>::infinity()), limit(n);
    parallel_for(n, threads, [&](int i) {
        DataPoint& d = (*data)[i];
        if (d.c.face >= 0) {
            const subdiv::LimitSurface::Projection local = surface.project_with_distance(d.p, d.c);
            d.c = local.foot;
            d2[i] = local.distance2;
        }
        limit[i] = std::sqrt(d2[i]);
    });
    // A walk from the tessellation's closest point can only find a closer foot when that point is
    // closer than the local foot (up to the tessellation's own error), so the search only looks
    // that far: most points are near their local foot, and the small sphere prunes most of the
    // tessellation.
    const std::unique_ptr<const detail::SurfaceProjector> built = building.get();
    const detail::SurfaceProjector& projector = *built;
    const std::vector<accel::ClosestHit> seeds = projector.index().query_all_within(points, limit, threads);
    parallel_for(n, threads, [&](int i) {
        if (seeds[i].triangle < 0 || !(seeds[i].distance * seeds[i].distance < d2[i])) return;
        DataPoint& d = (*data)[i];
        const subdiv::LimitSurface::Projection global =
            surface.project_with_distance(d.p, projector.param_of(seeds[i].triangle, seeds[i].barycentric));
        if (global.distance2 < d2[i]) d.c = global.foot, d2[i] = global.distance2;
    });
    double sum = 0;
    for (double x : d2) sum += x;
    return d2.empty() ? 0.0 : std::sqrt(sum / d2.size());
}

std::string format(const char* fmt, double a, double b = 0, double c = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a, b, c);
    return buf;
}

/// Checks that a stencil on `face` uses the face's control points, in their (sorted) order.
void check_clique(const detail::NormalEquations& normal, int face, const Combo& c) {
    const std::vector<int>& vars = normal.clique(face);
    QC_CHECK(vars.size() == c.size() && std::equal(vars.begin(), vars.end(), c.begin(),
                                                   [](int v, const auto& vw) { return v == vw.first; }),
             "fit: a stencil on face " + std::to_string(face) + " uses other control points than the face");
}

/// check_clique() of a stencil's own control points (levels >= 1, where they are the variables).
void check_clique(const detail::NormalEquations& normal, int face, const std::vector<int>& indices) {
    QC_CHECK(normal.clique(face) == indices,
             "fit: a stencil on face " + std::to_string(face) + " uses other control points than the face");
}

/// Runs the rounds of one level from `state` (variables and correspondences on topo.mesh_level
/// faces); leaves the best variables and their correspondences in `state`.
LevelReport fit_level(const Context& ctx, const LevelTopology& topo, subdiv::LimitSurface& surface, LevelState& state,
                      int extra_rounds) {
    const FitOptions& o = ctx.options;
    LevelReport rep;
    rep.level = topo.level;
    rep.control_points = topo.num_vars;
    StageSeconds& sec = rep.seconds;

    const std::vector<Combo> laplacian = laplacian_rows(topo);
    const std::vector<subdiv::FacePoint> s_params = surface_samples(surface.num_faces(), o.surface_samples_per_face);
    const int nd = static_cast<int>(state.data.size()), ns = static_cast<int>(s_params.size());
    const bool direct = o.solver == FitSolver::Direct;
    // The surface samples' closest input points of the previous round: the distance to the old
    // closest point bounds the search for the new one.
    std::vector<accel::ClosestHit> hits;
    // Ceres minimises 1/2 sum |r|^2: weight 1/N per data point, beta/N per surface sample on
    // average (each is weighted by its share of the surface area), lambda/N per control point, so
    // the terms' sizes do not depend on the sample counts.
    const double data_weight = 1.0 / std::max(nd, 1), surface_weight = o.surface_to_input_weight / std::max(ns, 1);
    const double delta2 = std::pow(o.huber_scale * ctx.diagonal, 2);

    surface.set_points(topo.expand(state.vars));
    auto clock = Clock::now();
    double best = data_rms(surface, state.data, ctx.threads);
    sec.evaluation += seconds_since(clock);
    LevelState best_state = state;
    rep.stop_reason = "max_iterations";
    // FitSolver::Direct: the pattern of the normal equations, fixed for the level: one clique per
    // face (the control points of its stencil, the same at every point of the face) and one per
    // Laplacian row.
    const int nf = surface.num_faces();
    std::optional<detail::NormalEquations> normal;
    if (direct) {
        std::vector<std::vector<int>> cliques(nf + laplacian.size());
        parallel_for(nf, ctx.threads, [&](int f) {
            const subdiv::LimitStencil st = surface.stencil({f, 0.5, 0.5});
            for (const auto& vw : topo.compose(st.indices, st.position_weights)) cliques[f].push_back(vw.first);
        });
        for (size_t k = 0; k < laplacian.size(); ++k)
            for (const auto& vw : laplacian[k]) cliques[nf + k].push_back(vw.first);
        normal.emplace(topo.num_vars, std::move(cliques));
    }
    std::vector<int> clique_size(nf), sample_face(ns);
    if (normal)
        for (int f = 0; f < nf; ++f) clique_size[f] = static_cast<int>(normal->clique(f).size());
    for (int i = 0; i < ns; ++i) sample_face[i] = s_params[i].face;
    // The surface samples keep their (face, u, v) all level, and so their weights on the variables:
    // Ceres' cost functions take the position weights as combinations (and each round evaluates
    // the samples' limit points afresh); the direct solver keeps the position and derivative
    // weights packed by face, in the order of the face's clique. Kept whole, the samples' stencils
    // took more memory than all else of a fit with 64 samples a face.
    std::optional<FaceOrderedWeights> surf_packed, surf_du, surf_dv;
    if (direct) {
        surf_packed.emplace(sample_face, clique_size);
        surf_du.emplace(sample_face, clique_size);
        surf_dv.emplace(sample_face, clique_size);
    }
    std::vector<Combo> surf_combo(direct ? 0 : ns);
    parallel_for(ns, ctx.threads, [&](int i) {
        thread_local subdiv::LimitStencil s;  // storage reused from sample to sample
        surface.stencil(s_params[i], &s);
        Combo c = topo.compose(s.indices, s.position_weights);
        if (!direct) {
            surf_combo[i] = std::move(c);
            return;
        }
        const int face = s_params[i].face;
        check_clique(*normal, face, c);
        double* w = surf_packed->of_point(i);
        for (const auto& vw : c) *w++ = vw.second;
        for (const auto& [packed, weights] :
             {std::pair{&*surf_du, &s.du_weights}, std::pair{&*surf_dv, &s.dv_weights}}) {
            const Combo d = topo.compose(s.indices, *weights);
            check_clique(*normal, face, d);
            double* out = packed->of_point(i);
            for (const auto& vw : d) *out++ = vw.second;
        }
    });
    // A sample's limit point (position and derivatives) with the variables `vars`.
    auto surface_point = [&](int i, const std::vector<Vec3>& vars) {
        if (!direct) return surface.evaluate(s_params[i]);
        subdiv::LimitPoint e;
        const std::vector<int>& clique = normal->clique(s_params[i].face);
        const double *wp = surf_packed->of_point(i), *wu = surf_du->of_point(i), *wv = surf_dv->of_point(i);
        for (size_t a = 0; a < clique.size(); ++a) {
            const Vec3& x = vars[clique[a]];
            e.position += x * wp[a];
            e.du += x * wu[a];
            e.dv += x * wv[a];
        }
        return e;
    };
    // Once the data RMS stalls, one last round with the final (smallest) smoothness weight, so an
    // early stop does not leave the surface biased by a large smoothness term.
    bool final_round = false;
    const int rounds = o.outer_iterations + extra_rounds;
    for (int round = 0; round < rounds; ++round) {
        const double t = o.outer_iterations > 1 ? std::min(1.0, double(round) / (o.outer_iterations - 1)) : 1.0;
        const double lambda = final_round ? o.smoothness_end
                              : o.smoothness_start > 0 && o.smoothness_end > 0
                                  ? o.smoothness_start * std::pow(o.smoothness_end / o.smoothness_start, t)
                                  : o.smoothness_start + (o.smoothness_end - o.smoothness_start) * t;

        // Tangential weight of the data residuals: point-to-point in the first round (the surface
        // normals of the start can be meaningless: the limit of a coarse cage folds onto itself),
        // then halving down to tangential_weight.
        const double mu = std::max(o.tangential_weight, std::ldexp(1.0, -round));
        const double near2 = std::pow(kNearDistance * ctx.diagonal, 2);
        // Stencils of the data correspondences and of the surface samples.
        clock = Clock::now();
        std::vector<Combo> data_combo(direct ? 0 : nd);
        std::optional<FaceOrderedWeights> data_packed;
        if (direct) {
            std::vector<int> data_face(nd);
            for (int i = 0; i < nd; ++i) data_face[i] = state.data[i].c.face;
            data_packed.emplace(data_face, clique_size);
        }
        std::vector<Vec3> surf_pos(ns), data_pos(nd), data_normal(nd);
        std::vector<double> surf_weight(ns);
        parallel_for(nd, ctx.threads, [&](int i) {
            thread_local subdiv::LimitStencil s;  // storage reused from point to point
            surface.stencil(state.data[i].c, &s);
            if (direct && topo.map.empty()) {
                // The stencil is already on the variables (compose() would copy it as it is).
                check_clique(*normal, state.data[i].c.face, s.indices);
                std::copy(s.position_weights.begin(), s.position_weights.end(), data_packed->of_point(i));
            } else {
                Combo c = topo.compose(s.indices, s.position_weights);
                if (direct) {
                    check_clique(*normal, state.data[i].c.face, c);
                    double* w = data_packed->of_point(i);
                    for (const auto& vw : c) *w++ = vw.second;
                } else {
                    data_combo[i] = std::move(c);
                }
            }
            const subdiv::LimitPoint e = limit_point(surface, s);
            data_pos[i] = e.position;
            // Squared-distance minimisation approximates the distance well only near the surface
            // (distance small against the curvature radius); far points (a coarse level's surface,
            // which can fold onto itself) stay point-to-point.
            const Vec3 r = e.position - state.data[i].p;
            if (mu < 1 && dot(r, r) <= near2) data_normal[i] = e.normal;
        });
        // S_u and S_v of the samples, for the turned-over term only.
        const bool turned_over_term = o.turned_over_weight > 0 && o.surface_to_input_weight > 0;
        std::vector<Vec3> surf_du_now(turned_over_term ? ns : 0), surf_dv_now(turned_over_term ? ns : 0);
        parallel_for(ns, ctx.threads, [&](int i) {
            const subdiv::LimitPoint e = surface_point(i, state.vars);
            surf_pos[i] = e.position;
            if (turned_over_term) surf_du_now[i] = e.du, surf_dv_now[i] = e.dv;
            surf_weight[i] = norm(cross(e.du, e.dv));
        });
        // Each surface sample stands for the limit-surface area around it (|S_u x S_v| times the
        // same parametric cell), so the surface-to-input term integrates over the surface's area as
        // design.md §6 measures it. With equal weights a stretched part of the surface (a fin
        // pulled out between two parts of the input) counted as little as any other face.
        double area_sum = 0;
        for (double a : surf_weight) area_sum += a;
        for (double& a : surf_weight) a = area_sum > 0 ? surface_weight * ns * a / area_sum : surface_weight;
        sec.evaluation += seconds_since(clock);

        clock = Clock::now();
        if (hits.empty()) {
            hits = ctx.index.query_all(surf_pos, ctx.threads);
        } else {
            // Within the distance to the old closest point (a point of the mesh), with a margin for
            // rounding; a miss (rounding at the margin) is searched again without a limit.
            std::vector<double> limit(ns);
            for (int i = 0; i < ns; ++i) limit[i] = norm(surf_pos[i] - hits[i].point) * (1 + 1e-9) + 1e-12 * ctx.diagonal;
            hits = ctx.index.query_all_within(surf_pos, limit, ctx.threads);
            for (int i = 0; i < ns; ++i)
                if (hits[i].triangle < 0) hits[i] = ctx.index.query(surf_pos[i]);
        }
        sec.closest_points += seconds_since(clock);

        clock = Clock::now();
        std::vector<double> x(3 * static_cast<size_t>(topo.num_vars));
        for (int v = 0; v < topo.num_vars; ++v)
            for (int d = 0; d < 3; ++d) x[3 * v + d] = state.vars[v][d];
        // Data points and surface samples whose stencils use the same control points (those on
        // one control face) go into one residual block: Ceres then builds the structure of J^T J
        // from one product per face and pair of its control points, not one per point (that
        // set-up took about a quarter of botijo's fit). A Huber loss per block would then act
        // on a whole face, so the Huber loss is applied per point by reweighting: each residual
        // is scaled by sqrt(rho'(|r|^2)) at the round's start (1 within the threshold), which is
        // what the single Levenberg-Marquardt step of a round sees of it.
        // Each point's rows, scaled, in parallel; then grouped by face in order.
        auto scaled = [&](detail::StencilRows rows, const Vec3& at, double weight) {
            // rows at scale 1; `at` is the current limit point, where the residual is measured.
            double s2 = 0;
            for (int r = 0; r < rows.rows; ++r) {
                const double v = rows.a[3 * r] * at.x + rows.a[3 * r + 1] * at.y + rows.a[3 * r + 2] * at.z - rows.b[r];
                s2 += v * v;
            }
            const double scale = std::sqrt(weight * (s2 <= delta2 ? 1.0 : std::sqrt(delta2 / s2)));
            for (double& e : rows.a) e *= scale;
            for (double& e : rows.b) e *= scale;
            return rows;
        };
        auto weights_of = [](const Combo& c) {
            std::vector<double> out;
            out.reserve(c.size());
            for (const auto& vw : c) out.push_back(vw.second);
            return out;
        };
        // The direct path keeps the rows by face (slots of data_packed and surf_packed) and reads
        // their weights from there; Ceres' cost functions own theirs.
        std::vector<detail::StencilRows> data_rows(nd), surf_rows(o.surface_to_input_weight > 0 ? ns : 0);
        std::vector<char> surf_used(surf_rows.size(), 0);
        parallel_for(nd, ctx.threads, [&](int i) {
            const Vec3& n = data_normal[i];
            std::vector<double> wi = direct ? std::vector<double>{} : weights_of(data_combo[i]);
            data_rows[direct ? data_packed->slot_of[i] : i] =
                scaled(mu < 1 && dot(n, n) > 0.5
                           ? detail::tangent_weighted_rows(std::move(wi), state.data[i].p, n, mu, 1.0)
                           : detail::point_to_point_rows(std::move(wi), state.data[i].p, 1.0),
                       data_pos[i], data_weight);
        });
        // The turned-over term (FitOptions::turned_over_weight): one row for each surface sample
        // where the surface turns over against the input, sum_a (wu_a g_u + wv_a g_v) . x_a - b
        // over its face's control points (wu, wv: the weights of S_u and S_v), by the samples'
        // slots as surf_rows, made beside them.
        struct TurnedOverRow {
            Vec3 g_u, g_v;
            double b = 0;
            bool on = false;
        };
        std::vector<TurnedOverRow> turned_rows(turned_over_term ? ns : 0);
        // The row of sample i, whose closest input triangle has unit normal `unit`; off where the
        // surface faces the input's way.
        const auto turned_over_row = [&](int i, const Vec3& unit) {
            const Vec3 &du = surf_du_now[i], &dv = surf_dv_now[i];
            const double lu = norm(du), lv = norm(dv);
            if (!(lu > 0) || !(lv > 0)) return TurnedOverRow{};
            const double sine = dot(cross(du, dv), unit) / (lu * lv);
            if (sine >= 0) return TurnedOverRow{};
            // d sine = (dS_u . (S_v x n) + dS_v . (n x S_u)) / (|S_u| |S_v|), scaled.
            const double scale = o.turned_over_weight * ctx.diagonal * std::sqrt(surf_weight[i]);
            const double k = scale / (lu * lv);
            // At the current control points the row's sum is g_u . S_u + g_v . S_v, twice the
            // scaled sine (S_u x S_v is quadratic in them); b makes the residual the scaled sine.
            TurnedOverRow r{cross(dv, unit) * k, cross(unit, du) * k, 0, true};
            r.b = dot(r.g_u, du) + dot(r.g_v, dv) - scale * sine;
            return r;
        };
        parallel_for(static_cast<int>(surf_rows.size()), ctx.threads, [&](int i) {
            const Triangle& tri = ctx.mesh.triangles[hits[i].triangle];
            const Vec3& a = ctx.mesh.points[tri[0]];
            const Vec3 n = cross(ctx.mesh.points[tri[1]] - a, ctx.mesh.points[tri[2]] - a);
            const double len = norm(n);
            if (!(len > 0)) return;  // no rows
            const int slot = direct ? surf_packed->slot_of[i] : i;
            std::vector<double> wi = direct ? std::vector<double>{} : weights_of(surf_combo[i]);
            // Where the foot lies on an edge or at a vertex of its triangle (a zero weight), the
            // distance to the mesh grows along the offset from the foot, not along the triangle's
            // normal: the plane across that offset.
            const std::array<double, 3>& bary = hits[i].barycentric;
            const Vec3 offset = surf_pos[i] - hits[i].point;
            const double reach = norm(offset);
            const bool on_feature = bary[0] == 0 || bary[1] == 0 || bary[2] == 0;
            const Vec3 normal = o.surface_feature_feet && on_feature && reach > 0 ? offset / reach : n / len;
            detail::StencilRows rows = detail::point_to_plane_rows(std::move(wi), hits[i].point, normal, 1.0);
            surf_rows[slot] = scaled(std::move(rows), surf_pos[i], surf_weight[i]);
            surf_used[slot] = 1;
            if (turned_over_term) turned_rows[slot] = turned_over_row(i, n / len);
        });
        if (direct) {
            // The rows of each face's points, then the normal equations (design: normal_equations.h).
            const double lap2 = lambda > 0 ? lambda / laplacian.size() : 0.0;
            const double t_rows = seconds_since(clock);
            normal->assemble(
                [&](int k, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtb) {
                    const std::vector<int>& vars = normal->clique(k);
                    const int m = static_cast<int>(vars.size());
                    if (k >= nf) {
                        // lap2 |sum_a w_a x_a|^2 for each coordinate: blocks lap2 w_a w_b I.
                        if (lap2 == 0) return;
                        std::vector<double> w(m);
                        for (const auto& [v, weight] : laplacian[k - nf])
                            w[std::lower_bound(vars.begin(), vars.end(), v) - vars.begin()] = weight;
                        for (int b = 0; b < m; ++b)
                            for (int a = 0; a <= b; ++a)
                                for (int d = 0; d < 3; ++d) jtj(3 * a + d, 3 * b + d) = lap2 * w[a] * w[b];
                        return;
                    }
                    // The face's data points, then its surface samples, each in index order.
                    const int d0 = data_packed->begin[k], d1 = data_packed->begin[k + 1];
                    const int s0 = surf_rows.empty() ? 0 : surf_packed->begin[k];
                    const int s1 = surf_rows.empty() ? 0 : surf_packed->begin[k + 1];
                    int rows = 0;
                    for (int q = d0; q < d1; ++q) rows += data_rows[q].rows;
                    for (int q = s0; q < s1; ++q) rows += surf_used[q] ? surf_rows[q].rows : 0;
                    if (!turned_rows.empty())
                        for (int q = s0; q < s1; ++q) rows += turned_rows[q].on ? 1 : 0;
                    if (rows == 0) return;
                    Eigen::MatrixXd j(rows, 3 * m);
                    Eigen::VectorXd b(rows);
                    int row = 0;
                    auto put = [&](const detail::StencilRows& r, const double* w) {
                        for (int q = 0; q < r.rows; ++q, ++row) {
                            for (int a = 0; a < m; ++a)
                                for (int d = 0; d < 3; ++d) j(row, 3 * a + d) = w[a] * r.a[3 * q + d];
                            b(row) = r.b[q];
                        }
                    };
                    for (int q = d0; q < d1; ++q)
                        put(data_rows[q], data_packed->weights.data() + data_packed->at[q]);
                    for (int q = s0; q < s1; ++q)
                        if (surf_used[q]) put(surf_rows[q], surf_packed->weights.data() + surf_packed->at[q]);
                    if (!turned_rows.empty())
                        for (int q = s0; q < s1; ++q) {
                            const TurnedOverRow& t = turned_rows[q];
                            if (!t.on) continue;
                            const double* wu = surf_du->weights.data() + surf_du->at[q];
                            const double* wv = surf_dv->weights.data() + surf_dv->at[q];
                            for (int a = 0; a < m; ++a)
                                for (int d = 0; d < 3; ++d) j(row, 3 * a + d) = wu[a] * t.g_u[d] + wv[a] * t.g_v[d];
                            b(row++) = t.b;
                        }
                    jtj.selfadjointView<Eigen::Upper>().rankUpdate(j.transpose());
                    jtb.noalias() = j.transpose() * b;
                },
                ctx.threads);
            // Ceres' Levenberg-Marquardt starts with the damping diag(J^T J) / 1e4; the same here,
            // raised tenfold while the damped matrix is not positive definite.
            const double t_asm = seconds_since(clock);
            std::vector<double> next;
            bool solved = false;
            for (double damping = 1e-4; !solved && damping <= 1e2; damping *= 10) solved = normal->solve(x, damping, &next);
            const double setup = seconds_since(clock);
            ctx.progress(format("  normal equations: rows %.2f s, assembly %.2f s, total %.2f s", t_rows, t_asm, setup));
            sec.solve += setup;
            rep.iterations = round + 1;
            rep.solver_iterations += 1;
            if (!solved) {
                rep.stop_reason = "solver failed: the normal equations are not positive definite";
                break;
            }
            x.swap(next);
        } else {
            ceres::Problem problem;
            for (int v = 0; v < topo.num_vars; ++v) problem.AddParameterBlock(&x[3 * v], 3);
            std::vector<double*> blocks;
            auto split = [&](const Combo& c, std::vector<double>* w) {
                blocks.clear();
                w->clear();
                for (const auto& [v, weight] : c) blocks.push_back(&x[3 * v]), w->push_back(weight);
            };
            std::vector<double> w;
            // The stencils of all points on one face use the face's control points, in the same
            // (sorted) order, so the group of a point is that of its face.
            std::vector<int> group_of(surface.num_faces(), -1);
            std::vector<std::vector<int>> group_vars;
            std::vector<std::vector<detail::StencilRows>> groups;
            auto add = [&](int face, const Combo& c, detail::StencilRows&& rows) {
                int& g = group_of[face];
                if (g < 0) {
                    g = static_cast<int>(groups.size());
                    group_vars.emplace_back();
                    for (const auto& vw : c) group_vars.back().push_back(vw.first);
                    groups.emplace_back();
                }
                const std::vector<int>& vars = group_vars[g];
                QC_CHECK(vars.size() == c.size() && std::equal(vars.begin(), vars.end(), c.begin(),
                                                                [](int v, const auto& vw) { return v == vw.first; }),
                         "fit: two stencils on face " + std::to_string(face) + " use different control points");
                groups[g].push_back(std::move(rows));
            };
            for (int i = 0; i < nd; ++i) add(state.data[i].c.face, data_combo[i], std::move(data_rows[i]));
            for (int i = 0; i < static_cast<int>(surf_rows.size()); ++i)
                if (surf_used[i]) add(s_params[i].face, surf_combo[i], std::move(surf_rows[i]));
            // A group with more rows than unknowns (a coarse level's faces hold many points) goes in
            // as its Cholesky-compressed equivalent: the same steps, fewer rows for Ceres to multiply.
            std::vector<std::unique_ptr<ceres::CostFunction>> compressed(groups.size());
            std::vector<int> tall;
            for (size_t g = 0; g < groups.size(); ++g) {
                int rows = 0;
                for (const detail::StencilRows& r : groups[g]) rows += r.rows;
                if (rows > 3 * static_cast<int>(group_vars[g].size())) tall.push_back(static_cast<int>(g));
            }
            parallel_for(static_cast<int>(tall.size()), ctx.threads,
                         [&](int k) { compressed[tall[k]] = detail::compressed_group_cost(groups[tall[k]]); });
            for (size_t g = 0; g < groups.size(); ++g) {
                blocks.clear();
                for (int v : group_vars[g]) blocks.push_back(&x[3 * v]);
                problem.AddResidualBlock(compressed[g] ? compressed[g].release() : new detail::StencilGroupCost(std::move(groups[g])),
                                         nullptr, blocks);
            }
            for (int i = 0; i < static_cast<int>(turned_rows.size()); ++i) {
                const TurnedOverRow& t = turned_rows[i];
                if (!t.on) continue;
                subdiv::LimitStencil st;
                surface.stencil(s_params[i], &st);
                const Combo cu = topo.compose(st.indices, st.du_weights), cv = topo.compose(st.indices, st.dv_weights);
                QC_CHECK(cu.size() == cv.size(), "fit: S_u and S_v of one point use different control points");
                std::vector<Vec3> coefficients(cu.size());
                blocks.clear();
                for (size_t a = 0; a < cu.size(); ++a) {
                    QC_CHECK(cu[a].first == cv[a].first, "fit: S_u and S_v of one point use different control points");
                    coefficients[a] = t.g_u * cu[a].second + t.g_v * cv[a].second;
                    blocks.push_back(&x[3 * cu[a].first]);
                }
                problem.AddResidualBlock(detail::linear_row_cost(std::move(coefficients), t.b), nullptr, blocks);
            }
            if (lambda > 0) {
                const double scale = std::sqrt(lambda / laplacian.size());
                for (const Combo& row : laplacian) {
                    split(row, &w);
                    problem.AddResidualBlock(detail::smoothness_cost(w, scale), nullptr, blocks);
                }
            }
            ceres::Solver::Options so;
            // Dense only for a handful of variables: the dense path forms the full Jacobian (rows x 3n).
            so.linear_solver_type = topo.num_vars <= 16 ? ceres::DENSE_NORMAL_CHOLESKY : ceres::SPARSE_NORMAL_CHOLESKY;
            so.num_threads = ctx.threads;
            so.max_num_iterations = o.solver_iterations;
            // Ceres' gradient and parameter tolerances are absolute (or relative to |x| plus an absolute
            // term): on a mesh a millionth of a unit across they declare convergence before the first
            // step (eight at scale 1e-6 stopped at level 1 with relative RMS 3.2e-3 instead of 2.0e-3).
            // The rounds decide when to stop (min_improvement), so the solver always takes its steps.
            so.gradient_tolerance = 0;
            so.parameter_tolerance = 0;
            so.function_tolerance = 0;
            so.logging_type = ceres::SILENT;
            so.minimizer_progress_to_stdout = false;
            ceres::Solver::Summary summary;
            const double setup = seconds_since(clock);
            {
                const quadcage::detail::ScopedBlasThreads blas;  // CHOLMOD's dense kernels (blas_threads.h)
                ceres::Solve(so, &problem, &summary);
            }
            ctx.progress(format("  ceres: set-up %.2f s, preprocess %.2f s, jacobians %.2f s", setup,
                                summary.preprocessor_time_in_seconds, summary.jacobian_evaluation_time_in_seconds) +
                         format(", linear solver %.2f s, total %.2f s", summary.linear_solver_time_in_seconds,
                                summary.total_time_in_seconds));
            sec.solve += seconds_since(clock);
            rep.iterations = round + 1;
            rep.solver_iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
            if (!summary.IsSolutionUsable()) {
                rep.stop_reason = "solver failed: " + summary.message;
                break;
            }
        }
        for (int v = 0; v < topo.num_vars; ++v) state.vars[v] = {x[3 * v], x[3 * v + 1], x[3 * v + 2]};

        // New correspondences on the new surface: the better of the local projection from the old
        // foot and a projection from the closest point of a tessellation (update_correspondences).
        clock = Clock::now();
        surface.set_points(topo.expand(state.vars));
        const double rms = update_correspondences(surface, &state.data, ctx.threads);
        sec.evaluation += seconds_since(clock);
        ctx.progress("level " + std::to_string(topo.level) + " round " + std::to_string(round + 1) +
                     format(": data rms %.3e (relative), smoothness %.1e", rms / ctx.diagonal, lambda));
        if (rms > best) {
            state = best_state;  // the last round made things worse: keep the previous fit
            rep.stop_reason = "no improvement";
            break;
        }
        const double gain = best > 0 ? (best - rms) / best : 0.0;
        best = rms;
        best_state = state;
        if (final_round) {
            rep.stop_reason = "converged";
            break;
        }
        if (gain < o.min_improvement) {
            rep.stop_reason = format("converged (data rms improved by %.2g%% < %.2g%%)", 100 * gain, 100 * o.min_improvement);
            if (lambda <= o.smoothness_end || round + 1 == rounds) break;
            final_round = true;
        }
    }
    surface.set_points(topo.expand(state.vars));
    return rep;
}

void fill_error(LevelReport* rep, const ErrorMeasurement& m) {
    rep->absolute = m.absolute;
    rep->relative = m.relative;
    rep->diagonal = m.diagonal;
    rep->within_tolerance = m.within_tolerance;
}

}  // namespace

/// What a fit starts from: the layout's cage with its patch maps (fit_surface()), or a control
/// mesh of any polygons lying near the mesh (fit_control_mesh()).
struct Source {
    const Mesh& mesh;                     ///< The surface fitted.
    const layout::QuadLayout* layout;     ///< Patch maps for the parametric start; null: start from the cage.
    const accel::ClosestPointIndex& index;  ///< Of `mesh`.
    double build_seconds;                 ///< Building `index`.
    subdiv::CageRefinement level1;        ///< The cage refined once, with its stencils on the cage's points.
    std::vector<Vec3> cage_points;        ///< The level-0 points (variables of level 0).
    int cage_faces, level1_quads;
    std::string description;              ///< "cage of 40 quads", for the progress line.
};

/// The level passed to detail::face_segments() for a surface of `level` over `source`.
int search_level_of(const Source& src, int level, int faces) {
    return src.layout ? level : detail::search_level(faces);
}

FitResult fit_from(const Source& src, const FitOptions& options) {
    const auto start = Clock::now();
    const int threads = resolve_threads(options.threads);
    const accel::ClosestPointIndex& index = src.index;
    const double build_seconds = src.build_seconds;
    const Context ctx{src.mesh, options, index, bounding_box(src.mesh).diagonal(), threads};
    if (!(ctx.diagonal > 0)) throw InvalidInput("fit: the mesh has a zero bounding box");

    auto clock = Clock::now();
    const subdiv::CageRefinement& level1 = src.level1;
    std::optional<detail::PatchLocator> locator;
    if (src.layout) locator.emplace(*src.layout);
    std::vector<DataPoint> data0 = make_data_points(src.mesh, src.layout, options);
    const double setup_seconds = seconds_since(clock);
    // The input side of every level's error measurement, sampled once (evaluation time of the first level).
    clock = Clock::now();
    const detail::MeasuredMesh measured{src.mesh, index,
                                        detail::input_points(src.mesh, ctx.measure_options())};
    const double measure_setup_seconds = seconds_since(clock);
    ctx.progress("fit: " + std::to_string(data0.size()) + " data points, " + src.description);

    subdiv::LimitSurfaceOptions lso;
    lso.irregular_level = options.irregular_level;
    lso.threads = options.threads;

    // Both modes fit levels in turn, each from 2 on with the previous fit, refined, as a second
    // start, so a level need not end worse than the one before it, and `--level K` ends with the
    // same fit as the tolerance mode's level K. Level 1 never starts from level 0's fit: level 0
    // is the 8g-8 corners through the level-0 -> 1 map, whose limit can fold onto itself (the
    // 2 x 2 torus cage), a poor start (on botijo, level 1 from it ends at Hausdorff 7.1e-2, from
    // its parametric start at 3.8e-2). So `--level K` for K >= 1 starts at level 1.
    const int first = options.mode == FitMode::Level ? std::min(options.level, 1) : 0;
    const int last = options.mode == FitMode::Level ? options.level : options.max_level;
    FitResult result;
    LevelState state;
    std::shared_ptr<subdiv::LimitSurface> surface, kept_surface;  // kept: of the last accepted level
    std::vector<Vec3> kept_vars;
    LevelTopology topo;
    for (int level = first; level <= last; ++level) {
        const auto level_start = Clock::now();
        StageSeconds pre;
        clock = Clock::now();
        LevelTopology next = make_topology(level1, level);
        // Start of a layout's fit: control points at their patch coordinates on the mesh,
        // correspondences from the patch coordinates of the data points. Of a control mesh's fit:
        // the control mesh refined, and the data points' feet (unset here) projected onto its limit.
        const std::vector<Vec3> parametric = src.layout ? parametric_vars(*src.layout, *locator, next, threads)
                                             : level == 0 ? src.cage_points
                                                          : next.mesh.points;
        const size_t nd = level_data_count(data0.size(), next.mesh.num_quads(), options);
        LevelState parametric_state;
        parametric_state.data.assign(data0.begin(), data0.begin() + nd);
        if (src.layout)
            for (DataPoint& d : parametric_state.data) d.c = subdiv::descend(d.c, next.mesh_level);
        parametric_state.vars = parametric;
        LevelState warm;
        bool warm_new_points = false;
        if (level >= 2) {
            // The previous fit, refined: the same limit surface on the new control mesh, with the
            // previous feet one level down (the same surface points). Data points new at this
            // level start at their patch coordinates and are projected before the fit.
            warm.data = parametric_state.data;
            const bool deeper = next.mesh_level > topo.mesh_level;
            for (size_t i = 0; i < std::min(nd, state.data.size()); ++i)
                warm.data[i].c = deeper ? subdiv::to_child(state.data[i].c) : state.data[i].c;
            warm_new_points = nd > state.data.size();
            subdiv::QuadMesh prev = topo.mesh;
            prev.points = topo.expand(state.vars);
            if (deeper) {
                // Faces of both refinements come in the same order; their vertex numbering need not
                // (OpenSubdiv numbers edges as it builds them), so match vertices through face corners.
                const subdiv::QuadMesh refined = subdiv::refine_uniform(prev, 1);
                QC_CHECK(refined.num_quads() == next.mesh.num_quads(), "warm start: face counts differ");
                warm.vars.assign(next.mesh.points.size(), Vec3{});
                for (int f = 0; f < refined.num_quads(); ++f)
                    for (int k = 0; k < 4; ++k) warm.vars[next.mesh.quads[f][k]] = refined.points[refined.quads[f][k]];
            } else {
                warm.vars = prev.points;
            }
        }
        pre.parameterization += seconds_since(clock) + (level == first ? setup_seconds + build_seconds : 0.0);
        clock = Clock::now();
        surface = std::make_shared<subdiv::LimitSurface>(next.mesh, lso);
        pre.evaluation += seconds_since(clock) + (level == first ? measure_setup_seconds : 0.0);
        topo = std::move(next);
        const int search_level = search_level_of(src, level, topo.mesh.num_quads());
        LevelReport rep;
        if (options.measure_unfitted) {
            surface->set_points(topo.expand(parametric));
            detail::MeasureTimes mt;
            const ErrorMeasurement m =
                detail::measure(measured, *surface, search_level, ctx.measure_options(), &mt);
            rep.unfitted_relative_rms = m.relative.rms;
            rep.unfitted_relative_hausdorff = m.relative.hausdorff;
        }
        const double unfitted_rms = rep.unfitted_relative_rms, unfitted_h = rep.unfitted_relative_hausdorff;
        detail::MeasureTimes mt;
        // Fits from `st`, first projecting the data points onto the start's surface if `project`.
        auto run = [&](LevelState& st, bool project, ErrorMeasurement* m) {
            if (project) {
                clock = Clock::now();
                surface->set_points(topo.expand(st.vars));
                update_correspondences(*surface, &st.data, threads);
                pre.evaluation += seconds_since(clock);
            }
            // The extra rounds where this level's fit may be the result: the level asked for, or
            // any level in the tolerance mode.
            const bool final_level = options.mode == FitMode::Tolerance || level == last;
            LevelReport r = fit_level(ctx, topo, *surface, st, final_level ? options.extra_rounds : 0);
            *m = detail::measure(measured, *surface, search_level, ctx.measure_options(), &mt);
            return r;
        };
        const auto no_worse = [&](const ErrorMeasurement& e) {
            const FitError& prev = result.levels.back().relative;
            return e.relative.rms <= prev.rms && e.relative.hausdorff <= (1 - kHausdorffMargin) * prev.hausdorff;
        };
        ErrorMeasurement m;
        if (!src.layout && level >= 2) {
            // A control mesh's fit: the previous fit refined starts closer than the control mesh
            // refined, which is the same surface without the fit.
            state = std::move(warm);
            rep = run(state, warm_new_points, &m);
            rep.stop_reason += " (from the refined previous fit)";
        } else {
            state = std::move(parametric_state);
            rep = run(state, !src.layout, &m);
        }
        if (src.layout && level >= 2 && !no_worse(m)) {
            // The parametric start comes first because a coarse level can be degenerate (the limit
            // of the 2 x 2 torus cage folds onto itself) and its refinement a poor start; finer
            // levels, too, mostly end better from it. When that fit measures worse than the
            // previous level (RMS, or Hausdorff within kHausdorffMargin), fit again from the
            // previous fit refined once (the same surface, so it starts at the previous level's
            // errors) and keep the one no worse than the previous level, else the one with the
            // smaller RMS.
            ctx.progress("level " + std::to_string(level) + ": worse than level " + std::to_string(level - 1) +
                         ", fitting again from the refined previous fit");
            const LevelState parametric_fit = state;
            const LevelState warm_start = warm;
            ErrorMeasurement mw;
            LevelReport warm_rep = run(warm, warm_new_points, &mw);
            warm_rep.seconds.evaluation += rep.seconds.evaluation;
            warm_rep.seconds.closest_points += rep.seconds.closest_points;
            warm_rep.seconds.solve += rep.seconds.solve;
            if (no_worse(mw) != no_worse(m) ? no_worse(mw) : mw.relative.rms <= m.relative.rms) {
                rep = warm_rep;
                state = std::move(warm);
                m = mw;
                rep.stop_reason += " (from the refined previous fit)";
            } else {
                rep.seconds = warm_rep.seconds;
                rep.stop_reason += " (from the parametric start; the refined previous fit measured worse)";
                state = parametric_fit;
                surface->set_points(topo.expand(state.vars));
            }
            if (!no_worse(m)) {
                // Neither fit measured as well as the previous level (at the input's facets both
                // end at the same floor, and the rounds trade one error for the other): the
                // previous fit itself, refined, is the same surface.
                surface->set_points(topo.expand(warm_start.vars));
                const ErrorMeasurement m0 =
                    detail::measure(measured, *surface, search_level, ctx.measure_options(), &mt);
                if (m0.relative.rms <= m.relative.rms) {
                    state = warm_start;
                    m = m0;
                    rep.iterations = 0;
                    rep.stop_reason =
                        "both fits measured worse than the previous level: kept the refined previous fit";
                } else {
                    surface->set_points(topo.expand(state.vars));
                }
            }
        }
        rep.unfitted_relative_rms = unfitted_rms;
        rep.unfitted_relative_hausdorff = unfitted_h;
        rep.seconds.parameterization += pre.parameterization;
        rep.seconds.evaluation += pre.evaluation + mt.evaluation;
        rep.seconds.closest_points += pre.closest_points + mt.closest_points;
        fill_error(&rep, m);
        rep.seconds.total = seconds_since(level_start) +
                            (level == first ? build_seconds + setup_seconds + measure_setup_seconds : 0.0);
        ctx.progress("level " + std::to_string(level) + ": " + std::to_string(rep.control_points) +
                     " control points, " + format("relative rms %.3e, hausdorff %.3e, %.2f s", m.relative.rms,
                                                  m.relative.hausdorff, rep.seconds.total));
        if (options.mode == FitMode::Tolerance && level > first && m.relative.rms > result.levels.back().relative.rms) {
            // Even from the previous fit (level 1: from its parametric start) the finer level
            // measures worse: the fit has reached the resolution of the input (more control points
            // follow its facets). Going on cannot help. (Level mode goes on to the level asked for
            // and reports what it measures.)
            result.rejected_level = rep;
            ctx.progress("level " + std::to_string(level) + " measures worse than level " + std::to_string(level - 1) +
                         "; keeping level " + std::to_string(level - 1));
            break;
        }
        result.levels.push_back(rep);
        kept_surface = surface;
        kept_vars = state.vars;
        if (options.mode == FitMode::Tolerance && m.relative.rms <= options.tolerance) {
            result.tolerance_met = true;
            break;
        }
    }
    const LevelReport& fin = result.levels.back();
    result.fitted_corners = fin.level == 0 ? kept_vars : std::vector<Vec3>{};
    std::shared_ptr<const subdiv::LimitSurface> kept(kept_surface);
    result.surface = src.layout ? FittedSurface(kept, fin.level, src.cage_faces)
                                : FittedSurface(kept, fin.level, src.cage_faces, src.level1_quads);
    if (options.mode == FitMode::Level)
        result.message = "fitted level " + std::to_string(fin.level) + format(": relative rms %.3e", fin.relative.rms);
    else if (result.tolerance_met)
        result.message = "tolerance " + format("%.3g", options.tolerance) + " met at level " + std::to_string(fin.level) +
                         format(" (relative rms %.3e)", fin.relative.rms);
    else if (result.rejected_level)
        result.message = "tolerance " + format("%.3g", options.tolerance) + " not met: level " +
                         std::to_string(result.rejected_level->level) + " did not improve on level " +
                         std::to_string(fin.level) + format(" (relative rms %.3e", fin.relative.rms) +
                         format(" vs %.3e); the input's own resolution limits the fit", result.rejected_level->relative.rms);
    else
        result.message = "tolerance " + format("%.3g", options.tolerance) + " not met by max_level " +
                         std::to_string(options.max_level) + format(" (relative rms %.3e)", fin.relative.rms);
    ctx.progress(result.message + format(" in %.2f s", seconds_since(start)));
    return result;
}

FitResult fit_surface(const layout::QuadLayout& layout, const FitOptions& options) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("fit: " + why);
    validate_layout(layout);
    const auto clock = Clock::now();
    const accel::ClosestPointIndex index(layout.mesh);
    const int nq = layout.cage.num_quads();
    Source src{layout.mesh, &layout, index, seconds_since(clock), subdiv::refine_cage(layout.cage),
               layout.cage.points, nq, 4 * nq, "cage of " + std::to_string(nq) + " quads"};
    return fit_from(src, options);
}

FitResult fit_control_mesh(const Mesh& mesh, const PolygonMesh& cage, const FitOptions& options) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("fit: " + why);
    const auto clock = Clock::now();
    const accel::ClosestPointIndex index(mesh);
    const double build_seconds = seconds_since(clock);
    if (const std::string why = detail::check_control_mesh(mesh, index, cage, 0.1); !why.empty())
        throw InvalidInput("the control mesh cannot be fitted: " + why);
    subdiv::CageRefinement level1 = subdiv::refine_polygon_cage(cage);
    const int level1_quads = level1.level1.num_quads();
    Source src{mesh, nullptr, index, build_seconds, std::move(level1), cage.points, cage.num_faces(), level1_quads,
               "control mesh of " + std::to_string(cage.num_faces()) + " faces, " +
                   std::to_string(cage.num_vertices()) + " vertices"};
    FitResult result = fit_from(src, options);
    if (result.levels.back().level == 0) result.fitted_cage = PolygonMesh{result.fitted_corners, cage.faces};
    return result;
}

}  // namespace quadcage::fit

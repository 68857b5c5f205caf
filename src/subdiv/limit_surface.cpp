#include "quadcage/subdiv/limit_surface.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>

#include "detail/topology.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::subdiv {

namespace {

namespace Bfr = OpenSubdiv::Bfr;
namespace Far = OpenSubdiv::Far;

using ThreadedCache = Bfr::SurfaceFactoryCacheThreaded<std::shared_mutex, std::shared_lock<std::shared_mutex>,
                                                       std::unique_lock<std::shared_mutex>>;
using Factory = Bfr::RefinerSurfaceFactory<ThreadedCache>;
using Surface = Bfr::Surface<double>;

/// (u, v) of a point at fraction t along side k of a quad (from corner k to corner k+1) and at
/// depth d inside the quad, measured perpendicular to that side.
std::array<double, 2> from_side(int k, double t, double d) {
    switch (k) {
        case 0: return {t, d};
        case 1: return {1 - d, t};
        case 2: return {1 - t, 1 - d};
        default: return {d, 1 - t};
    }
}

}  // namespace

std::string LimitSurfaceOptions::validate() const {
    if (irregular_level < 1 || irregular_level > 10)
        return "irregular_level must be in [1, 10], got " + std::to_string(irregular_level);
    if (threads < 0) return "threads must be >= 0, got " + std::to_string(threads);
    return {};
}

struct LimitSurface::Impl {
    QuadMesh mesh;
    LimitSurfaceOptions options;
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::unique_ptr<Factory> factory;
    std::vector<Surface> surfaces;
    std::vector<std::vector<int>> cv;              ///< Per face: Bfr's control-point indices (may repeat).
    /// Per face: the positions of cv in increasing control-point order (stencil() merges repeated
    /// points in this order; sorted once here rather than at every stencil).
    std::vector<std::vector<int>> cv_order;
    std::vector<std::vector<double>> patch_points; ///< Per face: xyz of its patch points.
    /// Per face and side: the neighbouring face and its side on the same edge, or {-1, -1}.
    std::vector<std::array<std::array<int, 2>, 4>> neighbour;
    /// Per face and side: index of the undirected edge.
    std::vector<std::array<int, 4>> edge_id;
    int num_edges = 0;

    void check_face(int f) const {
        if (f < 0 || f >= static_cast<int>(surfaces.size()))
            throw InvalidInput("limit surface: face " + std::to_string(f) + " is out of range [0, " +
                               std::to_string(surfaces.size()) + ")");
    }

    void update_patch_points() {
        const int nf = static_cast<int>(surfaces.size());
        parallel_for(nf, options.threads, [&](int f) {
            const Surface& s = surfaces[f];
            patch_points[f].assign(3 * static_cast<size_t>(s.GetNumPatchPoints()), 0.0);
            s.PreparePatchPoints(&mesh.points[0].x, Surface::PointDescriptor(3), patch_points[f].data(),
                                 Surface::PointDescriptor(3));
        });
    }
};

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles for OpenSubdiv");

LimitSurface::LimitSurface(const QuadMesh& mesh, const LimitSurfaceOptions& options) : impl_(std::make_unique<Impl>()) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("LimitSurface: " + why);
    detail::validate_quad_mesh(mesh, 0, "LimitSurface");
    Impl& m = *impl_;
    m.mesh = mesh;
    m.options = options;
    m.refiner = detail::make_refiner(mesh, 0, false);
    Bfr::SurfaceFactory::Options fo;
    fo.SetApproxLevelSmooth(options.irregular_level);
    fo.SetApproxLevelSharp(options.irregular_level);
    m.factory = std::make_unique<Factory>(*m.refiner, fo);

    const int nf = mesh.num_quads();
    m.surfaces.resize(nf);
    m.cv.resize(nf);
    m.patch_points.resize(nf);
    m.cv_order.resize(nf);
    std::vector<char> ok(nf, 0);
    parallel_for(nf, options.threads, [&](int f) {
        ok[f] = m.factory->InitVertexSurface(f, &m.surfaces[f]) && m.surfaces[f].IsValid();
        if (!ok[f]) return;
        m.cv[f].resize(m.surfaces[f].GetNumControlPoints());
        m.surfaces[f].GetControlPointIndices(m.cv[f].data());
        const std::vector<int>& cv = m.cv[f];
        std::vector<int>& order = m.cv_order[f];
        order.resize(cv.size());
        for (size_t i = 0; i < cv.size(); ++i) order[i] = static_cast<int>(i);
        std::sort(order.begin(), order.end(), [&](int a, int b) { return cv[a] < cv[b]; });
    });
    for (int f = 0; f < nf; ++f)
        if (!ok[f]) throw InvalidInput("LimitSurface: face " + std::to_string(f) + " has no limit surface");

    // Adjacency through directed edges: side k of f runs a -> b; its twin runs b -> a.
    const long long nv = mesh.num_vertices();
    std::unordered_map<long long, int> directed;  // (a, b) -> 4f + k
    directed.reserve(4 * static_cast<size_t>(nf));
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) directed.emplace(mesh.quads[f][k] * nv + mesh.quads[f][(k + 1) % 4], 4 * f + k);
    m.neighbour.assign(nf, {});
    m.edge_id.assign(nf, {-1, -1, -1, -1});
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int a = mesh.quads[f][k], b = mesh.quads[f][(k + 1) % 4];
            const auto it = directed.find(b * nv + a);
            m.neighbour[f][k] = it == directed.end() ? std::array<int, 2>{-1, -1}
                                                     : std::array<int, 2>{it->second / 4, it->second % 4};
            if (m.edge_id[f][k] < 0) {
                m.edge_id[f][k] = m.num_edges;
                if (it != directed.end()) m.edge_id[it->second / 4][it->second % 4] = m.num_edges;
                ++m.num_edges;
            }
        }
    m.update_patch_points();
}

LimitSurface::~LimitSurface() = default;
LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;

const QuadMesh& LimitSurface::control_mesh() const { return impl_->mesh; }
int LimitSurface::num_faces() const { return impl_->mesh.num_quads(); }
int LimitSurface::num_control_points() const { return impl_->mesh.num_vertices(); }

void LimitSurface::set_points(const std::vector<Vec3>& points) {
    if (points.size() != impl_->mesh.points.size())
        throw InvalidInput("LimitSurface::set_points: got " + std::to_string(points.size()) + " points for " +
                           std::to_string(impl_->mesh.points.size()) + " control points");
    for (size_t i = 0; i < points.size(); ++i)
        if (!is_finite(points[i]))
            throw InvalidInput("LimitSurface::set_points: point " + std::to_string(i) + " is not finite");
    impl_->mesh.points = points;
    impl_->update_patch_points();
}

LimitPoint LimitSurface::evaluate(const FacePoint& p) const {
    impl_->check_face(p.face);
    const double uv[2] = {std::clamp(p.u, 0.0, 1.0), std::clamp(p.v, 0.0, 1.0)};
    LimitPoint out;
    impl_->surfaces[p.face].Evaluate(uv, impl_->patch_points[p.face].data(), Surface::PointDescriptor(3),
                                     &out.position.x, &out.du.x, &out.dv.x);
    const Vec3 n = cross(out.du, out.dv);
    const double len = norm(n);
    if (len > 0) out.normal = n / len;
    return out;
}

LimitStencil LimitSurface::stencil(const FacePoint& p) const {
    LimitStencil out;
    stencil(p, &out);
    return out;
}

void LimitSurface::stencil(const FacePoint& p, LimitStencil* out) const {
    impl_->check_face(p.face);
    const double uv[2] = {std::clamp(p.u, 0.0, 1.0), std::clamp(p.v, 0.0, 1.0)};
    const Surface& s = impl_->surfaces[p.face];
    const std::vector<int>& cv = impl_->cv[p.face];
    const size_t n = cv.size();
    thread_local std::vector<double> w;  // Bfr's weights, per control point of the patch
    w.resize(3 * n);
    s.EvaluateStencil(uv, w.data(), w.data() + n, w.data() + 2 * n);
    // Merge repeated control points (possible on coarse meshes; Ceres rejects repeated blocks).
    out->indices.clear();
    out->position_weights.clear();
    out->du_weights.clear();
    out->dv_weights.clear();
    out->indices.reserve(n);
    out->position_weights.reserve(n);
    out->du_weights.reserve(n);
    out->dv_weights.reserve(n);
    for (int i : impl_->cv_order[p.face]) {
        if (out->indices.empty() || out->indices.back() != cv[i]) {
            out->indices.push_back(cv[i]);
            out->position_weights.push_back(0);
            out->du_weights.push_back(0);
            out->dv_weights.push_back(0);
        }
        out->position_weights.back() += w[i];
        out->du_weights.back() += w[n + i];
        out->dv_weights.back() += w[2 * n + i];
    }
}

std::vector<int> LimitSurface::face_control_points(int f) const {
    impl_->check_face(f);
    std::vector<int> out = impl_->cv[f];
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

FacePoint LimitSurface::wrap(const FacePoint& p) const {
    impl_->check_face(p.face);
    if (!std::isfinite(p.u) || !std::isfinite(p.v)) throw InvalidInput("LimitSurface::wrap: (u, v) is not finite");
    FacePoint q = p;
    for (int step = 0; step < 4; ++step) {
        // Excursion beyond each side: side 0 is v = 0, 1 is u = 1, 2 is v = 1, 3 is u = 0.
        const double out[4] = {-q.v, q.u - 1, q.v - 1, -q.u};
        int k = 0;
        for (int i = 1; i < 4; ++i)
            if (out[i] > out[k]) k = i;
        if (out[k] <= 0) return q;
        // Fraction along side k (from corner k to corner k+1) and depth beyond it.
        const double t = std::clamp(k == 0 ? q.u : k == 1 ? q.v : k == 2 ? 1 - q.u : 1 - q.v, 0.0, 1.0);
        const auto [g, j] = impl_->neighbour[q.face][k];
        if (g < 0) {
            q.u = std::clamp(q.u, 0.0, 1.0);
            q.v = std::clamp(q.v, 0.0, 1.0);
            return q;
        }
        // The twin side runs the other way: fraction 1 - t, and the excursion becomes depth in g.
        const auto uv = from_side(j, 1 - t, out[k]);
        q = {g, uv[0], uv[1]};
    }
    q.u = std::clamp(q.u, 0.0, 1.0);
    q.v = std::clamp(q.v, 0.0, 1.0);
    return q;
}

FacePoint LimitSurface::project(const Vec3& q, const FacePoint& start, int iterations) const {
    return project_with_distance(q, start, iterations).foot;
}

LimitSurface::Projection LimitSurface::project_with_distance(const Vec3& q, const FacePoint& start, int iterations) const {
    FacePoint p = wrap(start);
    LimitPoint e = evaluate(p);
    double best = dot(e.position - q, e.position - q);
    for (int it = 0; it < iterations; ++it) {
        const Vec3 r = q - e.position;
        const double a11 = dot(e.du, e.du), a12 = dot(e.du, e.dv), a22 = dot(e.dv, e.dv);
        const double b1 = dot(e.du, r), b2 = dot(e.dv, r);
        // Gauss-Newton with a tiny Levenberg damping so degenerate derivatives cannot blow up.
        const double damp = 1e-12 * (a11 + a22) + 1e-300;
        const double det = (a11 + damp) * (a22 + damp) - a12 * a12;
        if (!(det > 0)) break;
        double du = ((a22 + damp) * b1 - a12 * b2) / det;
        double dv = ((a11 + damp) * b2 - a12 * b1) / det;
        // Converged when the step would move the foot by a tiny fraction of its distance to q (the
        // distance then changes by the square of that fraction) or of the patch's size.
        if (norm(e.du * du + e.dv * dv) <= 1e-3 * std::sqrt(best) + 1e-12 * (norm(e.du) + norm(e.dv))) break;
        // Stay local: at most half a face per step.
        const double len = std::hypot(du, dv);
        if (len > 0.5) du *= 0.5 / len, dv *= 0.5 / len;
        bool improved = false;
        for (int halving = 0; halving < 6 && !improved; ++halving) {
            const FacePoint c = wrap({p.face, p.u + du, p.v + dv});
            const LimitPoint ce = evaluate(c);
            const double d2 = dot(ce.position - q, ce.position - q);
            if (d2 <= best) {
                p = c, e = ce, best = d2, improved = true;
            } else {
                du *= 0.5, dv *= 0.5;
            }
        }
        if (!improved || std::hypot(du, dv) < 1e-12) break;
    }
    return {p, best};
}

LimitTessellation LimitSurface::tessellate(int n) const {
    const Impl& m = *impl_;
    const int nf = num_faces();
    if (n < 1) throw InvalidInput("LimitSurface::tessellate: n must be >= 1, got " + std::to_string(n));
    if (2.0 * n * n * nf > double(1 << 30))
        throw InvalidInput("LimitSurface::tessellate: " + std::to_string(n) + " segments per side on " +
                           std::to_string(nf) + " faces gives more than 2^30 triangles");
    const int nv = m.mesh.num_vertices();
    const int edge_base = nv;
    const int face_base = edge_base + m.num_edges * (n - 1);
    const long long total = face_base + static_cast<long long>(nf) * (n - 1) * (n - 1);
    LimitTessellation out;
    out.n = n;
    out.params.assign(static_cast<size_t>(total), FacePoint{});
    std::vector<char> assigned(static_cast<size_t>(total), 0);
    // Vertex id of grid point (i, j) of face f; records its (face, u, v) the first time it is seen.
    auto vertex = [&](int f, int i, int j) -> int {
        int id;
        const bool bu = i == 0 || i == n, bv = j == 0 || j == n;
        if (bu && bv) {
            const int k = i == 0 ? (j == 0 ? 0 : 3) : (j == 0 ? 1 : 2);
            id = m.mesh.quads[f][k];
        } else if (bu || bv) {
            // Side and the step index along it, from corner k to corner k+1.
            int k, s;
            if (j == 0) k = 0, s = i;
            else if (i == n) k = 1, s = j;
            else if (j == n) k = 2, s = n - i;
            else k = 3, s = n - j;
            const int a = m.mesh.quads[f][k], b = m.mesh.quads[f][(k + 1) % 4];
            // Edge points are numbered from the lower vertex index to the higher.
            const int from_low = a < b ? s : n - s;
            id = edge_base + m.edge_id[f][k] * (n - 1) + (from_low - 1);
        } else {
            id = face_base + (f * (n - 1) + (i - 1)) * (n - 1) + (j - 1);
        }
        if (!assigned[id]) {
            assigned[id] = 1;
            out.params[id] = {f, double(i) / n, double(j) / n};
        }
        return id;
    };
    out.mesh.triangles.reserve(2 * static_cast<size_t>(n) * n * nf);
    out.triangle_face.reserve(2 * static_cast<size_t>(n) * n * nf);
    for (int f = 0; f < nf; ++f)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const int a = vertex(f, i, j), b = vertex(f, i + 1, j), c = vertex(f, i + 1, j + 1), d = vertex(f, i, j + 1);
                out.mesh.triangles.push_back({a, b, c});
                out.mesh.triangles.push_back({a, c, d});
                out.triangle_face.push_back(f);
                out.triangle_face.push_back(f);
            }
    for (long long id = 0; id < total; ++id)
        QC_CHECK(assigned[id], "tessellation vertex " + std::to_string(id) + " was never placed");
    out.mesh.points.resize(static_cast<size_t>(total));
    parallel_for(static_cast<int>(total), m.options.threads,
                 [&](int id) { out.mesh.points[id] = evaluate(out.params[id]).position; });
    return out;
}

}  // namespace quadcage::subdiv

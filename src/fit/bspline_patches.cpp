#include "quadcage/fit/bspline_patches.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "quadcage/core/errors.h"
#include "quadcage/core/parallel.h"

namespace quadcage::fit {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Index of the knot span [knots[s], knots[s+1]) that holds t (clamped knots, degree 3).
int find_span(const std::vector<double>& knots, double t) {
    const int n = static_cast<int>(knots.size()) - 4;  // control points
    if (t >= knots[n]) return n - 1;
    if (t <= knots[3]) return 3;
    return static_cast<int>(std::upper_bound(knots.begin() + 3, knots.begin() + n + 1, t) - knots.begin()) -
           1;
}

/// The 4 non-zero cubic B-spline basis functions at t in span s and their derivatives
/// (Piegl & Tiller, The NURBS Book, A2.2 and A2.3).
void basis(const std::vector<double>& U, int s, double t, double N[4], double dN[4]) {
    double ndu[4][4], left[4], right[4];
    ndu[0][0] = 1;
    for (int j = 1; j <= 3; ++j) {
        left[j] = t - U[s + 1 - j];
        right[j] = U[s + j] - t;
        double saved = 0;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];
            const double temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= 3; ++j) N[j] = ndu[j][3];
    // First derivative: 3 * (N_{r,2} / (U[s+r] - U[s+r-3]) - N_{r+1,2} / (U[s+r+1] - U[s+r-2])).
    for (int r = 0; r <= 3; ++r) {
        double d = 0;
        if (r >= 1) d += ndu[r - 1][2] / ndu[3][r - 1];
        if (r <= 2) d -= ndu[r][2] / ndu[3][r];
        dN[r] = 3 * d;
    }
}

/// (i, j) of the s-th control point along side k of an n x n grid, from corner k.
std::array<int, 2> side_index(int k, int s, int n) {
    switch (k) {
        case 0:
            return {s, 0};
        case 1:
            return {n - 1, s};
        case 2:
            return {n - 1 - s, n - 1};
        default:
            return {0, n - 1 - s};
    }
}

/// (u, v) at fraction t along side k, from corner k.
std::array<double, 2> side_uv(int k, double t) {
    switch (k) {
        case 0:
            return {t, 0};
        case 1:
            return {1, t};
        case 2:
            return {1 - t, 1};
        default:
            return {0, 1 - t};
    }
}

/// The surface seen patch by patch.
struct Context {
    const FittedSurface* surface = nullptr;
    int descend_levels = 0;  ///< Control-mesh levels below a patch.
    int patches = 0;
    std::vector<std::array<bool, 4>> extraordinary;
    std::vector<std::array<int, 4>> corner_vertex;  ///< Control-mesh vertex at each patch corner.
    bool any_extraordinary = false;

    explicit Context(const FittedSurface& s) : surface(&s) {
        const subdiv::QuadMesh& mesh = s.control_mesh();
        const int lc = std::max(s.level(), 1);
        descend_levels = s.cage_quads() > 0 ? lc : lc - 1;
        patches = mesh.num_quads() >> (2 * descend_levels);
        QC_CHECK(patches << (2 * descend_levels) == mesh.num_quads(),
                 "patch count does not divide the control mesh");
        std::vector<int> valence(mesh.num_vertices(), 0);
        for (const auto& q : mesh.quads)
            for (int v : q) ++valence[v];
        extraordinary.assign(patches, {});
        corner_vertex.assign(patches, {});
        static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
        for (int p = 0; p < patches; ++p)
            for (int k = 0; k < 4; ++k) {
                const subdiv::FacePoint f = face_point(p, cu[k], cv[k]);
                const int v = mesh.quads[f.face][k];
                corner_vertex[p][k] = v;
                extraordinary[p][k] = valence[v] != 4;
                any_extraordinary = any_extraordinary || valence[v] != 4;
            }
    }
    subdiv::FacePoint face_point(int p, double u, double v) const {
        return subdiv::descend({p, std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)}, descend_levels);
    }
    Vec3 limit(int p, double u, double v) const { return surface->evaluate(face_point(p, u, v)).position; }
};

/// Breakpoints 0 = b0 < ... < bm = 1: spacing h = 2^-levels, plus h 2^-d and 1 - h 2^-d, d = 1..depth.
std::vector<double> breakpoints(int levels, int depth) {
    const double h = std::ldexp(1.0, -levels);
    std::vector<double> b;
    for (long long i = 0; i <= (1LL << levels); ++i) b.push_back(std::min(1.0, double(i) * h));
    for (int d = 1; d <= depth; ++d) {
        b.push_back(std::ldexp(h, -d));
        b.push_back(1 - std::ldexp(h, -d));
    }
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    return b;
}

/// Clamped knots over breakpoints b; `doubled` (if inside (0, 1/2)) and 1 - doubled get
/// multiplicity 2 (C1 there: OpenSubdiv's Gregory corner patch meets its neighbours with tangent
/// continuity only).
std::vector<double> clamped_knots(const std::vector<double>& b, double doubled = 0) {
    std::vector<double> k = {0, 0, 0};
    for (double x : b) {
        k.push_back(x);
        if (doubled > 0 && doubled < 0.5 && (x == doubled || x == 1 - doubled)) k.push_back(x);
    }
    k.insert(k.end(), {1, 1, 1});
    return k;
}

/// Whether cell (a, b) of an m x m cell grid is the innermost cell at an extraordinary corner.
bool corner_cell(const std::array<bool, 4>& ev, int a, int b, int m) {
    return (a == 0 && b == 0 && ev[0]) || (a == m - 1 && b == 0 && ev[1]) ||
           (a == m - 1 && b == m - 1 && ev[2]) || (a == 0 && b == m - 1 && ev[3]);
}

/// Which cells are approximations: the innermost cell at an extraordinary corner and every cell
/// inside the corner square of side `gregory` (OpenSubdiv's non-polynomial patch) there.
struct CellKinds {
    std::vector<double> b;  ///< Breakpoints.
    double gregory = 0;     ///< h 2^-polynomial_depth.
    int m() const { return static_cast<int>(b.size()) - 1; }
    bool innermost(const std::array<bool, 4>& ev, int a, int c) const { return corner_cell(ev, a, c, m()); }
    bool approximated(const std::array<bool, 4>& ev, int a, int c) const {
        if (innermost(ev, a, c)) return true;
        const bool lo_u = b[a + 1] <= gregory, hi_u = b[a] >= 1 - gregory;
        const bool lo_v = b[c + 1] <= gregory, hi_v = b[c] >= 1 - gregory;
        return (ev[0] && lo_u && lo_v) || (ev[1] && hi_u && lo_v) || (ev[2] && hi_u && hi_v) ||
               (ev[3] && lo_u && hi_v);
    }
    /// How far the corner cells reach along a side from an extraordinary corner.
    double corner_extent() const { return std::max(b[1], gregory); }
    /// The knot that gets multiplicity 2: the Gregory square's side, when cells lie inside it.
    double doubled() const { return b[1] < gregory ? gregory : 0; }
};

CellKinds cell_kinds(int levels, int depth, int polynomial_depth) {
    CellKinds k;
    k.b = breakpoints(levels, depth);
    k.gregory = std::ldexp(1.0, -levels - polynomial_depth);
    return k;
}

/// Inverse of the 4x4 collocation matrix of cell span s at the 4 sample parameters of the cell.
Eigen::Matrix4d collocation_inverse(const std::vector<double>& U, int s, const double t[4]) {
    Eigen::Matrix4d A;
    for (int r = 0; r < 4; ++r) {
        double N[4], dN[4];
        basis(U, s, t[r], N, dN);
        for (int c = 0; c < 4; ++c) A(r, c) = N[c];
    }
    return A.inverse();
}

/// Sample parameters inside cell [lo, hi]: s points at the centres of s equal parts.
double sample_in(double lo, double hi, int s, int i) {
    return lo + (hi - lo) * (i + 0.5) / s;
}

/// Least-squares fit of the control points `unknown` (ids into out.points) to the limit surface at
/// `samples` (u, v), the other control points held where they are.
void fit_points(const Context& ctx, int p, const std::vector<double>& U, const std::vector<int>& unknown,
                const std::vector<std::array<double, 2>>& samples, BSplinePatch& out) {
    if (unknown.empty() || samples.empty()) return;
    const int n = out.n;
    std::unordered_map<int, int> column;
    for (size_t i = 0; i < unknown.size(); ++i) column[unknown[i]] = static_cast<int>(i);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(samples.size()),
                                              static_cast<Eigen::Index>(unknown.size()));
    Eigen::MatrixXd B(static_cast<Eigen::Index>(samples.size()), 3);
    for (size_t r = 0; r < samples.size(); ++r) {
        const double u = samples[r][0], v = samples[r][1];
        const int su = find_span(U, u), sv = find_span(U, v);
        double Nu[4], dNu[4], Nv[4], dNv[4];
        basis(U, su, u, Nu, dNu);
        basis(U, sv, v, Nv, dNv);
        Vec3 rhs = ctx.limit(p, u, v);
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const int id = (su - 3 + i) + n * (sv - 3 + j);
                const double w = Nu[i] * Nv[j];
                const auto it = column.find(id);
                if (it != column.end())
                    A(static_cast<Eigen::Index>(r), it->second) += w;
                else
                    rhs -= out.points[id] * w;
            }
        for (int d = 0; d < 3; ++d) B(static_cast<Eigen::Index>(r), d) = rhs[d];
    }
    const Eigen::MatrixXd X = A.colPivHouseholderQr().solve(B);
    for (size_t i = 0; i < unknown.size(); ++i)
        out.points[unknown[i]] = Vec3{X(static_cast<Eigen::Index>(i), 0), X(static_cast<Eigen::Index>(i), 1),
                                      X(static_cast<Eigen::Index>(i), 2)};
}

/// Control points of patch p. Every polynomial cell (see CellKinds) gives the 16 control points
/// that act on it exactly, from 4x4 limit samples (only the cells near a corner when
/// `corners_only`). At an extraordinary corner the corner point is the limit point; the points no
/// polynomial cell determines are fitted by least squares inside the corner square: first those on
/// the two patch sides (from samples on the side only, so both patches along a side find the same
/// row), then the inner ones. Returns the largest disagreement between two polynomial cells about
/// one control point.
double build_patch(const Context& ctx, int p, const std::vector<double>& U, const CellKinds& kinds,
                   bool corners_only, BSplinePatch& out) {
    const std::vector<double>& b = kinds.b;
    const int m = kinds.m();  // cells per side
    const int n = static_cast<int>(U.size()) - 4;
    out.n = n;
    out.extraordinary = ctx.extraordinary[p];
    std::vector<Vec3> sum(static_cast<size_t>(n) * n);
    std::vector<Vec3> first(static_cast<size_t>(n) * n);
    std::vector<int> count(static_cast<size_t>(n) * n, 0);
    double spread = 0;
    const double extent = 4 * kinds.corner_extent();
    std::vector<Eigen::Matrix4d> inv(m);
    std::vector<std::array<double, 4>> ts(m);
    std::vector<int> span(m);
    for (int a = 0; a < m; ++a) {
        for (int r = 0; r < 4; ++r) ts[a][r] = b[a] + (b[a + 1] - b[a]) * r / 3.0;
        span[a] = find_span(U, 0.5 * (b[a] + b[a + 1]));
        inv[a] = collocation_inverse(U, span[a], ts[a].data());
    }
    auto near_corner = [&](int a) { return b[a + 1] <= extent || b[a] >= 1 - extent; };
    for (int a = 0; a < m; ++a)
        for (int c = 0; c < m; ++c) {
            if (kinds.approximated(out.extraordinary, a, c)) continue;
            if (corners_only && !(near_corner(a) && near_corner(c))) continue;
            // F = Au P Av^T on the cell: P = Au^-1 F Av^-T, per coordinate.
            Eigen::Matrix4d F[3];
            for (int r = 0; r < 4; ++r)
                for (int q = 0; q < 4; ++q) {
                    const Vec3 x = ctx.limit(p, ts[a][r], ts[c][q]);
                    for (int d = 0; d < 3; ++d) F[d](r, q) = x[d];
                }
            Eigen::Matrix4d P[3];
            for (int d = 0; d < 3; ++d) P[d] = inv[a] * F[d] * inv[c].transpose();
            for (int r = 0; r < 4; ++r)
                for (int q = 0; q < 4; ++q) {
                    const size_t id =
                        static_cast<size_t>(span[a] - 3 + r) + static_cast<size_t>(n) * (span[c] - 3 + q);
                    const Vec3 x{P[0](r, q), P[1](r, q), P[2](r, q)};
                    if (count[id] == 0)
                        first[id] = x;
                    else
                        spread = std::max(spread, norm(x - first[id]));
                    sum[id] += x;
                    ++count[id];
                }
        }
    out.points.assign(static_cast<size_t>(n) * n, Vec3{});
    for (size_t id = 0; id < out.points.size(); ++id)
        if (count[id] > 0) out.points[id] = sum[id] / count[id];
    static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
        if (!out.extraordinary[k]) continue;
        const auto ij = side_index(k, 0, n);
        const int corner_id = ij[0] + n * ij[1];
        out.points[corner_id] = ctx.limit(p, cu[k], cv[k]);
        count[corner_id] = 1;
        // The corner square in patch coordinates, and the free points of this corner.
        const bool hu = cu[k] == 1, hv = cv[k] == 1;
        const double g = kinds.corner_extent();
        auto in_u = [&](int i) { return hu ? i >= n / 2 : i < (n + 1) / 2; };
        std::vector<int> row_u, row_v, inner;  // along the side v = cv[k], along u = cu[k], the rest
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int id = i + n * j;
                if (count[id] > 0 || !in_u(i) || !(hv ? j >= n / 2 : j < (n + 1) / 2)) continue;
                if (j == (hv ? n - 1 : 0))
                    row_u.push_back(id);
                else if (i == (hu ? n - 1 : 0))
                    row_v.push_back(id);
                else
                    inner.push_back(id);
            }
        // Side samples at the centres of 8 equal parts of every cell inside the corner square,
        // mirrored for the far corners so that both patches along a side solve the same problem.
        std::vector<double> along;
        for (int a = 0; a < m && b[a + 1] <= g; ++a)
            for (int i = 0; i < 8; ++i) along.push_back(sample_in(b[a], b[a + 1], 8, i));
        auto mirror = [](bool high, double t) { return high ? 1 - t : t; };
        std::vector<std::array<double, 2>> su, sv, area;
        for (double t : along) {
            su.push_back({mirror(hu, t), cv[k]});
            sv.push_back({cu[k], mirror(hv, t)});
        }
        fit_points(ctx, p, U, row_u, su, out);
        fit_points(ctx, p, U, row_v, sv, out);
        for (int a = 0; a < m && b[a + 1] <= g; ++a)
            for (int c = 0; c < m && b[c + 1] <= g; ++c)
                for (int i = 0; i < 5; ++i)
                    for (int j = 0; j < 5; ++j)
                        area.push_back({mirror(hu, sample_in(b[a], b[a + 1], 5, i)),
                                        mirror(hv, sample_in(b[c], b[c + 1], 5, j))});
        fit_points(ctx, p, U, inner, area, out);
    }
    return spread;
}

double angle_deg(const Vec3& a, const Vec3& b) {
    const double na = norm(a), nb = norm(b);
    if (!(na > 0) || !(nb > 0)) return 0;
    const double c = std::clamp(dot(a, b) / (na * nb), -1.0, 1.0);
    const double s = norm(cross(a, b)) / (na * nb);
    return std::atan2(s, c) * 180 / kPi;
}

/// Largest deviation in the corner cells at extraordinary corners only (cheap: only the cells near
/// the corners are built).
double corner_deviation(const Context& ctx, int descend, int depth, int polynomial_depth, int samples,
                        int threads) {
    const CellKinds kinds = cell_kinds(descend, depth, polynomial_depth);
    const std::vector<double>& b = kinds.b;
    BSplinePatches tmp;
    tmp.knots = clamped_knots(b, kinds.doubled());
    tmp.patches.resize(ctx.patches);
    const int m = static_cast<int>(b.size()) - 1;
    std::vector<double> dev(ctx.patches, 0);
    parallel_for(ctx.patches, threads, [&](int p) {
        bool any = false;
        for (bool e : ctx.extraordinary[p]) any = any || e;
        if (!any) return;
        build_patch(ctx, p, tmp.knots, kinds, true, tmp.patches[p]);
        for (int a = 0; a < m; ++a)
            for (int c = 0; c < m; ++c) {
                if (!kinds.approximated(ctx.extraordinary[p], a, c)) continue;
                for (int i = 0; i <= samples; ++i)
                    for (int j = 0; j <= samples; ++j) {
                        const double u = b[a] + (b[a + 1] - b[a]) * i / samples;
                        const double v = b[c] + (b[c + 1] - b[c]) * j / samples;
                        dev[p] = std::max(dev[p],
                                          norm(evaluate_patch(tmp, p, u, v).position - ctx.limit(p, u, v)));
                    }
            }
    });
    return *std::max_element(dev.begin(), dev.end());
}

/// Shared sides, from the control mesh's directed edges.
std::vector<PatchEdge> patch_edges(const Context& ctx) {
    const subdiv::QuadMesh& mesh = ctx.surface->control_mesh();
    const long long nv = mesh.num_vertices();
    std::unordered_map<long long, int> directed;  // (a, b) -> 4 f + k
    for (int f = 0; f < mesh.num_quads(); ++f)
        for (int k = 0; k < 4; ++k)
            directed.emplace(mesh.quads[f][k] * nv + mesh.quads[f][(k + 1) % 4], 4 * f + k);
    std::vector<PatchEdge> edges;
    static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    for (int p = 0; p < ctx.patches; ++p)
        for (int k = 0; k < 4; ++k) {
            // The control face at corner k of p has its side k on side k of p (children keep the
            // parent's orientation, see subdiv::to_child()).
            const subdiv::FacePoint f = ctx.face_point(p, cu[k], cv[k]);
            const int a = mesh.quads[f.face][k], bb = mesh.quads[f.face][(k + 1) % 4];
            const auto it = directed.find(bb * nv + a);
            if (it == directed.end())
                throw InvalidInput("bspline_patches: the control mesh is open at patch " + std::to_string(p));
            const int q = (it->second / 4) >> (2 * ctx.descend_levels), j = it->second % 4;
            if (q > p || (q == p && j > k)) edges.push_back({{p, q}, {k, j}});
        }
    return edges;
}

}  // namespace

std::string BSplinePatchOptions::validate() const {
    if (!(tolerance >= 1e-9 && tolerance < 1))
        return "tolerance must be in [1e-9, 1) (relative to the diagonal)";
    if (!(diagonal >= 0) || !std::isfinite(diagonal)) return "diagonal must be finite and >= 0";
    if (max_depth < 1 || max_depth > 12) return "max_depth must be in [1, 12]";
    if (polynomial_depth < 1 || polynomial_depth > 10) return "polynomial_depth must be in [1, 10]";
    if (samples_per_cell < 1) return "samples_per_cell must be >= 1";
    if (edge_samples_per_cell < 1) return "edge_samples_per_cell must be >= 1";
    if (threads < 0) return "threads must be >= 0";
    return {};
}

PatchPoint evaluate_patch(const BSplinePatches& patches, int p, double u, double v) {
    if (p < 0 || p >= static_cast<int>(patches.patches.size()))
        throw InvalidInput("evaluate_patch: patch " + std::to_string(p) + " is out of range");
    const BSplinePatch& P = patches.patches[p];
    const std::vector<double>& U = patches.knots;
    u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
    const int su = find_span(U, u), sv = find_span(U, v);
    double Nu[4], dNu[4], Nv[4], dNv[4];
    basis(U, su, u, Nu, dNu);
    basis(U, sv, v, Nv, dNv);
    PatchPoint out;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const Vec3& c = P.at(su - 3 + i, sv - 3 + j);
            out.position += c * (Nu[i] * Nv[j]);
            out.du += c * (dNu[i] * Nv[j]);
            out.dv += c * (Nu[i] * dNv[j]);
        }
    return out;
}

PatchMeasurement measure_patches(const FittedSurface& surface, const BSplinePatches& patches,
                                 const BSplinePatchOptions& options) {
    if (const std::string why = options.validate(); !why.empty())
        throw InvalidInput("measure_patches: " + why);
    if (surface.empty()) throw InvalidInput("measure_patches: the surface is empty");
    const Context ctx(surface);
    if (static_cast<int>(patches.patches.size()) != ctx.patches)
        throw InvalidInput("measure_patches: " + std::to_string(patches.patches.size()) +
                           " patches for a surface of " + std::to_string(ctx.patches));
    CellKinds kinds;
    for (size_t i = 3; i + 3 < patches.knots.size(); ++i) kinds.b.push_back(patches.knots[i]);
    kinds.gregory = std::ldexp(1.0, -ctx.descend_levels - options.polynomial_depth);
    const std::vector<double>& b = kinds.b;
    const int m = kinds.m();
    const int s = options.samples_per_cell;
    struct Acc {
        double reg = 0, cor = 0;
        long long n = 0;
    };
    std::vector<Acc> acc(ctx.patches);
    parallel_for(ctx.patches, options.threads, [&](int p) {
        Acc& A = acc[p];
        for (int a = 0; a < m; ++a)
            for (int c = 0; c < m; ++c) {
                const bool corner = kinds.approximated(ctx.extraordinary[p], a, c);
                const int k = corner ? 4 * s : s;
                for (int i = 0; i < k; ++i)
                    for (int j = 0; j < k; ++j) {
                        const double u = sample_in(b[a], b[a + 1], k, i), v = sample_in(b[c], b[c + 1], k, j);
                        const double d = norm(evaluate_patch(patches, p, u, v).position - ctx.limit(p, u, v));
                        (corner ? A.cor : A.reg) = std::max(corner ? A.cor : A.reg, d);
                        ++A.n;
                    }
            }
        // The patch corners themselves.
        static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
        for (int k = 0; k < 4; ++k) {
            const double d =
                norm(evaluate_patch(patches, p, cu[k], cv[k]).position - ctx.limit(p, cu[k], cv[k]));
            (ctx.extraordinary[p][k] ? A.cor : A.reg) = std::max(ctx.extraordinary[p][k] ? A.cor : A.reg, d);
            ++A.n;
        }
    });
    PatchMeasurement out;
    for (const Acc& A : acc) {
        out.max_deviation_regular = std::max(out.max_deviation_regular, A.reg);
        out.max_deviation_corner = std::max(out.max_deviation_corner, A.cor);
        out.samples += A.n;
    }
    out.max_deviation = std::max(out.max_deviation_regular, out.max_deviation_corner);
    // Normal jumps across shared sides: parameters inside every knot interval and at the knots.
    std::vector<double> ts;
    for (int a = 0; a < m; ++a) {
        ts.push_back(b[a]);
        for (int i = 0; i < options.edge_samples_per_cell; ++i)
            ts.push_back(sample_in(b[a], b[a + 1], options.edge_samples_per_cell, i));
    }
    ts.push_back(1.0);
    const double t_in = kinds.corner_extent(), t_out = 1 - kinds.corner_extent();
    std::vector<std::array<double, 2>> jumps(patches.edges.size(), {0, 0});
    parallel_for(static_cast<int>(patches.edges.size()), options.threads, [&](int e) {
        const PatchEdge& E = patches.edges[e];
        const int p = E.patch[0], k = E.side[0], q = E.patch[1], j = E.side[1];
        const bool ev_start = ctx.extraordinary[p][k], ev_end = ctx.extraordinary[p][(k + 1) % 4];
        for (double t : ts) {
            const auto a = side_uv(k, t), c = side_uv(j, 1 - t);
            const PatchPoint x = evaluate_patch(patches, p, a[0], a[1]),
                             y = evaluate_patch(patches, q, c[0], c[1]);
            const double jump = angle_deg(cross(x.du, x.dv), cross(y.du, y.dv));
            const bool corner = (ev_start && t <= t_in) || (ev_end && t >= t_out);
            jumps[e][corner ? 1 : 0] = std::max(jumps[e][corner ? 1 : 0], jump);
        }
    });
    for (const auto& j : jumps) {
        out.max_normal_jump_regular_deg = std::max(out.max_normal_jump_regular_deg, j[0]);
        out.max_normal_jump_corner_deg = std::max(out.max_normal_jump_corner_deg, j[1]);
    }
    return out;
}

BSplinePatches bspline_patches(const FittedSurface& surface, const BSplinePatchOptions& options) {
    if (const std::string why = options.validate(); !why.empty())
        throw InvalidInput("bspline_patches: " + why);
    if (surface.empty()) throw InvalidInput("bspline_patches: the surface is empty");
    const Context ctx(surface);
    BSplinePatches out;
    out.diagonal = options.diagonal;
    if (out.diagonal == 0) {
        BoundingBox box;
        const auto& pts = surface.control_mesh().points;
        box.min = box.max = pts.front();
        for (const Vec3& x : pts)
            for (int d = 0; d < 3; ++d)
                box.min[d] = std::min(box.min[d], x[d]), box.max[d] = std::max(box.max[d], x[d]);
        out.diagonal = box.diagonal();
    }
    out.tolerance = options.tolerance * out.diagonal;
    const int descend = ctx.descend_levels;
    // With a whole control face per patch, the two cells next to a corner need depth 2 to be regular.
    const int min_depth = ctx.any_extraordinary ? (descend == 0 ? 2 : 1) : 0;
    int depth = min_depth;
    std::string why_stop = "no extraordinary corner: exact with uniform knots";
    if (ctx.any_extraordinary) {
        const int top = std::max(min_depth, options.max_depth);
        for (depth = min_depth;; ++depth) {
            const double d = corner_deviation(ctx, descend, depth, options.polynomial_depth,
                                              4 * options.samples_per_cell, options.threads);
            if (d <= out.tolerance) {
                why_stop = "corner cells within the tolerance";
                break;
            }
            if (depth >= top) {
                why_stop = "the deepest refinement allowed (" + std::to_string(top) +
                           ") does not reach the tolerance";
                break;
            }
        }
    }
    out.depth = depth;
    out.exact_everywhere = !ctx.any_extraordinary;
    const CellKinds kinds = cell_kinds(descend, depth, options.polynomial_depth);
    out.knots = clamped_knots(kinds.b, kinds.doubled());
    out.patches.resize(ctx.patches);
    std::vector<double> spread(ctx.patches, 0);
    parallel_for(ctx.patches, options.threads,
                 [&](int p) { spread[p] = build_patch(ctx, p, out.knots, kinds, false, out.patches[p]); });
    out.edges = patch_edges(ctx);
    // One position per surface corner (the limit point), then every shared row copied from one side
    // to the other: neighbouring faces then have bit-identical boundary curves.
    {
        std::unordered_map<int, Vec3> corner_point;
        for (int p = 0; p < ctx.patches; ++p)
            for (int k = 0; k < 4; ++k) {
                BSplinePatch& P = out.patches[p];
                const auto ij = side_index(k, 0, P.n);
                const auto it = corner_point.emplace(ctx.corner_vertex[p][k], P.at(ij[0], ij[1])).first;
                P.at(ij[0], ij[1]) = it->second;
            }
        for (const PatchEdge& E : out.edges) {
            const BSplinePatch& from = out.patches[E.patch[0]];
            BSplinePatch& to = out.patches[E.patch[1]];
            const int n = from.n;
            for (int s = 0; s < n; ++s) {
                const auto a = side_index(E.side[0], s, n), c = side_index(E.side[1], n - 1 - s, n);
                out.measurement.exactness =
                    std::max(out.measurement.exactness, norm(to.at(c[0], c[1]) - from.at(a[0], a[1])));
                to.at(c[0], c[1]) = from.at(a[0], a[1]);
            }
        }
    }
    const double exactness =
        std::max(out.measurement.exactness, *std::max_element(spread.begin(), spread.end()));
    out.measurement = measure_patches(surface, out, options);
    out.measurement.exactness = exactness;
    out.tolerance_met = out.measurement.max_deviation <= out.tolerance;
    char line[400];
    std::snprintf(
        line, sizeof line,
        "%d patches, %zu knots, depth %d: max deviation %.3g (%.3g of the diagonal; tolerance %.3g) - %s",
        ctx.patches, out.knots.size(), depth, out.measurement.max_deviation,
        out.measurement.max_deviation / out.diagonal, options.tolerance, why_stop.c_str());
    out.message = line;
    return out;
}

}  // namespace quadcage::fit

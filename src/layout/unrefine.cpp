#include "detail/unrefine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/retrace.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

namespace {

// A collapse keeps a triangle's plane if the moved corner is this close to it, relative to the
// triangle's size: splits put their points on input edges and faces up to rounding.
constexpr double kPlaneTolerance = 1e-9;

// A collapse may not make a triangle with an angle below this (radians, 2 degrees), unless the
// triangles it replaces had one as small: a sliver squeezes the patch maps (the largest conformal
// distortion went from 2.2e6 to 1.1e18 on input_wheel without this rule).
constexpr double kSmallestAngle = 2 * 3.14159265358979323846 / 180;

// Passes over the vertices at most (each after the first undoes what the last one exposed).
constexpr int kMaxPasses = 50;

// A vertex inside a layout edge is taken out of it (collapsed into the edge's next vertex) only
// where the edge turns there by at most this (radians, 10 degrees): the edge stays as smooth as the
// smoothness test asks (turns over 20 degrees counted), and flat stretches lose the points where
// they crossed the splits.
constexpr double kMaxStraightenedTurn = 10 * 3.14159265358979323846 / 180;

double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 p[3] = {a, b, c};
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const Vec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
        least = std::min(least, std::atan2(norm(cross(e1, e2)), dot(e1, e2)));
    }
    return least;
}

class Collapser {
public:
    Collapser(const QuadLayout& L, bool straighten)
        : straighten_(straighten),
          points_(L.mesh.points),
          tri_(L.mesh.triangles),
          patch_(L.triangle_patch),
          input_vertices_(L.input_vertices),
          paths_(L.mesh.num_vertices(), L.edge_paths) {
        const int n = L.mesh.num_vertices();
        around_.resize(n);
        for (int t = 0; t < static_cast<int>(tri_.size()); ++t)
            for (int v : tri_[t]) around_[v].push_back(t);
        dead_.assign(tri_.size(), 0);
        keep_.assign(n, 0);
        for (int v = 0; v < L.input_vertices; ++v) keep_[v] = 1;
        // A vertex inside one layout edge, on no other curve, may leave it (straighten()): its two
        // neighbours along the edge, kept up to date as vertices leave.
        along_.assign(n, {-1, -1});
        std::vector<int> on_paths(n, 0);
        for (const auto& path : L.edge_paths)
            for (int v : path) ++on_paths[v];
        for (const auto& path : L.edge_paths)
            for (size_t i = 0; i + 1 < path.size(); ++i)
                if (i > 0 && on_paths[path[i]] == 1) along_[path[i]] = {path[i - 1], path[i + 1]};
        curve_.assign(n, 0);
        for (const auto& path : L.edge_paths)
            for (int v : path) keep_[v] = curve_[v] = 1;
        for (const auto* cycles : {&L.orthogonal_system, &L.s_cycles})
            for (const Cycle& c : *cycles)
                for (int v : c) keep_[v] = curve_[v] = 1, along_[v] = {-1, -1};
        for (int v : L.corner_vertex) keep_[v] = 1, along_[v] = {-1, -1};
        for (int v = 0; v < L.input_vertices; ++v) along_[v] = {-1, -1};
    }

    // Collapses every vertex it may, later ones first, pass after pass; with `straighten`, takes
    // vertices out of straight stretches of the layout edges too, each pass followed by Delaunay
    // flips (flip()), which make room for more. Returns how many.
    int run(int first_added) {
        int removed = 0;
        for (int pass = 0; pass < kMaxPasses; ++pass) {
            int now = 0;
            for (int m = static_cast<int>(around_.size()) - 1; m >= first_added; --m)
                if (!around_[m].empty() &&
                    (keep_[m] ? straighten_ && along_[m][0] >= 0 && straighten(m) : collapse(m)))
                    ++now;
            removed += now;
            int flipped = 0;
            if (straighten_)
                for (int t = 0; t < static_cast<int>(tri_.size()); ++t)
                    for (int k = 0; k < 3 && !dead_[t]; ++k) flipped += flip(t, k);
            if (now == 0 && flipped == 0) break;
        }
        return removed;
    }

    bool removed(int v) const { return around_[v].empty(); }
    /// The triangles of each collapsed fan (a vertex inside a patch: one patch; one taken out of a
    /// layout edge: the edge's two).
    const std::vector<int>& changed() const { return changed_; }
    const std::vector<Triangle>& triangles() const { return tri_; }
    bool dead(int t) const { return dead_[t] != 0; }

private:
    std::vector<int> neighbours(int v) const {
        std::vector<int> out;
        for (int t : around_[v])
            for (int x : tri_[t])
                if (x != v) out.push_back(x);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    // The smallest angle of the triangles m's fan becomes when m moves onto n, or -1 if the move
    // would change the surface, flip or flatten a triangle, break the manifold or make a dividing
    // chord. `next`: m's other neighbour along its layout edge when m leaves it (the new edge n-next
    // is part of the edge, not a chord), else -1.
    double quality_of(int m, int n, const std::vector<int>& ring, int next = -1) const {
        const std::vector<int> ring_n = neighbours(n);
        // Link condition: m and n share exactly the third corners of the two triangles of edge m-n.
        std::vector<int> common, opposite;
        std::set_intersection(ring.begin(), ring.end(), ring_n.begin(), ring_n.end(),
                              std::back_inserter(common));
        for (int t : around_[m]) {
            const Triangle& f = tri_[t];
            if (std::find(f.begin(), f.end(), n) == f.end()) continue;
            for (int x : f)
                if (x != m && x != n) opposite.push_back(x);
        }
        std::sort(opposite.begin(), opposite.end());
        if (opposite.size() != 2 || opposite != common) return -1;
        const Vec3& pm = points_[m];
        const Vec3& pn = points_[n];
        double least = std::numeric_limits<double>::infinity(), before_least = least;
        for (int t : around_[m]) {
            const Triangle& f = tri_[t];
            before_least =
                std::min(before_least, smallest_angle(points_[f[0]], points_[f[1]], points_[f[2]]));
            if (std::find(f.begin(), f.end(), n) != f.end()) continue;
            const int k = static_cast<int>(std::find(f.begin(), f.end(), m) - f.begin());
            const int b = f[(k + 1) % 3], c = f[(k + 2) % 3];
            const Vec3& pb = points_[b];
            const Vec3& pc = points_[c];
            const Vec3 before = cross(pb - pm, pc - pm);
            const double area2 = norm(before);
            const double size = std::max({norm(pb - pm), norm(pc - pm), norm(pn - pm)});
            if (!(area2 > 0)) return -1;
            if (std::abs(dot(pn - pm, before)) > kPlaneTolerance * size * area2) return -1;
            const Vec3 after = cross(pb - pn, pc - pn);
            if (!(dot(after, before) > 0) || !(norm(after) > 1e-14 * size * size)) return -1;
            for (int x : {b, c})
                if (x != next && !std::binary_search(ring_n.begin(), ring_n.end(), x) &&
                    paths_.share_a_path(n, x))
                    return -1;
            least = std::min(least, smallest_angle(pn, pb, pc));
        }
        return least >= std::min(before_least, kSmallestAngle) ? least : -1;
    }

    bool collapse(int m) {
        const std::vector<int> ring = neighbours(m);
        int best = -1;
        double best_quality = 0;
        for (int n : ring) {
            const double q = quality_of(m, n, ring);
            if (q > best_quality) best_quality = q, best = n;
        }
        if (best < 0) return false;
        merge(m, best);
        return true;
    }

    // Takes m out of its layout edge where the edge runs nearly straight through it: m moves onto
    // one of its two neighbours along the edge (the better of the two by quality_of()).
    bool straighten(int m) {
        const auto [a, b] = along_[m];
        const Vec3 in = points_[m] - points_[a], out = points_[b] - points_[m];
        if (!(std::atan2(norm(cross(in, out)), dot(in, out)) <= kMaxStraightenedTurn)) return false;
        const std::vector<int> ring = neighbours(m);
        const double qa = quality_of(m, a, ring, b), qb = quality_of(m, b, ring, a);
        if (!(std::max(qa, qb) > 0)) return false;
        const int n = qa >= qb ? a : b, other = n == a ? b : a;
        merge(m, n);
        for (const auto& [x, y] : {std::pair{n, other}, std::pair{other, n}})
            if (along_[x][0] >= 0) along_[x][along_[x][0] == m ? 0 : 1] = y;
        along_[m] = {-1, -1};
        return true;
    }

    // Flips edge k of triangle t (corners k, k+1) where the Delaunay condition asks for it and the
    // surface stays the same: the two triangles are coplanar (inside one input face, or faces in
    // one plane) and make a convex quadrilateral, the edge is on no curve and not between two input
    // vertices (the input's own edges, unsplit, stay), and no dividing chord is made. The splits' fans of
    // slivers round a vertex that stays become fit for collapses.
    bool flip(int t, int k) {
        const int u = tri_[t][k], v = tri_[t][(k + 1) % 3], x = tri_[t][(k + 2) % 3];
        if ((curve_[u] && curve_[v]) || (u < input_vertices_ && v < input_vertices_)) return false;
        int t2 = -1;
        for (int s : around_[u])
            if (s != t && std::find(tri_[s].begin(), tri_[s].end(), v) != tri_[s].end()) t2 = s;
        if (t2 < 0 || patch_[t2] != patch_[t]) return false;
        int y = -1;
        for (int z : tri_[t2])
            if (z != u && z != v) y = z;
        if (y < 0 || y == x) return false;
        const Vec3 &pu = points_[u], &pv = points_[v], &px = points_[x], &py = points_[y];
        // Delaunay: the angles opposite the edge sum to more than pi.
        auto angle = [](const Vec3& at, const Vec3& a, const Vec3& b) {
            const Vec3 e1 = a - at, e2 = b - at;
            return std::atan2(norm(cross(e1, e2)), dot(e1, e2));
        };
        if (!(angle(px, pu, pv) + angle(py, pu, pv) > 3.14159265358979323846 + 1e-9)) return false;
        const Vec3 before = cross(pv - pu, px - pu);
        const double size = std::max({norm(pv - pu), norm(px - pu), norm(py - pu), norm(py - px)});
        if (!(std::abs(dot(py - pu, before)) <= kPlaneTolerance * size * norm(before))) return false;
        const Vec3 a1 = cross(pu - px, py - px), a2 = cross(pv - py, px - py);
        if (!(dot(a1, before) > 0) || !(dot(a2, before) > 0)) return false;
        if (!(norm(a1) > 1e-14 * size * size) || !(norm(a2) > 1e-14 * size * size)) return false;
        for (int s : around_[x])
            if (std::find(tri_[s].begin(), tri_[s].end(), y) != tri_[s].end())
                return false;  // x-y is an edge
        if (curve_[x] && curve_[y] && paths_.share_a_path(x, y)) return false;
        tri_[t] = {x, u, y};
        tri_[t2] = {y, v, x};
        auto& au = around_[u];
        au.erase(std::find(au.begin(), au.end(), t2));
        auto& av = around_[v];
        av.erase(std::find(av.begin(), av.end(), t));
        around_[x].push_back(t2);
        around_[y].push_back(t);
        changed_.push_back(t);
        changed_.push_back(t2);
        return true;
    }

    // Moves m onto its neighbour n: the two triangles of edge m-n go, the others take n for m.
    void merge(int m, int n) {
        const std::vector<int> fan = around_[m];
        changed_.insert(changed_.end(), fan.begin(), fan.end());
        for (int t : fan) {
            Triangle& f = tri_[t];
            if (std::find(f.begin(), f.end(), n) != f.end()) {
                dead_[t] = 1;
                for (int v : f) {
                    auto& a = around_[v];
                    a.erase(std::find(a.begin(), a.end(), t));
                }
            } else {
                *std::find(f.begin(), f.end(), m) = n;
                around_[n].push_back(t);
            }
        }
        around_[m].clear();
    }

    const bool straighten_;
    const std::vector<Vec3>& points_;
    std::vector<Triangle> tri_;
    const std::vector<int>& patch_;
    const int input_vertices_;
    std::vector<char> curve_;  // on a layout edge, a cycle or an S-cycle: its edges are not flipped
    std::vector<std::vector<int>> around_;
    std::vector<char> dead_;
    std::vector<char> keep_;
    std::vector<std::array<int, 2>> along_;  // a vertex's neighbours along its layout edge, or -1
    PathsThrough paths_;  // the layout edges: a new edge along one of them would be a dividing chord
    std::vector<int> changed_;
};

}  // namespace

int remove_unused_refinement(const QuadLayout& L, QuadLayout* out, std::vector<char>* changed,
                             bool straighten) {
    QC_CHECK(L.corner_uv.size() == L.mesh.triangles.size(),
             "remove_unused_refinement: the layout has no patch maps");
    Collapser c(L, straighten);
    const int removed = c.run(L.input_vertices);
    if (removed == 0) return 0;
    changed->assign(L.cage.num_quads(), 0);
    for (int t : c.changed()) (*changed)[L.triangle_patch[t]] = 1;
    const int n = L.mesh.num_vertices();
    std::vector<int> id(n, -1);
    Mesh mesh;
    for (int v = 0; v < n; ++v)
        if (!c.removed(v)) {
            id[v] = mesh.num_vertices();
            mesh.points.push_back(L.mesh.points[v]);
        }
    QC_CHECK(mesh.num_vertices() == n - removed, "remove_unused_refinement: vertex count");
    std::vector<int> patch;
    std::vector<std::array<UV, 3>> uv;
    for (size_t t = 0; t < c.triangles().size(); ++t) {
        if (c.dead(static_cast<int>(t))) continue;
        Triangle f = c.triangles()[t];
        for (int& v : f) v = id[v];
        mesh.triangles.push_back(f);
        patch.push_back(L.triangle_patch[t]);
        // A changed patch's maps are made again; t may be a triangle that changed corners.
        uv.push_back((*changed)[L.triangle_patch[t]] ? std::array<UV, 3>{} : L.corner_uv[t]);
    }
    auto renumber = [&](std::vector<int>& vertices) {
        for (int& v : vertices) {
            QC_CHECK(id[v] >= 0, "remove_unused_refinement: a kept vertex was removed");
            v = id[v];
        }
    };
    *out = L;
    for (auto& p : out->edge_paths) {
        p.erase(std::remove_if(p.begin(), p.end(), [&c](int v) { return c.removed(v); }), p.end());
        renumber(p);
    }
    for (auto& cycle : out->orthogonal_system) renumber(cycle);
    for (auto& cycle : out->s_cycles) renumber(cycle);
    renumber(out->corner_vertex);
    out->mesh = std::move(mesh);
    out->triangle_patch = std::move(patch);
    out->corner_uv = std::move(uv);
    return removed;
}

void undo_unused_refinement(QuadLayout* L, const std::function<void(const std::string&)>& say,
                            long long bound, const Mesh* input) {
    const auto start = std::chrono::steady_clock::now();
    for (const bool straighten : {false, true}) {
        if (straighten && !(bound >= 0 && L->mesh.num_vertices() - L->input_vertices > bound)) break;
        const std::string what = straighten ? "vertices taken out of straight stretches of the layout edges"
                                            : "vertices no layout curve runs through";
        QuadLayout lean;
        std::vector<char> changed;
        if (const int removed = remove_unused_refinement(*L, &lean, &changed, straighten); removed > 0) {
            parameterize_patches(&lean, &changed);
            if (const std::string problem = verify_quad_layout(lean); problem.empty()) {
                measure_quality(&lean);
                say("refinement: " + std::to_string(removed) + " " + what + " removed" +
                    (straighten ? " (over the bound of " + std::to_string(bound) + " without)" : ""));
                lean.seconds = L->seconds;
                *L = std::move(lean);
            } else {
                say("refinement: keeping the " + what + " (without them: " + problem + ")");
            }
        }
    }
    if (input && bound >= 0 && L->mesh.num_vertices() - L->input_vertices > bound) {
        QuadLayout traced;
        if (const std::string problem = retrace_on_input(*input, *L, &traced); !problem.empty()) {
            say("refinement: the curves not traced again on the input's triangles (" + problem + ")");
        } else if (traced.mesh.num_vertices() < L->mesh.num_vertices()) {
            measure_quality(&traced);
            say("refinement: the curves traced again on the input's triangles: " +
                std::to_string(traced.mesh.num_vertices() - traced.input_vertices) +
                " vertices added (were " + std::to_string(L->mesh.num_vertices() - L->input_vertices) + ")");
            traced.seconds = L->seconds;
            *L = std::move(traced);
        }
    }
    L->seconds.parameterization +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace quadcage::layout::detail

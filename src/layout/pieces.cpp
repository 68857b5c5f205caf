// The cut surface: pieces cut out by closed curves, the holes around them, and the small path
// helpers every stage of the layout uses.

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "detail/curves.h"
#include "detail/harmonic.h"
#include "detail/patches.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

std::string surface_size(const Builder& b) {
    return " (" + std::to_string(b.s_.mesh().triangles.size()) + " triangles)";
}


double path_length(const Mesh& m, const std::vector<int>& p) {
    double l = 0;
    for (size_t i = 0; i + 1 < p.size(); ++i) l += norm(m.points[p[i + 1]] - m.points[p[i]]);
    return l;
}

int common_vertex(const Cycle& a, const Cycle& b) {
    for (int v : a)
        if (std::find(b.begin(), b.end(), v) != b.end()) return v;
    return -1;
}

int vertex_at_fraction(const Mesh& m, const Cycle& c, size_t i0, double fraction) {
    const double total = cycle_length(m, c);
    double run = 0;
    const size_t n = c.size();
    size_t best = i0;
    double best_err = kInf;
    for (size_t k = 0; k < n; ++k) {
        const size_t i = (i0 + k) % n;
        const double err = std::abs(run - fraction * total);
        if (err < best_err) {
            best_err = err;
            best = i;
        }
        run += norm(m.points[c[(i + 1) % n]] - m.points[c[i]]);
    }
    return c[best];
}

int label_pieces(const Builder& b, const std::vector<int>& curve_ids, std::vector<int>* label) {
    std::vector<std::vector<int>> paths;
    for (int id : curve_ids) {
        std::vector<int> p = b.curves_[id];
        p.push_back(p.front());
        paths.push_back(std::move(p));
    }
    return detail::face_components(b.s_, detail::cut_half_edges(b.s_, paths), label);
}

int triangle_beside(const Surface& s, const Cycle& c, int side) {
    const int h = s.find_half_edge(c[0], c[1]);
    QC_CHECK(h >= 0, "triangle_beside: curve leaves the mesh edges");
    return (side == 0 ? h : s.twin(h)) / 3;
}

std::vector<int> side_toward(const Surface& s, const Cycle& c, int x, const std::vector<int>& label,
                             int piece) {
    const auto [prev, next] = neighbours_on(c, x);
    auto sec = sectors(s, x, prev, next);
    if (label[s.find_half_edge(x, prev) / 3] == piece) return sec[0];
    QC_CHECK(label[s.find_half_edge(x, next) / 3] == piece,
             "side_toward: neither side of the curve is in the piece");
    return sec[1];
}

std::vector<char> outside_piece(const Surface& s, const std::vector<int>& label, int piece) {
    std::vector<char> out(s.num_vertices(), 1);
    for (int t = 0; t < static_cast<int>(label.size()); ++t)
        if (label[t] == piece)
            for (int v : s.mesh().triangles[t]) out[v] = 0;
    return out;
}

int euler_characteristic(const Surface& s, const std::vector<int>& triangles, const std::function<bool(int)>& in) {
    // V - E + F by counting, not sorting (the neck search asks for it at every candidate loop):
    // each edge has two sides, so E = (3F + the sides whose other side is not one of them) / 2.
    std::vector<char> counted(s.num_vertices(), 0);
    long vertices = 0, open_sides = 0;
    for (int t : triangles)
        for (int k = 0; k < 3; ++k) {
            const int v = s.mesh().triangles[t][k];
            if (!counted[v]) counted[v] = 1, ++vertices;
            if (!in(s.twin(3 * t + k) / 3)) ++open_sides;
        }
    const long faces = static_cast<long>(triangles.size());
    return static_cast<int>(vertices - (3 * faces + open_sides) / 2 + faces);
}

int piece_euler_characteristic(const Surface& s, const std::vector<int>& label, int piece) {
    std::vector<int> triangles;
    for (int t = 0; t < static_cast<int>(label.size()); ++t)
        if (label[t] == piece) triangles.push_back(t);
    return euler_characteristic(s, triangles, [&](int t) { return label[t] == piece; });
}

std::vector<int> slice(const std::vector<int>& v, int from, int to) {  // [from, to)
    from = std::max(from, 0);
    to = std::min(to, static_cast<int>(v.size()));
    return from < to ? std::vector<int>(v.begin() + from, v.begin() + to) : std::vector<int>{};
}

int index_in(const std::vector<int>& v, int x) {
    const auto it = std::find(v.begin(), v.end(), x);
    return it == v.end() ? -1 : static_cast<int>(it - v.begin());
}

std::vector<double> distances_from(const Surface& s, const std::vector<char>& block, const std::vector<int>& vertices) {
    PathSearch q;
    q.blocked = &block;
    for (int v : vertices) q.sources.push_back({v, 0.0});
    return detail::dijkstra(s, q).distance;
}

namespace {

// The triangles marked in `tri` (all if empty) by their mean u, with the area at or below each
// one's level; triangles with a corner at +inf left out.
struct AreaByLevel {
    std::vector<double> levels, below;  // ascending; below.back() is the total
};

AreaByLevel area_by_level(const Surface& s, const std::vector<double>& u, const std::vector<char>& tri) {
    std::vector<std::pair<double, double>> by_level;  // (mean u, area)
    for (int t = 0; t < s.mesh().num_triangles(); ++t) {
        if (!tri.empty() && !tri[t]) continue;
        const auto& f = s.mesh().triangles[t];
        const double ut = (u[f[0]] + u[f[1]] + u[f[2]]) / 3;
        if (ut < kInf) by_level.push_back({ut, triangle_area(s.mesh(), t)});
    }
    std::sort(by_level.begin(), by_level.end());
    AreaByLevel out;
    double run = 0;
    for (const auto& [ut, a] : by_level) {
        run += a;
        out.levels.push_back(ut);
        out.below.push_back(run);
    }
    return out;
}

}  // namespace

double area_level(const Surface& s, const std::vector<double>& u, const std::vector<char>& tri,
                  double share) {
    const AreaByLevel a = area_by_level(s, u, tri);
    if (a.levels.empty()) return 0.5;
    const size_t k = static_cast<size_t>(
        std::lower_bound(a.below.begin(), a.below.end(), share * a.below.back()) - a.below.begin());
    return a.levels[std::min(k, a.levels.size() - 1)];
}

std::vector<double> area_quantiles(const Surface& s, const std::vector<double>& u) {
    const AreaByLevel a = area_by_level(s, u, {});
    std::vector<double> q(u.size(), kInf);
    for (size_t v = 0; v < u.size(); ++v) {
        if (!(u[v] < kInf)) continue;
        const size_t k =
            static_cast<size_t>(std::upper_bound(a.levels.begin(), a.levels.end(), u[v]) - a.levels.begin());
        q[v] = k > 0 && a.below.back() > 0 ? a.below[k - 1] / a.below.back() : 0.0;
    }
    return q;
}

std::vector<double> harmonic_across(const Surface& s, const Cycle& c) {
    const size_t n = c.size();
    QC_CHECK(n >= 3, "harmonic_across: a closed curve of fewer than 3 vertices");
    const Mesh& mesh = s.mesh();
    const int nv = s.num_vertices(), nt = mesh.num_triangles();
    std::vector<int> local(nv, -1);
    for (int v : c) local[v] = -2;  // on c
    int m = 0;
    for (int v = 0; v < nv; ++v)
        if (local[v] == -1) local[v] = m++;
    // Each corner's id: its unknown, or for a corner on c, m + the side of c its triangle lies on:
    // the sector (sectors()) its other corners lie in, or for a triangle of three curve vertices
    // (prev, c[i], next), the sector with no vertex.
    std::vector<int> slot(3 * static_cast<size_t>(nt), -1);
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles[t][k];
            if (local[v] >= 0) slot[3 * t + k] = local[v];
        }
    for (size_t i = 0; i < n; ++i) {
        const int x = c[i];
        const auto sec = sectors(s, x, c[(i + n - 1) % n], c[(i + 1) % n]);
        auto in_sector = [&](int side, int y) { return index_in(sec[side], y) >= 0; };
        for (const int h : s.out_half_edges(x)) {
            const int t = h / 3, y = s.to(h), z = s.to(s.rotate(h));
            const int side = in_sector(0, y) || in_sector(0, z)   ? 0
                             : in_sector(1, y) || in_sector(1, z) ? 1
                                                                  : (sec[0].empty() ? 0 : 1);
            for (int k = 0; k < 3; ++k)
                if (mesh.triangles[t][k] == x) slot[3 * t + k] = m + side;
        }
    }
    std::vector<int> tris(nt);
    std::iota(tris.begin(), tris.end(), 0);
    CotangentWeights weight(mesh);
    Eigen::MatrixXd x;
    const bool solved = harmonic_extension(
        weight, tris, slot, m, 1, [](int b, int) { return double(b); }, &x, HarmonicSolver::Supernodal);
    QC_CHECK(solved, "harmonic_across: the factorisation failed");
    std::vector<double> u(nv, kInf);
    for (int v = 0; v < nv; ++v)
        if (local[v] >= 0) u[v] = x(local[v], 0);
    return u;
}

Cut cut_by(const Builder& b, const std::vector<int>& ids) {
    Cut c;
    c.count = label_pieces(b, ids, &c.label);
    for (int id : ids)
        for (int side = 0; side < 2; ++side)
            c.holes[c.label[triangle_beside(b.s_, b.curves_[id], side)]].push_back({id, side});
    return c;
}


Pieces find_pieces(const Builder& b, const std::vector<int>& s_ids, int g) {
    const Cut cut = cut_by(b, s_ids);
    const int count = cut.count;
    const std::vector<int>& label = cut.label;
    QC_CHECK(count == 3 * g - 3, "the S-cycles cut " + std::to_string(count) +
                                     " pieces, want 3g-3 = " + std::to_string(3 * g - 3));
    Pieces out;
    out.holes.resize(count);
    for (const auto& [piece, holes] : cut.holes) out.holes[piece] = holes;
    int annuli = 0, shirts = 0;
    for (const auto& h : out.holes) {
        if (h.size() == 2)
            ++annuli;
        else if (h.size() == 4)
            ++shirts;
        else
            QC_CHECK(false, "a piece has " + std::to_string(h.size()) + " boundary cycles (want 2 or 4)");
    }
    QC_CHECK(annuli == 2 * g - 2 && shirts == g - 1,
             "pieces: " + std::to_string(annuli) + " handles and " + std::to_string(shirts) + " T-shirts");
    for (int id : s_ids) {
        const int l0 = label[triangle_beside(b.s_, b.curves_[id], 0)],
                  l1 = label[triangle_beside(b.s_, b.curves_[id], 1)];
        QC_CHECK(out.holes[l0].size() != out.holes[l1].size(),
                 "an S-cycle does not separate a handle from a T-shirt");
    }
    return out;
}

}  // namespace quadcage::layout::detail

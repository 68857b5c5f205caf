// The layouts of genus 1 (4 quads, paper Remark 1) and genus 0 (a 6-quad cube).

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

Network network_of_torus(Builder& b, const Say& say) {
    const int a = 0, bb = 1;
    for (int guard = 0; b.curves_[a].size() < 8 || b.curves_[bb].size() < 8; ++guard) {
        QC_CHECK(guard < 8, "torus: cycles stay too short after refinement");
        for (int id : {a, bb}) {
            const Cycle& c = b.curves_[id];
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i < c.size(); ++i) edges.push_back({c[i], c[(i + 1) % c.size()]});
            b.split_curve_edges(edges);
        }
    }
    const int v = common_vertex(b.curves_[a], b.curves_[bb]);
    say("second meridian");
    // The two pairs of parallel cycles cut the torus into its 4 quads: a and the second meridian
    // cut it into two annuli, b1 and the second longitude cut each of those in two. The second
    // cycle of each pair follows the level set that halves the area of the annulus its first one
    // leaves (harmonic_across(), as area_quantiles(): level 1/2), so that a big body with a small
    // handle can be shared among the four quads. (b1's half-way vertex and the cheapest loop
    // through it left the whole body of `generate handles -g 1` in one quad: area max/min 38-43.)
    // Each second cycle crosses its first one's partner once, where that runs nearest the level,
    // and keeps within a band round the level, the narrowest of kBands that lets it through,
    // costing its length times 1 + kLevelStick |u - level| and more beside other curves. The band
    // matters: by cost alone the second meridian of that body took a short loop round the handle
    // far off the level. Near the ends of a curve the band is not enforced (walls()): where level
    // sets fan out from a narrow place (the gap between a handle's feet) no band is wide enough
    // there. The field must have no extremum: with the distance ratio d0 / (d0 + d1) the level
    // closed round a handle's foot as well, and the second meridian took that loop (-r 4: area
    // max/min 13.4; --bumps 12 --seed 2 and 3: 18.6, 17.5). With the harmonic field: 1.11, 1.25,
    // 1.07, and at most 1.25 on every genus-1 mesh tried (README).
    constexpr double kBands[] = {0.05, 0.1, 0.2, kInf};
    // The vertex of curve c (rotated to start at `from`) nearest `level` of `field`, two or more
    // steps from `from` either way.
    auto nearest_level = [](const Cycle& c, int from, const std::vector<double>& field, double level) {
        const size_t n = c.size(), i0 = static_cast<size_t>(index_in(c, from));
        int pick = -1;
        for (size_t k = 2; k + 2 <= n; ++k) {
            const int x = c[(i0 + k) % n];
            if (pick < 0 || std::abs(field[x] - level) < std::abs(field[pick] - level)) pick = x;
        }
        return pick;
    };
    auto level_cost = [](const Surface& s, const std::function<double(int)>& near,
                         const std::vector<double>& field, double level) {
        return [&s, near, &field, level](int h) {
            const double du = std::abs(field[s.from(h)] - level) + std::abs(field[s.to(h)] - level);
            return near(h) * (1 + kLevelStick * 0.5 * std::min(du, 2.0));
        };
    };
    // The curves as walls, and with `band`, also every vertex farther than that from the level,
    // except within two rings of the vertices `ends` the curve leaves or reaches: where level sets
    // fan out from a narrow place, the level changes faster than one edge can follow.
    auto walls = [](const Builder& t, const std::vector<double>& field, double level, double band,
                    const std::vector<int>& ends) {
        std::vector<char> block = t.blocked(), exempt(block.size(), 0);
        for (int e : ends)
            for (int x : t.s_.ring(e)) {
                exempt[x] = 1;
                for (int y : t.s_.ring(x)) exempt[y] = 1;
            }
        for (size_t x = 0; x < block.size(); ++x)
            if (!exempt[x] && !(std::abs(field[x] - level) <= band)) block[x] = 1;
        return block;
    };
    // The level field of cycle c, and the vertex of the cycle `across` (which crosses c once, at v)
    // nearest its level: where the second cycle parallel to c will cross `across`. While that
    // vertex is off the level by more than the narrowest band, the edge of `across` that steps over
    // the level is split (a coarse mesh's edge between the feet of a small handle stepped from 0.1
    // to 0.87 of the area).
    auto level_crossing = [&](int c, int across, std::vector<double>* field) {
        int x = -1;
        for (int split = 0;; ++split) {
            b.split_chords();
            *field = area_quantiles(b.s_, harmonic_across(b.s_, b.curves_[c]));
            const Cycle& path = b.curves_[across];
            x = nearest_level(path, v, *field, 0.5);
            if (x < 0 || std::abs((*field)[x] - 0.5) <= kBands[0] || split == 8) break;
            const std::vector<double>& f = *field;
            std::vector<std::pair<int, int>> step;
            for (size_t i = 0; i < path.size() && step.empty(); ++i) {
                const int p = path[i], q = path[(i + 1) % path.size()];
                if (f[p] < kInf && f[q] < kInf && (f[p] - 0.5) * (f[q] - 0.5) < 0) step.push_back({p, q});
            }
            if (step.empty()) break;
            b.split_curve_edges(step);
        }
        return x;
    };
    std::vector<double> ua;
    const double la = 0.5;
    const int u = level_crossing(a, bb, &ua);
    QC_CHECK(u >= 0, "torus: b1 has no vertex for the second meridian");
    int alpha = -1;
    {
        const std::vector<char> curves = b.blocked();
        const auto cost = level_cost(b.s_, b.cost_near(curves, nullptr, kAdjacency), ua, la);
        const auto [p, n] = neighbours_on(b.curves_[bb], u);
        const auto sec = sectors(b.s_, u, p, n);
        std::vector<int> path;
        for (double band : kBands)
            if (path.empty() && std::abs(ua[u] - la) <= band)
                path = b.sector_path(u, sec[0], u, sec[1], walls(b, ua, la, band, {u}), cost, nullptr);
        QC_CHECK(!path.empty(), "torus: no second meridian");
        Cycle s{u};
        s.insert(s.end(), path.begin(), path.end());
        alpha = b.add_curve(s);
    }
    say("second longitude");
    // Second longitude: from w (the vertex of a nearest the halving level across b1) across one
    // annulus to a vertex y of the second meridian, then back across the other annulus; both sides
    // tried, the cheaper kept.
    std::vector<double> ub;
    const double lb = 0.5;
    const int w = level_crossing(bb, a, &ub);
    QC_CHECK(w >= 0, "torus: a1 has no vertex for the second longitude");
    double best = kInf;
    std::optional<Builder> best_builder;
    int best_beta = -1, best_y = -1;
    for (double band : kBands) {
        if (best_builder || !(std::abs(ub[w] - lb) <= band)) continue;
        for (int side = 0; side < 2; ++side) {
            Builder t = b;
            // ub is this field already unless split_chords() refines (level_crossing() left b's
            // chords split): one solve saved per side.
            const std::vector<double> ub1 =
                t.split_chords() > 0 ? area_quantiles(t.s_, harmonic_across(t.s_, t.curves_[bb])) : ub;
            const std::vector<char> block = walls(t, ub1, lb, band, {w});
            const auto cost = level_cost(t.s_, t.cost_near(t.blocked(), nullptr, kAdjacency), ub1, lb);
            const auto [pw, nw] = neighbours_on(t.curves_[a], w);
            const auto sec_w = sectors(t.s_, w, pw, nw);
            PathSearch q;
            q.blocked = &block;
            q.cost = cost;
            for (int x : sec_w[side])
                if (!block[x]) q.sources.push_back({x, t.edge_cost(cost, w, x)});
            const Cycle& al = t.curves_[alpha];
            for (int y : al) {
                if (y == u) continue;
                for (int x : t.s_.ring(y))
                    if (!block[x]) q.targets.push_back({x, t.edge_cost(cost, x, y)});
            }
            if (q.sources.empty() || q.targets.empty()) continue;
            const PathResult r = detail::dijkstra(t.s_, q);
            if (r.target < 0) continue;
            const std::vector<int> first = r.path_to(t.s_, r.target);
            int y = -1;
            double yc = kInf;
            for (int cand : t.s_.ring(r.target))
                if (cand != u && index_in(al, cand) >= 0 && t.edge_cost(cost, r.target, cand) < yc) {
                    yc = t.edge_cost(cost, r.target, cand);
                    y = cand;
                }
            QC_CHECK(y >= 0, "torus: second longitude lost its end");
            Cycle half{w};
            half.insert(half.end(), first.begin(), first.end());
            half.push_back(y);
            const int half_id = t.add_curve(half, false);
            t.split_chords();
            const std::vector<double> ub2 = area_quantiles(t.s_, harmonic_across(t.s_, t.curves_[bb]));
            const std::vector<char> block2 = walls(t, ub2, lb, band, {w, y});
            const auto cost2 = level_cost(t.s_, t.cost_near(t.blocked(), nullptr, kAdjacency), ub2, lb);
            const auto [py, ny] = neighbours_on(t.curves_[alpha], y);
            const auto sec_y = sectors(t.s_, y, py, ny);
            const int arrived = t.curves_[half_id][t.curves_[half_id].size() - 2];
            const int other = index_in(sec_y[0], arrived) >= 0 ? 1 : 0;
            const auto [pw2, nw2] = neighbours_on(t.curves_[a], w);
            const auto sec_w2 = sectors(t.s_, w, pw2, nw2);
            double second_cost = 0;
            const std::vector<int> second =
                t.sector_path(y, sec_y[other], w, sec_w2[1 - side], block2, cost2, &second_cost);
            if (second.empty()) continue;
            Cycle beta = t.curves_[half_id];
            beta.insert(beta.end(), second.begin(), second.end());
            t.obstacle_[half_id] = 0;
            const double total = r.target_cost + second_cost;
            if (total >= best) continue;
            best = total;
            best_y = y;
            best_beta = t.add_curve(beta);
            best_builder.emplace(std::move(t));
        }
    }
    QC_CHECK(best_builder.has_value(), "torus: no second longitude");
    b = std::move(*best_builder);
    Network net;
    net.corners = {v, u, w, best_y};
    net.closed = {{a, {v, w}}, {bb, {v, u}}, {alpha, {u, best_y}}, {best_beta, {w, best_y}}};
    return net;
}

Network network_of_cube(Builder& b, const Say& say) {
    const Mesh& m = b.s_.mesh();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Vec3& p : m.points) mean += Eigen::Vector3d(p.x, p.y, p.z);
    mean /= static_cast<double>(m.num_vertices());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& p : m.points) {
        const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
        cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    Eigen::Matrix3d axes = eig.eigenvectors();  // columns, ascending eigenvalues
    Eigen::Vector3d e1 = axes.col(2), e2 = axes.col(1);
    Eigen::Vector3d e3 = e1.cross(e2);
    const Eigen::Vector3d scale(std::sqrt(std::max(eig.eigenvalues()(2), 1e-300)),
                                std::sqrt(std::max(eig.eigenvalues()(1), 1e-300)),
                                std::sqrt(std::max(eig.eigenvalues()(0), 1e-300)));
    // Octant (sx, sy, sz) -> corner index: bottom ring (sz < 0) j = 0..3, top ring 4 + j, with j
    // running (-,-), (+,-), (+,+), (-,+): counter-clockwise about e3.
    const int sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    auto score = [&](int v, int k) {
        const Eigen::Vector3d d = Eigen::Vector3d(m.points[v].x, m.points[v].y, m.points[v].z) - mean;
        const int j = k % 4;
        const double sz = k < 4 ? -1 : 1;
        return sx[j] * d.dot(e1) / scale(0) + sy[j] * d.dot(e2) / scale(1) + sz * d.dot(e3) / scale(2);
    };
    // The best-scoring vertex for corner k among those `allowed` and not taken yet.
    std::array<int, 8> corner{};
    std::vector<char> taken(m.num_vertices(), 0);
    auto pick_corner = [&](int k, const std::function<bool(int)>& allowed) {
        double best = -kInf;
        int pick = -1;
        for (int v = 0; v < m.num_vertices(); ++v)
            if (!taken[v] && allowed(v) && score(v, k) > best) best = score(v, k), pick = v;
        QC_CHECK(pick >= 0, "cube: no vertex left for corner " + std::to_string(k));
        corner[k] = pick;
        taken[pick] = 1;
    };
    for (int k = 0; k < 4; ++k) pick_corner(k, [](int) { return true; });

    Network net;
    std::vector<char> is_corner(m.num_vertices(), 0);
    auto route = [&](int from, int to, const char* what) {
        b.split_chords();
        std::vector<char> block = b.blocked();
        for (size_t v = 0; v < block.size(); ++v) block[v] = block[v] || (v < is_corner.size() && is_corner[v]);
        const auto cost = b.cost_near(block, nullptr, kAdjacency);
        const std::vector<int> leave = b.s_.ring(from), arrive = b.s_.ring(to);
        const std::vector<int> interior = b.sector_path(from, leave, to, arrive, block, cost, nullptr);
        QC_CHECK(!interior.empty(), std::string("cube: an arc of the ") + what + " could not be routed");
        Cycle arc{from};
        arc.insert(arc.end(), interior.begin(), interior.end());
        arc.push_back(to);
        net.arcs.push_back(b.add_curve(arc, false));
    };
    // The bottom ring first. It cuts the sphere into two disks; the top corners are chosen in the
    // one that holds the top of the shape, then the four verticals run into it from the ring as
    // disjoint slits, and only then the top ring: the top corners lie on the boundary of the disk
    // left by the slits in the ring's cyclic order, so each top arc joins two consecutive ones
    // inside one region and every step is routable on any sphere. (Choosing the top corners by
    // their octant alone and routing the top ring before the verticals failed on a figure with
    // limbs: a top corner fell on the bottom's side, or the top ring ran against the bottom
    // ring's order, and a vertical found no way.)
    say("cube edges");
    for (int k = 0; k < 4; ++k) is_corner[corner[k]] = 1;
    for (int j = 0; j < 4; ++j) route(corner[j], corner[(j + 1) % 4], "bottom ring");
    std::vector<std::vector<int>> ring;
    for (int id : net.arcs) ring.push_back(b.curves_[id]);
    std::vector<int> label;
    QC_CHECK(detail::face_components(b.s_, detail::cut_half_edges(b.s_, ring), &label) == 2,
             "cube: the bottom ring does not cut the sphere in two");
    const Mesh& cut_mesh = b.s_.mesh();
    const std::vector<char> on_ring = b.blocked();
    std::vector<int> side_of(cut_mesh.num_vertices(), -1);
    for (int t = 0; t < cut_mesh.num_triangles(); ++t)
        for (int v : cut_mesh.triangles[t]) side_of[v] = label[t];
    int top = -1;
    double highest = -kInf;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v) {
        const Eigen::Vector3d d(cut_mesh.points[v].x - mean.x(), cut_mesh.points[v].y - mean.y(), cut_mesh.points[v].z - mean.z());
        if (!on_ring[v] && d.dot(e3) > highest) highest = d.dot(e3), top = v;
    }
    QC_CHECK(top >= 0, "cube: every vertex is on the bottom ring");
    const int top_side = side_of[top];
    // Top corners keep away from the ring (at least a third of the farthest distance from it on
    // that side): one next to it can be walled in by the ring and a vertical.
    std::vector<int> ring_vertices;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v)
        if (on_ring[v]) ring_vertices.push_back(v);
    const std::vector<double> from_ring =
        distances_from(b.s_, std::vector<char>(cut_mesh.num_vertices(), 0), ring_vertices);
    double farthest = 0;
    for (int v = 0; v < cut_mesh.num_vertices(); ++v)
        if (side_of[v] == top_side && !on_ring[v]) farthest = std::max(farthest, from_ring[v]);
    taken.resize(cut_mesh.num_vertices(), 0);
    for (int k = 4; k < 8; ++k) {
        pick_corner(k, [&](int v) { return !on_ring[v] && side_of[v] == top_side && from_ring[v] >= farthest / 3; });
        is_corner.resize(cut_mesh.num_vertices(), 0);
        is_corner[corner[k]] = 1;
    }
    net.corners.assign(corner.begin(), corner.end());
    for (int j = 0; j < 4; ++j) route(corner[j], corner[4 + j], "verticals");
    for (int j = 0; j < 4; ++j) route(corner[4 + j], corner[4 + (j + 1) % 4], "top ring");
    return net;
}

}  // namespace quadcage::layout::detail

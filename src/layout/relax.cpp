#include "detail/relax.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <numeric>

#include "detail/harmonic.h"
#include "detail/patches.h"
#include "detail/search.h"

namespace quadcage::layout::detail {

namespace {

// Regions with at least this many unknowns are factorised by CHOLMOD's supernodal LLT, smaller ones
// by Eigen's simplicial LDLT. On botijo split twice (regions of tens of thousands of vertices) the
// supernodal solves cut the two relaxations from 110.9 and 66.2 s to 89.1 and 50.0 s; on
// input_wheel (regions of a few thousand) they made the layout slower (38.3, 39.6 s -> 42.6, 46.0 s).
// The layouts were byte-identical both ways on every shared mesh tried (README, Benchmarks).
constexpr int kSupernodalUnknowns = 20000;

HarmonicSolver solver_for(int unknowns) {
    return unknowns >= kSupernodalUnknowns ? HarmonicSolver::Supernodal : HarmonicSolver::Simplicial;
}

// The area of the triangles `tris` as it lies in a map of them into [-1, 1]^2 (uv(i, k): the image
// of corner k of tris[i]), binned on a 32 x 32 grid: per non-empty bin, the area-weighted mean
// image of its triangles' centroids and their area (twice the area, as a weight).
std::vector<std::pair<UV, double>> area_in_map(const Mesh& mesh, const std::vector<int>& tris,
                                               const std::function<UV(int, int)>& uv) {
    constexpr int G = 32;
    std::vector<double> bin_area(G * G, 0.0);
    std::vector<UV> bin_moment(G * G, UV{0, 0});
    for (size_t i = 0; i < tris.size(); ++i) {
        const Triangle& tri = mesh.triangles[tris[i]];
        const Vec3& p0 = mesh.points[tri[0]];
        const double a = norm(cross(mesh.points[tri[1]] - p0, mesh.points[tri[2]] - p0));
        UV q{0, 0};
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 2; ++d) q[d] += uv(static_cast<int>(i), k)[d] / 3;
        const int bx = std::clamp(static_cast<int>((q[0] + 1) / 2 * G), 0, G - 1);
        const int by = std::clamp(static_cast<int>((q[1] + 1) / 2 * G), 0, G - 1);
        bin_area[by * G + bx] += a;
        for (int d = 0; d < 2; ++d) bin_moment[by * G + bx][d] += a * q[d];
    }
    std::vector<std::pair<UV, double>> mass;
    for (int b = 0; b < G * G; ++b)
        if (bin_area[b] > 0) mass.push_back({{bin_moment[b][0] / bin_area[b], bin_moment[b][1] / bin_area[b]}, bin_area[b]});
    return mass;
}

// The point p inside the regular 2d-gon (vertex j at angle pi j / d) whose fan of quads
// (p, vertex 2k, vertex 2k+1, vertex 2k+2) shares out `mass` (points with weights) most evenly: the
// least sum of squared quad masses, over a grid of points in the polygon's inner disk.
UV balancing_point(int degree, const std::vector<std::pair<UV, double>>& mass) {
    const double pi = std::acos(-1.0);
    constexpr int G = 24;
    const double inner = 0.9 * std::cos(pi / (2 * degree));
    auto wrap = [&](double t) { return t - 2 * pi * std::floor(t / (2 * pi)); };  // to [0, 2 pi)
    UV best{0, 0};
    double best_cost = std::numeric_limits<double>::infinity();
    const int corners = 2 * degree;
    std::vector<double> beta(corners), quad(degree), ux(corners), uy(corners), un(corners);
    // A direction whose angle to every polygon vertex is above this (as a sine) lies in the same
    // sector by cross products as by the angles below: those carry errors of a few 1e-16.
    constexpr double kClear = 1e-9;
    for (int a = 0; a < G; ++a)
        for (int b = 0; b < G; ++b) {
            const UV p{-1 + (a + 0.5) * 2.0 / G, -1 + (b + 0.5) * 2.0 / G};
            if (p[0] * p[0] + p[1] * p[1] > inner * inner) continue;
            // The polygon's vertices as seen from p, by angle from vertex 0 (increasing: p is inside).
            const double base = std::atan2(-p[1], 1 - p[0]);
            for (int j = 0; j < corners; ++j) {
                ux[j] = std::cos(pi * j / degree) - p[0];
                uy[j] = std::sin(pi * j / degree) - p[1];
                un[j] = std::sqrt(ux[j] * ux[j] + uy[j] * uy[j]);
                beta[j] = wrap(std::atan2(uy[j], ux[j]) - base);
            }
            std::fill(quad.begin(), quad.end(), 0.0);
            int last = 0;
            for (const auto& [q, w] : mass) {
                // The sector between vertices j and j + 1 that holds q: by cross products (no
                // atan2, the bulk of this search) where q is clear of the sector's sides, else by
                // the angles.
                const double rx = q[0] - p[0], ry = q[1] - p[1], rn = std::sqrt(rx * rx + ry * ry);
                // The bins come row by row, so the last sector found is the likeliest: the search
                // starts there (a sector clear of its sides is the only one).
                int j = -1;
                for (int i = 0; i < corners && j < 0; ++i) {
                    const int k = last + i < corners ? last + i : last + i - corners;
                    const int k1 = k + 1 < corners ? k + 1 : 0;
                    if (ux[k] * ry - uy[k] * rx > kClear * un[k] * rn &&
                        rx * uy[k1] - ry * ux[k1] > kClear * un[k1] * rn)
                        j = k;
                }
                if (j >= 0) last = j;
                if (j < 0) {
                    const double phi = wrap(std::atan2(q[1] - p[1], q[0] - p[0]) - base);
                    j = corners - 1;
                    while (j > 0 && beta[j] > phi) --j;
                }
                quad[j / 2] += w;
            }
            double cost = 0;
            for (double w : quad) cost += w * w;
            if (cost < best_cost) best_cost = cost, best = p;
        }
    return best;
}

// First steps of the edges leaving a new corner x: for each ray (angles in the map, in cyclic
// order), a distinct neighbour of x, in the same cyclic order, with the least sum of squared angles
// off the rays. angle(v): v's angle seen from x, or +inf if v may not be used. Empty if x has too
// few usable neighbours.
std::vector<int> first_steps(const Surface& s, int x, const std::vector<double>& ray,
                             const std::function<double(int)>& angle) {
    const double pi = std::acos(-1.0), inf = std::numeric_limits<double>::infinity();
    std::vector<std::pair<double, int>> around;
    for (int v : s.ring(x))
        if (const double a = angle(v); a < inf) around.push_back({a, v});
    std::sort(around.begin(), around.end());
    const int f = static_cast<int>(around.size()), d = static_cast<int>(ray.size());
    if (f < d) return {};
    auto off = [&](int k, int j) {
        const double t = around[j].first - ray[k];
        const double w = t - 2 * pi * std::floor((t + pi) / (2 * pi));
        return w * w;
    };
    // Spoke 0 to neighbour j0; then spokes 1..d-1 to neighbours j0 + i, i increasing (mod f).
    double best = inf;
    std::vector<int> result;
    std::vector<std::vector<double>> cost(d, std::vector<double>(f));
    std::vector<std::vector<int>> prev(d, std::vector<int>(f, -1));
    for (int j0 = 0; j0 < f; ++j0) {
        for (auto& row : cost) std::fill(row.begin(), row.end(), inf);
        cost[0][0] = off(0, j0);
        for (int k = 1; k < d; ++k)
            for (int i = k; i < f; ++i)
                for (int p = k - 1; p < i; ++p)
                    if (const double c = cost[k - 1][p] + off(k, (j0 + i) % f); c < cost[k][i]) {
                        cost[k][i] = c;
                        prev[k][i] = p;
                    }
        for (int i = d - 1; i < f; ++i)
            if (cost[d - 1][i] < best) {
                best = cost[d - 1][i];
                result.assign(d, -1);
                for (int k = d - 1, at = i; k >= 0; at = prev[k][at], --k) result[k] = around[(j0 + at) % f].second;
            }
    }
    return result;
}

// A network's cut half-edges, its patches (triangle labels, each patch's triangles in ascending
// order) and, per vertex, how many of its paths run through it (corners: their degree). The
// relaxations keep all of it up to date as they move edges and corners.
struct Network {
    std::vector<char> cut;
    std::vector<int> label;
    std::vector<std::vector<int>> patch_tris;
    std::vector<int> on_paths;

    Network(const Surface& s, const std::vector<std::vector<int>>& paths)
        : cut(cut_half_edges(s, paths)), on_paths(s.num_vertices(), 0) {
        patch_tris.resize(face_components(s, cut, &label));
        for (int t = 0; t < s.mesh().num_triangles(); ++t) patch_tris[label[t]].push_back(t);
        for (const auto& p : paths)
            for (int v : p) ++on_paths[v];
    }
};

}  // namespace

int relax_layout_edges(const Surface& s, std::vector<std::vector<int>>* paths, const RelaxOptions& options) {
    const Mesh& mesh = s.mesh();
    const int n = s.num_vertices(), nt = mesh.num_triangles();
    Network net(s, *paths);
    auto& [cut, label, patch_tris, on_paths] = net;
    CotangentWeights weight(mesh);

    std::vector<char> in_region(nt, 0);
    std::vector<int> local(n, -1);
    std::vector<double> h(n, 0.0);
    std::vector<char> blocked(n, 1), side_mask(n, 0);
    int moves = 0;
    for (int sweep = 0; sweep < options.sweeps; ++sweep) {
        for (auto& path : *paths) {
            if (path.size() < 2) continue;
            const int c0 = path.front(), c1 = path.back();
            const int h0 = s.find_half_edge(path[0], path[1]);
            const int la = label[h0 / 3], lb = label[s.twin(h0) / 3];
            if (la == lb) continue;

            // The region: triangles of both patches. Its boundary: vertices on other paths.
            std::vector<int> tris;
            std::merge(patch_tris[la].begin(), patch_tris[la].end(), patch_tris[lb].begin(), patch_tris[lb].end(),
                       std::back_inserter(tris));
            for (int t : tris) in_region[t] = 1;
            for (int v : path) --on_paths[v];
            std::vector<int> interior, boundary;
            // The two patches must meet along this edge only (else their union is no disk: the
            // level-0 cage has multi-edges, e.g. every pair of neighbours on a torus).
            int shared = 0;
            for (int t : tris)
                for (int k = 0; k < 3; ++k) {
                    const int he = 3 * t + k;
                    if (cut[he] && label[t] == la && label[s.twin(he) / 3] == lb) ++shared;
                }
            bool disk = shared == static_cast<int>(path.size()) - 1;
            for (int t : tris)
                for (int v : mesh.triangles[t]) {
                    if (local[v] != -1) continue;
                    if (on_paths[v] > 0) {
                        // 1: touches patch la only, 2: lb only, 3: both (the corners c0, c1 only,
                        // unless the patches share another edge).
                        local[v] = -2 - static_cast<int>(boundary.size());
                        boundary.push_back(v);
                    } else {
                        local[v] = static_cast<int>(interior.size());
                        interior.push_back(v);
                    }
                }
            for (int t : tris)
                for (int v : mesh.triangles[t])
                    if (local[v] <= -2) side_mask[v] |= label[t] == la ? 1 : 2;
            for (int v : boundary) {
                if (side_mask[v] == 3 && v != c0 && v != c1) disk = false;
                h[v] = side_mask[v] == 1 ? 0.0 : side_mask[v] == 2 ? 1.0 : 0.5;
            }
            std::vector<int> new_path;
            const int m = static_cast<int>(interior.size());
            if (disk && m > 0) {
                std::vector<int> slot;
                for (int t : tris)
                    for (int v : mesh.triangles[t]) slot.push_back(local[v] >= 0 ? local[v] : m - 2 - local[v]);
                Eigen::MatrixXd x;
                if (harmonic_extension(
                        weight, tris, slot, m, 1, [&](int b, int) { return h[boundary[b]]; }, &x, solver_for(m))) {
                    for (int i = 0; i < m; ++i) h[interior[i]] = x(i, 0);
                    // Shortest path c0 -> c1 through interior vertices, cheapest near h = 1/2.
                    for (int v : interior) blocked[v] = 0;
                    blocked[c1] = 0;
                    PathSearch q;
                    q.sources = {{c0, 0.0}};
                    q.targets = {{c1, 0.0}};
                    q.blocked = &blocked;
                    const auto cost = [&](int he) {
                        const int a = s.from(he), b = s.to(he);
                        if (a == c0 && b == c1) return std::numeric_limits<double>::infinity();
                        const double da = 2 * h[a] - 1, db = 2 * h[b] - 1;
                        return s.length(he) * (1 + options.middle * 0.5 * (da * da + db * db));
                    };
                    const PathResult r = dijkstra_with(s, q, cost);
                    if (r.target == c1) new_path = r.path_to(s, c1);
                    for (int v : interior) blocked[v] = 1;
                    blocked[c1] = 1;
                }
            }
            if (new_path.size() >= 3 && new_path != path) {
                mark_path(s, path, &cut, 0);
                mark_path(s, new_path, &cut, 1);
                path = new_path;
                // Relabel the region: the side left of the new path's first edge is patch la.
                std::vector<int> stack{s.find_half_edge(path[0], path[1]) / 3};
                for (int t : tris) label[t] = lb;
                label[stack[0]] = la;
                flood_triangles(s, cut, stack, [&](int o) {
                    if (!in_region[o] || label[o] == la) return false;
                    label[o] = la;
                    return true;
                });
                patch_tris[la].clear();
                patch_tris[lb].clear();
                for (int t : tris) patch_tris[label[t]].push_back(t);
                ++moves;
            }
            for (int v : path) ++on_paths[v];
            for (int t : tris) {
                in_region[t] = 0;
                for (int v : mesh.triangles[t]) local[v] = -1, side_mask[v] = 0;
            }
        }
    }
    return moves;
}

int relax_layout_corners(const Surface& s, std::vector<int>* corners, std::vector<std::vector<int>>* paths,
                         const RelaxOptions& options) {
    const Mesh& mesh = s.mesh();
    const int n = s.num_vertices(), nt = mesh.num_triangles();
    Network net(s, *paths);
    auto& [cut, label, patch_tris, on_paths] = net;
    std::vector<char> is_corner(n, 0);
    for (int c : *corners) is_corner[c] = 1;
    CotangentWeights weight(mesh);

    // Scratch, reset after each corner.
    std::vector<char> on_spoke(n, 0), blocked(n, 1);
    std::vector<int> tri_index(nt, -1);
    std::vector<UV> vertex_uv(n, UV{0, 0});
    int moves = 0;
    for (size_t ci = 0; ci < corners->size(); ++ci) {
        const int c = (*corners)[ci];
        // The spokes: c's layout edges, as paths from c.
        std::vector<int> spoke_ids;
        std::vector<std::vector<int>> spokes;
        bool loop = false;
        for (size_t p = 0; p < paths->size(); ++p) {
            const std::vector<int>& path = (*paths)[p];
            if (path.front() == c && path.back() == c) {
                loop = true;
            } else if (path.front() == c) {
                spoke_ids.push_back(static_cast<int>(p));
                spokes.push_back(path);
            } else if (path.back() == c) {
                spoke_ids.push_back(static_cast<int>(p));
                spokes.emplace_back(path.rbegin(), path.rend());
            }
        }
        const int degree = static_cast<int>(spokes.size());
        if (loop || degree < 3) continue;
        // The star: c's patches, each once (their union is a disk once the surface is cut along every
        // layout edge but the spokes: the ends of the spokes may be one corner, reached twice).
        std::vector<int> patches;
        for (int h : s.out_half_edges(c)) patches.push_back(label[h / 3]);
        std::sort(patches.begin(), patches.end());
        patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
        if (static_cast<int>(patches.size()) != degree) continue;
        std::vector<int> tris;
        for (int l : patches) tris.insert(tris.end(), patch_tris[l].begin(), patch_tris[l].end());
        std::sort(tris.begin(), tris.end());
        const int F = static_cast<int>(tris.size());
        for (int i = 0; i < F; ++i) tri_index[tris[i]] = i;
        for (const auto& sp : spokes)
            for (size_t i = 0; i + 1 < sp.size(); ++i) on_spoke[sp[i]] = 1;
        // Across a half-edge inside the star: both sides in the star, and no layout edge but a spoke.
        auto open = [&](int h) {
            return tri_index[s.twin(h) / 3] >= 0 && (!cut[h] || on_spoke[s.from(h)] || on_spoke[s.to(h)]);
        };
        // The star's vertices: triangle corners (slot 3 i + k: corner k of tris[i]) joined across
        // open half-edges. Free ones (inside the star, c and its spokes included) are numbered
        // 0..m-1, those on its boundary m, m+1, ...
        std::vector<int> root(3 * F);
        std::iota(root.begin(), root.end(), 0);
        auto find = [&](int a) {
            while (root[a] != a) a = root[a] = root[root[a]];
            return a;
        };
        for (int i = 0; i < F; ++i)
            for (int k = 0; k < 3; ++k)
                if (const int h = 3 * tris[i] + k; open(h)) {
                    const int o = s.twin(h), j = tri_index[o / 3];
                    // o runs to(h) -> from(h): its corner o % 3 is to(h), the next one from(h).
                    const int pairs[2][2] = {{3 * i + k, 3 * j + (o % 3 + 1) % 3}, {3 * i + (k + 1) % 3, 3 * j + o % 3}};
                    for (const auto& pr : pairs) root[find(pr[0])] = find(pr[1]);
                }
        std::vector<int> slot(3 * F, 0), id_of_root(3 * F, 0), free_vertex, boundary_vertex;
        for (int a = 0; a < 3 * F; ++a) {
            const int r = find(a);
            if (r == a) {
                const int v = mesh.triangles[tris[a / 3]][a % 3];
                if (on_paths[v] > 0 && !on_spoke[v]) {
                    id_of_root[r] = -1 - static_cast<int>(boundary_vertex.size());
                    boundary_vertex.push_back(v);
                } else {
                    id_of_root[r] = static_cast<int>(free_vertex.size());
                    free_vertex.push_back(v);
                }
            }
        }
        const int m = static_cast<int>(free_vertex.size()), B = static_cast<int>(boundary_vertex.size());
        // A vertex inside the star (of its triangles, not on a layout edge other than a spoke).
        auto local_free = [&](int v) { return on_paths[v] == 0 || on_spoke[v]; };
        for (int a = 0; a < 3 * F; ++a) {
            const int id = id_of_root[find(a)];
            slot[a] = id >= 0 ? id : m - 1 - id;
        }
        // A disk: one simple boundary loop, through boundary vertices only; Euler characteristic 1.
        bool disk = true;
        int boundary_edges = 0;
        std::vector<int> next_on_boundary(B, -1);
        for (int i = 0; i < F; ++i)
            for (int k = 0; k < 3; ++k)
                if (!open(3 * tris[i] + k)) {
                    const int a = slot[3 * i + k] - m, b = slot[3 * i + (k + 1) % 3] - m;
                    if (a < 0 || b < 0 || next_on_boundary[a] != -1) {
                        disk = false;
                    } else {
                        next_on_boundary[a] = b;
                    }
                    ++boundary_edges;
                }
        disk = disk && m + B - (3 * F + boundary_edges) / 2 + F == 1;
        // The spokes' ends, as boundary vertices of the star.
        std::vector<int> end_id(degree, -1);
        for (int k = 0; disk && k < degree; ++k) {
            const auto& sp = spokes[k];
            const int h = s.find_half_edge(sp[sp.size() - 2], sp.back());
            if (h < 0 || tri_index[h / 3] < 0) {
                disk = false;
                break;
            }
            end_id[k] = slot[3 * tri_index[h / 3] + (h % 3 + 1) % 3] - m;
            if (end_id[k] < 0) disk = false;
        }
        // The boundary loop from the first spoke's end; its corners alternate: a spoke's end, the
        // corner diagonal to c in the next patch, ...
        std::vector<int> ring, ring_corners;
        if (disk) {
            for (int b = end_id[0]; b >= 0 && static_cast<int>(ring.size()) < boundary_edges;) {
                ring.push_back(b);
                b = next_on_boundary[b];
                if (b == end_id[0]) break;
            }
            for (size_t i = 0; i < ring.size(); ++i)
                if (is_corner[boundary_vertex[ring[i]]]) ring_corners.push_back(static_cast<int>(i));
            disk = static_cast<int>(ring.size()) == boundary_edges &&
                   static_cast<int>(ring_corners.size()) == 2 * degree;
            for (size_t j = 0; disk && j < ring_corners.size(); ++j) {
                const bool is_end = std::find(end_id.begin(), end_id.end(), ring[ring_corners[j]]) != end_id.end();
                if (is_end != (j % 2 == 0)) disk = false;
            }
        }
        std::vector<int> ends_in_order, diagonals;  // boundary ids, in the loop's order
        std::vector<UV> free_uv(m), boundary_uv(B);
        std::vector<int> candidates;  // free ids, the nearest to the balancing point first
        if (disk && m > 1) {
            // The boundary onto the regular 2d-gon, its corners at the vertices, sides by arc length.
            const double pi = std::acos(-1.0);
            const int R = static_cast<int>(ring.size());
            auto at = [&](int i) { return s.point(boundary_vertex[ring[i % R]]); };
            for (int j = 0; j < 2 * degree; ++j) {
                const int i0 = ring_corners[j], i1 = j + 1 < 2 * degree ? ring_corners[j + 1] : ring_corners[0] + R;
                const double a0 = pi * j / degree, a1 = pi * (j + 1) / degree;
                const UV p0{std::cos(a0), std::sin(a0)}, p1{std::cos(a1), std::sin(a1)};
                double total = 0, walked = 0;
                for (int i = i0; i < i1; ++i) total += norm(at(i + 1) - at(i));
                for (int i = i0; i < i1; ++i) {
                    const double f = total > 0 ? walked / total : 0.0;
                    boundary_uv[ring[i % R]] = {p0[0] + f * (p1[0] - p0[0]), p0[1] + f * (p1[1] - p0[1])};
                    walked += norm(at(i + 1) - at(i));
                }
                (j % 2 == 0 ? ends_in_order : diagonals).push_back(ring[i0]);
            }
            Eigen::MatrixXd x;
            if (harmonic_extension(
                    weight, tris, slot, m, 2, [&](int b, int col) { return boundary_uv[b][col]; }, &x, solver_for(m))) {
                for (int i = 0; i < m; ++i) free_uv[i] = {x(i, 0), x(i, 1)};
                // Halfway from the centre of the map (which keeps the patches' shapes) to the point
                // that splits the area evenly.
                UV target = balancing_point(degree, area_in_map(mesh, tris, [&](int i, int k) {
                    const int id = slot[3 * i + k];
                    return id < m ? free_uv[id] : boundary_uv[id - m];
                }));
                for (double& t : target) t *= options.balance;
                std::vector<std::pair<double, int>> by_distance(m);
                for (int i = 0; i < m; ++i)
                    by_distance[i] = {(free_uv[i][0] - target[0]) * (free_uv[i][0] - target[0]) +
                                          (free_uv[i][1] - target[1]) * (free_uv[i][1] - target[1]),
                                      i};
                const int keep = std::min(m, std::max(1, options.corner_candidates));
                std::partial_sort(by_distance.begin(), by_distance.begin() + keep, by_distance.end());
                for (int i = 0; i < keep; ++i) candidates.push_back(by_distance[i].second);
            }
        }
        // The new corner: the first candidate from which every spoke can be rerouted. Each spoke
        // first gets its own neighbour of the candidate, in the rays' cyclic order, and then runs
        // along its ray in the map to its end's copy (a free vertex has one copy in the star; an
        // end may have two). Vertex-disjoint paths from the corner to the ends in that order
        // cannot cross: the star splits into the old patches' sectors.
        int new_corner = -1;
        std::vector<std::vector<int>> new_spokes;  // in the loop's order
        const double inf = std::numeric_limits<double>::infinity();
        for (int i = 0; i < m; ++i) vertex_uv[free_vertex[i]] = free_uv[i];
        for (int candidate : candidates) {
            const int nc = free_vertex[candidate];
            if (nc == c) break;
            const UV a = free_uv[candidate];
            auto angle = [&](const UV& q) { return std::atan2(q[1] - a[1], q[0] - a[0]); };
            std::vector<double> ray(degree);
            for (int k = 0; k < degree; ++k) ray[k] = angle(boundary_uv[ends_in_order[k]]);
            const std::vector<int> first = first_steps(s, nc, ray, [&](int v) {
                return local_free(v) ? angle(vertex_uv[v]) : inf;
            });
            if (first.empty()) continue;
            for (int v : free_vertex) blocked[v] = 0;
            blocked[nc] = 1;
            for (int v : first) blocked[v] = 1;
            new_spokes.clear();
            for (int k = 0; k < degree; ++k) {
                const int e = ends_in_order[k], end = boundary_vertex[e];
                const UV b = boundary_uv[e];
                const double bx = b[0] - a[0], by = b[1] - a[1], bb = bx * bx + by * by;
                auto off_ray = [&](int v) {
                    if (v == end) return 0.0;
                    const double px = vertex_uv[v][0] - a[0], py = vertex_uv[v][1] - a[1];
                    const double f = bb > 0 ? std::clamp((px * bx + py * by) / bb, 0.0, 1.0) : 0.0;
                    return (px - f * bx) * (px - f * bx) + (py - f * by) * (py - f * by);
                };
                PathSearch q;
                q.sources = {{first[k], 0.0}};
                q.targets = {{end, 0.0}};
                q.blocked = &blocked;
                const auto cost = [&](int he) {
                    const int i = tri_index[he / 3], to = s.to(he);
                    if (i < 0 || (to == end && slot[3 * i + (he % 3 + 1) % 3] != m + e)) return inf;
                    return s.length(he) * (1 + options.ray * 0.5 * (off_ray(s.from(he)) + off_ray(to)));
                };
                blocked[end] = 0;
                const PathResult r = dijkstra_with(s, q, cost);
                blocked[end] = 1;
                if (r.target != end) break;
                std::vector<int> route{nc};
                for (int v : r.path_to(s, end)) route.push_back(v);
                for (size_t i = 1; i + 1 < route.size(); ++i) blocked[route[i]] = 1;
                new_spokes.push_back(std::move(route));
            }
            for (int v : free_vertex) blocked[v] = 1;
            if (static_cast<int>(new_spokes.size()) == degree) {
                new_corner = nc;
                break;
            }
        }
        if (new_corner >= 0) {
            // Cut along the new spokes; each sector takes the label of the patch whose diagonal
            // corner it holds.
            for (const auto& sp : spokes) mark_path(s, sp, &cut, 0);
            for (const auto& sp : new_spokes) mark_path(s, sp, &cut, 1);
            std::vector<int> old_label(F);
            for (int i = 0; i < F; ++i) old_label[i] = label[tris[i]], label[tris[i]] = -1;
            bool ok = true;
            for (int d : diagonals) {
                int seed = -1;
                for (int a = 0; a < 3 * F && seed < 0; ++a)
                    if (slot[a] == m + d) seed = a / 3;
                const int l = old_label[seed];
                seed = tris[seed];
                if (label[seed] != -1) ok = false;
                label[seed] = l;
                std::vector<int> stack{seed};
                flood_triangles(s, cut, stack, [&](int o) {
                    if (tri_index[o] < 0 || label[o] != -1) return false;
                    label[o] = l;
                    return true;
                });
            }
            for (int t : tris) ok = ok && label[t] != -1;
            if (ok) {
                for (const auto& sp : spokes)
                    for (int v : sp) --on_paths[v];
                for (int k = 0; k < degree; ++k) {
                    // The spoke to the k-th end is replaced by the new one to the same end, in its direction.
                    const auto e = std::find(ends_in_order.begin(), ends_in_order.end(), end_id[k]) - ends_in_order.begin();
                    std::vector<int> route = new_spokes[e];
                    for (int v : route) ++on_paths[v];
                    if ((*paths)[spoke_ids[k]].back() == c) std::reverse(route.begin(), route.end());
                    (*paths)[spoke_ids[k]] = route;
                }
                is_corner[c] = 0;
                is_corner[new_corner] = 1;
                (*corners)[ci] = new_corner;
                for (int l : patches) patch_tris[l].clear();
                for (int t : tris) patch_tris[label[t]].push_back(t);
                ++moves;
            } else {
                for (const auto& sp : new_spokes) mark_path(s, sp, &cut, 0);
                for (const auto& sp : spokes) mark_path(s, sp, &cut, 1);
                for (int i = 0; i < F; ++i) label[tris[i]] = old_label[i];
            }
        }
        for (int t : tris) tri_index[t] = -1;
        for (const auto& sp : spokes)
            for (int v : sp) on_spoke[v] = 0;
    }
    return moves;
}

}  // namespace quadcage::layout::detail

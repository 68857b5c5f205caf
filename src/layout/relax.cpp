#include "detail/relax.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "detail/patches.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

int relax_layout_edges(const Surface& s, std::vector<std::vector<int>>* paths, const RelaxOptions& options) {
    const Mesh& mesh = s.mesh();
    const int n = s.num_vertices(), nt = mesh.num_triangles();
    std::vector<char> cut = cut_half_edges(s, *paths);
    std::vector<int> label;
    // Each patch's triangles, in ascending order (kept up to date as edges move).
    std::vector<std::vector<int>> patch_tris(face_components(s, cut, &label));
    for (int t = 0; t < nt; ++t) patch_tris[label[t]].push_back(t);
    // Per vertex: how many paths run through it (corners: their degree).
    std::vector<int> on_paths(n, 0);
    for (const auto& p : *paths)
        for (int v : p) ++on_paths[v];

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
                        local[v] = -2;
                        boundary.push_back(v);
                    } else {
                        local[v] = static_cast<int>(interior.size());
                        interior.push_back(v);
                    }
                }
            for (int t : tris)
                for (int v : mesh.triangles[t])
                    if (local[v] == -2) side_mask[v] |= label[t] == la ? 1 : 2;
            for (int v : boundary) {
                if (side_mask[v] == 3 && v != c0 && v != c1) disk = false;
                h[v] = side_mask[v] == 1 ? 0.0 : side_mask[v] == 2 ? 1.0 : 0.5;
            }
            std::vector<int> new_path;
            const int m = static_cast<int>(interior.size());
            if (disk && m > 0) {
                // Harmonic h on the interior: clamped cotangent weights (positive, SPD).
                std::vector<Eigen::Triplet<double>> entries;
                Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m), diagonal = Eigen::VectorXd::Zero(m);
                for (int t : tris) {
                    const Triangle& tri = mesh.triangles[t];
                    for (int k = 0; k < 3; ++k) {
                        const int i = tri[k], j = tri[(k + 1) % 3];
                        const double w = std::max(half_cotangent(mesh, i, j, tri[(k + 2) % 3]), 0.025);
                        const int li = local[i], lj = local[j];
                        if (li >= 0) diagonal[li] += w;
                        if (lj >= 0) diagonal[lj] += w;
                        if (li >= 0 && lj >= 0) {
                            entries.emplace_back(li, lj, -w);
                            entries.emplace_back(lj, li, -w);
                        } else if (li >= 0) {
                            rhs[li] += w * h[j];
                        } else if (lj >= 0) {
                            rhs[lj] += w * h[i];
                        }
                    }
                }
                for (int i = 0; i < m; ++i) entries.emplace_back(i, i, diagonal[i]);
                Eigen::SparseMatrix<double> A(m, m);
                A.setFromTriplets(entries.begin(), entries.end());
                Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
                if (solver.info() == Eigen::Success) {
                    const Eigen::VectorXd x = solver.solve(rhs);
                    for (int i = 0; i < m; ++i) h[interior[i]] = x[i];
                    // Shortest path c0 -> c1 through interior vertices, cheapest near h = 1/2.
                    for (int v : interior) blocked[v] = 0;
                    blocked[c1] = 0;
                    PathSearch q;
                    q.sources = {{c0, 0.0}};
                    q.targets = {{c1, 0.0}};
                    q.blocked = &blocked;
                    q.cost = [&](int he) {
                        const int a = s.from(he), b = s.to(he);
                        if (a == c0 && b == c1) return std::numeric_limits<double>::infinity();
                        const double da = 2 * h[a] - 1, db = 2 * h[b] - 1;
                        return s.length(he) * (1 + options.middle * 0.5 * (da * da + db * db));
                    };
                    const PathResult r = dijkstra(s, q);
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

}  // namespace quadcage::layout::detail

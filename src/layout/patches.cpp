#include "detail/patches.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "detail/curves.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;
/// Reweighting rounds of the stretch-minimising patch maps (each one sparse factorisation).
constexpr int kStretchIterations = 8;

}  // namespace

void quad_boundary(const QuadLayout& layout, int q, std::vector<int>* loop, std::vector<int>* side) {
    loop->clear();
    side->clear();
    const auto& quad = layout.cage.quads[q];
    for (int k = 0; k < 4; ++k) {
        const auto& edge = layout.cage.edges[quad.edges[k]];
        std::vector<int> path = layout.edge_paths[quad.edges[k]];
        if (edge.corners[0] != quad.corners[k]) std::reverse(path.begin(), path.end());
        for (size_t i = 0; i + 1 < path.size(); ++i) {
            loop->push_back(path[i]);
            side->push_back(k);
        }
    }
}

UV side_point(int k, double t) {
    switch (k) {
        case 0:
            return {t, 0.0};
        case 1:
            return {1.0, t};
        case 2:
            return {1.0 - t, 1.0};
        default:
            return {0.0, 1.0 - t};
    }
}

std::vector<UV> boundary_positions(const Mesh& mesh, const std::vector<int>& loop, const std::vector<int>& side) {
    const size_t n = loop.size();
    auto step = [&](size_t i) { return norm(mesh.points[loop[(i + 1) % n]] - mesh.points[loop[i]]); };
    std::array<double, 4> length{0, 0, 0, 0};
    for (size_t i = 0; i < n; ++i) length[side[i]] += step(i);
    std::vector<UV> uv(n);
    double run = 0;
    for (size_t i = 0; i < n; ++i) {
        const int k = side[i];
        if (i == 0 || side[i - 1] != k) run = 0;
        uv[i] = side_point(k, length[k] > 0 ? run / length[k] : 0.0);
        run += step(i);
    }
    return uv;
}

void mark_path(const Surface& s, const std::vector<int>& path, std::vector<char>* cut, char value) {
    for (size_t i = 0; i + 1 < path.size(); ++i) {
        const int h = s.find_half_edge(path[i], path[i + 1]);
        QC_CHECK(h >= 0, "mark_path: a path leaves the mesh edges");
        (*cut)[h] = (*cut)[s.twin(h)] = value;
    }
}

double half_cotangent(const Mesh& mesh, int i, int j, int o) {
    const Vec3 a = mesh.points[i] - mesh.points[o], b = mesh.points[j] - mesh.points[o];
    const double c = norm(cross(a, b));
    return 0.5 * (c > 0 ? std::clamp(dot(a, b) / c, -1e3, 1e3) : 1e3);
}

std::vector<char> cut_half_edges(const Surface& s, const std::vector<std::vector<int>>& paths) {
    std::vector<char> cut(s.num_half_edges(), 0);
    for (const auto& p : paths) mark_path(s, p, &cut, 1);
    return cut;
}

int face_components(const Surface& s, const std::vector<char>& cut, std::vector<int>* label) {
    const int nt = s.num_half_edges() / 3;
    label->assign(nt, -1);
    int count = 0;
    std::vector<int> stack;
    for (int f0 = 0; f0 < nt; ++f0) {
        if ((*label)[f0] >= 0) continue;
        (*label)[f0] = count;
        stack.push_back(f0);
        flood_triangles(s, cut, stack, [&](int o) {
            if ((*label)[o] >= 0) return false;
            (*label)[o] = count;
            return true;
        });
        ++count;
    }
    return count;
}

int next_cut_half_edge(const Surface& s, const std::vector<char>& cut, int h) {
    int g = 3 * (h / 3) + (h % 3 + 1) % 3;  // leaves to(h) inside the same triangle
    for (int guard = 0; !cut[g]; ++guard) {
        QC_CHECK(guard < 1000000, "next_cut_half_edge: no cut edge around a vertex");
        const int t = s.twin(g);
        g = 3 * (t / 3) + (t % 3 + 1) % 3;
    }
    return g;
}

std::string extract_cage(const Surface& s, const std::vector<int>& corners,
                         const std::vector<std::vector<int>>& paths, QuadLayout* layout) {
    const int n = s.num_vertices();
    std::vector<int> cid(n, -1);
    for (size_t c = 0; c < corners.size(); ++c) cid[corners[c]] = static_cast<int>(c);
    std::unordered_map<std::uint64_t, int> path_of_edge;
    for (size_t p = 0; p < paths.size(); ++p) {
        const auto& path = paths[p];
        if (path.size() < 2 || cid[path.front()] < 0 || cid[path.back()] < 0)
            return "layout edge " + std::to_string(p) + " does not join two corners";
        for (size_t i = 1; i + 1 < path.size(); ++i)
            if (cid[path[i]] >= 0) return "layout edge " + std::to_string(p) + " passes through a corner";
        for (size_t i = 0; i + 1 < path.size(); ++i)
            if (!path_of_edge.emplace(edge_key(path[i], path[i + 1]), static_cast<int>(p)).second)
                return "two layout edges share a mesh edge";
    }
    const std::vector<char> cut = cut_half_edges(s, paths);
    std::vector<int> label;
    const int np = face_components(s, cut, &label);

    // Per patch: the boundary half-edge leaving its lowest-numbered corner.
    std::vector<int> start(np, -1), boundary_count(np, 0);
    for (int h = 0; h < s.num_half_edges(); ++h) {
        if (!cut[h]) continue;
        const int p = label[h / 3];
        ++boundary_count[p];
        const int c = cid[s.from(h)];
        if (c >= 0 && (start[p] < 0 || c < cid[s.from(start[p])])) start[p] = h;
    }
    subdiv::Cage cage;
    for (int v : corners) cage.points.push_back(s.point(v));
    cage.edges.resize(paths.size());
    for (size_t e = 0; e < paths.size(); ++e) {
        cage.edges[e].corners = {cid[paths[e].front()], cid[paths[e].back()]};
        cage.edges[e].quads = {-1, -1};
        cage.edges[e].sides = {-1, -1};
    }
    // Euler characteristic of each patch (V - E + F over its closure) must be 1: a disk.
    std::vector<int> faces(np, 0);
    for (int t = 0; t < s.num_half_edges() / 3; ++t) ++faces[label[t]];
    std::vector<std::vector<int>> patch_vertices(np);
    for (int t = 0; t < s.num_half_edges() / 3; ++t)
        for (int v : s.mesh().triangles[t]) patch_vertices[label[t]].push_back(v);
    for (auto& pv : patch_vertices) {
        std::sort(pv.begin(), pv.end());
        pv.erase(std::unique(pv.begin(), pv.end()), pv.end());
    }
    for (int p = 0; p < np; ++p) {
        const long edges = (3L * faces[p] + boundary_count[p]) / 2;
        const long chi = static_cast<long>(patch_vertices[p].size()) - edges + faces[p];
        if (chi != 1)
            return "patch " + std::to_string(p) + " is not a disk (Euler characteristic " +
                   std::to_string(chi) + ")";
        if (start[p] < 0) return "patch " + std::to_string(p) + " has no corner on its boundary";
        std::vector<int> loop;
        int h = start[p];
        do {
            loop.push_back(h);
            h = next_cut_half_edge(s, cut, h);
            if (loop.size() > static_cast<size_t>(boundary_count[p]))
                return "patch " + std::to_string(p) + " boundary does not close";
        } while (h != start[p]);
        if (static_cast<int>(loop.size()) != boundary_count[p])
            return "patch " + std::to_string(p) + " has more than one boundary loop";
        std::vector<int> at;  // loop positions of corners
        for (size_t i = 0; i < loop.size(); ++i)
            if (cid[s.from(loop[i])] >= 0) at.push_back(static_cast<int>(i));
        if (at.size() != 4)
            return "patch " + std::to_string(p) + " has " + std::to_string(at.size()) + " corners, not 4";
        subdiv::Cage::Quad quad;
        for (int k = 0; k < 4; ++k) {
            quad.corners[k] = cid[s.from(loop[at[k]])];
            for (int j = 0; j < k; ++j)
                if (quad.corners[j] == quad.corners[k])
                    return "patch " + std::to_string(p) + " meets a corner twice";
            const int first = loop[at[k]];
            const auto it = path_of_edge.find(edge_key(s.from(first), s.to(first)));
            QC_CHECK(it != path_of_edge.end(), "extract_cage: boundary edge on no layout edge");
            const int e = it->second;
            // The side must be the whole layout edge.
            const int end_pos = at[(k + 1) % 4];
            std::vector<int> side{s.from(first)};
            for (int i = at[k]; i != end_pos; i = (i + 1) % static_cast<int>(loop.size()))
                side.push_back(s.to(loop[i]));
            std::vector<int> path = paths[e];
            if (path.front() != side.front()) std::reverse(path.begin(), path.end());
            if (path != side)
                return "patch " + std::to_string(p) + " side " + std::to_string(k) +
                       " is not one layout edge";
            quad.edges[k] = e;
            auto& edge = cage.edges[e];
            const int slot = edge.quads[0] < 0 ? 0 : 1;
            if (edge.quads[slot] >= 0)
                return "layout edge " + std::to_string(e) + " borders more than two patch sides";
            edge.quads[slot] = p;
            edge.sides[slot] = k;
        }
        cage.quads.push_back(quad);
    }
    for (size_t e = 0; e < cage.edges.size(); ++e)
        if (cage.edges[e].quads[1] < 0)
            return "layout edge " + std::to_string(e) + " borders fewer than two patch sides";
    if (const std::string problem = subdiv::check_cage(cage); !problem.empty()) return "cage: " + problem;
    layout->cage = std::move(cage);
    layout->corner_vertex = corners;
    layout->triangle_patch = std::move(label);
    layout->edge_paths = paths;
    return "";
}

void parameterize_patches(QuadLayout* layout, const std::vector<char>* only) {
    const Mesh& mesh = layout->mesh;
    const int n = mesh.num_vertices(), nt = mesh.num_triangles(), nq = layout->cage.num_quads();
    std::vector<std::vector<int>> patch_triangles(nq);
    for (int t = 0; t < nt; ++t) patch_triangles[layout->triangle_patch[t]].push_back(t);
    if (only)
        QC_CHECK(static_cast<int>(layout->corner_uv.size()) == nt && static_cast<int>(only->size()) == nq,
                 "parameterize_patches: the maps to keep do not match the mesh");
    else
        layout->corner_uv.assign(nt, {});
    std::vector<int> local(n, -1);  // index among the patch's unknowns, or -2 on its boundary
    std::vector<UV> boundary_uv(n);
    std::vector<int> loop, side;
    // Per-vertex stretch sums of the patch being mapped (zero between patches).
    std::vector<double> sigma_sum(n, 0), area_sum(n, 0);
    for (int q = 0; q < nq; ++q) {
        if (only && !(*only)[q]) continue;
        quad_boundary(*layout, q, &loop, &side);
        const std::vector<UV> on_sides = boundary_positions(mesh, loop, side);
        for (size_t i = 0; i < loop.size(); ++i) {
            boundary_uv[loop[i]] = on_sides[i];
            local[loop[i]] = -2;
        }
        std::vector<int> unknowns;
        for (int t : patch_triangles[q])
            for (int v : mesh.triangles[t])
                if (local[v] == -1) {
                    local[v] = static_cast<int>(unknowns.size());
                    unknowns.push_back(v);
                }
        const int m = static_cast<int>(unknowns.size());
        std::vector<UV> uv_of(m, UV{0.5, 0.5});
        auto uv = [&](int v) { return local[v] >= 0 ? uv_of[local[v]] : boundary_uv[v]; };
        auto folds = [&]() {
            for (int t : patch_triangles[q]) {
                const Triangle& tri = mesh.triangles[t];
                const UV a = uv(tri[0]), b = uv(tri[1]), c = uv(tri[2]);
                if (!((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]) > 0)) return true;
            }
            return false;
        };
        if (m > 0) {
            // Edges of the patch with their clamped cotangent weights: symmetric and positive, so
            // the system is SPD and the map cannot fold (Tutte / Floater) while staying close to
            // conformal.
            std::unordered_map<std::uint64_t, double> cot;
            for (int t : patch_triangles[q]) {
                const Triangle& tri = mesh.triangles[t];
                for (int k = 0; k < 3; ++k) {
                    const int i = tri[k], j = tri[(k + 1) % 3];
                    cot[edge_key(i, j)] += half_cotangent(mesh, i, j, tri[(k + 2) % 3]);
                }
            }
            // In key order (the hash map's order is not deterministic).
            const std::vector<std::pair<std::uint64_t, double>> sorted = [&] {
                std::vector<std::pair<std::uint64_t, double>> v(cot.begin(), cot.end());
                std::sort(v.begin(), v.end());
                return v;
            }();
            std::vector<std::pair<int, int>> edges;
            std::vector<double> base;
            for (const auto& [key, w] : sorted) {
                edges.push_back({static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu)});
                base.push_back(std::max(w, 0.05));
            }
            Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
            bool analysed = false;
            // Solves the patch with edge weights w (same sparsity every time: analysed once).
            auto solve = [&](const std::vector<double>& w) {
                std::vector<Eigen::Triplet<double>> entries;
                Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(m, 2);
                std::vector<double> diagonal(m, 0);
                for (size_t k = 0; k < edges.size(); ++k) {
                    const auto [i, j] = edges[k];
                    const int li = local[i], lj = local[j];
                    if (li >= 0) diagonal[li] += w[k];
                    if (lj >= 0) diagonal[lj] += w[k];
                    if (li >= 0 && lj >= 0) {
                        entries.emplace_back(li, lj, -w[k]);
                        entries.emplace_back(lj, li, -w[k]);
                    } else if (li >= 0) {
                        rhs(li, 0) += w[k] * boundary_uv[j][0];
                        rhs(li, 1) += w[k] * boundary_uv[j][1];
                    } else if (lj >= 0) {
                        rhs(lj, 0) += w[k] * boundary_uv[i][0];
                        rhs(lj, 1) += w[k] * boundary_uv[i][1];
                    }
                }
                for (int i = 0; i < m; ++i) entries.emplace_back(i, i, diagonal[i]);
                Eigen::SparseMatrix<double> A(m, m);
                A.setFromTriplets(entries.begin(), entries.end());
                if (!analysed) solver.analyzePattern(A), analysed = true;
                solver.factorize(A);
                if (solver.info() != Eigen::Success) return false;
                const Eigen::MatrixX2d x = solver.solve(rhs);
                for (int i = 0; i < m; ++i) uv_of[i] = {x(i, 0), x(i, 1)};
                return true;
            };
            auto must_solve = [&](const std::vector<double>& w) {
                QC_CHECK(solve(w), "parameterize_patches: factorisation failed on patch " + std::to_string(q));
            };
            std::vector<double> w = base;
            must_solve(w);
            if (folds()) {
                // In long thin patches the cotangent map squeezes some triangles below rounding;
                // Tutte's uniform weights squeeze less.
                w.assign(edges.size(), 1.0);
                must_solve(w);
            }
            // Stretch minimisation (Yoshizawa, Belyaev & Seidel 2004): a harmonic map squeezes the
            // far end of a bulging patch (a head bounded by a loop round the neck) exponentially,
            // and the fit would put almost no control points there. Reweight each edge by the local
            // L2 stretch of its end vertices and solve again; keep the least stretched map. The
            // weights stay positive and symmetric: still a Tutte map, still SPD.
            if (!folds()) {
                const std::vector<int>& tris = patch_triangles[q];
                std::vector<double> area3(tris.size());
                double total3 = 0;
                for (size_t k = 0; k < tris.size(); ++k) total3 += area3[k] = triangle_area(mesh, tris[k]);
                // Patch L2 stretch of the current map (uv scaled to the patch's 3D area) and the
                // per-vertex stretch in sigma_sum; infinite if a triangle is degenerate in uv.
                auto stretch = [&]() {
                    double e = 0;
                    for (size_t k = 0; k < tris.size(); ++k) {
                        const Triangle& tri = mesh.triangles[tris[k]];
                        const UV a = uv(tri[0]), b = uv(tri[1]), c = uv(tri[2]);
                        const double two_a = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                        if (!(two_a > 0)) return std::numeric_limits<double>::infinity();
                        const Vec3 &p0 = mesh.points[tri[0]], &p1 = mesh.points[tri[1]], &p2 = mesh.points[tri[2]];
                        // Derivatives of the inverse map (uv -> 3D); with the unit square scaled to
                        // the patch's 3D area, Sander's L2 stretch is (|d/ds|^2 + |d/dt|^2) / 2.
                        const Vec3 ds = (p0 * (b[1] - c[1]) + p1 * (c[1] - a[1]) + p2 * (a[1] - b[1])) / two_a;
                        const Vec3 dt = (p0 * (c[0] - b[0]) + p1 * (a[0] - c[0]) + p2 * (b[0] - a[0])) / two_a;
                        const double l2 = 0.5 * (dot(ds, ds) + dot(dt, dt)) / total3;
                        e += area3[k] * l2;
                        for (int v : tri) sigma_sum[v] += area3[k] * l2, area_sum[v] += area3[k];
                    }
                    return std::sqrt(e / total3);
                };
                std::vector<UV> best_uv = uv_of;
                double best = stretch();
                for (int it = 0; it < kStretchIterations && std::isfinite(best); ++it) {
                    for (size_t k = 0; k < edges.size(); ++k) {
                        const auto [i, j] = edges[k];
                        auto sigma = [&](int v) {
                            return area_sum[v] > 0 && sigma_sum[v] > 0 ? std::sqrt(sigma_sum[v] / area_sum[v]) : 1.0;
                        };
                        w[k] /= std::sqrt(sigma(i) * sigma(j));
                    }
                    for (int t : tris)
                        for (int v : mesh.triangles[t]) sigma_sum[v] = area_sum[v] = 0;
                    if (!solve(w)) break;
                    const double e = folds() ? std::numeric_limits<double>::infinity() : stretch();
                    if (!(e < 0.99 * best)) break;
                    best = e;
                    best_uv = uv_of;
                }
                uv_of = best_uv;
                for (int t : tris)
                    for (int v : mesh.triangles[t]) sigma_sum[v] = area_sum[v] = 0;
            }
        }
        for (int t : patch_triangles[q])
            for (int k = 0; k < 3; ++k) {
                const int v = mesh.triangles[t][k];
                layout->corner_uv[t][k] = local[v] >= 0 ? uv_of[local[v]] : boundary_uv[v];
            }
        for (int v : unknowns) local[v] = -1;
        for (int v : loop) local[v] = -1;
    }
}

void measure_quality(QuadLayout* layout) {
    const Mesh& mesh = layout->mesh;
    LayoutQuality& qual = layout->quality;
    qual = LayoutQuality{};
    const double area = surface_area(mesh);
    // Patch areas.
    std::vector<double> patch_area(layout->cage.num_quads(), 0);
    for (int t = 0; t < mesh.num_triangles(); ++t)
        patch_area[layout->triangle_patch[t]] += triangle_area(mesh, t);
    const auto [lo, hi] = std::minmax_element(patch_area.begin(), patch_area.end());
    qual.patch_area_max_over_min = *lo > 0 ? *hi / *lo : std::numeric_limits<double>::infinity();
    // Total layout edge length.
    double total = 0;
    for (const auto& p : layout->edge_paths)
        for (size_t i = 0; i + 1 < p.size(); ++i) total += norm(mesh.points[p[i + 1]] - mesh.points[p[i]]);
    qual.edge_length_over_sqrt_area = total / std::sqrt(area);
    // Corner sector angles, as issue #20 defines them (and check_layout.py --quality measures them):
    // the chord from the corner to the point a tenth of each layout edge's arc length along it,
    // projected on the corner's tangent plane (area-weighted normal); the directions sorted by angle
    // round the normal; each gap's deviation from 360 / degree.
    const Surface s(mesh);
    std::vector<std::vector<Vec3>> leaving(layout->cage.num_corners());
    auto chord = [&](const std::vector<int>& path, double path_length) {
        const double r = 0.1 * path_length;
        double run = 0;
        for (size_t i = 0; i + 1 < path.size(); ++i) {
            const double l = norm(mesh.points[path[i + 1]] - mesh.points[path[i]]);
            if (run + l >= r) {
                const double f = l > 0 ? (r - run) / l : 0;
                return mesh.points[path[i]] + (mesh.points[path[i + 1]] - mesh.points[path[i]]) * f -
                       mesh.points[path[0]];
            }
            run += l;
        }
        return mesh.points[path.back()] - mesh.points[path[0]];
    };
    for (size_t e = 0; e < layout->edge_paths.size(); ++e) {
        std::vector<int> p = layout->edge_paths[e];
        double len = 0;
        for (size_t i = 0; i + 1 < p.size(); ++i) len += norm(mesh.points[p[i + 1]] - mesh.points[p[i]]);
        for (int end = 0; end < 2; ++end) {
            if (end == 1) std::reverse(p.begin(), p.end());
            leaving[layout->cage.edges[e].corners[end]].push_back(chord(p, len));
        }
    }
    double dev_sum = 0;
    int dev_count = 0;
    for (int c = 0; c < layout->cage.num_corners(); ++c) {
        const auto& dirs = leaving[c];
        if (dirs.size() < 2) continue;
        const auto [e1, e2] = tangent_frame(vertex_normal(s, layout->corner_vertex[c]));
        std::vector<double> angle;
        for (const Vec3& d : dirs) angle.push_back(std::atan2(dot(d, e2), dot(d, e1)));
        std::sort(angle.begin(), angle.end());
        const double ideal = 2 * kPi / static_cast<double>(dirs.size());
        for (size_t k = 0; k < angle.size(); ++k) {
            const double gap = k + 1 < angle.size() ? angle[k + 1] - angle[k] : angle[0] + 2 * kPi - angle[k];
            const double d = std::abs(gap - ideal) * 180.0 / kPi;
            dev_sum += d;
            ++dev_count;
            qual.corner_angle_max_deviation_deg = std::max(qual.corner_angle_max_deviation_deg, d);
        }
    }
    qual.corner_angle_mean_deviation_deg = dev_count ? dev_sum / dev_count : 0;
    // Conformal distortion sigma1/sigma2 of each triangle's map into its patch square.
    double weighted = 0, weight = 0;
    for (int t = 0; t < mesh.num_triangles(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const auto& uv = layout->corner_uv[t];
        const double uv_area = 0.5 * ((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1]) -
                                      (uv[2][0] - uv[0][0]) * (uv[1][1] - uv[0][1]));
        if (!(uv_area > 0)) {
            ++qual.flipped_triangles;
            continue;
        }
        const Vec3 e1 = mesh.points[tri[1]] - mesh.points[tri[0]],
                   e2 = mesh.points[tri[2]] - mesh.points[tri[0]];
        const double l1 = norm(e1);
        const double a3 = norm(cross(e1, e2));
        if (!(l1 > 0) || !(a3 > 0)) continue;
        // Local 2D frame of the triangle: x along e1.
        const double x2 = dot(e2, e1) / l1, y2 = a3 / l1;
        // J maps (x, y) to (u, v): J * [l1 x2; 0 y2] = [du1 du2; dv1 dv2].
        const double du1 = uv[1][0] - uv[0][0], du2 = uv[2][0] - uv[0][0];
        const double dv1 = uv[1][1] - uv[0][1], dv2 = uv[2][1] - uv[0][1];
        const double j11 = du1 / l1, j21 = dv1 / l1;
        const double j12 = (du2 - j11 * x2) / y2, j22 = (dv2 - j21 * x2) / y2;
        const double fro = j11 * j11 + j12 * j12 + j21 * j21 + j22 * j22;
        const double det = std::abs(j11 * j22 - j12 * j21);
        const double disc = std::sqrt(std::max(0.0, fro * fro - 4 * det * det));
        const double s1 = std::sqrt(0.5 * (fro + disc));
        const double s2 = s1 > 0 ? det / s1 : 0.0;  // s1 * s2 = |det J|; stabler than the difference
        const double d = s2 > 0 ? s1 / s2 : std::numeric_limits<double>::infinity();
        const double w = 0.5 * a3;
        weighted += w * std::log(d);  // geometric mean: one sliver must not swamp the figure
        weight += w;
        qual.distortion_max = std::max(qual.distortion_max, d);
    }
    qual.distortion_mean = weight > 0 ? std::exp(weighted / weight) : 0;
}

}  // namespace quadcage::layout::detail

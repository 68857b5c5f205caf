// verify_quad_layout(): the layout's own check, independent of how the layout was built.

#include <algorithm>
#include <cmath>
#include <map>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/surface.h"
#include "quadcage/core/validate.h"
#include "quadcage/layout/quad_layout.h"

namespace quadcage::layout {

namespace {

std::string num(long v) {
    return std::to_string(v);
}

}  // namespace

std::string verify_quad_layout(const QuadLayout& L) {
    const Mesh& mesh = L.mesh;
    const ValidationReport report = validate(mesh);
    if (report.components.size() != 1 || !report.components[0].quaddable() ||
        !report.components[0].consistently_oriented)
        return "the layout mesh is not one closed, oriented, manifold surface";
    const int g = report.components[0].genus;
    if (g != L.genus) return "genus " + num(L.genus) + " recorded, the mesh has genus " + num(g);
    if (const std::string c = subdiv::check_cage(L.cage); !c.empty()) return "cage: " + c;

    // Counts and degrees: the minimum for the genus (Lemma 4, Corollary 2, Remark 1; a cube for g = 0).
    const int want_quads = g >= 2 ? 10 * g - 10 : (g == 1 ? 4 : 6);
    const int want_corners = g >= 2 ? 8 * g - 8 : (g == 1 ? 4 : 8);
    const int want_degree = g >= 2 ? 5 : (g == 1 ? 4 : 3);
    if (L.cage.num_quads() != want_quads) return num(L.cage.num_quads()) + " quads, want " + num(want_quads);
    if (L.cage.num_corners() != want_corners)
        return num(L.cage.num_corners()) + " corners, want " + num(want_corners);
    std::vector<int> degree(L.cage.num_corners(), 0);
    for (const auto& e : L.cage.edges)
        for (int c : e.corners) ++degree[c];
    for (int c = 0; c < L.cage.num_corners(); ++c)
        if (degree[c] != want_degree)
            return "corner " + num(c) + " has degree " + num(degree[c]) + ", want " + num(want_degree);
    // Rule (iii): two quads share at most two sides, and never two adjacent ones.
    std::map<std::pair<int, int>, std::vector<int>> shared;
    for (int q = 0; q < L.cage.num_quads(); ++q)
        for (int k = 0; k < 4; ++k) {
            const auto& e = L.cage.edges[L.cage.quads[q].edges[k]];
            const int other = e.quads[0] == q && e.sides[0] == k ? e.quads[1] : e.quads[0];
            if (other == q) return "quad " + num(q) + " borders itself";
            shared[{q, other}].push_back(k);
        }
    for (const auto& [pair, sides] : shared)
        if (sides.size() > 2 || (sides.size() == 2 && (sides[1] - sides[0]) % 4 != 2))
            return "quads " + num(pair.first) + " and " + num(pair.second) +
                   " share adjacent sides or more than two";

    // Corners sit on mesh vertices; layout edges are simple mesh-edge paths between their corners,
    // disjoint but at corners.
    const int n = mesh.num_vertices(), nt = mesh.num_triangles();
    if (static_cast<int>(L.corner_vertex.size()) != L.cage.num_corners())
        return "corner_vertex has the wrong size";
    std::vector<int> corner_of(n, -1);
    for (int c = 0; c < L.cage.num_corners(); ++c) {
        const int v = L.corner_vertex[c];
        if (v < 0 || v >= n) return "corner " + num(c) + " is no mesh vertex";
        if (corner_of[v] >= 0) return "two corners on mesh vertex " + num(v);
        corner_of[v] = c;
        if (L.cage.points[c] != mesh.points[v]) return "corner " + num(c) + " is not at its mesh vertex";
    }
    const detail::Surface s(mesh);
    if (L.edge_paths.size() != L.cage.edges.size()) return "edge_paths has the wrong size";
    std::vector<int> path_of_vertex(n, -1);
    for (size_t e = 0; e < L.edge_paths.size(); ++e) {
        const auto& p = L.edge_paths[e];
        if (p.size() < 2 || p.front() != L.corner_vertex[L.cage.edges[e].corners[0]] ||
            p.back() != L.corner_vertex[L.cage.edges[e].corners[1]])
            return "layout edge " + num(static_cast<long>(e)) + " does not run between its corners";
        for (size_t i = 0; i + 1 < p.size(); ++i)
            if (s.find_half_edge(p[i], p[i + 1]) < 0)
                return "layout edge " + num(static_cast<long>(e)) + " leaves the mesh edges";
        for (size_t i = 1; i + 1 < p.size(); ++i) {
            if (corner_of[p[i]] >= 0)
                return "layout edge " + num(static_cast<long>(e)) + " passes through a corner";
            if (path_of_vertex[p[i]] >= 0)
                return "layout edges " + num(path_of_vertex[p[i]]) + " and " + num(static_cast<long>(e)) +
                       " meet away from corners";
            path_of_vertex[p[i]] = static_cast<int>(e);
        }
    }

    // Patches: each a connected disk bounded by exactly its quad's 4 sides, walked with the patch on the
    // left.
    if (static_cast<int>(L.triangle_patch.size()) != nt) return "triangle_patch has the wrong size";
    const std::vector<char> cut = detail::cut_half_edges(s, L.edge_paths);
    std::vector<int> component;
    const int nc = detail::face_components(s, cut, &component);
    if (nc != L.cage.num_quads())
        return "the layout edges cut " + num(nc) + " regions, not " + num(L.cage.num_quads());
    std::vector<int> patch_of_component(nc, -1), boundary(L.cage.num_quads(), 0);
    for (int t = 0; t < nt; ++t) {
        const int p = L.triangle_patch[t];
        if (p < 0 || p >= L.cage.num_quads()) return "triangle " + num(t) + " has no valid patch";
        int& pc = patch_of_component[component[t]];
        if (pc >= 0 && pc != p) return "a region of the layout carries two patch labels";
        pc = p;
        for (int k = 0; k < 3; ++k)
            if (cut[3 * t + k]) ++boundary[p];
    }
    std::vector<char> seen(L.cage.num_quads(), 0);
    for (int pc : patch_of_component) {
        if (seen[pc]) return "patch " + num(pc) + " is not connected";
        seen[pc] = 1;
    }
    std::vector<std::vector<int>> patch_triangles(L.cage.num_quads());
    for (int t = 0; t < nt; ++t) patch_triangles[L.triangle_patch[t]].push_back(t);
    std::vector<int> loop, side;
    for (int q = 0; q < L.cage.num_quads(); ++q) {
        detail::quad_boundary(L, q, &loop, &side);
        if (static_cast<int>(loop.size()) != boundary[q])
            return "patch " + num(q) + " has a boundary other than its 4 sides";
        for (size_t i = 0; i < loop.size(); ++i) {
            const int h = s.find_half_edge(loop[i], loop[(i + 1) % loop.size()]);
            if (h < 0 || L.triangle_patch[h / 3] != q)
                return "patch " + num(q) + " does not lie to the left of its sides";
        }
        std::vector<int> tv;
        const long faces = static_cast<long>(patch_triangles[q].size());
        for (int t : patch_triangles[q])
            tv.insert(tv.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
        std::sort(tv.begin(), tv.end());
        tv.erase(std::unique(tv.begin(), tv.end()), tv.end());
        const long chi = static_cast<long>(tv.size()) - (3 * faces + boundary[q]) / 2 + faces;
        if (chi != 1) return "patch " + num(q) + " is not a disk (Euler characteristic " + num(chi) + ")";
    }

    // Maps: inside the unit square, sides by arc length (so neighbours agree), no flipped triangle.
    if (static_cast<int>(L.corner_uv.size()) != nt) return "corner_uv has the wrong size";
    constexpr double tol = 1e-9;
    for (int t = 0; t < nt; ++t) {
        const auto& uv = L.corner_uv[t];
        for (const UV& p : uv)
            if (!(p[0] >= -tol && p[0] <= 1 + tol && p[1] >= -tol && p[1] <= 1 + tol))
                return "triangle " + num(t) + " maps outside the unit square";
        const double area =
            (uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1]) - (uv[2][0] - uv[0][0]) * (uv[1][1] - uv[0][1]);
        if (!(area > 0)) return "triangle " + num(t) + " is flipped or degenerate in its patch map";
    }
    std::vector<UV> expected(n);
    std::vector<char> on_boundary(n, 0);
    for (int q = 0; q < L.cage.num_quads(); ++q) {
        detail::quad_boundary(L, q, &loop, &side);
        const std::vector<UV> on_sides = detail::boundary_positions(mesh, loop, side);
        for (size_t i = 0; i < loop.size(); ++i) {
            expected[loop[i]] = on_sides[i];
            on_boundary[loop[i]] = 1;
        }
        for (int t : patch_triangles[q]) {
            for (int k = 0; k < 3; ++k) {
                const int v = mesh.triangles[t][k];
                if (!on_boundary[v]) continue;
                const UV& got = L.corner_uv[t][k];
                if (std::abs(got[0] - expected[v][0]) > tol || std::abs(got[1] - expected[v][1]) > tol)
                    return "patch " + num(q) + " maps boundary vertex " + num(v) + " off its side position";
            }
        }
        for (int v : loop) on_boundary[v] = 0;
    }
    return "";
}

}  // namespace quadcage::layout

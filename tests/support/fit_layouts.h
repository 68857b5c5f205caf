#pragma once
// Hand-built quad layouts with exact patch coordinates, for fit tests that must not wait for
// layout::build_quad_layout(): a torus cut into its 2 x 2 grid blocks (4 quads, multi-edge cage)
// and a cube-sphere cut into its 6 cube faces.

#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "quadcage/core/shapes.h"
#include "quadcage/layout/quad_layout.h"
#include "support/quad_shapes.h"

namespace quadcage::test {

/// shapes::torus(n_major, n_minor, R, r) with the 4-quad layout of torus_cage(): patch 2a + b is
/// grid block (a, b) (half the grid in each direction), (u, v) linear in the grid indices.
/// \pre n_major and n_minor are even and >= 4.
inline layout::QuadLayout torus_layout(int n_major, int n_minor, double R = 1.0, double r = 0.35) {
    layout::QuadLayout L;
    L.mesh = shapes::torus(n_major, n_minor, R, r);
    L.input_vertices = L.mesh.num_vertices();
    L.genus = 1;
    const int hM = n_major / 2, hm = n_minor / 2;
    auto id = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
    std::vector<Vec3> corners;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            L.corner_vertex.push_back(id(a * hM, b * hm));
            corners.push_back(L.mesh.points[id(a * hM, b * hm)]);
        }
    L.cage = torus_cage(corners);
    // shapes::torus emits, per grid cell (i, j) in order, (i,j)(i+1,j)(i+1,j+1) and (i,j)(i+1,j+1)(i,j+1).
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j) {
            const int a = i / hM, b = j / hm;
            auto uv = [&](int di, int dj) {
                return layout::UV{double(i + di - a * hM) / hM, double(j + dj - b * hm) / hm};
            };
            L.triangle_patch.push_back(2 * a + b);
            L.corner_uv.push_back({uv(0, 0), uv(1, 0), uv(1, 1)});
            L.triangle_patch.push_back(2 * a + b);
            L.corner_uv.push_back({uv(0, 0), uv(1, 1), uv(0, 1)});
        }
    return L;
}

/// A sphere of radius `radius` made of the 6 faces of a cube, each an n x n grid pushed onto the
/// sphere (equal-angle warp), with the 6-quad cube layout: patch q is cube face q of cube_quads()
/// and (u, v) = grid indices / n. Corners have valence 3.
inline layout::QuadLayout cube_sphere_layout(int n, double radius = 1.0) {
    layout::QuadLayout L;
    L.genus = 0;
    const subdiv::QuadMesh cube = cube_quads(1.0);
    std::map<std::tuple<int, int, int>, int> vertex_of;
    auto vertex = [&](const Vec3& p) {
        // Lattice key of a cube point: coordinates are multiples of 2/n in [-1, 1].
        const auto key = std::make_tuple(static_cast<int>(std::lround((p.x + 1) * n / 2)),
                                         static_cast<int>(std::lround((p.y + 1) * n / 2)),
                                         static_cast<int>(std::lround((p.z + 1) * n / 2)));
        auto [it, fresh] = vertex_of.emplace(key, L.mesh.num_vertices());
        if (fresh) {
            const double a = kPi / 4;
            const Vec3 w{std::tan(a * p.x), std::tan(a * p.y), std::tan(a * p.z)};
            L.mesh.points.push_back(w * (radius / norm(w)));
        }
        return it->second;
    };
    for (int q = 0; q < cube.num_quads(); ++q) {
        const Vec3 o = cube.points[cube.quads[q][0]];
        const Vec3 du = cube.points[cube.quads[q][1]] - o, dv = cube.points[cube.quads[q][3]] - o;
        auto at = [&](int i, int j) { return vertex(o + du * (double(i) / n) + dv * (double(j) / n)); };
        auto uv = [&](int i, int j) { return layout::UV{double(i) / n, double(j) / n}; };
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                L.mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                L.corner_uv.push_back({uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)});
                L.triangle_patch.push_back(q);
                L.mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
                L.corner_uv.push_back({uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)});
                L.triangle_patch.push_back(q);
            }
    }
    L.input_vertices = L.mesh.num_vertices();
    subdiv::QuadMesh corners = cube;
    for (int c = 0; c < 8; ++c) {
        L.corner_vertex.push_back(vertex(cube.points[c]));
        corners.points[c] = L.mesh.points[L.corner_vertex[c]];
    }
    L.cage = cage_from_simple(corners);
    return L;
}

}  // namespace quadcage::test

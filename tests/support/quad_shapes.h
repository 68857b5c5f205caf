#pragma once
// Quad control meshes and cages shared by the subdiv and fit tests.

#include <cmath>
#include <map>
#include <utility>

#include "quadcage/core/shapes.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::test {

constexpr double kPi = 3.14159265358979323846;

/// The cube [-h, h]^3 as 6 quads (all corners of valence 3), counter-clockwise from outside.
inline subdiv::QuadMesh cube_quads(double h = 1.0) {
    subdiv::QuadMesh m;
    for (int i = 0; i < 8; ++i) m.points.push_back({i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h});
    m.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return m;
}

/// A torus as an nu x nv grid of quads (all regular), vertex (i, j) at index i*nv + j.
inline subdiv::QuadMesh torus_quads(int nu, int nv, double R = 2.0, double r = 0.7) {
    subdiv::QuadMesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            m.points.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
        }
    auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    return m;
}

/// Every triangle of an icosahedron split into 3 quads (corner, edge midpoint, centroid, edge
/// midpoint): 60 quads whose 12 icosahedron vertices have valence 5, like the corners of a
/// 10g-10 cage; centroids have valence 3, edge midpoints valence 4.
inline subdiv::QuadMesh icosahedron_quads() {
    const Mesh ico = shapes::icosphere(0, 1.0);
    subdiv::QuadMesh m;
    m.points = ico.points;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        auto [it, fresh] = mid.emplace(key, m.num_vertices());
        if (fresh) m.points.push_back((ico.points[a] + ico.points[b]) * 0.5);
        return it->second;
    };
    for (const Triangle& t : ico.triangles) {
        const int c = m.num_vertices();
        m.points.push_back((ico.points[t[0]] + ico.points[t[1]] + ico.points[t[2]]) / 3.0);
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3], p = t[(k + 2) % 3];
            m.quads.push_back({a, midpoint(a, b), c, midpoint(p, a)});
        }
    }
    return m;
}

/// Explicit edges for a face-vertex quad list in which every edge is determined by its ends.
inline subdiv::Cage cage_from_simple(const subdiv::QuadMesh& m) {
    subdiv::Cage cage;
    cage.points = m.points;
    std::map<std::pair<int, int>, int> id;
    for (int q = 0; q < m.num_quads(); ++q) {
        subdiv::Cage::Quad quad;
        quad.corners = m.quads[q];
        for (int k = 0; k < 4; ++k) {
            const int a = m.quads[q][k], b = m.quads[q][(k + 1) % 4];
            auto [it, fresh] = id.emplace(std::minmax(a, b), cage.num_edges());
            if (fresh) {
                cage.edges.push_back({{a, b}, {q, -1}, {k, -1}});
            } else {
                cage.edges[it->second].quads[1] = q;
                cage.edges[it->second].sides[1] = k;
            }
            quad.edges[k] = it->second;
        }
        cage.quads.push_back(quad);
    }
    return cage;
}

/// The 4-quad torus cage (2 x 2 grid, corners (i, j) in {0,1}^2 at index 2i + j) with multi-edges:
/// neighbouring corners are joined by two edges. Quad 2a + b covers grid block (a, b) with corners
/// (a,b), (a+1,b), (a+1,b+1), (a,b+1). `points` gives the 4 corner positions.
inline subdiv::Cage torus_cage(const std::vector<Vec3>& points) {
    subdiv::Cage cage;
    cage.points = points;
    auto corner = [](int i, int j) { return 2 * (i % 2) + (j % 2); };
    auto U = [](int i, int j) { return 2 * (i % 2) + (j % 2); };      // (i,j) -> (i+1,j)
    auto W = [](int i, int j) { return 4 + 2 * (i % 2) + (j % 2); };  // (i,j) -> (i,j+1)
    cage.edges.resize(8);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            cage.edges[U(i, j)].corners = {corner(i, j), corner(i + 1, j)};
            cage.edges[W(i, j)].corners = {corner(i, j), corner(i, j + 1)};
        }
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            const int q = cage.num_quads();
            subdiv::Cage::Quad quad;
            quad.corners = {corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)};
            quad.edges = {U(i, j), W(i + 1, j), U(i, j + 1), W(i, j)};
            cage.quads.push_back(quad);
            cage.edges[U(i, j)].quads[0] = q, cage.edges[U(i, j)].sides[0] = 0;
            cage.edges[W(i + 1, j)].quads[0] = q, cage.edges[W(i + 1, j)].sides[0] = 1;
            cage.edges[U(i, j + 1)].quads[1] = q, cage.edges[U(i, j + 1)].sides[1] = 2;
            cage.edges[W(i, j)].quads[1] = q, cage.edges[W(i, j)].sides[1] = 3;
        }
    return cage;
}

/// torus_cage() with corners on a torus (R, r) at angles pi*i + 0.3, pi*j + 0.5.
inline subdiv::Cage torus_cage(double R = 2.0, double r = 0.8) {
    std::vector<Vec3> p;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            const double u = kPi * i + 0.3, v = kPi * j + 0.5;
            p.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
        }
    return torus_cage(p);
}

}  // namespace quadcage::test

#pragma once
// A 4-quad layout network on shapes::torus(), built by hand from grid lines, for the tests of the
// layout's stages (patches, relaxation) below build_quad_layout().

#include <vector>

#include "quadcage/core/shapes.h"

namespace quadcage::test {

/// Corners and layout edges of a grid of patches on shapes::torus(n_major, n_minor): the meridians
/// at major indices `is` and the longitudes at minor indices `js` (increasing; vertex (i, j) is
/// i * n_minor + j). Corners at their crossings; each edge a grid-line path from a corner to the
/// next one. With 2 lines each way every pair of neighbouring corners is joined twice, as in the
/// level-0 torus cage.
struct TorusNetwork {
    Mesh mesh;
    std::vector<int> corners;
    std::vector<std::vector<int>> paths;
};

inline TorusNetwork torus_network(int n_major, int n_minor, const std::vector<int>& is, const std::vector<int>& js) {
    TorusNetwork t;
    t.mesh = shapes::torus(n_major, n_minor);
    auto id = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
    for (int i : is)
        for (int j : js) t.corners.push_back(id(i, j));
    for (int i : is)
        for (size_t k = 0; k < js.size(); ++k) {
            const int j0 = js[k], j1 = k + 1 < js.size() ? js[k + 1] : js[0] + n_minor;
            std::vector<int> p;
            for (int j = j0; j <= j1; ++j) p.push_back(id(i, j));
            t.paths.push_back(p);
        }
    for (int j : js)
        for (size_t k = 0; k < is.size(); ++k) {
            const int i0 = is[k], i1 = k + 1 < is.size() ? is[k + 1] : is[0] + n_major;
            std::vector<int> p;
            for (int i = i0; i <= i1; ++i) p.push_back(id(i, j));
            t.paths.push_back(p);
        }
    return t;
}

}  // namespace quadcage::test

#include "detail/patch_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "quadcage/core/errors.h"

namespace quadcage::fit::detail {

namespace {

/// Barycentric coordinates of (u, v) in the triangle a, b, c of the plane; false if degenerate.
bool barycentric(const layout::UV& a, const layout::UV& b, const layout::UV& c, double u, double v,
                 std::array<double, 3>* w) {
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if (!(std::abs(det) > 0)) return false;
    const double l1 = ((u - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (v - a[1])) / det;
    const double l2 = ((b[0] - a[0]) * (v - a[1]) - (u - a[0]) * (b[1] - a[1])) / det;
    *w = {1 - l1 - l2, l1, l2};
    return true;
}

int cell_of(double x, int grid) { return std::clamp(static_cast<int>(std::floor(x * grid)), 0, grid - 1); }

}  // namespace

PatchLocator::PatchLocator(const layout::QuadLayout& layout) : layout_(layout) {
    const int nq = layout.cage.num_quads();
    std::vector<int> count(nq, 0);
    for (int p : layout.triangle_patch) ++count[p];
    patches_.resize(nq);
    for (int q = 0; q < nq; ++q) {
        patches_[q].grid = std::clamp(static_cast<int>(std::sqrt(count[q] / 2.0)), 1, 512);
        patches_[q].cells.resize(static_cast<size_t>(patches_[q].grid) * patches_[q].grid);
    }
    for (int t = 0; t < layout.mesh.num_triangles(); ++t) {
        Patch& patch = patches_[layout.triangle_patch[t]];
        const auto& uv = layout.corner_uv[t];
        double lo[2] = {1, 1}, hi[2] = {0, 0};
        for (const auto& c : uv)
            for (int d = 0; d < 2; ++d) lo[d] = std::min(lo[d], c[d]), hi[d] = std::max(hi[d], c[d]);
        const int g = patch.grid;
        for (int i = cell_of(lo[0], g); i <= cell_of(hi[0], g); ++i)
            for (int j = cell_of(lo[1], g); j <= cell_of(hi[1], g); ++j) patch.cells[i * g + j].push_back(t);
    }
}

MeshSample PatchLocator::locate(int q, double u, double v) const {
    QC_CHECK(q >= 0 && q < static_cast<int>(patches_.size()), "PatchLocator: patch out of range");
    u = std::clamp(u, 0.0, 1.0);
    v = std::clamp(v, 0.0, 1.0);
    const Patch& patch = patches_[q];
    const int g = patch.grid, ci = cell_of(u, g), cj = cell_of(v, g);
    int best = -1;
    double best_violation = std::numeric_limits<double>::infinity();
    std::array<double, 3> best_w{};
    // Rings of cells around (ci, cj) until some triangle is found (ring 0 nearly always suffices).
    for (int ring = 0; ring < g && best < 0; ++ring)
        for (int i = std::max(0, ci - ring); i <= std::min(g - 1, ci + ring); ++i)
            for (int j = std::max(0, cj - ring); j <= std::min(g - 1, cj + ring); ++j) {
                if (std::max(std::abs(i - ci), std::abs(j - cj)) != ring) continue;
                for (int t : patch.cells[i * g + j]) {
                    const auto& uv = layout_.corner_uv[t];
                    std::array<double, 3> w;
                    if (!barycentric(uv[0], uv[1], uv[2], u, v, &w)) continue;
                    const double violation = -std::min({w[0], w[1], w[2]});
                    // Ties go to the lowest triangle index (cells list triangles in index order).
                    if (violation < best_violation) best = t, best_violation = violation, best_w = w;
                }
            }
    QC_CHECK(best >= 0, "PatchLocator: patch " + std::to_string(q) + " has no usable triangle");
    if (best_violation > 0) {
        for (double& x : best_w) x = std::max(0.0, x);
        const double s = best_w[0] + best_w[1] + best_w[2];
        for (double& x : best_w) x /= s;
    }
    MeshSample out;
    out.triangle = best;
    out.bary = best_w;
    const Triangle& tri = layout_.mesh.triangles[best];
    out.point = layout_.mesh.points[tri[0]] * best_w[0] + layout_.mesh.points[tri[1]] * best_w[1] +
                layout_.mesh.points[tri[2]] * best_w[2];
    return out;
}

}  // namespace quadcage::fit::detail

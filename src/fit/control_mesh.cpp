// A user's control mesh (`quadcage fit --cage`): checks against the mesh, and components matched.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "detail/control_mesh.h"
#include "quadcage/core/errors.h"
#include "quadcage/fit/fit.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/limit_surface.h"

namespace quadcage::fit {
namespace {

int find_root(std::vector<int>& parent, int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/// Component of every vertex (numbered by first vertex), connected through faces.
std::vector<int> vertex_components(const PolygonMesh& cage, int* count) {
    std::vector<int> parent(cage.num_vertices());
    std::iota(parent.begin(), parent.end(), 0);
    for (const auto& f : cage.faces)
        for (size_t k = 1; k < f.size(); ++k) parent[find_root(parent, f[k])] = find_root(parent, f[0]);
    std::vector<int> label(cage.num_vertices(), -1), of_root(cage.num_vertices(), -1);
    *count = 0;
    for (int v = 0; v < cage.num_vertices(); ++v) {
        int& r = of_root[find_root(parent, v)];
        if (r < 0) r = (*count)++;
        label[v] = r;
    }
    return label;
}

/// Genus of a closed connected polygon mesh (V - E + F = 2 - 2g).
int genus_of(const PolygonMesh& cage) {
    long long corners = 0;
    for (const auto& f : cage.faces) corners += static_cast<long long>(f.size());
    const long long chi = cage.num_vertices() - corners / 2 + cage.num_faces();
    return static_cast<int>((2 - chi) / 2);
}

/// Genus of a closed connected triangle mesh.
int genus_of(const Mesh& mesh) {
    std::vector<char> used(mesh.num_vertices(), 0);
    for (const Triangle& t : mesh.triangles)
        for (int v : t) used[v] = 1;
    const long long v = std::count(used.begin(), used.end(), 1);
    const long long chi = v - 3LL * mesh.num_triangles() / 2 + mesh.num_triangles();
    return static_cast<int>((2 - chi) / 2);
}

BoundingBox box_of(const std::vector<Vec3>& points) {
    BoundingBox b{points.front(), points.front()};
    for (const Vec3& p : points)
        for (int d = 0; d < 3; ++d) b.min[d] = std::min(b.min[d], p[d]), b.max[d] = std::max(b.max[d], p[d]);
    return b;
}

/// Volume shared by two boxes, each first grown by 1% of its diagonal (a flat part has no volume).
double overlap(BoundingBox a, BoundingBox b) {
    double v = 1;
    for (BoundingBox* x : {&a, &b}) {
        const double pad = 0.01 * x->diagonal();
        for (int d = 0; d < 3; ++d) x->min[d] -= pad, x->max[d] += pad;
    }
    for (int d = 0; d < 3; ++d) v *= std::max(0.0, std::min(a.max[d], b.max[d]) - std::max(a.min[d], b.min[d]));
    return v;
}

}  // namespace

namespace detail {

std::string check_control_mesh(const Mesh& mesh, const accel::ClosestPointIndex& index, const PolygonMesh& cage,
                               double max_mean_distance) {
    if (std::string why = subdiv::check_polygon_cage(cage); !why.empty()) return why;
    int components = 0;
    vertex_components(cage, &components);
    if (components != 1) return "it has " + std::to_string(components) + " connected components, the mesh 1";
    const int genus = genus_of(cage), mesh_genus = genus_of(mesh);
    if (genus != mesh_genus)
        return "its genus is " + std::to_string(genus) + ", the mesh's " + std::to_string(mesh_genus) +
               " (a control mesh must have the topology of the surface it approximates)";
    // Where its limit surface lies: the mean distance of a tessellation's vertices to the mesh.
    const subdiv::CageRefinement level1 = subdiv::refine_polygon_cage(cage);
    subdiv::LimitSurfaceOptions lso;
    lso.irregular_level = 2;  // a coarse look suffices
    const subdiv::LimitSurface limit(level1.level1, lso);
    const subdiv::LimitTessellation tess = limit.tessellate(2);
    double sum = 0;
    for (const accel::ClosestHit& h : index.query_all(tess.mesh.points)) sum += h.distance;
    const double mean = sum / std::max<size_t>(tess.mesh.points.size(), 1);
    const double diagonal = bounding_box(mesh).diagonal();
    if (!(mean <= max_mean_distance * diagonal)) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "it is far from the mesh: its limit surface lies %.3g%% of the mesh's bounding-box diagonal "
                      "away on average (at most %.3g%%); is it the cage of this mesh, in the same units and place?",
                      100 * mean / diagonal, 100 * max_mean_distance);
        return buf;
    }
    return {};
}

}  // namespace detail

std::string check_control_mesh(const Mesh& mesh, const PolygonMesh& cage, double max_mean_distance) {
    const accel::ClosestPointIndex index(mesh);
    return detail::check_control_mesh(mesh, index, cage, max_mean_distance);
}

std::vector<PolygonMesh> match_control_mesh(const std::vector<Mesh>& components, const PolygonMesh& cage) {
    if (components.empty()) throw InvalidInput("match_control_mesh: no mesh components");
    if (cage.num_faces() == 0 || cage.num_vertices() == 0) throw InvalidInput("the control mesh has no faces");
    for (const auto& f : cage.faces)
        for (int v : f)
            if (v < 0 || v >= cage.num_vertices())
                throw InvalidInput("the control mesh has a face with a vertex index out of range");
    int count = 0;
    const std::vector<int> label = vertex_components(cage, &count);
    // Unused vertices are components of their own: leave them out.
    std::vector<char> used(cage.num_vertices(), 0);
    for (const auto& f : cage.faces)
        for (int v : f) used[v] = 1;
    std::vector<PolygonMesh> parts(count);
    std::vector<int> local(cage.num_vertices(), -1);
    for (int v = 0; v < cage.num_vertices(); ++v)
        if (used[v]) local[v] = parts[label[v]].num_vertices(), parts[label[v]].points.push_back(cage.points[v]);
    for (const auto& f : cage.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(local[v]);
        parts[label[f[0]]].faces.push_back(std::move(g));
    }
    parts.erase(std::remove_if(parts.begin(), parts.end(), [](const PolygonMesh& p) { return p.faces.empty(); }),
                parts.end());
    const size_t n = components.size();
    if (parts.size() != n)
        throw InvalidInput("the control mesh has " + std::to_string(parts.size()) + " connected component" +
                           (parts.size() == 1 ? "" : "s") + ", the mesh " + std::to_string(n) +
                           " (give one control mesh component per mesh component)");
    if (n == 1) return parts;
    std::vector<PolygonMesh> out(n);
    std::vector<char> taken(n, 0);
    for (PolygonMesh& part : parts) {
        const BoundingBox b = box_of(part.points);
        size_t best = n;
        double best_overlap = 0;
        for (size_t i = 0; i < n; ++i) {
            const double o = overlap(b, bounding_box(components[i]));
            if (o > best_overlap) best = i, best_overlap = o;
        }
        if (best == n || taken[best])
            throw InvalidInput("the control mesh's components do not match the mesh's one to one (by the overlap of "
                               "their bounding boxes)");
        taken[best] = 1;
        out[best] = std::move(part);
    }
    return out;
}

}  // namespace quadcage::fit

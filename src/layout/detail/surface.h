#pragma once
// A closed, oriented triangle surface that curves live on: half-edge adjacency derived from the
// triangle list, rotation order around vertices, batched edge splits (new vertices only at edge
// midpoints, input vertices never move) and Dijkstra searches that avoid blocked vertices.

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::layout::detail {

class Surface {
public:
    /// \pre mesh is closed, manifold and consistently oriented.
    explicit Surface(Mesh mesh);

    const Mesh& mesh() const { return mesh_; }
    Mesh& mutable_mesh() { return mesh_; }
    int num_vertices() const { return mesh_.num_vertices(); }
    int num_half_edges() const { return 3 * mesh_.num_triangles(); }
    const Vec3& point(int v) const { return mesh_.points[v]; }

    // Half-edge h = 3*t + k runs from corner k to corner k+1 of triangle t.
    int from(int h) const { return mesh_.triangles[h / 3][h % 3]; }
    int to(int h) const { return mesh_.triangles[h / 3][(h % 3 + 1) % 3]; }
    int twin(int h) const { return twin_[h]; }
    int out_half_edge(int v) const { return out_[v]; }
    /// The next outgoing half-edge around from(h), in the surface's rotation order.
    int rotate(int h) const { return twin_[3 * (h / 3) + (h % 3 + 2) % 3]; }
    double length(int h) const { return norm(point(to(h)) - point(from(h))); }

    /// Neighbours of v in rotation order (starting anywhere).
    std::vector<int> ring(int v) const;
    /// Outgoing half-edges of v in rotation order.
    std::vector<int> out_half_edges(int v) const;
    /// Half-edge from a to b, or -1.
    int find_half_edge(int a, int b) const;

    /// Splits every listed undirected edge (pairs of vertex indices) at its midpoint, in one batch.
    /// Returns the new vertex of each edge, in the order given. Rebuilds the adjacency.
    std::vector<int> split_edges(const std::vector<std::pair<int, int>>& edges);

    /// Rebuilds twins and outgoing half-edges from the triangles.
    void rebuild();

private:
    Mesh mesh_;
    std::vector<int> twin_;
    std::vector<int> out_;
};

/// Whether the two triangles of half-edge h are this close to one plane: the cosine of the angle
/// between their normals is at least min_cos.
bool flat_edge(const Surface& s, int h, double min_cos);

/// Splits every edge longer than max_length at its midpoint, over passes until none is (input
/// vertices stay, in order; new ones are appended). Returns the number of vertices added. (Every
/// long edge: sparing some, e.g. creases, would leave the triangles along them to be split towards
/// them forever.)
int split_long_edges(Surface* s, double max_length);

/// Inserts into each curve the midpoints of its split edges. `split` lists (a, b, m): edge a-b was
/// split at new vertex m. Closed curves also walk the edge from their last vertex to their first.
void insert_midpoints(std::vector<std::vector<int>>& curves, const std::vector<std::array<int, 3>>& split,
                      bool closed = true);

/// A single-source or multi-source Dijkstra on the vertex graph of a Surface.
struct PathSearch {
    /// Starting vertices with their initial costs.
    std::vector<std::pair<int, double>> sources;
    /// Goal vertices with a cost added on arrival; empty: settle every reachable vertex.
    std::vector<std::pair<int, double>> targets;
    /// Vertices that may not be entered (sources may be blocked: they are entered anyway).
    const std::vector<char>* blocked = nullptr;
    /// Cost of half-edge h; default: its length.
    std::function<double(int)> cost;
    /// Vertices farther than this are not settled (their distance stays +inf).
    double max_distance = std::numeric_limits<double>::infinity();
    /// Without targets: stop once every one of these vertices is settled (empty: settle all).
    std::vector<int> settle;
};

struct PathResult {
    std::vector<double> distance;       ///< Per vertex; +inf when not reached.
    std::vector<int> parent_half_edge;  ///< Half-edge used to reach the vertex, -1 at sources.
    int target = -1;                    ///< Best target reached (-1: none).
    double target_cost = 0;             ///< Its distance plus its arrival cost.
    /// Vertices from a source to `v`.
    std::vector<int> path_to(const Surface& s, int v) const;
};

PathResult dijkstra(const Surface& s, const PathSearch& search);

/// The unit normal at v: the sum of its triangles' area vectors, normalised ((0, 0, 1) if it is 0);
/// the normal check_layout.py --quality measures corner angles about.
Vec3 vertex_normal(const Surface& s, int v);

/// Two unit vectors that make a right-handed frame with unit normal n (the corner angles' plane).
std::array<Vec3, 2> tangent_frame(const Vec3& n);

/// Lowers `distance`, the distances of a search without cost (edge lengths) from some sources, to
/// those of the same search with `sources` (at cost 0) added: the values dijkstra() gives for all
/// the sources together (each is the least rounded sum along a path, whatever order finds it), found
/// from the new sources only where they are nearer. `blocked` and `max_distance` as for PathSearch,
/// and the same as the search's that made `distance`.
void lower_distances(const Surface& s, const std::vector<int>& sources, const std::vector<char>* blocked,
                     double max_distance, std::vector<double>* distance);

}  // namespace quadcage::layout::detail

#include "quadcage/subdiv/cage.h"

#include <algorithm>
#include <map>
#include <string>

#include "quadcage/core/errors.h"

namespace quadcage::subdiv {

namespace {

std::string at(const char* what, int index) {
    return std::string(what) + " " + std::to_string(index);
}

/// Merges repeated indices so each stencil lists a point once, and sets the level-1 points.
void apply_stencils(const std::vector<Vec3>& points, CageRefinement* out) {
    for (Stencil& s : out->stencils) {
        std::sort(s.begin(), s.end());
        Stencil merged;
        for (const auto& [i, w] : s) {
            if (!merged.empty() && merged.back().first == i)
                merged.back().second += w;
            else
                merged.push_back({i, w});
        }
        s.swap(merged);
    }
    out->level1.points.resize(out->stencils.size());
    for (size_t i = 0; i < out->stencils.size(); ++i) {
        Vec3 p{0, 0, 0};
        for (const auto& [j, w] : out->stencils[i]) p = p + points[j] * w;
        out->level1.points[i] = p;
    }
}

/// The undirected edges of a polygon mesh, numbered in order of first use walking the faces, and
/// the edge of every face side (side k joins corners k and k+1).
struct PolygonEdges {
    std::vector<std::array<int, 2>> ends;        ///< Lower, higher vertex index.
    std::vector<std::vector<int>> faces;         ///< Faces using each edge (a face once per side).
    std::vector<std::vector<int>> side_edge;     ///< [face][side] -> edge.
    std::vector<int> forward_uses;               ///< Sides walking each edge from ends[0] to ends[1].
};

/// "the 144th vertex": counted from 1 in file order, which means the same in every format (OBJ
/// indices count from 1, PLY and OFF indices from 0).
std::string nth(int index, const char* what) {
    const int n = index + 1, tens = n % 100;
    const char* suffix = tens >= 11 && tens <= 13 ? "th" : n % 10 == 1 ? "st" : n % 10 == 2 ? "nd" : n % 10 == 3 ? "rd" : "th";
    return "the " + std::to_string(n) + suffix + " " + what;
}

PolygonEdges polygon_edges(const PolygonMesh& cage) {
    PolygonEdges out;
    std::map<std::pair<int, int>, int> index;
    out.side_edge.resize(cage.faces.size());
    for (size_t f = 0; f < cage.faces.size(); ++f) {
        const auto& face = cage.faces[f];
        for (size_t k = 0; k < face.size(); ++k) {
            const int a = face[k], b = face[(k + 1) % face.size()];
            const auto key = std::minmax(a, b);
            auto [it, added] = index.try_emplace({key.first, key.second}, static_cast<int>(out.ends.size()));
            if (added) {
                out.ends.push_back({key.first, key.second});
                out.faces.emplace_back();
                out.forward_uses.push_back(0);
            }
            out.faces[it->second].push_back(static_cast<int>(f));
            out.forward_uses[it->second] += a < b;
            out.side_edge[f].push_back(it->second);
        }
    }
    return out;
}

}  // namespace

std::string check_polygon_cage(const PolygonMesh& cage) {
    const int nv = cage.num_vertices(), nf = cage.num_faces();
    if (nf == 0) return "it has no faces";
    for (int v = 0; v < nv; ++v)
        if (!is_finite(cage.points[v])) return nth(v, "vertex") + " has a NaN or infinite coordinate";
    std::vector<int> uses(nv, 0);
    for (int f = 0; f < nf; ++f) {
        const auto& face = cage.faces[f];
        if (face.size() < 3) return nth(f, "face") + " has fewer than 3 corners";
        for (size_t k = 0; k < face.size(); ++k) {
            if (face[k] < 0 || face[k] >= nv) return nth(f, "face") + " has a vertex index out of range";
            for (size_t j = 0; j < k; ++j)
                if (face[j] == face[k]) return nth(f, "face") + " repeats " + nth(face[k], "vertex");
            ++uses[face[k]];
        }
    }
    for (int v = 0; v < nv; ++v)
        if (uses[v] == 0) return nth(v, "vertex") + " is used by no face";
    const PolygonEdges edges = polygon_edges(cage);
    for (size_t e = 0; e < edges.ends.size(); ++e) {
        const std::string name = "the edge between " + nth(edges.ends[e][0], "vertex") + " and " +
                                 nth(edges.ends[e][1], "vertex").substr(4);
        const size_t n = edges.faces[e].size();
        if (n == 1) return "it is open: " + name + " has one face (a closed surface has two on every edge)";
        if (n > 2) return "it is non-manifold: " + name + " has " + std::to_string(n) + " faces";
        if (edges.forward_uses[e] != 1)
            return "it is not consistently oriented: both faces at " + name + " walk it in the same direction";
    }
    // Around every vertex the faces must form one fan (a disk), not several that touch at it.
    std::vector<std::vector<std::pair<int, int>>> fan(nv);  // (incoming side's edge, outgoing side's edge)
    for (int f = 0; f < nf; ++f) {
        const auto& face = cage.faces[f];
        const int n = static_cast<int>(face.size());
        for (int k = 0; k < n; ++k)
            fan[face[k]].push_back({edges.side_edge[f][(k + n - 1) % n], edges.side_edge[f][k]});
    }
    for (int v = 0; v < nv; ++v) {
        // Walk from one face to the next across the shared edge; a disk visits every face.
        std::map<int, int> next;  // outgoing edge -> index in fan
        for (size_t i = 0; i < fan[v].size(); ++i) next[fan[v][i].first] = static_cast<int>(i);
        size_t seen = 0;
        int i = 0;
        do {
            ++seen;
            const auto it = next.find(fan[v][i].second);
            if (it == next.end()) break;
            i = it->second;
        } while (i != 0 && seen <= fan[v].size());
        if (seen != fan[v].size())
            return "it is non-manifold at " + nth(v, "vertex") + ": its faces form more than one fan";
    }
    return {};
}

CageRefinement refine_polygon_cage(const PolygonMesh& cage) {
    if (const std::string problem = check_polygon_cage(cage); !problem.empty())
        throw InvalidInput("invalid control mesh: " + problem);
    const PolygonEdges edges = polygon_edges(cage);
    const int nv = cage.num_vertices(), ne = static_cast<int>(edges.ends.size()), nf = cage.num_faces();
    CageRefinement out;
    out.stencils.resize(nv + ne + nf);
    auto edge_point = [&](int e) { return nv + e; };
    auto face_point = [&](int f) { return nv + ne + f; };
    for (int f = 0; f < nf; ++f)
        for (int c : cage.faces[f]) out.stencils[face_point(f)].push_back({c, 1.0 / cage.faces[f].size()});
    // Edge point: the mean of the two ends and the two face points.
    for (int e = 0; e < ne; ++e) {
        Stencil& s = out.stencils[edge_point(e)];
        for (int c : edges.ends[e]) s.push_back({c, 0.25});
        for (int f : edges.faces[e])
            for (int c : cage.faces[f]) s.push_back({c, 0.25 / cage.faces[f].size()});
    }
    // Vertex point: (Q + 2R + (n-3) S) / n, Q the mean of the n face points, R of the n edge midpoints.
    std::vector<int> valence(nv, 0);
    for (const auto& e : edges.ends)
        for (int c : e) ++valence[c];
    for (int v = 0; v < nv; ++v) out.stencils[v].push_back({v, double(valence[v] - 3) / valence[v]});
    for (const auto& face : cage.faces)
        for (int v : face) {
            const double w = 1.0 / (double(valence[v]) * valence[v] * face.size());
            for (int c : face) out.stencils[v].push_back({c, w});
        }
    for (const auto& e : edges.ends)
        for (int v : e) {
            const double w = 1.0 / (double(valence[v]) * valence[v]);  // (2/n) * (1/n) * (1/2)
            out.stencils[v].push_back({e[0], w});
            out.stencils[v].push_back({e[1], w});
        }
    apply_stencils(cage.points, &out);
    for (int f = 0; f < nf; ++f) {
        const auto& face = cage.faces[f];
        const int n = static_cast<int>(face.size());
        const int fp = face_point(f);
        auto ep = [&](int k) { return edge_point(edges.side_edge[f][(k + n) % n]); };
        if (n == 4) {  // the quadrant convention of refine_cage(): child k keeps the parent's (u, v)
            out.level1.quads.push_back({face[0], ep(0), fp, ep(3)});
            out.level1.quads.push_back({ep(0), face[1], ep(1), fp});
            out.level1.quads.push_back({fp, ep(1), face[2], ep(2)});
            out.level1.quads.push_back({ep(3), fp, ep(2), face[3]});
        } else {
            for (int k = 0; k < n; ++k) out.level1.quads.push_back({face[k], ep(k), fp, ep(k - 1)});
        }
    }
    return out;
}

std::string check_cage(const Cage& cage) {
    const int nc = cage.num_corners(), ne = cage.num_edges(), nq = cage.num_quads();
    if (nq == 0) return "the cage has no quads";
    for (int c = 0; c < nc; ++c)
        if (!is_finite(cage.points[c])) return at("corner", c) + " has a non-finite position";
    std::vector<int> uses(ne, 0);
    // Half-edge view: quad q side k is half-edge 4q+k, from corners[k] to corners[k+1].
    std::vector<int> twin(4 * nq, -1);
    for (int q = 0; q < nq; ++q) {
        const auto& quad = cage.quads[q];
        for (int k = 0; k < 4; ++k) {
            const int c = quad.corners[k], e = quad.edges[k];
            if (c < 0 || c >= nc) return at("quad", q) + " has an out-of-range corner";
            if (e < 0 || e >= ne) return at("quad", q) + " has an out-of-range edge";
            for (int j = 0; j < k; ++j)
                if (quad.corners[j] == c) return at("quad", q) + " repeats a corner";
            const auto& edge = cage.edges[e];
            const int a = quad.corners[k], b = quad.corners[(k + 1) % 4];
            const bool forward = edge.corners[0] == a && edge.corners[1] == b;
            const bool backward = edge.corners[0] == b && edge.corners[1] == a;
            if (!forward && !backward)
                return at("quad", q) + " side " + std::to_string(k) + " is not on its edge's corners";
            int slot = -1;
            for (int i = 0; i < 2; ++i)
                if (edge.quads[i] == q && edge.sides[i] == k) slot = i;
            if (slot < 0) return at("edge", e) + " does not record its use by " + at("quad", q);
            ++uses[e];
        }
    }
    for (int e = 0; e < ne; ++e) {
        const auto& edge = cage.edges[e];
        if (uses[e] != 2)
            return at("edge", e) + " is used by " + std::to_string(uses[e]) + " quad sides, not 2";
        if (edge.corners[0] == edge.corners[1]) return at("edge", e) + " is a loop";
        if (edge.quads[0] == edge.quads[1] && edge.sides[0] == edge.sides[1])
            return at("edge", e) + " records the same quad side twice";
        const int h0 = 4 * edge.quads[0] + edge.sides[0], h1 = 4 * edge.quads[1] + edge.sides[1];
        // Opposite directions: the start corner of one use is the end corner of the other.
        const auto start = [&](int h) { return cage.quads[h / 4].corners[h % 4]; };
        if (start(h0) == start(h1))
            return at("edge", e) + " is walked twice in the same direction (inconsistent orientation)";
        twin[h0] = h1;
        twin[h1] = h0;
    }
    // Around each corner: leaving half-edge h (side k of q, starting at the corner) -> previous side
    // of q ends at the corner -> its twin leaves the corner in the next quad. One cycle per corner.
    std::vector<int> seen_corner(nc, 0);
    std::vector<char> visited(4 * nq, 0);
    for (int h = 0; h < 4 * nq; ++h) {
        if (visited[h]) continue;
        const int c = cage.quads[h / 4].corners[h % 4];
        if (seen_corner[c]++) return at("corner", c) + " is a pinch: its quads form more than one fan";
        int x = h;
        do {
            visited[x] = 1;
            const int prev = 4 * (x / 4) + (x % 4 + 3) % 4;  // ends at c
            x = twin[prev];                                  // starts at c
        } while (x != h);
    }
    for (int c = 0; c < nc; ++c)
        if (!seen_corner[c]) return at("corner", c) + " is not used by any quad";
    return {};
}

CageRefinement refine_cage(const Cage& cage) {
    if (const std::string problem = check_cage(cage); !problem.empty())
        throw InvalidInput("invalid cage: " + problem);
    const int nc = cage.num_corners(), ne = cage.num_edges(), nq = cage.num_quads();
    CageRefinement out;
    out.stencils.resize(nc + ne + nq);
    auto face_point = [&](int q) { return nc + ne + q; };
    auto edge_point = [&](int e) { return nc + e; };
    // Face points: average of the 4 corners.
    for (int q = 0; q < nq; ++q)
        for (int c : cage.quads[q].corners) out.stencils[face_point(q)].push_back({c, 0.25});
    // Edge points: average of the two ends and the two adjacent face points.
    for (int e = 0; e < ne; ++e) {
        const auto& edge = cage.edges[e];
        Stencil& s = out.stencils[edge_point(e)];
        s.push_back({edge.corners[0], 0.25});
        s.push_back({edge.corners[1], 0.25});
        for (int q : edge.quads)
            for (int c : cage.quads[q].corners) s.push_back({c, 0.0625});
    }
    // Vertex points: (Q + 2R + (n-3) S) / n with Q the mean of the n adjacent face points, R the
    // mean of the n edge midpoints and n the valence. Every edge end and quad corner counts once,
    // so multi-edges and repeated quads are handled by construction.
    std::vector<int> valence(nc, 0);
    for (const auto& edge : cage.edges)
        for (int c : edge.corners) ++valence[c];
    for (int c = 0; c < nc; ++c) out.stencils[c].push_back({c, double(valence[c] - 3) / valence[c]});
    for (const auto& quad : cage.quads)
        for (int k = 0; k < 4; ++k) {
            const int c = quad.corners[k];
            const double w = 1.0 / (double(valence[c]) * valence[c]);  // (1/n) * (1/n) of the face point
            for (int d : quad.corners) out.stencils[c].push_back({d, 0.25 * w});
        }
    for (const auto& edge : cage.edges)
        for (int i = 0; i < 2; ++i) {
            const int c = edge.corners[i];
            const double w = 2.0 / (double(valence[c]) * valence[c]);  // (2/n) * (1/n) of the midpoint
            out.stencils[c].push_back({edge.corners[0], 0.5 * w});
            out.stencils[c].push_back({edge.corners[1], 0.5 * w});
        }
    apply_stencils(cage.points, &out);
    // Child 4q+k covers the quadrant of corner k and keeps the parent's orientation: its corners in
    // order are the points at parametric (0,0),(1,0),(1,1),(0,1) of that quadrant.
    out.level1.quads.reserve(4 * nq);
    for (int q = 0; q < nq; ++q) {
        const auto& quad = cage.quads[q];
        const int c0 = quad.corners[0], c1 = quad.corners[1], c2 = quad.corners[2], c3 = quad.corners[3];
        const int e0 = edge_point(quad.edges[0]), e1 = edge_point(quad.edges[1]);
        const int e2 = edge_point(quad.edges[2]), e3 = edge_point(quad.edges[3]);
        const int f = face_point(q);
        out.level1.quads.push_back({c0, e0, f, e3});
        out.level1.quads.push_back({e0, c1, e1, f});
        out.level1.quads.push_back({f, e1, c2, e2});
        out.level1.quads.push_back({e3, f, e2, c3});
    }
    return out;
}

FacePoint to_child(const FacePoint& p) {
    const bool right = p.u >= 0.5, top = p.v >= 0.5;
    // Quadrant -> corner index: (0,0)->0, (1,0)->1, (1,1)->2, (0,1)->3.
    const int k = top ? (right ? 2 : 3) : (right ? 1 : 0);
    FacePoint c;
    c.face = 4 * p.face + k;
    c.u = std::clamp(2 * p.u - (right ? 1.0 : 0.0), 0.0, 1.0);
    c.v = std::clamp(2 * p.v - (top ? 1.0 : 0.0), 0.0, 1.0);
    return c;
}

FacePoint descend(FacePoint p, int levels) {
    for (int i = 0; i < levels; ++i) p = to_child(p);
    return p;
}

}  // namespace quadcage::subdiv

#include "quadcage/bench/peer.h"

#include <algorithm>
#include <fstream>
#include <numeric>
#include <sstream>
#include <vector>

#include "quadcage/core/errors.h"

namespace quadcage::bench {
namespace {

int find_root(std::vector<int>& parent, int v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

}  // namespace

PolygonMeshStats polygon_obj_stats(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InvalidInput(path + ": cannot open the peer's output");
    long long vertex_count = 0;
    std::vector<std::vector<int>> faces;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        std::istringstream s(line);
        std::string key;
        if (!(s >> key)) continue;
        if (key == "v") {
            ++vertex_count;
        } else if (key == "f") {
            std::vector<int> face;
            std::string tok;
            while (s >> tok) {
                long long v = 0;
                try {
                    v = std::stoll(tok.substr(0, tok.find('/')));
                } catch (const std::exception&) {
                    throw InvalidInput(path + ":" + std::to_string(number) + ": malformed face corner '" + tok + "'");
                }
                const long long idx = v < 0 ? vertex_count + v : v - 1;
                if (idx < 0 || idx >= vertex_count)
                    throw InvalidInput(path + ":" + std::to_string(number) + ": face index " + std::to_string(v) +
                                       " out of range (" + std::to_string(vertex_count) + " vertices so far)");
                face.push_back(static_cast<int>(idx));
            }
            if (face.size() >= 3) faces.push_back(std::move(face));
        }
    }
    PolygonMeshStats st;
    if (faces.empty()) return st;
    const int nv = static_cast<int>(vertex_count);
    std::vector<std::pair<int, int>> edges;
    std::vector<int> parent(nv);
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<char> used(nv, 0);
    for (const auto& f : faces) {
        st.quads += f.size() == 4;
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            used[a] = 1;
            if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
            parent[find_root(parent, a)] = find_root(parent, b);
        }
    }
    // Face sides as (undirected edge, +1 if it runs low -> high): how many faces use each edge, and
    // whether two faces run along it the same way.
    std::vector<std::pair<std::pair<int, int>, int>> sides;
    for (const auto& f : faces) {
        bool repeated = false;
        for (size_t k = 0; k < f.size(); ++k) {
            for (size_t l = k + 1; l < f.size(); ++l) repeated = repeated || f[k] == f[l];
            const int a = f[k], b = f[(k + 1) % f.size()];
            if (a != b) sides.push_back({{std::min(a, b), std::max(a, b)}, a < b ? 1 : -1});
        }
        st.degenerate_faces += repeated;
    }
    std::sort(sides.begin(), sides.end());
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        int forward = 0;
        while (j < sides.size() && sides[j].first == sides[i].first) forward += sides[j++].second > 0;
        const size_t uses = j - i;
        if (uses == 1) ++st.boundary_edges;
        else if (uses > 2) ++st.nonmanifold_edges;
        else if (forward != 1) ++st.misoriented_edges;
        i = j;
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<int> valence(nv, 0);
    for (const auto& e : edges) ++valence[e.first], ++valence[e.second];
    st.faces = static_cast<int>(faces.size());
    st.edges = static_cast<int>(edges.size());
    for (int v = 0; v < nv; ++v) {
        if (!used[v]) continue;
        ++st.vertices;
        if (valence[v] != 4) ++st.irregular_vertices;
        if (find_root(parent, v) == v) ++st.components;
    }
    st.euler_characteristic = st.vertices - st.edges + st.faces;
    const int twice_genus = 2 * st.components - st.euler_characteristic;
    if (twice_genus >= 0 && twice_genus % 2 == 0) st.genus = twice_genus / 2;
    return st;
}

std::string peer_cage_problem(const PolygonMeshStats& st, int genus, int components) {
    const auto n = [](int v) { return std::to_string(v); };
    if (st.faces == 0) return "empty output (no faces)";
    if (st.quads != st.faces) return "not all quads (" + n(st.faces - st.quads) + " of " + n(st.faces) + " faces are not)";
    if (st.degenerate_faces > 0) return "degenerate (" + n(st.degenerate_faces) + " faces with a repeated vertex)";
    if (st.boundary_edges > 0) return "open (" + n(st.boundary_edges) + " boundary edges)";
    if (st.nonmanifold_edges > 0) return "non-manifold (" + n(st.nonmanifold_edges) + " edges in more than 2 faces)";
    if (st.misoriented_edges > 0) return "inconsistently oriented (" + n(st.misoriented_edges) + " edges)";
    if (st.components != components) return "wrong component count " + n(st.components) + " (input " + n(components) + ")";
    if (!st.genus) return "genus undefined (Euler characteristic " + n(st.euler_characteristic) + ")";
    if (*st.genus != genus) return "wrong genus " + n(*st.genus) + " (input " + n(genus) + ")";
    return {};
}

}  // namespace quadcage::bench

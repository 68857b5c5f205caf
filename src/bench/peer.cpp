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

}  // namespace quadcage::bench

#include "quadcage/core/openmesh_bridge.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <climits>
#include <string>
#include <vector>

#include "quadcage/core/errors.h"

namespace quadcage {
namespace {
using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

PolygonMeshSummary summarize(const OmMesh& m) {
    PolygonMeshSummary s;
    s.vertices = static_cast<int>(m.n_vertices());
    s.faces = static_cast<int>(m.n_faces());
    s.edges = static_cast<int>(m.n_edges());
    int lo = INT_MAX, hi = 0;
    for (auto f : m.faces()) {
        const int val = static_cast<int>(m.valence(f));
        lo = std::min(lo, val);
        hi = std::max(hi, val);
    }
    s.min_face_valence = s.faces ? lo : 0;
    s.max_face_valence = hi;
    for (auto e : m.edges())
        if (m.is_boundary(e)) ++s.boundary_edges;
    for (auto v : m.vertices())
        if (m.is_isolated(v)) ++s.isolated_vertices;
    return s;
}

// Points and normals in double precision: the decimated points are written back as the input's are.
struct DoubleTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using OmTriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
}  // namespace

Mesh decimated(const Mesh& mesh, int vertices) {
    if (vertices < 4) throw InvalidInput("decimated(): at least 4 vertices, got " + std::to_string(vertices));
    OmTriMesh m;
    std::vector<OmTriMesh::VertexHandle> handle;
    handle.reserve(mesh.points.size());
    for (const Vec3& p : mesh.points) handle.push_back(m.add_vertex(OmTriMesh::Point(p.x, p.y, p.z)));
    for (const Triangle& t : mesh.triangles)
        if (!m.add_face(handle[t[0]], handle[t[1]], handle[t[2]]).is_valid())
            throw InvalidInput("decimated(): the mesh is not a manifold (OpenMesh refused a triangle)");
    m.request_vertex_status();
    m.request_edge_status();
    m.request_face_status();
    // Rounds: the edges shortest first, each collapsed to its midpoint unless OpenMesh's link
    // condition (is_collapse_ok) forbids both directions or a triangle round it would turn by more
    // than kMaxTurn or lose its area; a collapse locks the ring round the kept vertex for the round,
    // so the collapses of a round are independent.
    constexpr double kMaxTurn = 0.5;  // cosine: 60 degrees
    using P = OmTriMesh::Point;
    auto normal_of = [](const P& a, const P& b, const P& c) { return OpenMesh::cross(b - a, c - a); };
    // Whether the triangles round v (other than those of edge h), with v moved to x, keep their
    // orientation within kMaxTurn and their area.
    auto keeps_shape = [&](OmTriMesh::HalfedgeHandle h, OmTriMesh::VertexHandle v, const P& x) {
        const OmTriMesh::FaceHandle f0 = m.face_handle(h), f1 = m.opposite_face_handle(h);
        for (auto f : m.vf_range(v)) {
            if (f == f0 || f == f1) continue;
            P before[3], after[3];
            int k = 0;
            for (auto w : m.fv_range(f)) {
                before[k] = m.point(w);
                after[k] = w == v ? x : m.point(w);
                ++k;
            }
            const P n0 = normal_of(before[0], before[1], before[2]), n1 = normal_of(after[0], after[1], after[2]);
            const double l0 = n0.norm(), l1 = n1.norm();
            if (!(l1 > 1e-12 * l0) || OpenMesh::dot(n0, n1) < kMaxTurn * l0 * l1) return false;
        }
        return true;
    };
    long long alive = static_cast<long long>(m.n_vertices());
    // The live edges by (squared length, index). A round changes only the edges round the vertices
    // it kept: the others stay in order, and those are sorted again and merged in.
    std::vector<std::pair<double, int>> order, changed, merged;
    for (auto e : m.edges()) order.push_back({m.calc_edge_sqr_length(e), e.idx()});
    std::sort(order.begin(), order.end());
    std::vector<char> moved(m.n_edges(), 0);
    std::vector<OmTriMesh::VertexHandle> kept_vertices;
    for (bool first = true; alive > vertices; first = false) {
        if (!first) {
            changed.clear();
            for (auto v : kept_vertices)
                for (auto e : m.ve_range(v))
                    if (!moved[e.idx()]) moved[e.idx()] = 1, changed.push_back({m.calc_edge_sqr_length(e), e.idx()});
            std::sort(changed.begin(), changed.end());
            size_t live = 0;
            for (const auto& entry : order)
                if (!moved[entry.second] && !m.status(m.edge_handle(entry.second)).deleted()) order[live++] = entry;
            order.resize(live);
            merged.resize(order.size() + changed.size());
            std::merge(order.begin(), order.end(), changed.begin(), changed.end(), merged.begin());
            order.swap(merged);
            for (const auto& entry : changed) moved[entry.second] = 0;
        }
        kept_vertices.clear();
        std::vector<char> locked(m.n_vertices(), 0);
        long long collapsed = 0;
        for (const auto& [length, index] : order) {
            if (alive <= vertices) break;
            const auto e = m.edge_handle(index);
            if (m.status(e).deleted()) continue;
            auto h = m.halfedge_handle(e, 0);
            const auto a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
            if (locked[a.idx()] || locked[b.idx()]) continue;
            const P mid = (m.point(a) + m.point(b)) * 0.5;
            if (!m.is_collapse_ok(h)) {
                h = m.opposite_halfedge_handle(h);
                if (!m.is_collapse_ok(h)) continue;
            }
            if (!keeps_shape(h, a, mid) || !keeps_shape(h, b, mid)) continue;
            const auto kept = m.to_vertex_handle(h);
            m.collapse(h);
            m.set_point(kept, mid);
            locked[kept.idx()] = 1;
            for (auto w : m.vv_range(kept)) locked[w.idx()] = 1;
            kept_vertices.push_back(kept);
            --alive, ++collapsed;
        }
        if (collapsed == 0) break;
    }
    m.garbage_collection();
    Mesh out;
    out.points.reserve(m.n_vertices());
    for (auto v : m.vertices()) {
        const P& p = m.point(v);
        out.points.push_back({p[0], p[1], p[2]});
    }
    out.triangles.reserve(m.n_faces());
    for (auto f : m.faces()) {
        Triangle t{};
        int k = 0;
        for (auto v : m.fv_range(f)) t[k++] = v.idx();
        out.triangles.push_back(t);
    }
    return out;
}

PolygonMeshSummary read_with_openmesh(const std::string& path) {
    OmMesh m;
    if (!OpenMesh::IO::read_mesh(m, path))
        throw InvalidInput(path + ": OpenMesh could not read this file");
    return summarize(m);
}

std::string openmesh_version() {
    OmMesh m;  // a tetrahedron through the half-edge kernel
    std::vector<OmMesh::VertexHandle> v;
    for (int i = 0; i < 4; ++i) v.push_back(m.add_vertex(OmMesh::Point(i == 1, i == 2, i == 3)));
    m.add_face(v[0], v[2], v[1]);
    m.add_face(v[0], v[1], v[3]);
    m.add_face(v[0], v[3], v[2]);
    m.add_face(v[1], v[2], v[3]);
    const PolygonMeshSummary s = summarize(m);
    return "OpenMesh " + std::to_string(OM_GET_VER) + "." +
           std::to_string(OM_GET_MAJ) + " (tetrahedron: chi=" + std::to_string(s.euler_characteristic()) +
           (s.closed() ? ", closed)" : ", open)");
}

}  // namespace quadcage

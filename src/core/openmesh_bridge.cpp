#include "quadcage/core/openmesh_bridge.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <algorithm>
#include <climits>

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
}  // namespace

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

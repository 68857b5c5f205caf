#include "quadcage/subdiv/catmull_clark.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/version.h>

#include <memory>
#include <cstdio>
#include <unordered_set>

#include "quadcage/core/errors.h"
#include "detail/topology.h"

// OPENSUBDIV_VERSION is a bare token (v3_5_0); spell it as a string.
#define QC_STRINGIFY2(x) #x
#define QC_STRINGIFY(x) QC_STRINGIFY2(x)

namespace quadcage::subdiv {

namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

/// A position as PrimvarRefiner wants it: Clear() and AddWithWeight().
struct Point {
    double x = 0, y = 0, z = 0;

    void Clear(void* = nullptr) { x = y = z = 0; }
    void AddWithWeight(const Point& src, double weight) {
        x += weight * src.x;
        y += weight * src.y;
        z += weight * src.z;
    }
};

/// Weights in double: the fit compares against these limits at ~1e-6 of the diagonal and more.
using PrimvarRefiner = Far::PrimvarRefinerReal<double>;

constexpr long long kMaxRefinedQuads = 1LL << 28;

}  // namespace

namespace detail {

void validate_quad_mesh(const QuadMesh& cage, int levels, const char* who) {
    const std::string prefix = std::string(who) + ": ";
    if (levels < 0 || levels > kMaxRefinementLevel)
        throw InvalidInput(prefix + "refinement level " + std::to_string(levels) +
                           " is outside [0, " + std::to_string(kMaxRefinementLevel) + "]");
    if (cage.quads.empty() || cage.points.empty())
        throw InvalidInput(prefix + "the cage has no quads");
    if (static_cast<long long>(cage.quads.size()) << (2 * levels) > kMaxRefinedQuads)
        throw InvalidInput(prefix + "refining " + std::to_string(cage.quads.size()) +
                           " quads " + std::to_string(levels) +
                           " times gives more than 2^28 quads; use fewer levels");
    const int nv = cage.num_vertices();
    // Directed edges seen so far, keyed (from, to).
    std::unordered_set<long long> directed;
    directed.reserve(4 * cage.quads.size());
    std::vector<char> used(nv, 0);
    for (int f = 0; f < cage.num_quads(); ++f) {
        const auto& q = cage.quads[f];
        for (int k = 0; k < 4; ++k) {
            const int v = q[k];
            if (v < 0 || v >= nv)
                throw InvalidInput(prefix + "quad " + std::to_string(f) + " refers to vertex " +
                                   std::to_string(v) + " but the cage has " + std::to_string(nv) +
                                   " vertices");
            if (!is_finite(cage.points[v]))
                throw InvalidInput(prefix + "vertex " + std::to_string(v) +
                                   " has a non-finite coordinate");
            used[v] = 1;
            for (int j = 0; j < k; ++j)
                if (q[j] == v)
                    throw InvalidInput(prefix + "quad " + std::to_string(f) + " uses vertex " +
                                       std::to_string(v) + " twice");
        }
        for (int k = 0; k < 4; ++k) {
            const int a = q[k], b = q[(k + 1) % 4];
            if (!directed.insert(static_cast<long long>(a) * nv + b).second)
                throw InvalidInput(
                    prefix + "edge " + std::to_string(a) + "->" + std::to_string(b) + " of quad " +
                    std::to_string(f) +
                    " is used twice in the same direction: the cage has a multi-edge, an edge "
                    "with more than two quads, or inconsistent orientation (a level-0 layout "
                    "cage must be refined once on its own edge structure first, design.md §3)");
        }
    }
    // OpenSubdiv would carry an unused point along as an isolated vertex, breaking V = F + 2 - 2g
    // and the vertex order callers rely on.
    for (int v = 0; v < nv; ++v)
        if (!used[v])
            throw InvalidInput(prefix + "vertex " + std::to_string(v) +
                               " is used by no quad; remove unused vertices from the cage");
}

std::unique_ptr<Far::TopologyRefiner> make_refiner(const QuadMesh& cage, int levels,
                                                   bool for_limit) {
    std::vector<int> verts_per_face(cage.quads.size(), 4);
    std::vector<Far::Index> face_verts;
    face_verts.reserve(4 * cage.quads.size());
    for (const auto& q : cage.quads) face_verts.insert(face_verts.end(), q.begin(), q.end());

    Far::TopologyDescriptor desc;
    desc.numVertices = cage.num_vertices();
    desc.numFaces = cage.num_quads();
    desc.numVertsPerFace = verts_per_face.data();
    desc.vertIndicesPerFace = face_verts.data();

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
    if (!refiner)
        throw InvalidInput("OpenSubdiv rejected the cage topology (" +
                           std::to_string(cage.num_quads()) + " quads)");
    if (levels > 0) {
        Far::TopologyRefiner::UniformOptions options(levels);
        options.fullTopologyInLastLevel = for_limit;
        refiner->RefineUniform(options);
    }
    QC_CHECK(refiner->GetMaxLevel() == levels, "OpenSubdiv refined to an unexpected level");
    return refiner;
}

}  // namespace detail

namespace {

using detail::make_refiner;

/// Positions of every vertex of the last refinement level.
std::vector<Point> refined_points(const Far::TopologyRefiner& refiner, const QuadMesh& cage) {
    std::vector<Point> src(cage.points.size());
    for (size_t v = 0; v < cage.points.size(); ++v)
        src[v] = {cage.points[v].x, cage.points[v].y, cage.points[v].z};
    const PrimvarRefiner primvar(refiner);
    for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
        std::vector<Point> dst(refiner.GetLevel(level).GetNumVertices());
        primvar.Interpolate(level, src, dst);
        src.swap(dst);
    }
    return src;
}

std::vector<Vec3> to_vec3(const std::vector<Point>& pts) {
    std::vector<Vec3> out(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) out[i] = {pts[i].x, pts[i].y, pts[i].z};
    return out;
}

}  // namespace

QuadMesh refine_uniform(const QuadMesh& cage, int levels) {
    detail::validate_quad_mesh(cage, levels, "refine_uniform");
    if (levels == 0) return cage;
    const auto refiner = make_refiner(cage, levels, false);
    const Far::TopologyLevel& last = refiner->GetLevel(levels);

    QuadMesh out;
    out.points = to_vec3(refined_points(*refiner, cage));
    out.quads.resize(last.GetNumFaces());
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = last.GetFaceVertices(f);
        QC_CHECK(fv.size() == 4, "Catmull-Clark refinement produced a non-quad");
        out.quads[f] = {fv[0], fv[1], fv[2], fv[3]};
    }
    return out;
}

std::vector<Vec3> limit_positions(const QuadMesh& cage, int levels) {
    detail::validate_quad_mesh(cage, levels, "limit_positions");
    const auto refiner = make_refiner(cage, levels, true);
    const std::vector<Point> points = refined_points(*refiner, cage);
    std::vector<Point> limit(points.size());
    PrimvarRefiner(*refiner).Limit(points, limit);
    return to_vec3(limit);
}

std::string polygon_obj_text(const PolygonMesh& mesh, const std::string& comment) {
    std::string out = "# " + comment + "\n";
    char buf[128];
    for (const Vec3& p : mesh.points) {
        std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
        out += buf;
    }
    for (const auto& f : mesh.faces) {
        out += 'f';
        for (int v : f) out += ' ' + std::to_string(v + 1);
        out += '\n';
    }
    return out;
}

std::string quad_obj_text(const QuadMesh& mesh, const std::string& comment) {
    PolygonMesh p{mesh.points, {}};
    p.faces.reserve(mesh.quads.size());
    for (const auto& q : mesh.quads) p.faces.emplace_back(q.begin(), q.end());
    return polygon_obj_text(p, comment);
}

std::string opensubdiv_version() {
    QuadMesh cube;
    for (int i = 0; i < 8; ++i)
        cube.points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    cube.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const auto refiner = detail::make_refiner(cube, 1, false);
    return std::string("OpenSubdiv ") + QC_STRINGIFY(OPENSUBDIV_VERSION) + " (cube refined: " +
           std::to_string(refiner->GetLevel(1).GetNumFaces()) + " faces)";
}

}  // namespace quadcage::subdiv

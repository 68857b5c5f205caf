#pragma once
// Exact evaluation of the Catmull-Clark limit surface of a simple quad control mesh, as positions,
// derivatives and linear stencils on the control points (OpenSubdiv Bfr; design.md §5).

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/subdiv/cage.h"
#include "quadcage/subdiv/catmull_clark.h"

namespace quadcage::subdiv {

/// Options for LimitSurface.
struct LimitSurfaceOptions {
    /// Refinement depth with which OpenSubdiv approximates patches around extraordinary vertices
    /// (Bfr "approximation level", 1..10). The default of OpenSubdiv (2) is off by ~2e-3 of the
    /// diagonal near valence-5 corners; 6 is below 1e-6 of it. Keep it fixed for a whole fit.
    int irregular_level = 6;
    /// Threads used to build the per-face surfaces and to update patch points (0 = all cores).
    int threads = 0;
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// The limit surface and its first derivatives at one surface point.
struct LimitPoint {
    Vec3 position;
    Vec3 du;      ///< dS/du in the face's parameterisation.
    Vec3 dv;      ///< dS/dv.
    Vec3 normal;  ///< Unit du x dv (outward for counter-clockwise quads); zero where du x dv = 0.
};

/// The limit position and derivatives at one surface point as weights on control points:
/// position = sum position_weights[i] * points[indices[i]], same for du and dv. Each control point
/// appears once (weights of repeated points are summed). Position weights sum to 1, derivative
/// weights to 0.
struct LimitStencil {
    std::vector<int> indices;
    std::vector<double> position_weights;
    std::vector<double> du_weights;
    std::vector<double> dv_weights;
};

/// A dense, watertight triangulation of the limit surface: every face is cut into n x n small
/// quads, each split into 2 triangles (counter-clockwise like the faces); vertices on control-mesh
/// edges and corners are shared between the faces that meet there.
struct LimitTessellation {
    Mesh mesh;                      ///< Positions on the limit surface.
    std::vector<FacePoint> params;  ///< The (face, u, v) of each vertex (one of them on shared edges).
    std::vector<int> triangle_face; ///< The control-mesh face each triangle lies on.
    int n = 0;                      ///< Segments per face side.
};

/// The Catmull-Clark limit surface of a simple quad mesh (see QuadMesh), built once per topology.
///
/// Construction builds one OpenSubdiv Bfr::Surface per face (in parallel). Positions of the
/// control points can then be changed with set_points() without rebuilding anything. All const
/// member functions are thread-safe (they may run concurrently with each other, not with
/// set_points()). Movable, not copyable.
class LimitSurface {
public:
    /// \pre mesh is a simple quad mesh (see QuadMesh) with finite points; every face must have a
    ///      limit surface (true for closed meshes and for boundaries with EDGE_ONLY interpolation).
    /// \throw InvalidInput as refine_uniform() does, or if options are invalid.
    explicit LimitSurface(const QuadMesh& mesh, const LimitSurfaceOptions& options = {});
    ~LimitSurface();
    LimitSurface(LimitSurface&&) noexcept;
    LimitSurface& operator=(LimitSurface&&) noexcept;
    LimitSurface(const LimitSurface&) = delete;
    LimitSurface& operator=(const LimitSurface&) = delete;

    /// The control mesh (with the current points).
    const QuadMesh& control_mesh() const;
    int num_faces() const;           ///< Quads of the control mesh.
    int num_control_points() const;  ///< Points of the control mesh.

    /// Replaces the control-point positions (same topology).
    /// \throw InvalidInput if the count differs or a point is not finite.
    void set_points(const std::vector<Vec3>& points);

    /// Limit position, derivatives and normal at p with the current points.
    /// \pre 0 <= p.face < num_faces(); u, v are clamped to [0, 1].
    /// \throw InvalidInput if p.face is out of range.
    LimitPoint evaluate(const FacePoint& p) const;

    /// Weights on the control points for the limit position and derivatives at p (independent of
    /// the points' positions). \pre and \throw as evaluate().
    LimitStencil stencil(const FacePoint& p) const;

    /// stencil() into `out`, reusing its storage: a caller that takes many stencils in turn
    /// (the fit: every data point, every round) allocates once. \pre and \throw as evaluate().
    void stencil(const FacePoint& p, LimitStencil* out) const;

    /// The control points that influence face f (sorted, unique).
    /// \throw InvalidInput if f is out of range.
    std::vector<int> face_control_points(int f) const;

    /// Moves a point whose (u, v) left its face's unit square into the neighbouring face across the
    /// side it left by (repeatedly, at most 4 times); (u, v) inside [0,1]^2 is returned unchanged,
    /// and a point that would leave through an open boundary is clamped.
    /// \throw InvalidInput if p.face is out of range or u, v are not finite.
    FacePoint wrap(const FacePoint& p) const;

    /// The closest point of the limit surface to q found by Newton steps on |S(u,v) - q|^2 from
    /// `start`, walking across faces (wrap()). A local search: the caller supplies a good start.
    /// `iterations` bounds the steps. \throw as evaluate().
    FacePoint project(const Vec3& q, const FacePoint& start, int iterations = 12) const;

    /// A foot of project() and |S(foot) - q|^2 there (the value project() compared, so a caller
    /// need not evaluate the foot again).
    struct Projection {
        FacePoint foot;
        double distance2 = 0;
    };
    /// project(), with the squared distance it ends at. \throw as evaluate().
    Projection project_with_distance(const Vec3& q, const FacePoint& start, int iterations = 12) const;

    /// The dense tessellation (n >= 1 segments per face side) with the current points.
    /// \throw InvalidInput if n < 1 or the result would exceed 2^30 triangles.
    LimitTessellation tessellate(int n) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace quadcage::subdiv

#pragma once
// Error measurement shared by fit_surface() and measure_fit_error() (private to src/fit).

#include <chrono>
#include <vector>

#include "quadcage/accel/closest_point.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit::detail {

/// Closest points on a limit surface: a tessellation with `segments` per face side seeds each
/// query through an Embree index; Newton steps on the exact surface (LimitSurface::project) refine it.
/// The index is built fast (accel::BuildQuality::Fast): the fit builds one every round.
class SurfaceProjector {
public:
    SurfaceProjector(const subdiv::LimitSurface& surface, int segments, int threads);
    /// The surface point closest to each of `points` (parallel; deterministic); with `distances`,
    /// also each point's distance to it.
    std::vector<subdiv::FacePoint> project(const std::vector<Vec3>& points, std::vector<double>* distances = nullptr) const;
    const subdiv::LimitTessellation& tessellation() const { return tessellation_; }
    /// The Embree index of the tessellation (the seeds of project()).
    const accel::ClosestPointIndex& index() const { return index_; }
    /// The (face, u, v) of a point given by barycentric weights on a tessellation triangle.
    subdiv::FacePoint param_of(int triangle, const std::array<double, 3>& bary) const;

private:
    const subdiv::LimitSurface& surface_;
    subdiv::LimitTessellation tessellation_;
    accel::ClosestPointIndex index_;
    int threads_;
};

/// Time spent in the two query stages of a measurement.
struct MeasureTimes {
    double evaluation = 0;
    double closest_points = 0;
};

/// Segments per control face for a tessellation with `cage_segments` per level-0 cage quad side.
int face_segments(int cage_segments, int level);

/// The fewest segments per control face side of a tessellation that seeds projections onto the
/// surface. A walk on the exact surface only finds the foot in its seed's basin; from 2 segments a
/// face (face_segments() at level 4) a level-4 fit of torus.obj measured 1.28e-3 for a sample
/// 6.7e-4 from the surface, where the seed's cell bulged 2e-3 off its triangles.
inline constexpr int kSeedSegments = 4;

/// The level of a 40-quad cage (the layout cage of genus 5) whose refinement has about `faces`
/// faces, >= 1: face_segments() of it gives a user's control mesh of `faces` faces about as dense
/// a tessellation as a layout cage of as many faces gets (FittedSurface::search_level()).
int search_level(int faces);

/// The input side's points of measure(): options.samples area samples of the mesh (seed
/// options.seed), then every used vertex.
std::vector<Vec3> input_points(const Mesh& mesh, const MeasureOptions& options);

/// A mesh measured against: its index and the input side's points, the same for every surface
/// measured with the same options (a fit measures each level against them).
struct MeasuredMesh {
    const Mesh& mesh;
    const accel::ClosestPointIndex& index;  ///< Of `mesh`.
    std::vector<Vec3> points;               ///< input_points(mesh, options) of the options measured with.
};

/// measure_fit_error() with a ready index of the mesh; `level` is the surface's fit level.
ErrorMeasurement measure(const Mesh& mesh, const accel::ClosestPointIndex& mesh_index, const subdiv::LimitSurface& surface,
                         int level, const MeasureOptions& options, MeasureTimes* times = nullptr);

/// measure() with the input side's points sampled already (`input`, for the same `options`).
ErrorMeasurement measure(const MeasuredMesh& input, const subdiv::LimitSurface& surface, int level,
                         const MeasureOptions& options, MeasureTimes* times = nullptr);

/// RMS, mean and max of distances, summed in index order.
DistanceStats stats_of(const std::vector<double>& d);

/// Seconds since `start`.
double seconds_since(const std::chrono::steady_clock::time_point& start);

}  // namespace quadcage::fit::detail

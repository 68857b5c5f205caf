#pragma once
// Closest-point queries on a triangle mesh, accelerated by an Embree BVH (design.md §5).

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::accel {

/// The point of a triangle mesh closest to a query point.
struct ClosestHit {
    int triangle = -1;                      ///< Index into Mesh::triangles.
    Vec3 point;                             ///< Closest point, in the mesh's own coordinates.
    std::array<double, 3> barycentric{};    ///< Weights of the triangle's 3 vertices; sum to 1.
    double distance = 0;                    ///< Euclidean distance from the query to `point`.
};

/// How the BVH of a ClosestPointIndex is built. Only the speed differs: every query's answer is the
/// same bits with either.
enum class BuildQuality {
    /// Embree's medium quality (the high quality did not answer the fit's queries measurably faster).
    Medium,
    /// Embree's low quality (its Morton builder): about a third of the build time of Medium on 82k
    /// triangles (10 ms against 30 ms, one thread), for an index that answers only a few batches of
    /// queries before it is dropped, as the fit's limit-surface tessellations, rebuilt every round,
    /// do; their queries were no slower.
    Fast,
};

/// Exact closest-point queries on a fixed triangle mesh.
///
/// The BVH (Embree, built as BuildQuality asks) is built once in the constructor over coordinates
/// re-centred on the bounding-box centre, because Embree stores floats. The BVH only prunes; the distance to
/// each candidate triangle is computed in double precision from the original coordinates, and the
/// search radius is kept slightly above the best distance so float rounding of the BVH bounds cannot
/// discard the true closest triangle. Results are therefore the exact minimum over all triangles;
/// ties (equal distances) go to the lowest triangle index, so results do not depend on traversal order.
///
/// Queries are const and thread-safe. The index copies what it needs: the mesh may be destroyed
/// after construction. Non-copyable, movable; a moved-from index may only be destroyed or assigned.
class ClosestPointIndex {
public:
    /// Builds the index; `quality` trades build time against query time, never the answers.
    /// \pre Triangle indices are valid and the points finite (checked: throws InvalidInput otherwise).
    /// \throw InvalidInput if the mesh has no triangles, a vertex index is out of range or a used
    ///        point is not finite.
    /// \throw ResourceError if Embree fails for want of memory or a usable device (naming the call);
    ///        InternalError if Embree rejects a call as an invalid argument or operation (a bug).
    explicit ClosestPointIndex(const Mesh& mesh, BuildQuality quality = BuildQuality::Medium);
    ~ClosestPointIndex();
    ClosestPointIndex(ClosestPointIndex&& other) noexcept;
    ClosestPointIndex& operator=(ClosestPointIndex&& other) noexcept;
    ClosestPointIndex(const ClosestPointIndex&) = delete;
    ClosestPointIndex& operator=(const ClosestPointIndex&) = delete;

    /// The closest point of the mesh to p. Thread-safe.
    /// \throw InvalidInput if p is not finite.
    ClosestHit query(const Vec3& p) const;

    /// query() for every point, in parallel over `threads` std::threads (0 = hardware concurrency).
    /// Points are searched in Morton order, each within a bound from the one before it (which only
    /// prunes): the result is identical to calling query() on each point, whatever the thread count.
    /// \throw InvalidInput if a point is not finite (naming its index) or threads < 0.
    std::vector<ClosestHit> query_all(const std::vector<Vec3>& points, int threads = 0) const;

    /// query_all() within a limit per point: hits[i] is the closest point of the mesh to points[i]
    /// if its distance is at most max_distance[i], else a hit with triangle -1 and an infinite
    /// distance. A small limit prunes most of the BVH: a caller that only wants points closer than
    /// a candidate it already has (a local projection) pays for little more than that check.
    /// Deterministic, as query_all().
    /// \throw InvalidInput if the sizes differ, a distance is negative or NaN, a point is not
    ///        finite or threads < 0.
    std::vector<ClosestHit> query_all_within(const std::vector<Vec3>& points,
                                             const std::vector<double>& max_distance,
                                             int threads = 0) const;

    /// The mesh's first point on the ray from `origin` along `direction` (any length but zero),
    /// at most `max_distance` away, or a hit with triangle -1 and an infinite distance if there is
    /// none. Embree finds the triangle, in float; the point and its weights are then computed in
    /// double on that triangle (clamped onto it where rounding puts them just outside). Which of
    /// two triangles a ray through their common edge reports is Embree's choice. Thread-safe.
    /// \throw InvalidInput if origin or direction is not finite, direction is zero, or
    ///        max_distance is negative or NaN.
    ClosestHit first_hit(const Vec3& origin, const Vec3& direction, double max_distance) const;

    /// Number of triangles indexed.
    int num_triangles() const;

private:
    std::vector<ClosestHit> query_points(const std::vector<Vec3>& points,
                                         const std::vector<double>* limits, int threads) const;

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Version of the Embree library linked at run time, e.g. "Embree 3.13.5" (creates a device to ask).
/// \throw ResourceError if no Embree device can be created.
std::string embree_version();

}  // namespace quadcage::accel

#include "quadcage/accel/closest_point.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <thread>
#include <utility>

#include "detail/morton_order.h"
#include "quadcage/core/errors.h"

namespace quadcage::accel {

namespace {

/// A point on a triangle with its barycentric coordinates.
struct TrianglePoint {
    Vec3 point;
    std::array<double, 3> bary{};
};

/// Closest point to p on the segment [a, b]; t in [0, 1] is the weight of b.
double closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    if (!(len2 > 0)) return 0.0;
    return std::clamp(dot(p - a, ab) / len2, 0.0, 1.0);
}

/// Closest point on a (near-)degenerate triangle: the best of its three edges.
TrianglePoint closest_on_degenerate(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3* v[3] = {&a, &b, &c};
    TrianglePoint best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int e = 0; e < 3; ++e) {
        const int i = e, j = (e + 1) % 3;
        const double t = closest_on_segment(p, *v[i], *v[j]);
        const Vec3 q = *v[i] + (*v[j] - *v[i]) * t;
        const Vec3 d = p - q;
        const double d2 = dot(d, d);
        if (d2 < best_d2) {
            best_d2 = d2;
            best.point = q;
            best.bary = {0.0, 0.0, 0.0};
            best.bary[i] = 1.0 - t;
            best.bary[j] = t;
        }
    }
    return best;
}

/// Exact closest point on triangle abc, by classifying p into the triangle's Voronoi regions
/// (vertex, edge, face). Ericson, Real-Time Collision Detection, §5.1.5.
TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a;
    // The edge and face formulas divide by |ab|^2, |ac|^2, |bc|^2 and |ab x ac|^2; route triangles
    // whose area vanishes relative to their edges to the edge-only version.
    const Vec3 n = cross(ab, ac);
    const double n2 = dot(n, n);
    if (!(n2 > 1e-24 * dot(ab, ab) * dot(ac, ac))) return closest_on_degenerate(p, a, b, c);

    const Vec3 ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {a, {1, 0, 0}};

    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {b, {0, 1, 0}};

    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {a + ab * v, {1 - v, v, 0}};
    }

    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {c, {0, 0, 1}};

    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {a + ac * w, {1 - w, 0, w}};
    }

    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {b + (c - b) * w, {0, 1 - w, w}};
    }

    // Face region. Rounding can leave a weight a hair below 0: clamp and renormalise so the
    // reported point always lies on the triangle.
    const double denom = va + vb + vc;
    double v = std::max(0.0, vb / denom), w = std::max(0.0, vc / denom);
    double u = std::max(0.0, 1.0 - v - w);
    const double s = u + v + w;
    u /= s;
    v /= s;
    w /= s;
    return {a * u + b * v + c * w, {u, v, w}};
}

const char* embree_error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE: return "no error code";
        case RTC_ERROR_UNKNOWN: return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
        case RTC_ERROR_CANCELLED: return "cancelled";
    }
    return "unrecognised error";
}

// Embree's failures leave the library as its own type: invalid arguments and operations are ours
// to prevent (a bug), anything else is the system's (memory, CPU).
[[noreturn]] void throw_embree_error(RTCDevice device, const char* what) {
    const RTCError code = rtcGetDeviceError(device);
    const std::string message = std::string("Embree: ") + what + " failed: " + embree_error_name(code) +
                                " (error code " + std::to_string(static_cast<int>(code)) + ")";
    if (code == RTC_ERROR_INVALID_ARGUMENT || code == RTC_ERROR_INVALID_OPERATION) throw InternalError(message);
    throw ResourceError(message);
}

void check_embree(RTCDevice device, const char* what) {
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw_embree_error(device, what);
}

/// Embree coordinates are float; beyond this (in units of the scene's half extent) a query point is
/// answered by a linear scan instead, so squared distances inside Embree cannot overflow.
constexpr double kMaxEmbreeCoordinate = 1e15;

/// Relative slack added to the search radius (in Embree's scaled units, where the scene spans
/// [-1, 1]^3): about 16 float ulps, enough to cover rounding of the query point, the vertices and
/// Embree's own sphere-box test, so the BVH never prunes a triangle that is closer in double.
constexpr double kRadiusSlack = 1e-6;

/// The index's state: the Embree objects and a double-precision copy of the mesh.
struct IndexData {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<Vec3> points;  // original coordinates minus centre (double)
    std::vector<Triangle> triangles;
    Vec3 centre;
    double scale = 1.0;  // Embree coordinate = (p - centre) * scale

    IndexData() = default;
    IndexData(const IndexData&) = delete;
    IndexData& operator=(const IndexData&) = delete;
    ~IndexData() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

/// Per-query state handed to the Embree callback through userPtr.
struct QueryState {
    const IndexData* data = nullptr;
    Vec3 p;              // query point, centred, double
    double slack = 0;    // radius slack in Embree units
    double best_d2 = std::numeric_limits<double>::infinity();
    int best_triangle = -1;
    TrianglePoint best;
};

/// Offers triangle t to the running minimum; true if it became the best.
bool offer_triangle(QueryState& s, int t) {
    const Triangle& tri = s.data->triangles[t];
    const auto& pts = s.data->points;
    const TrianglePoint tp = closest_on_triangle(s.p, pts[tri[0]], pts[tri[1]], pts[tri[2]]);
    const Vec3 d = s.p - tp.point;
    const double d2 = dot(d, d);
    if (d2 < s.best_d2 || (d2 == s.best_d2 && t < s.best_triangle)) {
        s.best_d2 = d2;
        s.best_triangle = t;
        s.best = tp;
        return true;
    }
    return false;
}

bool point_query_callback(RTCPointQueryFunctionArguments* args) {
    auto& s = *static_cast<QueryState*>(args->userPtr);
    if (!offer_triangle(s, static_cast<int>(args->primID))) return false;
    const double r = std::sqrt(s.best_d2) * s.data->scale + s.slack;
    const float rf = std::nextafter(static_cast<float>(r), std::numeric_limits<float>::infinity());
    if (rf < args->query->radius) {
        args->query->radius = rf;
        return true;  // tells Embree the search sphere shrank
    }
    return false;
}

/// The closest point of the mesh to p, given that it lies within `bound` of p (infinity: no bound).
/// The bound only prunes the search: the answer is the same as without it. With `may_miss`, the
/// bound is a limit instead: nothing within it gives a hit with triangle -1.
ClosestHit closest(const IndexData& im, const Vec3& p, double bound, bool may_miss = false) {
    QueryState s;
    s.data = &im;
    s.p = p - im.centre;
    const Vec3 q = s.p * im.scale;
    const double qmax = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
    if (qmax <= kMaxEmbreeCoordinate) {
        s.slack = kRadiusSlack * (1.0 + qmax);
        RTCPointQuery query;
        query.x = static_cast<float>(q.x);
        query.y = static_cast<float>(q.y);
        query.z = static_cast<float>(q.z);
        query.time = 0.0f;
        // The same slack as the callback's shrinking radius, so the bound prunes no triangle that
        // is closer in double precision.
        query.radius = std::numeric_limits<float>::infinity();
        const double r = bound * im.scale + s.slack;
        if (std::isfinite(r) && r < 1e30)
            query.radius = std::nextafter(static_cast<float>(r), std::numeric_limits<float>::infinity());
        RTCPointQueryContext context;
        rtcInitPointQueryContext(&context);
        rtcPointQuery(im.scene, &query, &context, point_query_callback, &s);
    } else {
        for (int t = 0; t < static_cast<int>(im.triangles.size()); ++t) offer_triangle(s, t);
    }
    ClosestHit hit;
    if (may_miss && (s.best_triangle < 0 || std::sqrt(s.best_d2) > bound)) {
        hit.distance = std::numeric_limits<double>::infinity();
        return hit;
    }
    QC_CHECK(s.best_triangle >= 0, "Embree point query visited no triangle");

    hit.triangle = s.best_triangle;
    hit.point = s.best.point + im.centre;
    hit.barycentric = s.best.bary;
    hit.distance = std::sqrt(s.best_d2);
    return hit;
}

/// Interleaves the low 21 bits of x with two zero bits after each (for a 63-bit Morton code).
uint64_t spread_bits(uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

}  // namespace

struct ClosestPointIndex::Impl : IndexData {};

ClosestPointIndex::ClosestPointIndex(const Mesh& mesh, BuildQuality quality)
    : impl_(std::make_unique<Impl>()) {
    if (mesh.triangles.empty())
        throw InvalidInput("closest-point index: the mesh has no triangles");
    const int nv = mesh.num_vertices();
    std::vector<char> used(nv, 0);
    for (int t = 0; t < mesh.num_triangles(); ++t)
        for (int v : mesh.triangles[t]) {
            if (v < 0 || v >= nv)
                throw InvalidInput("closest-point index: triangle " + std::to_string(t) +
                                   " refers to vertex " + std::to_string(v) + " but the mesh has " +
                                   std::to_string(nv) + " vertices");
            if (!used[v] && !is_finite(mesh.points[v]))
                throw InvalidInput("closest-point index: vertex " + std::to_string(v) +
                                   " has a non-finite coordinate");
            used[v] = 1;
        }

    Impl& im = *impl_;
    const BoundingBox box = bounding_box(mesh);
    im.centre = (box.min + box.max) * 0.5;
    // Scale as well as re-centre, so Embree's floats see [-1, 1]^3 whatever the units are.
    const Vec3 half = (box.max - box.min) * 0.5;
    const double half_extent = std::max({half.x, half.y, half.z});
    im.scale = half_extent > 0 ? 1.0 / half_extent : 1.0;
    im.points.resize(nv);
    for (int v = 0; v < nv; ++v)
        if (used[v]) im.points[v] = mesh.points[v] - im.centre;
    im.triangles = mesh.triangles;

    im.device = rtcNewDevice(nullptr);
    if (!im.device) throw_embree_error(nullptr, "rtcNewDevice");
    im.scene = rtcNewScene(im.device);
    check_embree(im.device, "rtcNewScene");
    // The scene's and the geometry's quality both: the scene's alone still built the medium BVH.
    const RTCBuildQuality build =
        quality == BuildQuality::Fast ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM;
    rtcSetSceneBuildQuality(im.scene, build);

    RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    check_embree(im.device, "rtcNewGeometry");
    rtcSetGeometryBuildQuality(geom, build);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        im.triangles.size()));
    if (!vb || !ib) {
        rtcReleaseGeometry(geom);
        throw_embree_error(im.device, "rtcSetNewGeometryBuffer");
    }
    for (int v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k) vb[3 * v + k] = static_cast<float>(im.points[v][k] * im.scale);
    for (size_t t = 0; t < im.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) ib[3 * t + k] = static_cast<unsigned>(im.triangles[t][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(im.scene, geom);
    rtcReleaseGeometry(geom);  // the scene holds its own reference
    rtcCommitScene(im.scene);
    check_embree(im.device, "building the BVH");
}

ClosestPointIndex::~ClosestPointIndex() = default;
ClosestPointIndex::ClosestPointIndex(ClosestPointIndex&& other) noexcept = default;
ClosestPointIndex& ClosestPointIndex::operator=(ClosestPointIndex&& other) noexcept = default;

int ClosestPointIndex::num_triangles() const {
    QC_CHECK(impl_ != nullptr, "use of a moved-from ClosestPointIndex");
    return static_cast<int>(impl_->triangles.size());
}

ClosestHit ClosestPointIndex::query(const Vec3& p) const {
    QC_CHECK(impl_ != nullptr, "use of a moved-from ClosestPointIndex");
    if (!is_finite(p)) throw InvalidInput("closest-point query: the query point is not finite");
    return closest(*impl_, p, std::numeric_limits<double>::infinity());
}

ClosestHit ClosestPointIndex::first_hit(const Vec3& origin, const Vec3& direction, double max_distance) const {
    QC_CHECK(impl_ != nullptr, "use of a moved-from ClosestPointIndex");
    if (!is_finite(origin) || !is_finite(direction))
        throw InvalidInput("ray query: the origin or the direction is not finite");
    const double length = norm(direction);
    if (!(length > 0)) throw InvalidInput("ray query: the direction is zero");
    if (!(max_distance >= 0)) throw InvalidInput("ray query: the distance is negative or NaN");
    const Impl& im = *impl_;
    ClosestHit miss;
    miss.distance = std::numeric_limits<double>::infinity();
    const Vec3 o = (origin - im.centre) * im.scale;
    const Vec3 u = direction * (1 / length);
    if (std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)}) > kMaxEmbreeCoordinate) return miss;
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(o.x);
    rh.ray.org_y = static_cast<float>(o.y);
    rh.ray.org_z = static_cast<float>(o.z);
    rh.ray.dir_x = static_cast<float>(u.x);
    rh.ray.dir_y = static_cast<float>(u.y);
    rh.ray.dir_z = static_cast<float>(u.z);
    rh.ray.tnear = 0.0f;
    const double far = max_distance * im.scale;
    rh.ray.tfar = far < 1e30 ? std::nextafter(static_cast<float>(far), std::numeric_limits<float>::infinity())
                             : std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(im.scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return miss;

    // The crossing of the ray's line with the triangle's plane, in double, in the triangle's weights.
    const int t = static_cast<int>(rh.hit.primID);
    const Triangle& tri = im.triangles[t];
    const Vec3 a = im.points[tri[0]], b = im.points[tri[1]], c = im.points[tri[2]];
    const Vec3 p = origin - im.centre;
    const Vec3 n = cross(b - a, c - a);
    const double along = dot(n, u);
    double w1 = rh.hit.u, w2 = rh.hit.v;  // Embree's, where the ray runs in the plane
    if (along != 0) {
        const Vec3 x = p + u * (dot(n, a - p) / along);
        const double area2 = dot(n, n);
        w1 = dot(cross(c - x, a - x), n) / area2;
        w2 = dot(cross(a - x, b - x), n) / area2;
    }
    double w0 = 1 - w1 - w2;
    w0 = std::max(w0, 0.0), w1 = std::max(w1, 0.0), w2 = std::max(w2, 0.0);
    const double sum = w0 + w1 + w2;
    if (!(sum > 0)) return miss;
    ClosestHit hit;
    hit.triangle = t;
    hit.barycentric = {w0 / sum, w1 / sum, w2 / sum};
    hit.point = a * hit.barycentric[0] + b * hit.barycentric[1] + c * hit.barycentric[2] + im.centre;
    hit.distance = norm(hit.point - origin);
    if (hit.distance > max_distance) return miss;
    return hit;
}

std::vector<ClosestHit> ClosestPointIndex::query_all(const std::vector<Vec3>& points,
                                                     int threads) const {
    return query_points(points, nullptr, threads);
}

std::vector<ClosestHit> ClosestPointIndex::query_all_within(const std::vector<Vec3>& points,
                                                            const std::vector<double>& max_distance,
                                                            int threads) const {
    if (max_distance.size() != points.size())
        throw InvalidInput("closest-point query_all_within: " + std::to_string(points.size()) +
                           " points but " + std::to_string(max_distance.size()) + " distances");
    for (size_t i = 0; i < max_distance.size(); ++i)
        if (!(max_distance[i] >= 0))
            throw InvalidInput("closest-point query_all_within: distance " + std::to_string(i) +
                               " is negative or NaN");
    return query_points(points, &max_distance, threads);
}

std::vector<ClosestHit> ClosestPointIndex::query_points(const std::vector<Vec3>& points,
                                                        const std::vector<double>* limits,
                                                        int threads) const {
    QC_CHECK(impl_ != nullptr, "use of a moved-from ClosestPointIndex");
    if (threads < 0)
        throw InvalidInput("closest-point query_all: threads must be >= 0 (0 = all cores), got " +
                           std::to_string(threads));
    for (size_t i = 0; i < points.size(); ++i)
        if (!is_finite(points[i]))
            throw InvalidInput("closest-point query_all: query point " + std::to_string(i) +
                               " is not finite");

    // Points are answered in Morton order, each with the bound |p - p'| + d(p') from the point p'
    // answered before it in its block (the closest point of p' is that close to p): near points
    // give a small bound, and a small search sphere prunes most of the BVH. The bound does not
    // change any answer.
    const Impl& im = *impl_;
    std::vector<uint64_t> codes(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec3 q = (points[i] - im.centre) * im.scale;
        uint64_t code = 0;
        for (int k = 0; k < 3; ++k) {
            const double unit = std::clamp((q[k] + 1.0) * 0.5, 0.0, 1.0);
            code |= spread_bits(static_cast<uint64_t>(unit * 2097151.0)) << k;
        }
        codes[i] = code;
    }
    const std::vector<uint32_t> order = detail::order_by_code(codes);

    std::vector<ClosestHit> hits(points.size());
    constexpr size_t kBlock = 256;
    const size_t num_blocks = (points.size() + kBlock - 1) / kBlock;
    size_t num_threads = threads > 0 ? static_cast<size_t>(threads)
                                     : std::max(1u, std::thread::hardware_concurrency());
    num_threads = std::min(num_threads, num_blocks);

    // Each point's answer depends only on the point, so any block-to-thread assignment gives the
    // same result; blocks are handed out dynamically for load balance.
    std::atomic<size_t> next_block{0};
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto work = [&]() {
        try {
            while (!failed) {
                const size_t b = next_block++;
                if (b >= num_blocks) break;
                const size_t end = std::min(points.size(), (b + 1) * kBlock);
                const Vec3* prev = nullptr;
                double prev_distance = 0;
                for (size_t k = b * kBlock; k < end; ++k) {
                    const size_t i = order[k];
                    const double bound = prev ? norm(points[i] - *prev) + prev_distance
                                              : std::numeric_limits<double>::infinity();
                    if (limits) {
                        // The limit prunes too: a miss says nothing of the point's true distance,
                        // so the next point starts without a bound from it.
                        const double limit = (*limits)[i];
                        hits[i] = limit < bound ? closest(im, points[i], limit, true) : closest(im, points[i], bound);
                        if (hits[i].triangle >= 0 && hits[i].distance > limit) hits[i] = ClosestHit{-1, {}, {}, std::numeric_limits<double>::infinity()};
                        prev = hits[i].triangle >= 0 ? &points[i] : nullptr;
                    } else {
                        hits[i] = closest(im, points[i], bound);
                        prev = &points[i];
                    }
                    prev_distance = hits[i].distance;
                }
            }
        } catch (...) {
            if (!failed.exchange(true)) error = std::current_exception();
        }
    };
    if (num_threads <= 1) {
        work();
    } else {
        std::vector<std::thread> pool;
        pool.reserve(num_threads);
        for (size_t k = 0; k < num_threads; ++k) pool.emplace_back(work);
        for (std::thread& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
    return hits;
}

std::string embree_version() {
    RTCDevice device = rtcNewDevice(nullptr);
    if (!device) throw_embree_error(nullptr, "rtcNewDevice");
    const auto major = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MAJOR);
    const auto minor = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MINOR);
    const auto patch = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_PATCH);
    rtcReleaseDevice(device);
    return "Embree " + std::to_string(major) + "." + std::to_string(minor) + "." +
           std::to_string(patch);
}

}  // namespace quadcage::accel

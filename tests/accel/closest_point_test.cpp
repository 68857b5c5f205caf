#include "quadcage/accel/closest_point.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>

#include "detail/morton_order.h"
#include "quadcage/core/errors.h"

namespace quadcage::accel {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A closed UV sphere (two pole vertices) whose radius varies with direction, so the surface has no
// symmetry that could hide a wrong triangle choice. bump = 0 gives a plain sphere.
Mesh bumpy_sphere(int rings, int segments, double radius, double bump, const Vec3& centre = {}) {
    Mesh m;
    auto r_of = [&](double theta, double phi) {
        return radius * (1.0 + bump * std::sin(3 * theta) * std::cos(2 * phi + 0.3) +
                         0.5 * bump * std::cos(5 * phi));
    };
    m.points.push_back(centre + Vec3{0, 0, r_of(0, 0)});
    for (int i = 1; i < rings; ++i) {
        const double theta = kPi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double phi = 2 * kPi * j / segments;
            const double r = r_of(theta, phi);
            m.points.push_back(centre + Vec3{r * std::sin(theta) * std::cos(phi),
                                             r * std::sin(theta) * std::sin(phi),
                                             r * std::cos(theta)});
        }
    }
    m.points.push_back(centre + Vec3{0, 0, -r_of(kPi, 0)});
    const int south = static_cast<int>(m.points.size()) - 1;
    auto ring_vertex = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
    for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring_vertex(1, j), ring_vertex(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int a = ring_vertex(i, j), b = ring_vertex(i, j + 1);
            const int c = ring_vertex(i + 1, j), d = ring_vertex(i + 1, j + 1);
            m.triangles.push_back({a, c, d});
            m.triangles.push_back({a, d, b});
        }
    for (int j = 0; j < segments; ++j)
        m.triangles.push_back({south, ring_vertex(rings - 1, j + 1), ring_vertex(rings - 1, j)});
    return m;
}

double segment_distance2(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const Vec3 d = p - (a + ab * t);
    return dot(d, d);
}

// Reference point-triangle distance, by a different route from the library's (project onto the
// plane, test inside with signed areas, else the nearest edge).
double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double n2 = dot(n, n);
    if (n2 > 0) {
        const double h = dot(p - a, n) / n2;
        const Vec3 q = p - n * h;
        const double u = dot(cross(c - b, q - b), n);
        const double v = dot(cross(a - c, q - c), n);
        const double w = dot(cross(b - a, q - a), n);
        if (u >= 0 && v >= 0 && w >= 0) return std::abs(h) * std::sqrt(n2);
    }
    return std::sqrt(std::min({segment_distance2(p, a, b), segment_distance2(p, b, c),
                               segment_distance2(p, c, a)}));
}

double brute_force_distance(const Mesh& m, const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const Triangle& t : m.triangles)
        best = std::min(best, triangle_distance(p, m.points[t[0]], m.points[t[1]], m.points[t[2]]));
    return best;
}

std::vector<Vec3> random_points(const Mesh& m, int n, double margin, unsigned seed) {
    const BoundingBox box = bounding_box(m);
    const Vec3 pad = (box.max - box.min) * margin;
    std::mt19937 rng(seed);
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i) {
        Vec3 p;
        for (int k = 0; k < 3; ++k)
            p[k] = std::uniform_real_distribution<double>(box.min[k] - pad[k], box.max[k] + pad[k])(rng);
        pts.push_back(p);
    }
    return pts;
}

// Checks one hit against brute force and against itself: the reported distance is the true
// minimum, the point lies on the reported triangle, and the barycentrics reproduce the point.
void expect_consistent(const Mesh& m, const Vec3& p, const ClosestHit& hit, double tol) {
    ASSERT_GE(hit.triangle, 0);
    ASSERT_LT(hit.triangle, m.num_triangles());
    EXPECT_NEAR(hit.distance, brute_force_distance(m, p), tol);
    EXPECT_NEAR(norm(p - hit.point), hit.distance, tol);
    const Triangle& t = m.triangles[hit.triangle];
    EXPECT_NEAR(triangle_distance(hit.point, m.points[t[0]], m.points[t[1]], m.points[t[2]]), 0.0, tol);
    const Vec3 from_bary = m.points[t[0]] * hit.barycentric[0] + m.points[t[1]] * hit.barycentric[1] +
                           m.points[t[2]] * hit.barycentric[2];
    EXPECT_NEAR(norm(from_bary - hit.point), 0.0, tol);
}

TEST(AccelClosestPoint, MatchesBruteForceOnRandomPoints) {
    const Mesh m = bumpy_sphere(24, 40, 1.0, 0.15);
    const ClosestPointIndex index(m);
    EXPECT_EQ(index.num_triangles(), m.num_triangles());
    const double diag = bounding_box(m).diagonal();
    for (const Vec3& p : random_points(m, 3000, 0.3, 1)) {
        const ClosestHit hit = index.query(p);
        expect_consistent(m, p, hit, 1e-12 * diag);
    }
}

TEST(AccelClosestPoint, PointsOnTheSurfaceHaveZeroDistance) {
    const Mesh m = bumpy_sphere(16, 24, 2.0, 0.2);
    const ClosestPointIndex index(m);
    const double diag = bounding_box(m).diagonal();
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const int t = static_cast<int>(rng() % m.triangles.size());
        double u = unit(rng), v = unit(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const Triangle& tri = m.triangles[t];
        const Vec3 p = m.points[tri[0]] * (1 - u - v) + m.points[tri[1]] * u + m.points[tri[2]] * v;
        const ClosestHit hit = index.query(p);
        EXPECT_LT(hit.distance, 1e-14 * diag);
        EXPECT_LT(norm(hit.point - p), 1e-14 * diag);
    }
    for (const Vec3& p : m.points) EXPECT_EQ(index.query(p).distance, 0.0);
}

TEST(AccelClosestPoint, BarycentricsReproduceThePoint) {
    const Mesh m = bumpy_sphere(12, 20, 1.0, 0.1);
    const ClosestPointIndex index(m);
    for (const Vec3& p : random_points(m, 1000, 0.5, 3)) {
        const ClosestHit hit = index.query(p);
        const auto& b = hit.barycentric;
        EXPECT_NEAR(b[0] + b[1] + b[2], 1.0, 1e-14);
        for (double w : b) {
            EXPECT_GE(w, 0.0);
            EXPECT_LE(w, 1.0);
        }
        const Triangle& t = m.triangles[hit.triangle];
        const Vec3 q = m.points[t[0]] * b[0] + m.points[t[1]] * b[1] + m.points[t[2]] * b[2];
        EXPECT_LT(norm(q - hit.point), 1e-14);
    }
}

TEST(AccelClosestPoint, QueryAllEqualsSequentialQuery) {
    const Mesh m = bumpy_sphere(20, 32, 1.0, 0.2);
    const ClosestPointIndex index(m);
    const std::vector<Vec3> pts = random_points(m, 5000, 0.4, 4);
    std::vector<ClosestHit> expected;
    for (const Vec3& p : pts) expected.push_back(index.query(p));
    for (int threads : {0, 1, 2, 3, 7}) {
        const std::vector<ClosestHit> got = index.query_all(pts, threads);
        ASSERT_EQ(got.size(), expected.size());
        for (size_t i = 0; i < pts.size(); ++i) {
            EXPECT_EQ(got[i].triangle, expected[i].triangle) << "point " << i << " threads " << threads;
            EXPECT_EQ(got[i].point, expected[i].point);
            EXPECT_EQ(got[i].barycentric, expected[i].barycentric);
            EXPECT_EQ(got[i].distance, expected[i].distance);
        }
    }
    EXPECT_TRUE(index.query_all({}).empty());
}

TEST(AccelClosestPoint, QueryAllWithinAnswersExactlyTheHitsInsideTheLimit) {
    const Mesh m = bumpy_sphere(20, 32, 1.0, 0.2);
    const ClosestPointIndex index(m);
    const std::vector<Vec3> pts = random_points(m, 4000, 0.4, 5);
    const std::vector<ClosestHit> full = index.query_all(pts, 1);
    // Limits around each true distance: a quarter of the points just below it (a miss), a quarter
    // exactly at it, the rest above; and one of 0 for a point not on the surface.
    std::mt19937 rng(6);
    std::vector<double> limit(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
        const double d = full[i].distance;
        limit[i] = i % 4 == 0 ? d * 0.999 : i % 4 == 1 ? d : d * (1.0 + 0.01 * (rng() % 100));
    }
    int misses = 0;
    for (int threads : {1, 2, 3}) {
        const std::vector<ClosestHit> got = index.query_all_within(pts, limit, threads);
        ASSERT_EQ(got.size(), pts.size());
        misses = 0;
        for (size_t i = 0; i < pts.size(); ++i) {
            if (full[i].distance > limit[i]) {
                EXPECT_EQ(got[i].triangle, -1) << "point " << i;
                EXPECT_TRUE(std::isinf(got[i].distance));
                ++misses;
                continue;
            }
            EXPECT_EQ(got[i].triangle, full[i].triangle) << "point " << i << " threads " << threads;
            EXPECT_EQ(got[i].point, full[i].point);
            EXPECT_EQ(got[i].distance, full[i].distance);
        }
    }
    EXPECT_EQ(misses, static_cast<int>((pts.size() + 3) / 4));
    // Infinite limits are query_all().
    const std::vector<ClosestHit> unbounded =
        index.query_all_within(pts, std::vector<double>(pts.size(), std::numeric_limits<double>::infinity()));
    for (size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(unbounded[i].triangle, full[i].triangle);
    EXPECT_THROW(index.query_all_within(pts, std::vector<double>(3, 1.0)), InvalidInput);
    EXPECT_THROW(index.query_all_within({Vec3{}}, {-1.0}), InvalidInput);
    EXPECT_THROW(index.query_all_within({Vec3{}}, {std::nan("")}), InvalidInput);
}

TEST(AccelClosestPoint, FastBuildGivesTheSameHits) {
    // The build quality changes the BVH, which only prunes: every hit must be the same bits, with
    // and without limits, on points near the surface (the fit's case) and far from it.
    const Mesh m = bumpy_sphere(40, 64, 1.0, 0.2);
    const ClosestPointIndex medium(m), fast(m, BuildQuality::Fast);
    EXPECT_EQ(fast.num_triangles(), m.num_triangles());
    std::vector<Vec3> pts = random_points(m, 3000, 0.4, 7);
    for (const Vec3& p : random_points(m, 3000, 0.02, 8)) pts.push_back(medium.query(p).point * 1.001);
    const std::vector<ClosestHit> a = medium.query_all(pts, 2), b = fast.query_all(pts, 2);
    std::vector<double> limit(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) limit[i] = a[i].distance * (i % 3 == 0 ? 0.5 : 1.5);
    const std::vector<ClosestHit> aw = medium.query_all_within(pts, limit, 2),
                                  bw = fast.query_all_within(pts, limit, 2);
    for (size_t i = 0; i < pts.size(); ++i) {
        EXPECT_EQ(b[i].triangle, a[i].triangle) << "point " << i;
        EXPECT_EQ(b[i].point, a[i].point);
        EXPECT_EQ(b[i].barycentric, a[i].barycentric);
        EXPECT_EQ(b[i].distance, a[i].distance);
        EXPECT_EQ(bw[i].triangle, aw[i].triangle) << "point " << i;
        EXPECT_EQ(bw[i].point, aw[i].point);
        EXPECT_EQ(bw[i].distance, aw[i].distance);
    }
}

TEST(AccelClosestPoint, FarAwayPoints) {
    const Mesh m = bumpy_sphere(12, 20, 1.0, 0.15);
    const ClosestPointIndex index(m);
    std::mt19937 rng(5);
    std::normal_distribution<double> gauss;
    for (double far : {10.0, 1e3, 1e6, 1e12, 1e18, 1e100}) {
        for (int i = 0; i < 20; ++i) {
            Vec3 dir{gauss(rng), gauss(rng), gauss(rng)};
            const Vec3 p = dir * (far / norm(dir));
            const ClosestHit hit = index.query(p);
            const double expected = brute_force_distance(m, p);
            EXPECT_NEAR(hit.distance, expected, 1e-12 * expected) << "at distance " << far;
            EXPECT_LT(norm(hit.point), 1.5);  // on the mesh, not somewhere odd
        }
    }
}

TEST(AccelClosestPoint, LargeCoordinateOffsetKeepsDoublePrecision) {
    // A unit-size mesh 1e4 away from the origin: in float its coordinates only resolve ~1e-3.
    const Vec3 offset{1e4, -1e4, 1e4};
    const Mesh near_origin = bumpy_sphere(32, 48, 0.5, 0.2);
    Mesh shifted = near_origin;
    for (Vec3& p : shifted.points) p += offset;
    const ClosestPointIndex a(near_origin), b(shifted);

    // Points within a few 1e-3 of the surface are the hard ones: other triangles are then almost
    // as close as the right one, and float bounds at 1e4 would prune the right one now and then
    // (with neither re-centring nor radius slack, 7 of these 41000 queries come out wrong).
    std::vector<Vec3> queries = random_points(near_origin, 1000, 0.3, 6);
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> unit(0.0, 1.0), height(-3e-3, 3e-3);
    for (int i = 0; i < 40000; ++i) {
        const Triangle& t = near_origin.triangles[rng() % near_origin.triangles.size()];
        const Vec3 &p0 = near_origin.points[t[0]], &p1 = near_origin.points[t[1]],
                   &p2 = near_origin.points[t[2]];
        double u = unit(rng), v = unit(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const Vec3 n = cross(p1 - p0, p2 - p0);
        queries.push_back(p0 * (1 - u - v) + p1 * u + p2 * v + n * (height(rng) / norm(n)));
    }
    std::vector<Vec3> moved = queries;
    for (Vec3& p : moved) p += offset;
    const std::vector<ClosestHit> ha = a.query_all(queries), hb = b.query_all(moved);
    int wrong = 0;
    for (size_t i = 0; i < queries.size(); ++i) {
        const bool ok = std::abs(hb[i].distance - ha[i].distance) < 1e-10 &&
                        norm(hb[i].point - offset - ha[i].point) < 1e-10;
        if (!ok) ++wrong;
        if (i < 500) {  // the near-origin index itself is checked against brute force elsewhere
            EXPECT_NEAR(hb[i].distance, brute_force_distance(shifted, moved[i]), 1e-10);
        }
    }
    EXPECT_EQ(wrong, 0) << "of " << queries.size() << " queries";
    for (const Vec3& p : shifted.points) EXPECT_EQ(b.query(p).distance, 0.0);
}

TEST(AccelClosestPoint, TinyAndHugeScales) {
    for (double scale : {1e-9, 1e9}) {
        const Mesh m = bumpy_sphere(10, 16, scale, 0.2);
        const ClosestPointIndex index(m);
        for (const Vec3& p : random_points(m, 300, 0.3, 7))
            EXPECT_NEAR(index.query(p).distance, brute_force_distance(m, p), 1e-12 * scale);
    }
}

TEST(AccelClosestPoint, DegenerateTrianglesAreHandled) {
    // A zero-area triangle (collinear) and one with a repeated vertex next to a proper one.
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 1}, {3, 3, 3}};
    m.triangles = {{0, 1, 2}, {0, 0, 5}, {0, 3, 4}};
    const ClosestPointIndex index(m);
    for (const Vec3& p : random_points(m, 500, 0.5, 8)) {
        const ClosestHit hit = index.query(p);
        expect_consistent(m, p, hit, 1e-12);
    }
}

TEST(AccelClosestPoint, MovedIndexStillAnswers) {
    const Mesh m = bumpy_sphere(8, 12, 1.0, 0.0);
    ClosestPointIndex first(m);
    ClosestPointIndex second(std::move(first));
    EXPECT_NEAR(second.query({0, 0, 3}).distance, 2.0, 1e-12);
    ClosestPointIndex third(bumpy_sphere(4, 6, 5.0, 0.0));
    third = std::move(second);
    EXPECT_NEAR(third.query({0, 0, 3}).distance, 2.0, 1e-12);
}

// The nearest crossing of the ray from o along the unit u with any triangle of m, within far
// (infinity if none), by a route of its own: each triangle's plane, then signed areas.
double brute_force_ray(const Mesh& m, const Vec3& o, const Vec3& u, double far) {
    double best = std::numeric_limits<double>::infinity();
    for (const Triangle& t : m.triangles) {
        const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
        const Vec3 n = cross(b - a, c - a);
        if (dot(n, u) == 0) continue;
        const double s = dot(n, a - o) / dot(n, u);
        if (s < 0 || s > far) continue;
        const Vec3 x = o + u * s;
        if (dot(cross(b - a, x - a), n) >= 0 && dot(cross(c - b, x - b), n) >= 0 && dot(cross(a - c, x - c), n) >= 0)
            best = std::min(best, s);
    }
    return best;
}

TEST(AccelClosestPoint, RaysHitWhereBruteForceDoes) {
    const Mesh m = bumpy_sphere(24, 40, 1.0, 0.15);
    const ClosestPointIndex index(m);
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, 1.0);
    int hits = 0, misses = 0;
    for (const Vec3& o : random_points(m, 2000, 0.3, 5)) {
        Vec3 u{gauss(rng), gauss(rng), gauss(rng)};
        u = u * (1 / norm(u));
        const double far = 1.0;
        const double expected = brute_force_ray(m, o, u, far);
        const ClosestHit hit = index.first_hit(o, u * 3.0, far);  // the direction's length is ignored
        if (!std::isfinite(expected)) {
            // Embree may still report a hit at the very end of the range or on an edge that rounding
            // put outside; the brute force's own range is exact.
            if (hit.triangle >= 0) {
                EXPECT_GT(hit.distance, far - 1e-6);
            }
            ++misses;
            continue;
        }
        ASSERT_GE(hit.triangle, 0) << "ray from " << o.x << " " << o.y << " " << o.z;
        ++hits;
        EXPECT_NEAR(hit.distance, expected, 1e-6);
        EXPECT_NEAR(norm(hit.point - (o + u * expected)), 0.0, 1e-6);
        const Triangle& t = m.triangles[hit.triangle];
        const auto& w = hit.barycentric;
        EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-14);
        const Vec3 from_weights = m.points[t[0]] * w[0] + m.points[t[1]] * w[1] + m.points[t[2]] * w[2];
        EXPECT_LT(norm(from_weights - hit.point), 1e-14);
    }
    EXPECT_GT(hits, 200);  // both kinds of ray are exercised
    EXPECT_GT(misses, 200);
}

TEST(AccelClosestPoint, RejectsBadInput) {
    EXPECT_THROW(ClosestPointIndex(Mesh{}), InvalidInput);
    Mesh bad = bumpy_sphere(4, 6, 1.0, 0.0);
    bad.triangles.push_back({0, 1, bad.num_vertices()});
    EXPECT_THROW(ClosestPointIndex{bad}, InvalidInput);
    Mesh nan = bumpy_sphere(4, 6, 1.0, 0.0);
    nan.points[2].x = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(ClosestPointIndex{nan}, InvalidInput);

    const ClosestPointIndex index(bumpy_sphere(4, 6, 1.0, 0.0));
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_THROW(index.query({inf, 0, 0}), InvalidInput);
    EXPECT_THROW(index.query_all({{0, 0, 0}, {0, std::nan(""), 0}}), InvalidInput);
    EXPECT_THROW(index.query_all({{0, 0, 0}}, -1), InvalidInput);
    EXPECT_THROW(index.first_hit({0, 0, 0}, {0, 0, 0}, 1.0), InvalidInput);
    EXPECT_THROW(index.first_hit({0, 0, 0}, {1, 0, 0}, -1.0), InvalidInput);
    EXPECT_THROW(index.first_hit({inf, 0, 0}, {1, 0, 0}, 1.0), InvalidInput);
}

TEST(AccelMortonOrder, OrderByCodeIsStdSortOfCodeIndexPairs) {
    // Codes of every width (the skipped high passes), with many repeats (the index breaks ties).
    std::mt19937_64 rng(9);
    for (int bits : {0, 1, 11, 12, 40, 63, 64}) {
        for (size_t n : {size_t{0}, size_t{1}, size_t{7}, size_t{5000}}) {
            std::vector<std::uint64_t> codes(n);
            const std::uint64_t mask = bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
            for (auto& c : codes) c = rng() & mask;
            for (size_t i = 0; i < n / 3; ++i) codes[rng() % n] = codes[rng() % n];
            std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs(n);
            for (size_t i = 0; i < n; ++i) pairs[i] = {codes[i], static_cast<std::uint32_t>(i)};
            std::sort(pairs.begin(), pairs.end());
            const std::vector<std::uint32_t> order = detail::order_by_code(codes);
            ASSERT_EQ(order.size(), n);
            for (size_t k = 0; k < n; ++k)
                ASSERT_EQ(order[k], pairs[k].second) << bits << " bits, n " << n << ", k " << k;
        }
    }
}

TEST(AccelVersion, EmbreeVersionIsReportedAtRunTime) {
    const std::string v = embree_version();
    EXPECT_EQ(v.rfind("Embree 3.", 0), 0u) << v;
}

}  // namespace
}  // namespace quadcage::accel

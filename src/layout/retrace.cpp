#include "detail/retrace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <unordered_map>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "quadcage/accel/closest_point.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

namespace {

using Key = std::uint64_t;

// Barycentric weights this small put a layout vertex on an input edge: the splits put their points
// on input edges up to rounding.
constexpr double kOnEdge = 1e-9;

// A uniform grid of the input triangles' bounding boxes, to find the triangle a point lies in.
class TriangleGrid {
public:
    explicit TriangleGrid(const Mesh& m) : m_(m) {
        lo_ = hi_ = m.points.empty() ? Vec3{} : m.points[0];
        for (const Vec3& p : m.points) {
            lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y), std::min(lo_.z, p.z)};
            hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y), std::max(hi_.z, p.z)};
        }
        diag_ = norm(hi_ - lo_);
        const double cells = std::max(1.0, std::cbrt(static_cast<double>(m.triangles.size())));
        cell_ = std::max(diag_ / cells, 1e-300);
        for (int k = 0; k < 3; ++k) n_[k] = std::max(1, static_cast<int>(std::ceil(extent(k) / cell_)) + 1);
        for (int t = 0; t < static_cast<int>(m.triangles.size()); ++t) {
            Vec3 a = m.points[m.triangles[t][0]], b = a;
            for (int v : m.triangles[t]) {
                const Vec3& p = m.points[v];
                a = {std::min(a.x, p.x), std::min(a.y, p.y), std::min(a.z, p.z)};
                b = {std::max(b.x, p.x), std::max(b.y, p.y), std::max(b.z, p.z)};
            }
            const std::array<int, 3> i0 = cell_of(a), i1 = cell_of(b);
            for (int x = i0[0]; x <= i1[0]; ++x)
                for (int y = i0[1]; y <= i1[1]; ++y)
                    for (int z = i0[2]; z <= i1[2]; ++z) cells_[index({x, y, z})].push_back(t);
        }
    }

    double diag() const { return diag_; }

    // The triangle p lies in (within `tolerance` of its plane and inside it up to kOnEdge), the
    // closest such, with p's barycentric weights there; -1 if none.
    int locate(const Vec3& p, double tolerance, std::array<double, 3>* w) const {
        const auto it = cells_.find(index(cell_of(p)));
        if (it == cells_.end()) return -1;
        int best = -1;
        double best_score = std::numeric_limits<double>::infinity();
        for (int t : it->second) {
            const Triangle& f = m_.triangles[t];
            const Vec3 a = m_.points[f[0]], b = m_.points[f[1]], c = m_.points[f[2]];
            const Vec3 n = cross(b - a, c - a);
            const double area2 = dot(n, n);
            if (!(area2 > 0)) continue;
            const double d = std::abs(dot(p - a, n)) / std::sqrt(area2);
            if (d > tolerance) continue;
            const std::array<double, 3> u = {dot(cross(b - p, c - p), n) / area2,
                                             dot(cross(c - p, a - p), n) / area2,
                                             dot(cross(a - p, b - p), n) / area2};
            const double outside = -std::min({u[0], u[1], u[2]});
            if (outside > kOnEdge) continue;
            const double score = d + std::max(0.0, outside) * diag_;
            if (score < best_score) best_score = score, best = t, *w = u;
        }
        return best;
    }

private:
    double extent(int k) const { return k == 0 ? hi_.x - lo_.x : k == 1 ? hi_.y - lo_.y : hi_.z - lo_.z; }
    std::array<int, 3> cell_of(const Vec3& p) const {
        const double c[3] = {p.x - lo_.x, p.y - lo_.y, p.z - lo_.z};
        std::array<int, 3> i{};
        for (int k = 0; k < 3; ++k)
            i[k] = std::clamp(static_cast<int>(std::floor(c[k] / cell_)), 0, n_[k] - 1);
        return i;
    }
    long long index(const std::array<int, 3>& i) const {
        return (static_cast<long long>(i[2]) * n_[1] + i[1]) * n_[0] + i[0];
    }

    const Mesh& m_;
    Vec3 lo_, hi_;
    double diag_ = 0, cell_ = 1;
    int n_[3] = {1, 1, 1};
    std::unordered_map<long long, std::vector<int>> cells_;
};

struct P2 {
    double x = 0, y = 0;
};
P2 operator-(P2 a, P2 b) {
    return {a.x - b.x, a.y - b.y};
}
double cross2(P2 a, P2 b) {
    return a.x * b.y - a.y * b.x;
}
double orient(P2 a, P2 b, P2 c) {
    return cross2(b - a, c - a);
}

// An input triangle's plane, with 2D coordinates that keep its orientation.
struct Frame {
    Vec3 origin, e1, e2;
    P2 at(const Vec3& p) const { return {dot(p - origin, e1), dot(p - origin, e2)}; }
};
Frame frame_of(const Mesh& m, int f) {
    const Triangle& t = m.triangles[f];
    const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    Vec3 n = cross(b - a, c - a);
    n = n * (1 / norm(n));
    Vec3 e1 = b - a;
    e1 = e1 * (1 / norm(e1));
    return {a, e1, cross(n, e1)};
}

// Where the line through P and Q (at P + s (Q - P)) meets the line of side k of input triangle t
// (at its first end plus u times the side), in frame fr; false if they are parallel.
bool meets_side(const Mesh& input, const Frame& fr, const Triangle& t, int k, P2 P, P2 Q, double* s, double* u) {
    const P2 A = fr.at(input.points[t[k]]), B = fr.at(input.points[t[(k + 1) % 3]]);
    const double den = cross2(Q - P, B - A);
    if (den == 0) return false;
    *s = cross2(A - P, B - A) / den;
    *u = cross2(A - P, Q - P) / den;
    return true;
}

// Whether segments ab and cd cross or overlap other than at an endpoint they share; eps is a length.
bool segments_conflict(P2 a, P2 b, P2 c, P2 d, bool share_a_c, bool share_a_d, bool share_b_c, bool share_b_d,
                       double eps) {
    const double lab = std::hypot(b.x - a.x, b.y - a.y), lcd = std::hypot(d.x - c.x, d.y - c.y);
    const double o1 = orient(a, b, c) / lab, o2 = orient(a, b, d) / lab;
    const double o3 = orient(c, d, a) / lcd, o4 = orient(c, d, b) / lcd;
    const bool shared = share_a_c || share_a_d || share_b_c || share_b_d;
    if (std::abs(o1) <= eps && std::abs(o2) <= eps) {
        // Collinear: overlap beyond a shared endpoint?
        const P2 u = {(b.x - a.x) / lab, (b.y - a.y) / lab};
        auto s = [&](P2 p) { return (p.x - a.x) * u.x + (p.y - a.y) * u.y; };
        const double s0 = std::min(s(c), s(d)), s1 = std::max(s(c), s(d));
        return std::min(lab, s1) - std::max(0.0, s0) > eps;
    }
    if (shared) {
        // Touching at the shared endpoint only, unless the other end lies on the first segment.
        return false;
    }
    const bool cross_ab = (o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps);
    const bool cross_cd = (o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps);
    if (cross_ab && cross_cd) return true;
    // An endpoint of one on the other (a T-junction).
    auto on = [eps](P2 p, P2 s0, P2 s1, double o) {
        if (std::abs(o) > eps) return false;
        const double l = std::hypot(s1.x - s0.x, s1.y - s0.y);
        const double t = ((p.x - s0.x) * (s1.x - s0.x) + (p.y - s0.y) * (s1.y - s0.y)) / l;
        return t > eps && t < l - eps;
    };
    return on(c, a, b, o1) || on(d, a, b, o2) || on(a, c, d, o3) || on(b, c, d, o4);
}

// Turns and containment are judged by the sine of the angle, not the area, so that regions far
// smaller than their input triangle (curves passing 1e-7 apart) are judged as well as large ones;
// below this sine, three points count as collinear (rounding leaves about 1e-14 on an input edge).
constexpr double kSine = 1e-10;

double length(P2 a) {
    return std::hypot(a.x, a.y);
}

// Whether c lies strictly to the left of a->b, by more than rounding.
bool left_of(P2 a, P2 b, P2 c) {
    return orient(a, b, c) > kSine * length(b - a) * length(c - a);
}

// Triangulates the simple counter-clockwise polygon `poly` (indices into pts) by clipping the ear
// with the largest smallest angle each time. False if it finds no ear (a degenerate polygon).
bool clip_ears(const std::vector<P2>& pts, std::vector<int> poly, std::vector<std::array<int, 3>>* out) {
    auto angle_at = [&](int a, int b, int c) {
        const P2 u = pts[a] - pts[b], v = pts[c] - pts[b];
        return std::atan2(std::abs(cross2(u, v)), u.x * v.x + u.y * v.y);
    };
    while (poly.size() > 3) {
        const int n = static_cast<int>(poly.size());
        int best = -1;
        double best_quality = -1;
        for (int i = 0; i < n; ++i) {
            const int a = poly[(i + n - 1) % n], b = poly[i], c = poly[(i + 1) % n];
            if (!left_of(pts[a], pts[b], pts[c])) continue;
            bool empty = true;
            for (int k : poly) {
                if (k == a || k == b || k == c) continue;
                const P2 p = pts[k];
                if (!left_of(pts[b], pts[a], p) && !left_of(pts[c], pts[b], p) &&
                    !left_of(pts[a], pts[c], p)) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            const double q = std::min({angle_at(a, b, c), angle_at(b, c, a), angle_at(c, a, b)});
            if (q > best_quality) best_quality = q, best = i;
        }
        if (best < 0) return false;
        out->push_back({poly[(best + n - 1) % n], poly[best], poly[(best + 1) % n]});
        poly.erase(poly.begin() + best);
    }
    if (!left_of(pts[poly[0]], pts[poly[1]], pts[poly[2]])) return false;
    out->push_back({poly[0], poly[1], poly[2]});
    return true;
}

// The values in both lists.
std::vector<int> shared(const std::vector<int>& a, const std::vector<int>& b) {
    std::vector<int> r;
    for (int f : a)
        if (std::find(b.begin(), b.end(), f) != b.end()) r.push_back(f);
    return r;
}

// Input triangles' frames, made as needed.
class Frames {
public:
    explicit Frames(const Mesh& m) : m_(m), frames_(m.triangles.size()), made_(m.triangles.size(), 0) {}
    const Frame& operator()(int f) {
        if (!made_[f]) frames_[f] = frame_of(m_, f), made_[f] = 1;
        return frames_[f];
    }

private:
    const Mesh& m_;
    std::vector<Frame> frames_;
    std::vector<char> made_;
};

// The triangle to the left of each directed edge of a mesh, through each vertex's outgoing edges
// in compressed rows (no hashing: the cut meshes have millions of edges).
class LeftOf {
public:
    explicit LeftOf(const Mesh& m) : start_(m.points.size() + 1, 0) {
        for (const Triangle& t : m.triangles)
            for (int v : t) ++start_[v + 1];
        for (size_t v = 1; v < start_.size(); ++v) start_[v] += start_[v - 1];
        to_.resize(start_.back());
        triangle_.resize(start_.back());
        std::vector<int> at(start_.begin(), start_.end() - 1);
        for (int f = 0; f < static_cast<int>(m.triangles.size()); ++f)
            for (int k = 0; k < 3; ++k) {
                const int a = m.triangles[f][k];
                to_[at[a]] = m.triangles[f][(k + 1) % 3];
                triangle_[at[a]++] = f;
            }
    }
    // The triangle with the directed edge a -> b, or -1.
    int operator()(int a, int b) const {
        for (int i = start_[a]; i < start_[a + 1]; ++i)
            if (to_[i] == b) return triangle_[i];
        return -1;
    }

private:
    std::vector<int> start_, to_, triangle_;
};

}  // namespace

InputAdjacency::InputAdjacency(const Mesh& input) : vertex_faces(input.points.size()), mesh(input) {
    for (int f = 0; f < input.num_triangles(); ++f)
        for (int k = 0; k < 3; ++k) vertex_faces[input.triangles[f][k]].push_back(f);
}

std::vector<int> InputAdjacency::edge(int a, int b) const {
    std::vector<int> faces;
    if (a == b) return faces;
    for (int f : vertex_faces[a]) {
        const Triangle& t = mesh.triangles[f];
        if (t[0] == b || t[1] == b || t[2] == b) faces.push_back(f);
    }
    return faces;
}

std::string cut_input_along(const Mesh& input, const InputAdjacency& adjacency, const CurvesOnInput& c_in,
                            const std::vector<Vec3>& written, const PatchAt& patch_at, const QuadLayout& like,
                            QuadLayout* out) {
    const int nin = input.num_vertices();
    const int n = static_cast<int>(c_in.points.size());
    const int nf = input.num_triangles();
    const std::vector<Vec3>& points = c_in.points;
    const std::vector<std::vector<int>>& place = c_in.place;
    std::vector<std::vector<int>> paths = c_in.edge_paths, system = c_in.orthogonal_system,
                                  s_cycles = c_in.s_cycles;
    Frames frame(input);

    // The graph of the mesh edges the curves run along.
    struct Curve {
        const std::vector<int>* vertices;
        bool closed;
    };
    std::vector<Curve> curves;
    for (const auto& p : paths) curves.push_back({&p, false});
    for (const auto& c : system) curves.push_back({&c, true});
    for (const auto& c : s_cycles) curves.push_back({&c, true});
    std::vector<std::vector<int>> next(n);
    auto link = [&](int a, int b) {
        if (a == b) return;
        if (std::find(next[a].begin(), next[a].end(), b) == next[a].end())
            next[a].push_back(b), next[b].push_back(a);
    };
    for (const Curve& c : curves) {
        const auto& p = *c.vertices;
        for (size_t i = 0; i + 1 < p.size(); ++i) link(p[i], p[i + 1]);
        if (c.closed && p.size() > 1) link(p.back(), p.front());
    }
    std::vector<char> node(n, 0);
    for (int v = 0; v < n; ++v)
        if (!next[v].empty() && (next[v].size() != 2 || v < nin)) node[v] = 1;
    for (int v : c_in.corners) node[v] = 1;

    // Chains: maximal runs of the curve graph between nodes (a closed run starts and ends at its
    // lowest vertex).
    std::vector<std::vector<int>> chains;
    std::unordered_map<Key, char> walked;
    auto walk = [&](int from, int first) {
        std::vector<int> chain = {from, first};
        walked[edge_key(from, first)] = 1;
        int prev = from, cur = first;
        while (!node[cur] && cur != from) {
            const int nx = next[cur][0] == prev ? next[cur][1] : next[cur][0];
            walked[edge_key(cur, nx)] = 1;
            chain.push_back(nx);
            prev = cur, cur = nx;
        }
        chains.push_back(std::move(chain));
    };
    for (int v = 0; v < n; ++v)
        if (node[v])
            for (int w : next[v])
                if (!walked.count(edge_key(v, w))) walk(v, w);
    for (int v = 0; v < n; ++v)
        for (int w : next[v])
            if (!walked.count(edge_key(v, w))) {
                node[v] = 1;  // a closed curve met by no other: v, its lowest vertex, is kept
                walk(v, w);
            }

    // Each chain keeps its ends and, greedily from its start, the last point of each stretch that
    // lies in one input triangle; `fixed` points are kept whatever.
    std::vector<std::vector<char>> fixed(chains.size()), kept(chains.size());
    for (size_t c = 0; c < chains.size(); ++c) {
        fixed[c].assign(chains[c].size(), 0);
        fixed[c].front() = fixed[c].back() = 1;
    }
    auto simplify = [&](size_t c) {
        const auto& ch = chains[c];
        auto& k = kept[c];
        k.assign(ch.size(), 0);
        k[0] = 1;
        size_t start = 0;
        std::vector<int> common = place[ch[0]];
        for (size_t i = 1; i < ch.size(); ++i) {
            std::vector<int> with = shared(common, place[ch[i]]);
            if (with.empty()) {
                if (i - 1 == start) return false;  // two neighbours in no common triangle
                k[i - 1] = 1;
                start = i - 1;
                with = shared(place[ch[i - 1]], place[ch[i]]);
                if (with.empty()) return false;
            }
            common = std::move(with);
            if (fixed[c][i]) {
                k[i] = 1;
                start = i;
                common = place[ch[i]];
            }
        }
        return true;
    };
    for (size_t c = 0; c < chains.size(); ++c)
        if (!simplify(c)) return "two neighbouring curve vertices share no input triangle";

    // Until the pieces in every input triangle are apart: a piece that crosses or touches another,
    // or runs through a kept point, keeps the points it skipped.
    struct Piece {
        int chain, from, to;  // chain positions
    };
    std::vector<Piece> pieces;
    for (int round = 0;; ++round) {
        if (round > 64) return "the curves' pieces could not be kept apart";
        pieces.clear();
        std::vector<std::vector<int>> in_face(nf), points_in_face(nf);
        std::vector<char> point_listed(n, 0);
        for (size_t c = 0; c < chains.size(); ++c) {
            int last = 0;
            for (int i = 1; i < static_cast<int>(chains[c].size()); ++i)
                if (kept[c][i]) {
                    const int a = chains[c][last], b = chains[c][i];
                    const std::vector<int> faces = shared(place[a], place[b]);
                    if (faces.empty()) return "a curve piece lies in no input triangle";
                    for (int f : faces) in_face[f].push_back(static_cast<int>(pieces.size()));
                    pieces.push_back({static_cast<int>(c), last, i});
                    for (int v : {a, b})
                        if (!point_listed[v]) {
                            point_listed[v] = 1;
                            for (int f : place[v]) points_in_face[f].push_back(v);
                        }
                    last = i;
                }
        }
        std::vector<char> bad(pieces.size(), 0);
        bool any = false;
        for (int f = 0; f < nf; ++f) {
            if (in_face[f].empty()) continue;
            const Frame& fr = frame(f);
            const Triangle& t = input.triangles[f];
            double scale = 0;
            for (int k = 0; k < 3; ++k)
                scale = std::max(scale, norm(input.points[t[k]] - input.points[t[(k + 1) % 3]]));
            const double eps = 1e-10 * scale;
            auto ends = [&](int p) {
                const Piece& q = pieces[p];
                return std::array<int, 2>{chains[q.chain][q.from], chains[q.chain][q.to]};
            };
            const auto& list = in_face[f];
            for (size_t i = 0; i < list.size(); ++i) {
                const auto e = ends(list[i]);
                const P2 a = fr.at(points[e[0]]), b = fr.at(points[e[1]]);
                for (size_t j = i + 1; j < list.size(); ++j) {
                    const auto g = ends(list[j]);
                    if ((e[0] == g[0] && e[1] == g[1]) || (e[0] == g[1] && e[1] == g[0])) {
                        bad[list[i]] = bad[list[j]] = 1;  // two pieces on one segment
                        continue;
                    }
                    const P2 c = fr.at(points[g[0]]), d = fr.at(points[g[1]]);
                    if (segments_conflict(a, b, c, d, e[0] == g[0], e[0] == g[1], e[1] == g[0], e[1] == g[1],
                                          eps))
                        bad[list[i]] = bad[list[j]] = 1;
                }
                // Kept points (and the triangle's corners) inside the piece.
                auto check_point = [&](int v) {
                    if (v == e[0] || v == e[1]) return;
                    const P2 p = fr.at(points[v]);
                    const double l = std::hypot(b.x - a.x, b.y - a.y);
                    if (std::abs(orient(a, b, p)) / l > eps) return;
                    const double s = ((p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y)) / l;
                    if (s > eps && s < l - eps) bad[list[i]] = 1;
                };
                for (int v : points_in_face[f]) check_point(v);
                for (int v : t) check_point(v);
            }
        }
        for (size_t p = 0; p < pieces.size(); ++p) {
            if (!bad[p]) continue;
            const Piece& q = pieces[p];
            if (q.to == q.from + 1) continue;  // a mesh edge already: the other piece gives way
            for (int i = q.from + 1; i < q.to; ++i) fixed[q.chain][i] = 1;
            any = true;
        }
        if (!any) {
            bool unresolved = false;
            for (size_t p = 0; p < pieces.size(); ++p) unresolved |= bad[p] != 0;
            if (unresolved) return "two curves cross inside an input triangle";
            break;
        }
        for (size_t c = 0; c < chains.size(); ++c)
            if (!simplify(c)) return "two neighbouring curve vertices share no input triangle";
    }

    // The new vertices: the input's, then the kept ones in their order.
    std::vector<char> keep(n, 0);
    for (int v = 0; v < nin; ++v) keep[v] = 1;
    for (size_t c = 0; c < chains.size(); ++c)
        for (size_t i = 0; i < chains[c].size(); ++i)
            if (kept[c][i]) keep[chains[c][i]] = 1;
    std::vector<int> id(n, -1);
    Mesh mesh;
    for (int v = 0; v < n; ++v)
        if (keep[v]) {
            id[v] = mesh.num_vertices();
            mesh.points.push_back(v < static_cast<int>(written.size()) ? written[v] : points[v]);
        }

    // Each input triangle cut along its pieces and triangulated; face_of[t]: its input triangle.
    std::vector<std::vector<int>> points_of(nf);
    for (int v = nin; v < n; ++v)
        if (keep[v])
            for (int f : place[v]) points_of[f].push_back(v);
    std::vector<std::vector<std::array<int, 2>>> cuts(nf);  // pieces inside one triangle
    for (const Piece& q : pieces) {
        const int a = chains[q.chain][q.from], b = chains[q.chain][q.to];
        const std::vector<int> faces = shared(place[a], place[b]);
        if (faces.size() == 1) cuts[faces[0]].push_back({a, b});
    }
    std::vector<int> face_of;
    for (int f = 0; f < nf; ++f) {
        const Triangle& t = input.triangles[f];
        if (points_of[f].empty() && cuts[f].empty()) {
            mesh.triangles.push_back(t);
            face_of.push_back(f);
            continue;
        }
        const Frame& fr = frame(f);
        // Local vertices: the corners, then the points on the sides and inside.
        std::vector<int> local(t.begin(), t.end());
        for (int v : points_of[f]) local.push_back(v);
        std::map<int, int> local_of;
        for (int i = 0; i < static_cast<int>(local.size()); ++i) local_of[local[i]] = i;
        std::vector<P2> pts;
        for (int v : local) pts.push_back(fr.at(v < nin ? input.points[v] : points[v]));
        std::vector<std::array<int, 2>> segs;
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            std::vector<std::pair<double, int>> along;
            const Vec3 d = input.points[b] - input.points[a];
            for (int v : points_of[f]) {
                const auto& fs = place[v];
                if (v < nin || fs.size() != 2) continue;
                const auto& e = adjacency.edge(a, b);
                if (!(std::find(e.begin(), e.end(), fs[0]) != e.end() &&
                      std::find(e.begin(), e.end(), fs[1]) != e.end()))
                    continue;
                along.push_back({dot(points[v] - input.points[a], d), v});
            }
            std::sort(along.begin(), along.end());
            int prev = local_of[a];
            for (const auto& [s, v] : along) {
                segs.push_back({prev, local_of[v]});
                prev = local_of[v];
            }
            segs.push_back({prev, local_of[b]});
        }
        for (const auto& c : cuts[f]) segs.push_back({local_of[c[0]], local_of[c[1]]});
        // The planar graph's faces, each traced with its inside on the left.
        const int m = static_cast<int>(local.size());
        std::vector<std::vector<int>> out_of(m);
        for (const auto& s : segs) out_of[s[0]].push_back(s[1]), out_of[s[1]].push_back(s[0]);
        for (int i = 0; i < m; ++i) {
            auto& o = out_of[i];
            std::sort(o.begin(), o.end());
            if (std::adjacent_find(o.begin(), o.end()) != o.end()) return "a piece doubles an input edge";
            std::sort(o.begin(), o.end(), [&](int x, int y) {
                const P2 u = pts[x] - pts[i], w = pts[y] - pts[i];
                return std::atan2(u.y, u.x) < std::atan2(w.y, w.x);
            });
        }
        std::map<std::pair<int, int>, char> traced;
        for (int i = 0; i < m; ++i)
            for (int j : out_of[i]) {
                if (traced.count({i, j})) continue;
                std::vector<int> poly;
                int a = i, b = j;
                while (!traced.count({a, b})) {
                    traced[{a, b}] = 1;
                    poly.push_back(a);
                    if (poly.size() > static_cast<size_t>(2 * segs.size() + 2))
                        return "a region did not close";
                    const auto& o = out_of[b];
                    const int back = static_cast<int>(std::find(o.begin(), o.end(), a) - o.begin());
                    const int nx = o[(back + static_cast<int>(o.size()) - 1) % static_cast<int>(o.size())];
                    a = b, b = nx;
                }
                double area = 0;
                for (size_t k = 0; k < poly.size(); ++k)
                    area += cross2(pts[poly[k]], pts[poly[(k + 1) % poly.size()]]);
                if (area <= 0) continue;  // the outside of the triangle
                std::vector<int> sorted = poly;
                std::sort(sorted.begin(), sorted.end());
                if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
                    return "a curve ends inside an input triangle";
                std::vector<std::array<int, 3>> tris;
                if (!clip_ears(pts, poly, &tris))
                    return "a region of an input triangle could not be triangulated";
                for (const auto& tr : tris) {
                    mesh.triangles.push_back({id[local[tr[0]]], id[local[tr[1]]], id[local[tr[2]]]});
                    face_of.push_back(f);
                }
            }
    }

    // The layout edges' pieces, in the new numbering.
    std::unordered_map<Key, char> on_edge_path;
    QuadLayout r = like;
    r.input_vertices = nin;
    r.edge_paths = std::move(paths);
    r.orthogonal_system = std::move(system);
    r.s_cycles = std::move(s_cycles);
    auto renumber = [&](std::vector<int>& path) {
        std::vector<int> kept_path;
        for (int v : path)
            if (keep[v]) kept_path.push_back(id[v]);
        path = std::move(kept_path);
    };
    for (auto& p : r.edge_paths) {
        renumber(p);
        for (size_t i = 0; i + 1 < p.size(); ++i) on_edge_path[edge_key(p[i], p[i + 1])] = 1;
    }
    const PathsThrough sides(mesh.num_vertices(), r.edge_paths);
    for (auto& c : r.orthogonal_system) renumber(c);
    for (auto& c : r.s_cycles) renumber(c);
    r.corner_vertex = c_in.corners;
    for (int& v : r.corner_vertex) v = id[v];
    for (size_t k = 0; k < r.corner_vertex.size(); ++k) r.cage.points[k] = mesh.points[r.corner_vertex[k]];

    // Patches: the regions between the layout edges, each given the patch that held most of its
    // area (patch_at() of each new triangle's centroid).
    const int nt = static_cast<int>(mesh.triangles.size());
    std::vector<int> old_patch(nt, -1);
    std::vector<double> area(nt, 0);
    for (int t = 0; t < nt; ++t) {
        const Triangle& tr = mesh.triangles[t];
        const Vec3 c3 = (mesh.points[tr[0]] + mesh.points[tr[1]] + mesh.points[tr[2]]) * (1.0 / 3);
        area[t] = 0.5 * norm(cross(mesh.points[tr[1]] - mesh.points[tr[0]],
                                   mesh.points[tr[2]] - mesh.points[tr[0]]));
        old_patch[t] = patch_at(face_of[t], c3);
        if (old_patch[t] < 0) return "a new triangle lies over no old one";
    }
    const LeftOf left_of(mesh);
    std::vector<int> region(nt, -1);
    std::vector<std::vector<double>> votes;
    const int quads = like.cage.num_quads();
    for (int s = 0; s < nt; ++s) {
        if (region[s] >= 0) continue;
        const int rg = static_cast<int>(votes.size());
        votes.emplace_back(quads, 0.0);
        std::vector<int> stack = {s};
        region[s] = rg;
        while (!stack.empty()) {
            const int t = stack.back();
            stack.pop_back();
            votes[rg][old_patch[t]] += area[t];
            for (int k = 0; k < 3; ++k) {
                const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
                if (on_edge_path.count(edge_key(a, b))) continue;
                const int u = left_of(b, a);
                if (u >= 0 && region[u] < 0) region[u] = rg, stack.push_back(u);
            }
        }
    }
    if (static_cast<int>(votes.size()) != quads)
        return std::to_string(votes.size()) + " regions between the layout edges, not " +
               std::to_string(quads);
    std::vector<int> patch_of_region(quads), taken(quads, 0);
    for (int rg = 0; rg < quads; ++rg) {
        patch_of_region[rg] =
            static_cast<int>(std::max_element(votes[rg].begin(), votes[rg].end()) - votes[rg].begin());
        if (taken[patch_of_region[rg]]++) return "two regions took the same patch";
    }
    std::vector<int> patch(nt);
    for (int t = 0; t < nt; ++t) patch[t] = patch_of_region[region[t]];

    // An edge inside a patch between two points of one layout edge would cut the patch map: split at
    // its midpoint (inside the input triangle, or on the input edge it runs along), which joins the
    // cycles that ran along it.
    auto directed = [](int a, int b) {
        return (static_cast<Key>(a) << 32) | static_cast<Key>(static_cast<std::uint32_t>(b));
    };
    // The triangle a directed edge bounds: left_of() for the triangles as they were, `changed` for
    // the edges of those split since.
    std::vector<char> split(mesh.triangles.size(), 0);
    std::unordered_map<Key, int> changed;
    auto triangle_of = [&](int a, int b) {
        if (const auto it = changed.find(directed(a, b)); it != changed.end()) return it->second;
        const int t = left_of(a, b);
        return t >= 0 && !split[t] ? t : -1;
    };
    const int boundary_known = mesh.num_vertices();  // the midpoints below are on no layout edge
    std::unordered_map<Key, int> midpoint;
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
            if (a >= boundary_known || b >= boundary_known) continue;
            if (on_edge_path.count(edge_key(a, b)) || !sides.share_a_path(a, b)) continue;
            const int u = triangle_of(b, a);
            if (u < 0) return "an edge with one triangle";
            int ku = 0;
            while (mesh.triangles[u][ku] != b) ++ku;
            const int c = mesh.triangles[t][(k + 2) % 3], d = mesh.triangles[u][(ku + 2) % 3];
            const int mid = mesh.num_vertices();
            mesh.points.push_back((mesh.points[a] + mesh.points[b]) * 0.5);
            midpoint[edge_key(a, b)] = mid;
            const int t2 = static_cast<int>(mesh.triangles.size()), u2 = t2 + 1;
            mesh.triangles[t] = {a, mid, c};
            mesh.triangles.push_back({mid, b, c});
            patch.push_back(patch[t]);
            mesh.triangles[u] = {b, mid, d};
            mesh.triangles.push_back({mid, a, d});
            patch.push_back(patch[u]);
            changed.erase(directed(a, b));
            changed.erase(directed(b, a));
            split[t] = split[u] = 1;
            split.resize(mesh.triangles.size(), 1);
            for (int s : {t, t2, u, u2})
                for (int j = 0; j < 3; ++j)
                    changed[directed(mesh.triangles[s][j], mesh.triangles[s][(j + 1) % 3])] = s;
            k = -1;  // this triangle's edges again
        }

    for (auto* cycles : {&r.orthogonal_system, &r.s_cycles})
        for (auto& c : *cycles) {
            std::vector<int> with;
            for (size_t i = 0; i < c.size(); ++i) {
                with.push_back(c[i]);
                if (const auto it = midpoint.find(edge_key(c[i], c[(i + 1) % c.size()]));
                    it != midpoint.end())
                    with.push_back(it->second);
            }
            c = std::move(with);
        }
    r.mesh = std::move(mesh);
    r.triangle_patch = std::move(patch);
    r.corner_uv.assign(r.mesh.triangles.size(), {});
    r.edges_smoothed = true;
    parameterize_patches(&r);
    if (std::string problem = verify_quad_layout(r); !problem.empty()) return problem;
    *out = std::move(r);
    return "";
}


std::string retrace_on_input(const Mesh& input, const QuadLayout& L, QuadLayout* out) {
    const int nin = L.input_vertices;
    if (nin != input.num_vertices()) return "the layout is not of this input";
    const int n = L.mesh.num_vertices();
    const int nf = static_cast<int>(input.triangles.size());
    for (const Triangle& t : input.triangles)
        if (!(norm(cross(input.points[t[1]] - input.points[t[0]], input.points[t[2]] - input.points[t[0]])) >
              0))
            return "the input has a triangle of zero area";

    // Where each layout vertex lies on the input.
    const InputAdjacency adjacency(input);
    const auto& vertex_faces = adjacency.vertex_faces;
    const TriangleGrid grid(input);
    const double tolerance = 1e-8 * grid.diag();
    // Where each layout vertex lies on the input: the input triangles it is in (one inside a
    // triangle, two on an edge, all round an input vertex).
    std::vector<std::vector<int>> place(n);
    std::vector<Vec3> points = L.mesh.points;
    for (int v = 0; v < n; ++v) {
        if (v < nin) {
            place[v] = vertex_faces[v];
            continue;
        }
        std::array<double, 3> w{};
        const int f = grid.locate(points[v], tolerance, &w);
        if (f < 0) return "layout vertex " + std::to_string(v) + " lies on no input triangle";
        const Triangle& t = input.triangles[f];
        int zeros = 0, zero = -1;
        for (int k = 0; k < 3; ++k)
            if (w[k] <= kOnEdge) ++zeros, zero = k;
        if (zeros >= 2) return "layout vertex " + std::to_string(v) + " lies on an input vertex";
        if (zeros == 1) {
            const int a = t[(zero + 1) % 3], b = t[(zero + 2) % 3];
            place[v] = adjacency.edge(a, b);
            // Exactly on the edge, as the split that made it meant.
            const double s = w[(zero + 2) % 3] / (w[(zero + 1) % 3] + w[(zero + 2) % 3]);
            points[v] = input.points[a] + (input.points[b] - input.points[a]) * s;
        } else {
            place[v] = {f};
        }
    }

    Frames frame(input);

    // The curves. Where the refinement was undone inside a plane, a mesh edge can cross input
    // edges between coplanar triangles: the points where it does are added to the curves through it.
    std::vector<std::vector<int>> paths = L.edge_paths, system = L.orthogonal_system, s_cycles = L.s_cycles;
    std::unordered_map<Key, std::vector<int>> crossings;  // by mesh edge, from its lower vertex
    auto neighbour = [&](int f, int a, int b) {
        for (int g : adjacency.edge(a, b))
            if (g != f) return g;
        return -1;
    };
    std::string crossing_problem;
    auto cross_between = [&](int a, int b) -> const std::vector<int>& {
        const Key key = edge_key(a, b);
        if (auto it = crossings.find(key); it != crossings.end()) return it->second;
        std::vector<int>& made = crossings[key];
        const int lo = std::min(a, b), hi = std::max(a, b);
        const Vec3 p = points[lo], q = points[hi];
        // The triangle of lo's that the edge leaves it into.
        int f = -1;
        double best = -std::numeric_limits<double>::infinity();
        for (int g : place[lo]) {
            const Frame& fr = frame(g);
            const Triangle& t = input.triangles[g];
            const P2 x = fr.at(p + (q - p) * 1e-6);
            const double in = std::min({orient(fr.at(input.points[t[0]]), fr.at(input.points[t[1]]), x),
                                        orient(fr.at(input.points[t[1]]), fr.at(input.points[t[2]]), x),
                                        orient(fr.at(input.points[t[2]]), fr.at(input.points[t[0]]), x)});
            if (in > best) best = in, f = g;
        }
        double at = 0;
        for (int step = 0; f >= 0 && step < 10000; ++step) {
            if (std::find(place[hi].begin(), place[hi].end(), f) != place[hi].end()) return made;
            const Frame& fr = frame(f);
            const Triangle& t = input.triangles[f];
            const P2 P = fr.at(p), Q = fr.at(q);
            double first = std::numeric_limits<double>::infinity(), u_first = 0;
            int k_first = -1;
            for (int k = 0; k < 3; ++k) {
                double s = 0, u = 0;
                if (!meets_side(input, fr, t, k, P, Q, &s, &u)) continue;
                if (s > at + 1e-12 && s < first && u >= -1e-9 && u <= 1 + 1e-9)
                    first = s, u_first = u, k_first = k;
            }
            if (k_first < 0 || first >= 1) break;
            if (u_first <= 1e-9 || u_first >= 1 - 1e-9) {
                crossing_problem = "a mesh edge passes through an input vertex";
                return made;
            }
            const int ea = t[k_first], eb = t[(k_first + 1) % 3];
            const int v = static_cast<int>(points.size());
            points.push_back(input.points[ea] + (input.points[eb] - input.points[ea]) * u_first);
            place.push_back(adjacency.edge(ea, eb));
            made.push_back(v);
            at = first;
            f = neighbour(f, ea, eb);
        }
        crossing_problem = "a mesh edge could not be followed across the input's triangles";
        return made;
    };
    auto expand = [&](std::vector<int>& curve, bool closed) {
        std::vector<int> out;
        const size_t m = curve.size();
        for (size_t i = 0; i < m; ++i) {
            out.push_back(curve[i]);
            if (i + 1 == m && !closed) break;
            const int a = curve[i], b = curve[(i + 1) % m];
            if (!shared(place[a], place[b]).empty()) continue;
            const std::vector<int> between = cross_between(a, b);
            if (a < b)
                out.insert(out.end(), between.begin(), between.end());
            else
                out.insert(out.end(), between.rbegin(), between.rend());
        }
        curve = std::move(out);
    };
    for (auto& c : paths) expand(c, false);
    for (auto& c : system) expand(c, true);
    for (auto& c : s_cycles) expand(c, true);
    if (!crossing_problem.empty()) return crossing_problem;

    CurvesOnInput curves;
    curves.points = std::move(points);
    curves.place = std::move(place);
    curves.edge_paths = std::move(paths);
    curves.orthogonal_system = std::move(system);
    curves.s_cycles = std::move(s_cycles);
    curves.corners = L.corner_vertex;

    // Each new triangle takes the patch of the old triangle its centroid lies deepest in, among the
    // old triangles of its input triangle. An old triangle lies in each input triangle of its
    // vertices' that is in its plane (more than one where the undoing of the refinement joined
    // coplanar triangles).
    std::vector<std::vector<int>> old_in_face(nf);
    for (int t = 0; t < static_cast<int>(L.mesh.triangles.size()); ++t) {
        const Triangle& tr = L.mesh.triangles[t];
        Vec3 normal = cross(curves.points[tr[1]] - curves.points[tr[0]], curves.points[tr[2]] - curves.points[tr[0]]);
        const double length = norm(normal);
        if (!(length > 0)) continue;
        normal = normal * (1 / length);
        std::vector<int> faces;
        for (int v : tr)
            for (int f : curves.place[v])
                if (std::find(faces.begin(), faces.end(), f) == faces.end()) faces.push_back(f);
        for (int f : faces) {
            const Frame& fr = frame(f);
            if (dot(cross(fr.e1, fr.e2), normal) > 1 - 1e-9) old_in_face[f].push_back(t);
        }
    }
    const PatchAt patch_at = [&](int f, const Vec3& c3) {
        const Frame& fr = frame(f);
        const P2 c = fr.at(c3);
        double best = -std::numeric_limits<double>::infinity();
        int patch = -1;
        for (int o : old_in_face[f]) {
            const Triangle& ot = L.mesh.triangles[o];
            const P2 a = fr.at(curves.points[ot[0]]), b = fr.at(curves.points[ot[1]]), d = fr.at(curves.points[ot[2]]);
            const double whole = orient(a, b, d);
            if (!(whole > 0)) continue;
            const double inside = std::min({orient(a, b, c), orient(b, d, c), orient(d, a, c)}) / whole;
            if (inside > best) best = inside, patch = L.triangle_patch[o];
        }
        return patch;
    };

    // The layout's own points are written as they were (those on input edges were put exactly on
    // them above, for the geometry only).
    return cut_input_along(input, adjacency, curves, L.mesh.points, patch_at, L, out);
}

namespace {

// Barycentric weights this small put a projected point on the input edge or vertex it is nearest.
constexpr double kOnInputEdge = 1e-9;

// The way across the input from point p to point q (each inside an input triangle, on an input
// edge or at an input vertex): from p, and then from each point where it enters a triangle,
// straight towards q in that triangle's plane. Its crossings of input edges are appended to points
// and place (and their ids to *crossed). False if the way is lost: q lies behind it in a
// triangle's plane, it reaches no triangle of q's within 64 triangles, or it runs through an input
// vertex.
bool walk_between(const Mesh& input, const InputAdjacency& adjacency, Frames& frame, std::vector<Vec3>& points,
                  std::vector<std::vector<int>>& place, int p, int q, std::vector<int>* crossed) {
    if (!shared(place[p], place[q]).empty()) return true;
    // Where the way from P towards Q leaves triangle t (frame fr) forward, by more than rounding
    // and not through the side it came in by: that side k and the fraction u along it; false if Q
    // lies behind.
    auto exit_of = [&](const Frame& fr, const Triangle& t, P2 P, P2 Q, int* k_out, double* u_out) {
        double best_s = -std::numeric_limits<double>::infinity();
        *k_out = -1;
        for (int k = 0; k < 3; ++k) {
            double s = 0, u = 0;
            if (!meets_side(input, fr, t, k, P, Q, &s, &u)) continue;
            if (u < -1e-9 || u > 1 + 1e-9 || !(s > 1e-9)) continue;
            if (s > best_s) best_s = s, *u_out = u, *k_out = k;
        }
        return *k_out >= 0;
    };
    // The triangles of p's, those the way towards q leaves p into most first.
    std::vector<std::pair<double, int>> starts;
    for (int g : place[p]) {
        const Frame& fr = frame(g);
        const Triangle& t = input.triangles[g];
        const P2 x = fr.at(points[p] + (points[q] - points[p]) * 1e-6);
        const double in = std::min({orient(fr.at(input.points[t[0]]), fr.at(input.points[t[1]]), x),
                                    orient(fr.at(input.points[t[1]]), fr.at(input.points[t[2]]), x),
                                    orient(fr.at(input.points[t[2]]), fr.at(input.points[t[0]]), x)});
        starts.push_back({-in, g});
    }
    std::sort(starts.begin(), starts.end());
    const std::vector<int>& targets = place[q];
    const size_t before = points.size(), crossed_before = crossed->size();
    // Tried from each of p's triangles, in that order, while the first step finds no way forward.
    for (const auto& [unused, first] : starts) {
        int f = first;
        int from = p;       // where the way entered f
        Vec3 heading{};     // the way's direction in the triangle before f (zero in p's own)
        bool forward = true;
        for (int step = 0; step < 64; ++step) {
            if (std::find(targets.begin(), targets.end(), f) != targets.end()) return true;
            const Frame& fr = frame(f);
            const Triangle& t = input.triangles[f];
            const P2 P = fr.at(points[from]);
            int k = -1;
            double u = 0;
            if (!exit_of(fr, t, P, fr.at(points[q]), &k, &u)) {
                // Past a crease q can lie behind the side the way came in by, in this triangle's
                // plane: the way then goes on straight, its heading unfolded across that side.
                if (step == 0) {
                    forward = false;
                    break;
                }
                if (!exit_of(fr, t, P, P2{P.x + dot(heading, fr.e1), P.y + dot(heading, fr.e2)}, &k, &u)) return false;
            }
            if (u <= 1e-9 || u >= 1 - 1e-9) return false;  // through an input vertex
            const int a = t[k], b = t[(k + 1) % 3];
            const std::vector<int>& faces = adjacency.edge(a, b);
            if (faces.size() != 2) return false;
            const Vec3 exit = input.points[a] + (input.points[b] - input.points[a]) * u;
            const int g = faces[0] == f ? faces[1] : faces[0];
            // The heading in g: along the side as it was, and across it into g as far as it went
            // across it out of f.
            const Vec3 d = exit - points[from];
            const Vec3 side = (input.points[b] - input.points[a]) * (1 / norm(input.points[b] - input.points[a]));
            const Frame& fg = frame(g);
            Vec3 into = cross(cross(fg.e1, fg.e2), side);
            const Triangle& tg = input.triangles[g];
            const int c = tg[0] != a && tg[0] != b ? tg[0] : tg[1] != a && tg[1] != b ? tg[1] : tg[2];
            if (dot(into, input.points[c] - exit) < 0) into = into * -1.0;
            heading = side * dot(d, side) + into * norm(d - side * dot(d, side));
            from = static_cast<int>(points.size());
            crossed->push_back(from);
            points.push_back(exit);
            place.push_back(faces);
            f = g;
        }
        if (forward) return false;
        points.resize(before);
        place.resize(before);
        crossed->resize(crossed_before);
    }
    return false;
}

// How trace_from_proxy() carries the proxy's points onto the input.
enum class Carry { ClosestPoint, AlongNormals };

std::string carry_from_proxy(const Mesh& input, const InputAdjacency& adjacency,
                             const accel::ClosestPointIndex& on_input, const QuadLayout& proxy, Carry how,
                             QuadLayout* out) {
    const int nin = input.num_vertices();
    Frames frame(input);
    std::vector<Vec3> points = input.points;
    std::vector<std::vector<int>> place = adjacency.vertex_faces;

    // The median length of the edges between the first `below` points of m (0 if none).
    auto median_edge = [](const Mesh& m, int below) {
        std::vector<double> lengths;
        for (const Triangle& t : m.triangles)
            for (int k = 0; k < 3; ++k) {
                const int a = t[k], b = t[(k + 1) % 3];
                if (a < b && b < below) lengths.push_back(norm(m.points[a] - m.points[b]));
            }
        if (lengths.empty()) return 0.0;
        std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2), lengths.end());
        return lengths[lengths.size() / 2];
    };
    // The input's median edge length: the samples' spacing along the proxy's edges.
    const double input_edge = median_edge(input, nin);
    const double spacing = input_edge > 0 ? input_edge : 1.0;
    const double proxy_edge = std::max(spacing, median_edge(proxy.mesh, proxy.input_vertices));
    // How far along its normal a proxy point looks for the input, in the proxy's median edges.
    constexpr double kRayReach = 2;
    const double ray_limit = kRayReach * proxy_edge;
    // The proxy's normals at its points (area-weighted), interpolated along its edges.
    const std::vector<Vec3>& proxy_points = proxy.mesh.points;
    std::vector<Vec3> proxy_normal(proxy_points.size());
    for (const Triangle& t : proxy.mesh.triangles) {
        const Vec3 n = cross(proxy_points[t[1]] - proxy_points[t[0]], proxy_points[t[2]] - proxy_points[t[0]]);
        for (int v : t) proxy_normal[v] = proxy_normal[v] + n;
    }
    for (Vec3& n : proxy_normal)
        if (const double l = norm(n); l > 0) n = n * (1 / l);

    // The proxy's points projected onto the input. A whole region of space (a normal cone) has its
    // closest point at an input vertex or on an input edge, and curves through it would meet there:
    // such a point is moved off it, into the triangle round it that its offset from the surface,
    // taken along the surface, points into, by a distance that grows with that offset (at most
    // kSpread of the median edge, and a quarter of the way across the triangle). Distinct offsets
    // stay distinct, and in their order round the vertex.
    constexpr double kSpread = 0.1;
    auto inside = [&](int f, const Vec3& p) {  // p's barycentric weights in f, all above rounding
        const Triangle& t = input.triangles[f];
        const Vec3 A = input.points[t[0]], B = input.points[t[1]], C = input.points[t[2]];
        const Vec3 n = cross(B - A, C - A);
        const double area2 = dot(n, n);
        return dot(cross(B - p, C - p), n) / area2 > 1e-6 && dot(cross(C - p, A - p), n) / area2 > 1e-6 &&
               dot(cross(A - p, B - p), n) / area2 > 1e-6;
    };
    auto add_point = [&](const Vec3& p, std::vector<int> where) {
        points.push_back(p);
        place.push_back(std::move(where));
        return static_cast<int>(points.size()) - 1;
    };
    // y moved into f along the unit direction u (in f's plane) by up to `far`, halved until inside.
    auto moved_into = [&](int f, const Vec3& y, const Vec3& u, double far) -> int {
        for (int halving = 0; halving < 30; ++halving, far *= 0.5)
            if (inside(f, y + u * far)) return add_point(y + u * far, {f});
        return -1;
    };
    // Along the proxy's normals (Carry::AlongNormals), a point reaches the nearest input point on
    // the line through x along n, within ray_limit, whose triangle faces the way n does. That map is
    // continuous where the closest point is not (across a ridge seen from inside, or where a part
    // is thinner than the proxy's distance from it). Where no such point is found, the closest
    // point is taken.
    auto input_normal = [&](int f) {
        const Triangle& g = input.triangles[f];
        return cross(input.points[g[1]] - input.points[g[0]], input.points[g[2]] - input.points[g[0]]);
    };
    auto along_normal = [&](const Vec3& x, const Vec3& n) {
        accel::ClosestHit best;
        best.distance = std::numeric_limits<double>::infinity();
        if (!(norm(n) > 0)) return best;
        // Each ray starts a little behind x, so a point on the input (a proxy point that is an
        // input point, or lies in an input triangle's plane) finds the triangle it is in.
        const Vec3 unit = n * (1 / norm(n));
        const double behind = 1e-6 * proxy_edge;
        for (const Vec3& direction : {unit, unit * -1.0}) {
            accel::ClosestHit hit = on_input.first_hit(x - direction * behind, direction, ray_limit + behind);
            if (hit.triangle < 0 || !(dot(input_normal(hit.triangle), n) > 0)) continue;
            hit.distance = norm(hit.point - x);
            if (hit.distance < best.distance) best = hit;
        }
        return best;
    };
    auto project = [&](const Vec3& x, const Vec3& n) {
        accel::ClosestHit hit = on_input.query(x);
        if (how == Carry::AlongNormals)
            if (const accel::ClosestHit ray = along_normal(x, n); ray.triangle >= 0) hit = ray;
        const Triangle& t = input.triangles[hit.triangle];
        const std::array<double, 3>& w = hit.barycentric;
        int zeros = 0, zero = -1;
        for (int k = 0; k < 3; ++k)
            if (w[k] <= kOnInputEdge) ++zeros, zero = k;
        if (zeros == 0)
            return add_point(input.points[t[0]] * w[0] + input.points[t[1]] * w[1] + input.points[t[2]] * w[2],
                             {hit.triangle});
        const int vertex = zeros >= 2 ? t[std::max_element(w.begin(), w.end()) - w.begin()] : -1;
        const int ea = t[(zero + 1) % 3], eb = t[(zero + 2) % 3];
        const std::vector<int>& faces = vertex >= 0 ? adjacency.vertex_faces[vertex] : adjacency.edge(ea, eb);
        Vec3 y;
        if (vertex >= 0) {
            y = input.points[vertex];
        } else {
            const double u = w[(zero + 2) % 3] / (w[(zero + 1) % 3] + w[(zero + 2) % 3]);
            y = input.points[ea] + (input.points[eb] - input.points[ea]) * u;
        }
        Vec3 normal{};
        for (int f : faces) {
            const Triangle& g = input.triangles[f];
            normal = normal + cross(input.points[g[1]] - input.points[g[0]], input.points[g[2]] - input.points[g[0]]);
        }
        const double nl = norm(normal);
        Vec3 d = x - y;
        if (nl > 0) d = d - normal * (dot(d, normal) / (nl * nl));
        const double r = norm(d);
        const double far = kSpread * spacing * r / (r + spacing);
        // The triangle round y that d points into most, and d in its plane.
        int best = -1;
        double best_score = -std::numeric_limits<double>::infinity();
        Vec3 best_u{};
        if (r > 0)
            for (int f : faces) {
                const Frame& fr = frame(f);
                const P2 D = {dot(d, fr.e1), dot(d, fr.e2)};
                const double length = std::hypot(D.x, D.y);
                if (!(length > 0)) continue;
                const Vec3 u = (fr.e1 * D.x + fr.e2 * D.y) * (1 / length);
                // How far inside f a short step along u from y lands (its smallest weight, over the step).
                const Triangle& g = input.triangles[f];
                const Vec3 A = input.points[g[0]], B = input.points[g[1]], C = input.points[g[2]];
                const Vec3 n = cross(B - A, C - A);
                const double area2 = dot(n, n);
                const Vec3 q = y + u * (1e-3 * spacing);
                const double score = std::min({dot(cross(B - q, C - q), n), dot(cross(C - q, A - q), n),
                                               dot(cross(A - q, B - q), n)}) / area2;
                if (score > best_score) best_score = score, best = f, best_u = u;
            }
        if (best >= 0 && far > 0) {
            const Triangle& g = input.triangles[best];
            double size = std::numeric_limits<double>::infinity();
            for (int k = 0; k < 3; ++k) size = std::min(size, norm(input.points[g[k]] - input.points[g[(k + 1) % 3]]));
            const int moved = moved_into(best, y, best_u, std::min(far, 0.25 * size));
            if (moved >= 0) return moved;
        }
        if (vertex >= 0) return vertex;
        return add_point(y, faces);
    };

    // Samples along each proxy edge the curves use about an input edge apart (the median), each
    // walked to the next; where a walk is lost, the midpoint between its samples is projected too.
    // Where nearby proxy points land far apart (a ray that grazes the input, or one point carried
    // along its normal and the next to its closest point), the two are joined along input edges: the
    // shortest way from a corner of the first's triangle to one of the second's, through input
    // vertices, if it is at most kBridge median edges of the proxy long (a longer jump is across a
    // part thinner than the proxy's triangles, and the way fails). The jumps grow with the
    // proxy's distance from the input, so with its edges, not the input's.
    constexpr double kBridge = 2;
    const double bridge_limit = kBridge * proxy_edge;
    std::vector<std::vector<int>> neighbours;  // made if needed
    auto bridge = [&](int ia, int ib, std::vector<int>* chain) {
        if (neighbours.empty()) {
            neighbours.resize(nin);
            for (const Triangle& t : input.triangles)
                for (int k = 0; k < 3; ++k) neighbours[t[k]].push_back(t[(k + 1) % 3]);
        }
        std::vector<int> ends;  // the corners of q's triangles
        for (int f : place[ib]) ends.insert(ends.end(), input.triangles[f].begin(), input.triangles[f].end());
        std::unordered_map<int, double> distance;
        std::unordered_map<int, int> previous;
        using Entry = std::pair<double, int>;
        std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
        for (int f : place[ia])
            for (int v : input.triangles[f]) {
                const double d = norm(points[v] - points[ia]);
                if (const auto it = distance.find(v); it == distance.end() || d < it->second)
                    distance[v] = d, previous[v] = -1, queue.push({d, v});
            }
        int end = -1;
        for (int pops = 0; !queue.empty() && pops < 4096; ++pops) {
            const auto [d, v] = queue.top();
            queue.pop();
            if (d > bridge_limit) break;  // a jump across a thin part, not a ridge
            if (d > distance[v]) continue;
            if (std::find(ends.begin(), ends.end(), v) != ends.end()) {
                end = v;
                break;
            }
            for (int w : neighbours[v]) {
                const double dw = d + norm(points[w] - points[v]);
                if (const auto it = distance.find(w); it == distance.end() || dw < it->second)
                    distance[w] = dw, previous[w] = v, queue.push({dw, w});
            }
        }
        if (end < 0) return false;
        std::vector<int> path;
        for (int v = end; v >= 0; v = previous[v])
            if (v != ia && v != ib) path.push_back(v);
        chain->insert(chain->end(), path.rbegin(), path.rend());
        return true;
    };
    struct Sample {
        Vec3 point, normal;
    };
    std::function<bool(const Sample&, int, const Sample&, int, int, std::vector<int>*)> trace =
        [&](const Sample& A, int ia, const Sample& B, int ib, int depth, std::vector<int>* chain) {
            const size_t before = points.size();
            std::vector<int> crossed;
            if (walk_between(input, adjacency, frame, points, place, ia, ib, &crossed)) {
                chain->insert(chain->end(), crossed.begin(), crossed.end());
                return true;
            }
            points.resize(before);
            place.resize(before);
            if (depth == 0) return bridge(ia, ib, chain);
            const Sample M = {(A.point + B.point) * 0.5, (A.normal + B.normal) * 0.5};
            const int im = project(M.point, M.normal);
            if (!trace(A, ia, M, im, depth - 1, chain)) return false;
            chain->push_back(im);
            return trace(M, im, B, ib, depth - 1, chain);
        };
    std::vector<int> id(proxy_points.size(), -1);
    auto point_of = [&](int v) {
        if (id[v] < 0) id[v] = project(proxy_points[v], proxy_normal[v]);
        return id[v];
    };
    std::unordered_map<Key, std::vector<int>> chain_of;  // by proxy edge, from its lower vertex
    std::string problem;
    auto chain = [&](int a, int b) -> const std::vector<int>& {
        const Key key = edge_key(a, b);
        if (auto it = chain_of.find(key); it != chain_of.end()) return it->second;
        const int lo = std::min(a, b), hi = std::max(a, b);
        std::vector<int>& made = chain_of[key];
        const Sample A = {proxy_points[lo], proxy_normal[lo]}, B = {proxy_points[hi], proxy_normal[hi]};
        const int samples = static_cast<int>(std::floor(norm(B.point - A.point) / spacing));
        Sample from = A;
        int at = point_of(lo);
        const int end = point_of(hi);
        for (int i = 1; i <= samples + 1 && problem.empty(); ++i) {
            const double s = static_cast<double>(i) / (samples + 1);
            const Sample to = i <= samples ? Sample{A.point + (B.point - A.point) * s, A.normal + (B.normal - A.normal) * s} : B;
            const int next = i <= samples ? project(to.point, to.normal) : end;
            if (!trace(from, at, to, next, 8, &made)) problem = "a curve could not be followed onto the input";
            if (i <= samples) made.push_back(next);
            from = to, at = next;
        }
        return made;
    };
    auto follow = [&](const std::vector<int>& curve, bool closed) {
        std::vector<int> r;
        const size_t m = curve.size();
        for (size_t i = 0; i < m && problem.empty(); ++i) {
            r.push_back(point_of(curve[i]));
            if (i + 1 == m && !closed) break;
            const int a = curve[i], b = curve[(i + 1) % m];
            const std::vector<int>& between = chain(a, b);
            if (a < b)
                r.insert(r.end(), between.begin(), between.end());
            else
                r.insert(r.end(), between.rbegin(), between.rend());
        }
        return r;
    };
    // Points in a row that landed on one input vertex count once.
    auto once = [](std::vector<int> c, bool closed) {
        c.erase(std::unique(c.begin(), c.end()), c.end());
        while (closed && c.size() > 1 && c.back() == c.front()) c.pop_back();
        return c;
    };
    CurvesOnInput curves;
    for (const auto& c : proxy.edge_paths) curves.edge_paths.push_back(once(follow(c, false), false));
    for (const auto& c : proxy.orthogonal_system) curves.orthogonal_system.push_back(once(follow(c, true), true));
    for (const auto& c : proxy.s_cycles) curves.s_cycles.push_back(once(follow(c, true), true));
    for (int v : proxy.corner_vertex) curves.corners.push_back(point_of(v));
    if (!problem.empty()) return problem;
    curves.points = std::move(points);
    curves.place = std::move(place);

    // Each new triangle takes the patch of the proxy's triangle nearest its centroid.
    const accel::ClosestPointIndex on_proxy(proxy.mesh);
    const PatchAt patch_at = [&](int, const Vec3& c) {
        const accel::ClosestHit hit = on_proxy.query(c);
        return hit.triangle < 0 ? -1 : proxy.triangle_patch[hit.triangle];
    };
    return cut_input_along(input, adjacency, curves, input.points, patch_at, proxy, out);
}

}  // namespace

std::string trace_from_proxy(const Mesh& input, const QuadLayout& proxy, QuadLayout* out, std::string* how) {
    for (const Triangle& t : input.triangles)
        if (!(norm(cross(input.points[t[1]] - input.points[t[0]], input.points[t[2]] - input.points[t[0]])) >
              0))
            return "the input has a triangle of zero area";
    const InputAdjacency adjacency(input);
    const accel::ClosestPointIndex on_input(input);
    // Each way folds the curves somewhere the other does not: the closest point where the copy is
    // farther from a thin part or a sharp ridge than its width, the copy's normals where they
    // converge faster than the input's (in a fillet, where a handle meets a body).
    const std::string closest = carry_from_proxy(input, adjacency, on_input, proxy, Carry::ClosestPoint, out);
    if (closest.empty()) {
        if (how) *how = "at the closest points";
        return "";
    }
    const std::string along = carry_from_proxy(input, adjacency, on_input, proxy, Carry::AlongNormals, out);
    if (along.empty()) {
        if (how) *how = "along the copy's normals";
        return "";
    }
    return closest + " at the closest points, " + along + " along the copy's normals";
}

}  // namespace quadcage::layout::detail

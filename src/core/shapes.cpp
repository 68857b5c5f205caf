#include "quadcage/core/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "quadcage/core/errors.h"

namespace quadcage::shapes {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Refuse requests whose output could not be indexed with int (or would exhaust memory) before
// allocating anything.
constexpr std::int64_t kMaxTriangles = 100'000'000;

void require(bool ok, const std::string& what) {
    if (!ok) throw InvalidInput(what);
}

// require() for an integer option: "<where>: <name> must be in lo..hi, got <value>".
void require_in(int value, int lo, int hi, const std::string& where, const std::string& name) {
    require(value >= lo && value <= hi, where + ": " + name + " must be in " + std::to_string(lo) + ".." +
                                            std::to_string(hi) + ", got " + std::to_string(value));
}

Vec3 normalized(const Vec3& v) { return v / norm(v); }

// A fin: points pushed out along their rays from a body's centre by up to `length` body radii
// round `axis`, falling to 0 at `half_wide` radians from it along `wide` and, smoothly, at twice
// `half_thin` along `thin` (both unit, orthogonal to the axis and to each other): a thin, flat
// protrusion, as the limbs are round ones. Across, its profile is (1 - t^2 / 4)^3 (t: the angle
// over half_thin), smooth to its foot, so a few vertices across it make its sides.
struct Fin {
    Vec3 axis, wide, thin;
    double length, half_wide, half_thin;
};

// A fin round a random direction (z of the direction at most max_z) from uniform(), which gives
// numbers in (0, 1): 17-29 degrees to its tip either way along it, 5 to 8 times less across.
template <class Uniform>
Fin random_fin(Uniform& uniform, double max_length, double max_z) {
    Vec3 axis;
    do {
        const double z = 2 * uniform() - 1, phi = 2 * kPi * uniform();
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        axis = Vec3{r * std::cos(phi), r * std::sin(phi), z};
    } while (axis.z > max_z);
    // Any direction across the axis, from one more angle.
    const Vec3 e1 = normalized(cross(axis, std::abs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 e2 = cross(axis, e1);
    const double turn = 2 * kPi * uniform();
    const Vec3 wide = e1 * std::cos(turn) + e2 * std::sin(turn);
    const double length = 1.0 + (max_length - 1.0) * uniform();
    const double half_wide = 0.3 + 0.2 * uniform();
    return {axis, wide, cross(axis, wide), length, half_wide, half_wide / (5 + 3 * uniform())};
}

// How far the fins push a point whose direction from the centre is the unit vector d (in body
// radii, added to the radius).
double fin_push(const std::vector<Fin>& fins, const Vec3& d) {
    double add = 0;
    for (const Fin& f : fins) {
        const double a = dot(d, f.axis);
        if (a <= 0) continue;
        const double u = std::abs(std::atan2(dot(d, f.wide), a)) / f.half_wide;
        const double t = std::atan2(dot(d, f.thin), a) / f.half_thin;
        if (u < 1 && t * t < 4) add += f.length * std::pow(1 - u, 0.6) * std::pow(1 - t * t / 4, 3);
    }
    return add;
}

// ---------------------------------------------------------------------------------------------
// plate_with_holes

struct PlateLayout {
    int genus = 0;
    int cols = 0;    // holes per row
    int rows = 0;    // rows of holes
    int width = 1;   // W, along x
    int height = 1;  // H, along y
};

PlateLayout plate_layout(int genus) {
    PlateLayout l;
    l.genus = genus;
    // Integer ceil(sqrt(g)): floating-point sqrt may land just below an exact square.
    while (static_cast<std::int64_t>(l.cols) * l.cols < genus) ++l.cols;
    l.rows = l.cols == 0 ? 0 : static_cast<int>((std::int64_t{genus} + l.cols - 1) / l.cols);
    l.width = 2 * l.cols + 1;
    l.height = 2 * l.rows + 1;
    return l;
}

bool is_hole_cell(const PlateLayout& l, int cx, int cy) {
    if (cx % 2 == 0 || cy % 2 == 0) return false;
    const int c = (cx - 1) / 2, r = (cy - 1) / 2;
    return c < l.cols && r < l.rows && r * l.cols + c < l.genus;
}

struct IVec3 {
    int x = 0, y = 0, z = 0;
    IVec3 operator+(const IVec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
};

constexpr IVec3 kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

// Builds the boundary of a voxel solid. Vertices are deduplicated by integer grid coordinates so
// that equal corners are shared exactly, whatever the floating-point spacing.
class VoxelSurface {
public:
    // Grid point (i, j, k) in [0, nx] x [0, ny] x [0, nz] sits at (i/per_unit, j/per_unit,
    // height*k/nz); dividing (rather than multiplying by a step) keeps unit-grid positions exact.
    VoxelSurface(int nx, int ny, int nz, int per_unit, double height)
        : ny_(ny + 1), nz_(nz + 1), per_unit_(per_unit), height_(height) {
        QC_CHECK(nx >= 0 && ny >= 0 && nz >= 0, "voxel grid dimensions must be non-negative");
    }

    // Quad with corners o, o+u, o+u+v, o+v; its outward normal is u x v.
    void add_quad(IVec3 o, IVec3 u, IVec3 v) {
        const int p0 = vertex(o), p1 = vertex(o + u), p2 = vertex(o + u + v), p3 = vertex(o + v);
        // Alternate the diagonal in a checkerboard (neighbouring quads in a plane differ by one
        // unit in u or v, so the parity of the origin flips) to avoid a directional bias.
        if (((o.x + o.y + o.z) & 1) == 0) {
            mesh_.triangles.push_back({p0, p1, p2});
            mesh_.triangles.push_back({p0, p2, p3});
        } else {
            mesh_.triangles.push_back({p0, p1, p3});
            mesh_.triangles.push_back({p1, p2, p3});
        }
    }

    Mesh take() { return std::move(mesh_); }

private:
    int vertex(IVec3 p) {
        const std::int64_t key = (static_cast<std::int64_t>(p.x) * ny_ + p.y) * nz_ + p.z;
        const auto [it, inserted] = index_.try_emplace(key, mesh_.num_vertices());
        if (inserted) {
            const double z = p.z == nz_ - 1 ? height_ : height_ * p.z / (nz_ - 1);
            mesh_.points.push_back({static_cast<double>(p.x) / per_unit_,
                                    static_cast<double>(p.y) / per_unit_, z});
        }
        return it->second;
    }

    std::int64_t ny_, nz_;
    int per_unit_;
    double height_;
    Mesh mesh_;
    std::unordered_map<std::int64_t, int> index_;
};

// Smooth, injective, orientation-preserving map that takes the plate off the coordinate axes.
// The two shears are triangular (y moves with x only, z with x and y only), hence injective with
// unit Jacobian; the bend is a polar map with positive radius over less than half a turn.
class PlateBend {
public:
    PlateBend(double width, double height, double thickness)
        : width_(width), height_(height), half_t_(0.5 * thickness) {
        // Arc length of the mid-surface is kept, so the angle is width / radius <= 60 degrees;
        // the radius also stays above the half-thickness plus the wobble so that rho > 0.
        radius_ = std::max(width / (kPi / 3.0), thickness + 1.0);
    }

    Vec3 operator()(const Vec3& p) const {
        const double y = p.y + kShearY * std::sin(kPi * p.x / width_);
        const double z = p.z + kWobbleZ * std::sin(2.0 * kPi * p.x / width_) *
                                   std::cos(kPi * p.y / height_);
        const double theta = (p.x - 0.5 * width_) / radius_;
        const double rho = radius_ + (z - half_t_);
        return {0.5 * width_ + rho * std::sin(theta), y, rho * std::cos(theta) - radius_ + half_t_};
    }

private:
    static constexpr double kShearY = 0.1;
    static constexpr double kWobbleZ = 0.05;
    double width_, height_, half_t_, radius_ = 1.0;
};

// Taubin smoothing (Taubin 1995): a shrinking step lambda = 0.5 and an inflating step mu = -0.53 per
// pass round voxel steps off without shrinking the solid. Moves the points only.
void taubin_smooth(Mesh* mesh, int passes) {
    std::vector<std::vector<int>> nbr(mesh->points.size());
    for (const Triangle& t : mesh->triangles)
        for (int e = 0; e < 3; ++e) nbr[t[e]].push_back(t[(e + 1) % 3]), nbr[t[(e + 1) % 3]].push_back(t[e]);
    for (auto& v : nbr) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    std::vector<Vec3> next(mesh->points.size());
    for (int pass = 0; pass < 2 * passes; ++pass) {
        const double step = pass % 2 == 0 ? 0.5 : -0.53;
        for (size_t v = 0; v < mesh->points.size(); ++v) {
            Vec3 mean{};
            for (int w : nbr[v]) mean += mesh->points[w];
            mean = mean / static_cast<double>(nbr[v].size());
            next[v] = mesh->points[v] + (mean - mesh->points[v]) * step;
        }
        mesh->points.swap(next);
    }
}

// The boundary of a voxel solid given by solid(i, j, k) on [0, nx) x [0, ny) x [0, nz), voxels of
// side 1 / res (each face two triangles).
template <class Solid>
Mesh voxel_boundary(int nx, int ny, int nz, int res, const Solid& solid) {
    VoxelSurface surface(nx, ny, nz, res, static_cast<double>(nz) / res);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                if (!solid(i, j, k)) continue;
                if (!solid(i + 1, j, k)) surface.add_quad({i + 1, j, k}, kY, kZ);
                if (!solid(i - 1, j, k)) surface.add_quad({i, j, k}, kZ, kY);
                if (!solid(i, j + 1, k)) surface.add_quad({i, j + 1, k}, kZ, kX);
                if (!solid(i, j - 1, k)) surface.add_quad({i, j, k}, kX, kZ);
                if (!solid(i, j, k + 1)) surface.add_quad({i, j, k + 1}, kX, kY);
                if (!solid(i, j, k - 1)) surface.add_quad({i, j, k}, kY, kX);
            }
    return surface.take();
}

}  // namespace

Mesh icosphere(int subdivisions, double radius) {
    require_in(subdivisions, 0, 10, "icosphere", "subdivisions");
    require(std::isfinite(radius) && radius > 0,
            "icosphere: radius must be positive and finite, got " + std::to_string(radius));

    // The 12 icosahedron vertices are the cyclic permutations of (0, +-1, +-phi); its faces are
    // the triples of mutually adjacent vertices (edge length 2, the next distance is 2*phi).
    const double phi = 0.5 * (1.0 + std::sqrt(5.0));
    Mesh mesh;
    for (double a : {-1.0, 1.0})
        for (double b : {-phi, phi}) {
            mesh.points.push_back(normalized({0, a, b}));
            mesh.points.push_back(normalized({a, b, 0}));
            mesh.points.push_back(normalized({b, 0, a}));
        }
    const double edge2 = 4.0 / (1.0 + phi * phi);  // squared edge length on the unit sphere
    auto adjacent = [&](int i, int j) {
        const Vec3 d = mesh.points[i] - mesh.points[j];
        return dot(d, d) < 1.5 * edge2;
    };
    for (int i = 0; i < 12; ++i)
        for (int j = i + 1; j < 12; ++j)
            for (int k = j + 1; k < 12; ++k) {
                if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
                const Vec3 &a = mesh.points[i], &b = mesh.points[j], &c = mesh.points[k];
                // Convex and centred at the origin: outward means the normal points away from 0.
                if (dot(cross(b - a, c - a), a + b + c) > 0)
                    mesh.triangles.push_back({i, j, k});
                else
                    mesh.triangles.push_back({i, k, j});
            }
    QC_CHECK(mesh.num_triangles() == 20, "icosahedron must have 20 faces");

    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto [it, inserted] = midpoint.try_emplace(key, mesh.num_vertices());
            if (inserted) mesh.points.push_back(normalized(mesh.points[a] + mesh.points[b]));
            return it->second;
        };
        std::vector<Triangle> finer;
        finer.reserve(4 * mesh.triangles.size());
        for (const Triangle& t : mesh.triangles) {
            const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            finer.push_back({t[0], ab, ca});
            finer.push_back({t[1], bc, ab});
            finer.push_back({t[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        mesh.triangles = std::move(finer);
    }
    for (Vec3& p : mesh.points) p *= radius;
    return mesh;
}

Mesh torus(int n_major, int n_minor, double R, double r) {
    require(n_major >= 3 && n_minor >= 3, "torus: n_major and n_minor must be >= 3, got " +
                                              std::to_string(n_major) + " and " +
                                              std::to_string(n_minor));
    require(2 * static_cast<std::int64_t>(n_major) * n_minor <= kMaxTriangles,
            "torus: too many segments");
    require(std::isfinite(R) && std::isfinite(r) && r > 0 && r < R,
            "torus: radii must satisfy 0 < r < R, got R=" + std::to_string(R) +
                " r=" + std::to_string(r));

    Mesh mesh;
    mesh.points.reserve(static_cast<size_t>(n_major) * n_minor);
    for (int i = 0; i < n_major; ++i) {
        const double u = 2.0 * kPi * i / n_major;
        for (int j = 0; j < n_minor; ++j) {
            const double v = 2.0 * kPi * j / n_minor;
            const double ring = R + r * std::cos(v);
            mesh.points.push_back({ring * std::cos(u), ring * std::sin(u), r * std::sin(v)});
        }
    }
    auto id = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
    mesh.triangles.reserve(2 * static_cast<size_t>(n_major) * n_minor);
    for (int i = 0; i < n_major; ++i)
        for (int j = 0; j < n_minor; ++j) {
            // d/du x d/dv points away from the tube's core circle, i.e. outward.
            const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            mesh.triangles.push_back({a, b, c});
            mesh.triangles.push_back({a, c, d});
        }
    return mesh;
}

Mesh plate_with_holes(int genus, const PlateOptions& options) {
    require(genus >= 0, "plate_with_holes: genus must be >= 0, got " + std::to_string(genus));
    require(options.resolution >= 1, "plate_with_holes: resolution must be >= 1, got " +
                                         std::to_string(options.resolution));
    require(std::isfinite(options.thickness) && options.thickness > 0,
            "plate_with_holes: thickness must be positive and finite, got " +
                std::to_string(options.thickness));

    // Far above any test use; keeps the layout arithmetic below comfortably inside int.
    require(genus <= 1'000'000, "plate_with_holes: genus must be <= 1000000, got " +
                                    std::to_string(genus));
    const PlateLayout layout = plate_layout(genus);
    const std::int64_t res = options.resolution;
    // Kept in double until bounded: thickness * resolution may exceed any integer type.
    const double layers_real = std::max(1.0, std::round(options.thickness * options.resolution));
    const std::int64_t area_cells = static_cast<std::int64_t>(layout.width) * layout.height;
    const std::int64_t rim =
        2 * (layout.width + layout.height) + 4 * static_cast<std::int64_t>(genus);
    const double estimate = 4.0 * static_cast<double>(res * res) * static_cast<double>(area_cells) +
                            2.0 * static_cast<double>(res) * layers_real * static_cast<double>(rim);
    require(estimate <= static_cast<double>(kMaxTriangles),
            "plate_with_holes: genus/resolution/thickness give too large a mesh");
    const int layers = static_cast<int>(layers_real);

    const int nx = layout.width * options.resolution, ny = layout.height * options.resolution;
    auto solid = [&](int i, int j) {
        return i >= 0 && j >= 0 && i < nx && j < ny &&
               !is_hole_cell(layout, i / options.resolution, j / options.resolution);
    };

    // The solid is a prism over a planar region, so only the top, the bottom and the walls above
    // the region's boundary edges are needed, not a full voxel sweep.
    VoxelSurface surface(nx, ny, layers, options.resolution, options.thickness);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            if (!solid(i, j)) continue;
            surface.add_quad({i, j, layers}, kX, kY);  // top, +z
            surface.add_quad({i, j, 0}, kY, kX);       // bottom, -z
            for (int k = 0; k < layers; ++k) {
                if (!solid(i + 1, j)) surface.add_quad({i + 1, j, k}, kY, kZ);  // +x
                if (!solid(i - 1, j)) surface.add_quad({i, j, k}, kZ, kY);      // -x
                if (!solid(i, j + 1)) surface.add_quad({i, j + 1, k}, kZ, kX);  // +y
                if (!solid(i, j - 1)) surface.add_quad({i, j, k}, kX, kZ);      // -y
            }
        }
    Mesh mesh = surface.take();

    if (options.bend) {
        const PlateBend bend(layout.width, layout.height, options.thickness);
        for (Vec3& p : mesh.points) p = bend(p);
    }
    return mesh;
}

Mesh body_with_limbs(const LimbOptions& o) {
    require_in(o.limbs, 0, 32, "body_with_limbs", "limbs");
    require_in(o.fins, 0, 16, "body_with_limbs", "fins");
    require_in(o.subdivisions, 1, 8, "body_with_limbs", "subdivisions");
    require(std::isfinite(o.max_length) && o.max_length > 0, "body_with_limbs: max_length must be positive and finite");
    std::mt19937 rng(o.seed);
    // Uniform and normal numbers from the engine's raw output (its sequence is fixed by the
    // standard; the <random> distributions are not).
    auto uniform = [&] { return (rng() + 0.5) / 4294967296.0; };
    auto normal = [&] { return std::sqrt(-2 * std::log(uniform())) * std::cos(2 * 3.14159265358979323846 * uniform()); };
    struct Limb {
        Vec3 axis;
        double length, cos_width;
    };
    std::vector<Limb> limbs;
    for (int k = 0; k < o.limbs; ++k) {
        Vec3 d{normal(), normal(), normal()};
        d = d / norm(d);
        const double length = 1.0 + (o.max_length - 1.0) * uniform();
        limbs.push_back({d, length, 0.93 + 0.055 * uniform()});
    }
    // Drawn after the limbs: a figure's limbs do not depend on its fins.
    std::vector<Fin> fins;
    for (int k = 0; k < o.fins; ++k) fins.push_back(random_fin(uniform, o.max_length, 1.0));
    Mesh mesh = icosphere(o.subdivisions, 1.0);
    for (Vec3& p : mesh.points) {
        double r = 1.0 + fin_push(fins, p);
        for (const Limb& l : limbs) {
            const double c = dot(p, l.axis);
            if (c > l.cos_width) r += l.length * std::pow((c - l.cos_width) / (1 - l.cos_width), 0.6);
        }
        p = Vec3{p.x * (1 + 0.3 * p.z), p.y * 0.8, p.z * 1.3} * r;
    }
    return mesh;
}

Mesh body_with_handles(const HandleBodyOptions& o) {
    require_in(o.handles, 0, 64, "body_with_handles", "handles");
    require_in(o.body_cells, 4, 64, "body_with_handles", "body_cells");
    require_in(o.resolution, 2, 16, "body_with_handles", "resolution");
    require_in(o.smoothing, 0, 200, "body_with_handles", "smoothing");
    require_in(o.bumps, 0, 64, "body_with_handles", "bumps");
    require_in(o.fins, 0, 16, "body_with_handles", "fins");
    // Handle slots on the top face (z = body, in cells): posts at (x, y) and (x + 2, y), the bar
    // over x..x+2 one cell higher. Spread: a grid of columns 4 cells apart and rows 2 apart, in
    // the middle of the face; in a row: side by side along y at x = 1, 2 cells apart.
    const int n = o.handles;
    const int cols = o.in_a_row ? 1 : std::max(1, static_cast<int>(std::ceil(std::sqrt(double(n)))));
    const int rows = n == 0 ? 0 : (n + cols - 1) / cols;
    const int body = std::max({o.body_cells, 4 * cols + 1, 2 * rows + 1});
    std::vector<std::array<int, 2>> slots;
    for (int k = 0; k < n; ++k) {
        const int c = k % cols, r = k / cols;
        if (o.in_a_row) {
            slots.push_back({1, 1 + 2 * r});
        } else {
            // Centred: the grid spans 4 cols - 1 by 2 rows - 1 cells.
            const int x0 = (body - (4 * cols - 1)) / 2, y0 = (body - (2 * rows - 1)) / 2;
            slots.push_back({x0 + 4 * c, y0 + 2 * r});
        }
    }
    const int res = o.resolution;
    const std::int64_t estimate = 12LL * body * body * res * res + 40LL * n * res * res;
    require(estimate <= kMaxTriangles, "body_with_handles: the options give too large a mesh");
    const int nx = body * res, ny = body * res, nz = (body + 2) * res;
    std::vector<char> cell(static_cast<size_t>(body) * body * (body + 2), 0);
    auto cell_at = [&](int x, int y, int z) -> char& { return cell[(static_cast<size_t>(z) * body + y) * body + x]; };
    for (int z = 0; z < body; ++z)
        for (int y = 0; y < body; ++y)
            for (int x = 0; x < body; ++x) cell_at(x, y, z) = 1;
    for (const auto& [x, y] : slots) {
        cell_at(x, y, body) = cell_at(x + 2, y, body) = 1;
        for (int dx = 0; dx <= 2; ++dx) cell_at(x + dx, y, body + 1) = 1;
    }
    auto solid = [&](int i, int j, int k) {
        return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && cell_at(i / res, j / res, k / res);
    };
    Mesh mesh = voxel_boundary(nx, ny, nz, res, solid);
    // The cube onto a ball: each point scaled along its ray from the body's centre by
    // |q|_inf / |q|_2 (the cube's surface goes onto the inscribed sphere's radius). Injective along
    // every ray, so the surface stays embedded; the handles on the top go along, about unchanged
    // near the top's middle. The map's creases over the cube's diagonal planes are smoothed below.
    const Vec3 centre{0.5 * body, 0.5 * body, 0.5 * body};
    for (Vec3& p : mesh.points) {
        const Vec3 q = p - centre;
        const double inf = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}), two = norm(q);
        if (two > 0) p = centre + q * (inf / two);
    }
    taubin_smooth(&mesh, o.smoothing);
    if (o.bumps > 0 || o.fins > 0) {
        // Relief: each point moved along its ray from the centre by a factor 1 + a sum of Gaussian
        // bumps and dents (height 0.12..0.3 of the radius, width 0.25..0.5 radians) centred on
        // directions below the top's rim (direction z <= 0.4), faded out towards the top (nothing
        // at direction z >= 0.75), so the handles on the top stay as they are. The factor stays
        // positive, so the surface stays embedded.
        std::mt19937 rng(o.seed);
        auto uniform = [&] { return (rng() + 0.5) / 4294967296.0; };
        struct Bump {
            Vec3 dir;
            double height, width;
        };
        std::vector<Bump> bumps;
        while (static_cast<int>(bumps.size()) < o.bumps) {
            const double z = 2 * uniform() - 1, phi = 2 * 3.14159265358979323846 * uniform();
            const double r = std::sqrt(std::max(0.0, 1 - z * z));
            const double height = (0.12 + 0.18 * uniform()) * (uniform() < 0.7 ? 1 : -1);
            const double width = 0.25 + 0.25 * uniform();
            if (z <= 0.4) bumps.push_back({{r * std::cos(phi), r * std::sin(phi), z}, height, width});
        }
        // Fins round directions below the body's middle (z <= 0), drawn after the bumps (a body's
        // bumps do not depend on its fins), faded out towards the top as the bumps are.
        std::vector<Fin> fins;
        for (int k = 0; k < o.fins; ++k) fins.push_back(random_fin(uniform, 2.0, 0.0));
        for (Vec3& p : mesh.points) {
            const Vec3 q = p - centre;
            const double len = norm(q);
            if (!(len > 0)) continue;
            const Vec3 d = q / len;
            const double fade = std::clamp((0.75 - d.z) / 0.25, 0.0, 1.0);
            double factor = 1;
            for (const Bump& b : bumps) {
                const double angle = std::acos(std::clamp(dot(d, b.dir), -1.0, 1.0));
                factor += fade * b.height * std::exp(-0.5 * (angle / b.width) * (angle / b.width));
            }
            factor += fade * fin_push(fins, d);
            if (factor != 1) p = centre + q * std::max(factor, 0.3);
        }
    }
    return mesh;
}

// The chordal tolerance of a wheel's `cad` tessellation, relative to its bounding box's diagonal.
constexpr double kCadTolerance = 1e-3;

Mesh flat_faces_as_fans(const Mesh& input, double relative_tolerance) {
    Mesh mesh = input;
    const int n = mesh.num_vertices();
    Vec3 lo = n > 0 ? mesh.points[0] : Vec3{}, hi = lo;
    for (const Vec3& p : mesh.points)
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)},
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    const double tolerance = relative_tolerance * norm(hi - lo);
    std::vector<std::vector<int>> around(n);
    for (int t = 0; t < mesh.num_triangles(); ++t)
        for (int v : mesh.triangles[t]) around[v].push_back(t);
    std::vector<char> dead(mesh.triangles.size(), 0);
    auto ring_of = [&](int v) {
        std::vector<int> ring;
        for (int t : around[v])
            for (int x : mesh.triangles[t])
                if (x != v) ring.push_back(x);
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        return ring;
    };
    // Moves v onto its neighbour u if that keeps the mesh a manifold (v and u share exactly the
    // third corners of edge v-u's two triangles) and every moved triangle its orientation.
    auto collapse = [&](int v, int u, const std::vector<int>& ring, const Vec3& normal) {
        const std::vector<int> ring_u = ring_of(u);
        std::vector<int> common, opposite;
        std::set_intersection(ring.begin(), ring.end(), ring_u.begin(), ring_u.end(),
                              std::back_inserter(common));
        for (int t : around[v]) {
            const Triangle& f = mesh.triangles[t];
            if (std::find(f.begin(), f.end(), u) == f.end()) continue;
            for (int x : f)
                if (x != v && x != u) opposite.push_back(x);
        }
        std::sort(opposite.begin(), opposite.end());
        if (opposite.size() != 2 || opposite != common) return false;
        for (int t : around[v]) {
            Triangle f = mesh.triangles[t];
            if (std::find(f.begin(), f.end(), u) != f.end()) continue;
            *std::find(f.begin(), f.end(), v) = u;
            const Vec3 a = mesh.points[f[0]], b = mesh.points[f[1]], c = mesh.points[f[2]];
            const Vec3 area = cross(b - a, c - a);
            const double size = std::max({norm(b - a), norm(c - b), norm(a - c)});
            if (!(dot(area, normal) > std::max(0.87 * norm(area), 1e-12 * size * size))) return false;
        }
        for (int t : std::vector<int>(around[v])) {
            Triangle& f = mesh.triangles[t];
            if (std::find(f.begin(), f.end(), u) != f.end()) {
                dead[t] = 1;
                for (int x : f) around[x].erase(std::find(around[x].begin(), around[x].end(), t));
            } else {
                *std::find(f.begin(), f.end(), v) = u;
                around[u].push_back(t);
            }
        }
        around[v].clear();
        return true;
    };
    for (bool changed = true; changed;) {
        changed = false;
        for (int v = 0; v < n; ++v) {
            if (around[v].empty()) continue;
            Vec3 normal{0, 0, 0};
            for (int t : around[v]) {
                const Triangle& f = mesh.triangles[t];
                normal += cross(mesh.points[f[1]] - mesh.points[f[0]], mesh.points[f[2]] - mesh.points[f[0]]);
            }
            if (!(norm(normal) > 0)) continue;
            const Vec3 unit = normal * (1 / norm(normal));
            const std::vector<int> ring = ring_of(v);
            bool flat = true;
            for (int x : ring)
                flat = flat && std::abs(dot(mesh.points[x] - mesh.points[v], unit)) <= tolerance;
            if (!flat) continue;
            for (int u : ring)
                if (collapse(v, u, ring, unit)) {
                    changed = true;
                    break;
                }
        }
    }
    std::vector<int> id(n, -1);
    Mesh out;
    for (int v = 0; v < n; ++v)
        if (!around[v].empty()) id[v] = out.num_vertices(), out.points.push_back(mesh.points[v]);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        if (!dead[t])
            out.triangles.push_back(
                {id[mesh.triangles[t][0]], id[mesh.triangles[t][1]], id[mesh.triangles[t][2]]});
    return out;
}

Mesh wheel(const WheelOptions& o) {
    require_in(o.holes, 0, 64, "wheel", "holes");
    require_in(o.resolution, 2, 16, "wheel", "resolution");
    require_in(o.smoothing, 0, 200, "wheel", "smoothing");
    require_in(o.ribs, 0, 64, "wheel", "ribs");
    // In cells (the disc is one cell thick): holes of radius 1.5 on a ring with 1.5 of material
    // between neighbours, at least 6 from the axis; the axle hole of radius 1.25 in a hub of
    // radius 2.75; the rim 2.5 outside the holes.
    const double hole = 1.5, axle = 1.25, hub = 2.75;
    const double ring = std::max(6.0, o.holes * (2 * hole + 1.5) / (2 * kPi));
    const double outer = ring + hole + 2.5;
    const int res = o.resolution;
    const int n = static_cast<int>(std::ceil(2 * outer * res)) + 4;  // voxels across, with a margin
    const std::int64_t estimate = 8LL * n * n + 24LL * n * res;
    require(estimate <= kMaxTriangles, "wheel: the options give too large a mesh");
    const double centre = 0.5 * n / res;
    std::vector<Vec3> holes;
    for (int k = 0; k < o.holes; ++k) {
        const double a = 2 * kPi * (k + 0.5) / o.holes;
        holes.push_back({centre + ring * std::cos(a), centre + ring * std::sin(a), 0});
    }
    // The three layers' masks at the voxel centres: the disc; the hub and the rim's lip one cell
    // above it; the hub alone the next cell up.
    std::vector<std::vector<char>> layer(3, std::vector<char>(static_cast<size_t>(n) * n, 0));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = (i + 0.5) / res, y = (j + 0.5) / res;
            const double r = std::hypot(x - centre, y - centre);
            bool disc = r >= axle && r <= outer;
            for (const Vec3& h : holes) disc = disc && std::hypot(x - h.x, y - h.y) > hole;
            const size_t at = static_cast<size_t>(j) * n + i;
            // Ribs: radial bars 0.75 cells wide from the hub to half a cell short of the holes.
            bool rib = false;
            for (int k = 0; k < o.ribs && !rib; ++k) {
                const double a = 2 * kPi * k / o.ribs;
                const double along = (x - centre) * std::cos(a) + (y - centre) * std::sin(a);
                const double across = -(x - centre) * std::sin(a) + (y - centre) * std::cos(a);
                rib = along > 0 && r <= ring - hole - 0.5 && std::abs(across) <= 0.375;
            }
            layer[0][at] = disc;
            layer[1][at] = disc && (r <= hub || r >= outer - 1 || rib);
            layer[2][at] = disc && r <= hub;
        }
    // No two voxels of a layer may meet along an edge only (the solid would not be a manifold):
    // in every 2 x 2 block whose solids are diagonal, one empty voxel is filled, in the disc a
    // fixed one, above it one the layer below has, so every layer stays within the one below.
    // Then no two voxels meet in an edge or a corner alone anywhere.
    for (int l = 0; l < 3; ++l) {
        std::vector<char>& m = layer[l];
        auto at = [&](int i, int j) -> char& { return m[static_cast<size_t>(j) * n + i]; };
        for (bool changed = true; changed;) {
            changed = false;
            for (int j = 0; j + 1 < n; ++j)
                for (int i = 0; i + 1 < n; ++i) {
                    const bool a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
                    if (!((a && d && !b && !c) || (b && c && !a && !d))) continue;
                    // The block's two empty voxels: b and c when a and d are solid, else a and d.
                    const int first_i = a ? i + 1 : i, second_i = a ? i : i + 1;
                    const bool first = l == 0 || layer[l - 1][static_cast<size_t>(j) * n + first_i];
                    if (first) at(first_i, j) = 1;
                    else at(second_i, j + 1) = 1;
                    changed = true;
                }
        }
    }
    auto solid = [&](int i, int j, int k) {
        return i >= 0 && j >= 0 && k >= 0 && i < n && j < n && k < 3 * res &&
               layer[k / res][static_cast<size_t>(j) * n + i] != 0;
    };
    Mesh mesh = voxel_boundary(n, n, 3 * res, res, solid);
    taubin_smooth(&mesh, o.smoothing);
    if (o.cad) mesh = flat_faces_as_fans(mesh, kCadTolerance);
    // The holes are wide against the voxels and every layer is well joined, so the genus is the
    // axle's handle and one per hole.
    const std::int64_t chi = std::int64_t{mesh.num_vertices()} - 3 * std::int64_t{mesh.num_triangles()} / 2 +
                             mesh.num_triangles();
    QC_CHECK(chi == 2 - 2 * (o.holes + 1), "wheel: the voxel solid does not have genus holes + 1");
    return mesh;
}

}  // namespace quadcage::shapes

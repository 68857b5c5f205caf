#pragma once
// Deterministic sampling of triangle meshes (private to src/fit).

#include <array>
#include <cstdint>
#include <vector>

#include "quadcage/core/mesh.h"

namespace quadcage::fit::detail {

/// SplitMix64: a small generator whose stream is fixed by its seed on every platform (std::
/// distributions are not), so samples, and therefore reported errors, are reproducible.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

private:
    std::uint64_t state_;
};

/// A point on a triangle of a mesh.
struct MeshSample {
    int triangle = -1;
    std::array<double, 3> bary{};
    Vec3 point;
};

/// `count` points uniformly distributed by area (triangle by cumulative area, then a uniform point
/// in it), on `threads` threads (0: all cores); the samples do not depend on the thread count.
/// \pre the mesh has a triangle with positive area.
std::vector<MeshSample> sample_by_area(const Mesh& mesh, int count, std::uint64_t seed, int threads = 1);

/// One sample per used vertex (in vertex order), on the first triangle that uses it.
std::vector<MeshSample> sample_vertices(const Mesh& mesh);

}  // namespace quadcage::fit::detail

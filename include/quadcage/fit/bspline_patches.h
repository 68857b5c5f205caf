#pragma once
// The fitted limit surface as one bicubic tensor-product B-spline patch per cage quad, as plain data
// (issue 22; design.md §5 "CAD export"). No OpenCASCADE here: quadcage::cad turns these into a
// STEP/IGES solid, and any other CAD exporter can take them as they are.

#include <array>
#include <string>
#include <vector>

#include "quadcage/core/mesh.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit {

/// Options for bspline_patches().
struct BSplinePatchOptions {
    /// Largest deviation allowed between a patch and the limit surface, relative to `diagonal`.
    /// Only the innermost corner cells at extraordinary corners are approximated; everywhere else
    /// the patches are the limit surface to rounding. In [1e-9, 1).
    double tolerance = 1e-5;
    /// Length `tolerance` is relative to (the input mesh's bounding-box diagonal, as report.json's
    /// "diagonal"); 0: the bounding-box diagonal of the fitted control points. >= 0.
    double diagonal = 0;
    /// Most geometric knot refinements toward an extraordinary corner, 1..12.
    int max_depth = 10;
    /// The fit's FitOptions::irregular_level (OpenSubdiv's approximation level, 1..10): the limit
    /// surface is a polynomial on every cell of the refined grid down to this depth; the corner
    /// square of that depth is OpenSubdiv's Gregory patch, which the cells inside it approximate.
    int polynomial_depth = 6;
    /// Deviation samples per cell side (the innermost corner cells get 4x as many per side), >= 1.
    int samples_per_cell = 4;
    /// Normal-jump samples per cell along every shared patch side, >= 1.
    int edge_samples_per_cell = 4;
    int threads = 0;               ///< 0 = all cores.
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// One bicubic B-spline patch: a grid of n x n control points over the knot vector of its
/// BSplinePatches (the same in u and v). (u, v) = (0,0), (1,0), (1,1), (0,1) are the patch's
/// corners 0..3, counter-clockwise seen from outside (du x dv points outward), as in the cage.
struct BSplinePatch {
    int n = 0;                 ///< Control points per direction.
    std::vector<Vec3> points;  ///< points[i + n * j]: i along u, j along v.
    /// Whether corner k (as above) is an extraordinary vertex (valence != 4) of the surface.
    std::array<bool, 4> extraordinary{};
    const Vec3& at(int i, int j) const { return points[static_cast<size_t>(i) + static_cast<size_t>(n) * j]; }
    Vec3& at(int i, int j) { return points[static_cast<size_t>(i) + static_cast<size_t>(n) * j]; }
};

/// Two patch sides that meet: side k of a patch runs from its corner k to corner k+1 (side 0 is
/// v = 0, 1 is u = 1, 2 is v = 1, 3 is u = 0); the two sides run in opposite directions, so the point
/// at fraction t along side[0] of patch[0] is the point at 1 - t along side[1] of patch[1]. Their
/// control-point rows are identical (reversed), so the shell is watertight by construction.
struct PatchEdge {
    std::array<int, 2> patch{};
    std::array<int, 2> side{};
};

/// What bspline_patches() measured by sampling, in the units of the surface.
struct PatchMeasurement {
    double max_deviation = 0;          ///< Max distance patch -> limit surface at the same (patch, u, v).
    double max_deviation_regular = 0;  ///< ... in the cells where the limit surface is polynomial.
    double max_deviation_corner = 0;   ///< ... in the corner cells (the innermost cell at an
                                       ///< extraordinary corner, and every cell inside the corner
                                       ///< square of BSplinePatchOptions::polynomial_depth).
    double max_normal_jump_regular_deg = 0;  ///< Across shared sides, away from extraordinary corners.
    double max_normal_jump_corner_deg = 0;   ///< Across shared sides, along corner cells.
    /// Largest disagreement between two cells that determine the same control point (rounding only
    /// when the limit surface is polynomial where the construction assumes it).
    double exactness = 0;
    long long samples = 0;  ///< Deviation samples taken.
};

/// The patches of a fitted surface.
struct BSplinePatches {
    int degree = 3;  ///< In u and in v.
    /// Clamped knot vector (multiplicity degree+1 at 0 and 1, simple inside), the same for u and v
    /// and for every patch: uniform with spacing 2^-K at fit level K over a cage quad, plus knots at
    /// h*2^-d and 1 - h*2^-d (h = that spacing, d = 1..depth) toward the corners. n = knots - 4.
    std::vector<double> knots;
    std::vector<BSplinePatch>
        patches;  ///< One per level-0 cage quad (per level-1 quad of a cage with other faces).
    std::vector<PatchEdge> edges;  ///< Every shared side once.
    int depth = 0;                 ///< Geometric refinements toward the corners (0: no extraordinary corner).
    bool exact_everywhere = false;  ///< No extraordinary corner: the patches are the limit surface.
    double diagonal = 0;            ///< The length tolerances are relative to.
    double tolerance = 0;           ///< Absolute tolerance (BSplinePatchOptions::tolerance * diagonal).
    bool tolerance_met = false;     ///< measurement.max_deviation <= tolerance.
    PatchMeasurement measurement;
    std::string message;  ///< One line: depth, deviation, and why it stopped.
};

/// Position and first derivatives of a patch.
struct PatchPoint {
    Vec3 position, du, dv;
};

/// Evaluates patch `p` of `patches` at (u, v) in [0,1]^2 (clamped).
/// \throw InvalidInput if p is out of range.
PatchPoint evaluate_patch(const BSplinePatches& patches, int p, double u, double v);

/// The fitted limit surface as bicubic B-spline patches, one per level-0 cage quad (one per quad of
/// the cage refined once when the cage has other faces). Where the limit surface is a polynomial
/// (every cell of the refined knot grid down to polynomial_depth but the innermost one at an
/// extraordinary corner, as OpenSubdiv's Bfr represents it) the control points are recovered
/// exactly from 4x4 samples of the limit surface per cell; control points that only cells inside
/// Bfr's corner (Gregory) patch touch are the average of those cells' 4x4 interpolants, and the
/// innermost cell is the C2 continuation of its neighbours through the corner's limit point. The
/// depth grows from 1 until the deviation sampled in the corner cells is <= the tolerance or
/// max_depth is reached: a tolerance not met is reported
/// (tolerance_met, message), not thrown. A surface without extraordinary corners (genus 1) is exact
/// with uniform knots.
/// \throw InvalidInput if the options are invalid or the surface is empty.
BSplinePatches bspline_patches(const FittedSurface& surface, const BSplinePatchOptions& options = {});

/// Measures `patches` against `surface` (deviation by dense sampling, normal jumps across shared
/// sides); bspline_patches() already does this and stores the result.
/// \throw InvalidInput if the surface is empty or the patch count disagrees.
PatchMeasurement measure_patches(const FittedSurface& surface, const BSplinePatches& patches,
                                 const BSplinePatchOptions& options = {});

}  // namespace quadcage::fit

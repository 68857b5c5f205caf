#pragma once
// Closed test surfaces of known genus, used by the tests, the benchmarks and `quadcage generate`.
//
// Every mesh returned here is closed, edge- and vertex-manifold, consistently oriented with outward
// normals (positive signed volume), connected, free of degenerate triangles, and has no duplicate
// or unused vertices. All functions throw quadcage::InvalidInput for arguments outside their
// preconditions (including outputs too large to index with int).

#include "quadcage/core/mesh.h"

namespace quadcage::shapes {

/// Icosphere of radius `radius` centred at the origin: 20*4^subdivisions triangles,
/// 10*4^subdivisions + 2 vertices, all on the sphere; genus 0.
/// \pre 0 <= subdivisions <= 10, radius > 0 (finite).
Mesh icosphere(int subdivisions, double radius = 1.0);

/// Torus around the z axis (major radius R, minor radius r), `n_major` x `n_minor` quads split into
/// 2*n_major*n_minor triangles (n_major*n_minor vertices): genus 1. Vertex (i, j) sits at major
/// angle 2*pi*i/n_major and minor angle 2*pi*j/n_minor, index i*n_minor + j.
/// \pre n_major >= 3, n_minor >= 3, 0 < r < R (finite).
Mesh torus(int n_major, int n_minor, double R = 1.0, double r = 0.35);

/// Options for plate_with_holes().
struct PlateOptions {
    int resolution = 2;      ///< Sub-cells per coarse-grid unit along x and y (>= 1); more = finer.
    double thickness = 0.6;  ///< Plate thickness t in coarse-grid units (> 0, finite).
    bool bend = true;        ///< Bend the plate gently onto an arc so it is not axis-aligned.
};

/// A thickened plate with `genus` square holes: a mesh of genus exactly `genus` (a box for 0).
///
/// Layout before bending (coarse-grid units), for g = genus:
///  - cols = ceil(sqrt(g)) and rows = ceil(g / cols) (both 0 when g = 0);
///  - the plate is the box [0, W] x [0, H] x [0, t] with W = 2*cols + 1, H = 2*rows + 1 and
///    t = options.thickness (g = 0: the box [0,1] x [0,1] x [0,t]);
///  - hole k (0 <= k < g) lies in column c = k % cols and row r = k / cols and removes the prism
///    [2c+1, 2c+2] x [2r+1, 2r+2] x [0, t]. Holes are therefore unit squares, 1 apart and 1 from
///    the rim; only the last row may have empty slots (when cols does not divide g), which stay
///    solid (e.g. g = 3: cols = rows = 2, the slot [3,4] x [3,4] is solid).
///
/// Tight cycles, before bending: each hole is bordered by solid bars of width 1 (cross-section
/// 1 x t) on its left (x in [2c, 2c+1]) and below (y in [2r, 2r+1]), and also on its right and
/// above unless the neighbouring slot in the last row is empty. The shortest cycle going once
/// around such a bar (e.g. around the material between a hole and the rim) is the boundary of the
/// bar's cross-section, of length exactly 2*(1 + t); the shortest cycle going once around a hole
/// (along its wall) has length exactly 4 (so for t < 1 the bar cycles are the shorter). Both are
/// edge paths of the mesh at any resolution: e.g. the cross-section of the bar below hole k in the
/// plane x = 2c+1 (or in any plane x = m/res with 2c+1 <= m/res <= 2c+2), and the rim of hole k
/// at z = 0.
///
/// Mesh: every unit cell is split into resolution x resolution sub-cells and the thickness into
/// L = max(1, round(t * resolution)) layers; the output is the boundary of that voxel solid, each
/// boundary quad split into 2 triangles with the diagonal alternating in a checkerboard. Number of
/// triangles: 4*res^2*(W*H - g) on the top and bottom plus 2*res*L*(2*(W + H) + 4*g) on the walls
/// (1744 for genus 20 with the default options).
///
/// With `bend`, the points of the bend=false mesh (same vertex and triangle order) are moved by a
/// smooth, injective, orientation-preserving map: small shears y += 0.1*sin(pi*x/W) and
/// z += 0.05*sin(2*pi*x/W)*cos(pi*y/H), then a bend of the plate along x onto a circular arc
/// around an axis parallel to y below the plate, keeping the line x = W/2, z = t/2 fixed. The
/// mid-surface z = t/2 goes onto radius rho = max(3*W/pi, t + 1) with its lengths kept (total
/// angle W/rho <= 60 degrees); lengths along x on the top and bottom faces scale by about
/// 1 + t/(2*rho) and 1 - t/(2*rho). Hence:
///  - a bar cycle keeps its length to within 1% of 2*(1 + t) (checked by the tests): the bottom
///    side of a cross-section shrinks as much as the top side grows;
///  - a hole cycle on the top (bottom) face gets longer (shorter) by about t/rho (5% for genus 1
///    with t = 0.6).
/// Use bend=false where exact lengths or bounding boxes matter.
///
/// \pre 0 <= genus <= 1000000, options.resolution >= 1, options.thickness > 0 (finite), and at
///      most 1e8 triangles.
Mesh plate_with_holes(int genus, const PlateOptions& options = {});

/// Options for body_with_limbs().
struct LimbOptions {
    int limbs = 4;            ///< Protrusions, 0..32.
    int subdivisions = 4;     ///< Of the icosphere it is made from (20 * 4^s triangles), 1..8.
    unsigned seed = 1;        ///< Chooses the limbs' directions, lengths and widths.
    double max_length = 4.0;  ///< Longest possible limb, in body radii (> 0, finite).
    int fins = 0;             ///< Thin, flat protrusions besides the limbs, 0..16 (the same
                              ///< seed draws the same limbs whatever the fins).
};

/// A genus-0 figure with limbs, the shape class of cartoon characters and animals: an icosphere
/// squashed into an uneven ellipsoid (x by 1 + 0.3 z, y by 0.8, z by 1.3) whose points within a
/// cone around each of `limbs` random directions are pushed out radially, by up to 1..max_length
/// body radii at the cone's axis (cone half-angles 10-21 degrees). With `fins`, as many fins too:
/// round a random direction, points pushed out the same way within 17-29 degrees of it one way and,
/// falling smoothly, within 1/4 to 2/5 of that the other: a flat protrusion a few degrees thick.
/// Every direction and size comes from a std::mt19937 seeded with `seed` (the same figure
/// everywhere). Closed, manifold, genus 0.
/// \throw InvalidInput if the options are out of range.
Mesh body_with_limbs(const LimbOptions& options = {});

/// Options for body_with_handles().
struct HandleBodyOptions {
    int handles = 2;          ///< Handles, i.e. the genus, 0..64.
    bool in_a_row = false;    ///< false: spread over the body's top; true: side by side along one
                              ///< edge of it, the genus concentrated in one region.
    int body_cells = 8;       ///< Side of the body in cells (a handle's bar is 1 cell thick): about
                              ///< how many times larger than a handle the body is, 4..64. Raised
                              ///< where the handles need more room.
    int resolution = 3;       ///< Voxels per cell, 2..16.
    int smoothing = 12;       ///< Taubin smoothing passes (lambda 0.5, mu -0.53) that round the voxels, 0..200.
    int bumps = 0;            ///< Smooth bumps and dents on the body away from its top, 0..64: a body
                              ///< with detail of its own (a figure's head, limbs), not a plain ball.
    int fins = 0;             ///< Thin, flat protrusions (fins) on the body below its middle, 0..16,
                              ///< 1 to 2 body radii long: a creature with fins and handles.
    unsigned seed = 1;        ///< With bumps or fins: chooses their places, sizes and signs.
};

/// A big smooth body with small handles, the shape class whose minimal layouts crowd their corners
/// around the handles (issue 20): a cube of body_cells^3 unit cells with `handles` small loops on
/// its top face, voxelised at `resolution` voxels a cell, mapped onto a ball (each point along its
/// ray from the centre, by |q|_inf / |q|_2) and smoothed. Each handle is two 1-cell
/// posts two cells apart joined by a 1-cell bar on top, so its hole is one cell wide and high; two
/// handles are at least one cell apart, so no two voxels touch along an edge or a corner alone.
/// The voxel solid's boundary (each voxel face 2 triangles) is closed, manifold and of genus
/// `handles`; the map (injective along each ray) and Taubin smoothing move the points only, and so
/// do the bumps and the fins (as body_with_limbs()' fins, round directions below the middle), each
/// point along its ray from the centre, away from the top. Deterministic.
/// \throw InvalidInput if the options are out of range or the mesh would pass 1e8 triangles.
Mesh body_with_handles(const HandleBodyOptions& options = {});

/// The surface tessellated again as a CAD system exports a solid to a chordal tolerance: every
/// vertex whose neighbours all lie within relative_tolerance (of the bounding box's diagonal) of
/// the plane through it normal to its fan is removed, over passes, where a collapse into a
/// neighbour keeps the mesh a manifold and every moved triangle within 30 degrees of that normal.
/// Flat and nearly flat faces become fans of long, thin triangles between the vertices of their
/// borders (input_wheel's back face); curved parts keep their vertices. The genus is kept.
Mesh flat_faces_as_fans(const Mesh& mesh, double relative_tolerance);

/// Options for wheel().
struct WheelOptions {
    int holes = 6;        ///< Holes in a ring round the axle, 0..64: the genus is holes + 1.
    int resolution = 3;   ///< Voxels per cell (a cell is the disc's thickness), 2..16.
    int smoothing = 12;   ///< Taubin smoothing passes that round the voxels, 0..200.
    int ribs = 0;         ///< Radial ribs one cell high from the hub towards the holes, 0..64.
    bool cad = false;     ///< Tessellated as a CAD export (flat_faces_as_fans(), tolerance 1e-3).
};

/// A wheel, the shape class of input_wheel (issue 20): a disc one cell thick with an axle hole
/// through a hub that stands two cells proud on one side, `holes` round holes on a ring between the
/// hub and the rim, a lip one cell high round the rim on the hub's side, and optionally `ribs`
/// radial ribs one cell high from the hub towards the ring (input_wheel's fins). Its genus, holes +
/// 1, lies round a ring with one handle in the middle; input_wheel's minimal layout crowds its
/// curves round the hub. Hole radius 1.5 cells, 1.5 cells of material between two, the ring at
/// least 6 cells from the axis (further for many holes), the rim 2.5 cells outside it. Voxelised at
/// `resolution` voxels a cell (no two voxels meet in an edge or a corner alone) and smoothed.
/// Closed, manifold, deterministic.
/// \throw InvalidInput if the options are out of range or the mesh would pass 1e8 triangles.
Mesh wheel(const WheelOptions& options = {});

}  // namespace quadcage::shapes

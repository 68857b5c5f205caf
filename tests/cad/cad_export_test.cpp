#include "quadcage/cad/cad_export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"
#include "quadcage/fit/bspline_patches.h"
#include "quadcage/fit/fit.h"
#include "quadcage/subdiv/cage.h"
#include "support/files.h"

namespace quadcage::cad {
namespace {

namespace fs = std::filesystem;

// A real fit (layout + Ceres), kept small: these tests are about the export.
struct Case {
    fit::CageFit fit;
    double diagonal = 0;
    int genus = 0;
};

const Case& fitted(const std::string& name, int level) {
    static std::map<std::string, std::unique_ptr<Case>> cache;
    const std::string key = name + "@" + std::to_string(level);
    auto& slot = cache[key];
    if (slot) return *slot;
    Mesh mesh;
    int genus = 0;
    if (name == "icosphere")
        mesh = shapes::icosphere(3), genus = 0;
    else if (name == "torus")
        mesh = shapes::torus(32, 16), genus = 1;
    else if (name == "plate3")
        mesh = shapes::plate_with_holes(3), genus = 3;
    else
        mesh = read_mesh(std::string(QUADCAGE_DATA_DIR) + "/eight.off"), genus = 2;
    fit::FitOptions o;
    o.level = level;
    o.area_samples = 3000;
    o.error_samples = 5000;
    o.outer_iterations = 4;
    o.extra_rounds = 0;  // a quick fit: the export is what these test
    slot = std::make_unique<Case>();
    slot->fit = fit::fit_cage(mesh, {}, o);
    slot->diagonal = slot->fit.fit.levels.back().diagonal;
    slot->genus = genus;
    return *slot;
}

// Area and enclosed volume of a closed triangle mesh.
std::pair<double, double> area_volume(const Mesh& m) {
    double a = 0, v = 0;
    for (const auto& t : m.triangles) {
        const Vec3 &p = m.points[t[0]], &q = m.points[t[1]], &r = m.points[t[2]];
        a += 0.5 * norm(cross(q - p, r - p));
        v += dot(p, cross(q, r)) / 6;
    }
    return {a, v};
}

// Area and volume of the limit surface: fine tessellations, Richardson-extrapolated (error ~ n^-2).
std::pair<double, double> limit_area_volume(const fit::FittedSurface& s, int n) {
    const auto [a1, v1] = area_volume(s.limit().tessellate(n).mesh);
    const auto [a2, v2] = area_volume(s.limit().tessellate(2 * n).mesh);
    return {(4 * a2 - a1) / 3, (4 * v2 - v1) / 3};
}

// The largest distance from the read-back samples (a (grid + 1)^2 grid per face, u outer) to the
// limit surface. fit::distances_to_surface() starts each projection at the closest point of a
// tessellation, and where the fitted surface passes close to itself that point can lie on the other
// sheet, where the projection stops at a local minimum: the genus-3 plate fitted at level 1 has two
// sheets 1.6e-4 apart at a hole's rim (normals 147 deg apart), and a sample there measured 5.4e-4
// against a true 1e-14. So each sample is also projected from its own patch's point (the file's
// face k is patch k of bspline_patches(), at the same (u, v)). Every point reached lies on the
// surface, so the smaller distance still bounds the true one from above: no sample can pass that
// lies off the surface.
double worst_distance_to_surface(const fit::FittedSurface& surface, const ReadBack& back, int grid) {
    std::vector<Vec3> points;
    for (const auto& f : back.samples) points.insert(points.end(), f.begin(), f.end());
    const std::vector<double> projected = fit::distances_to_surface(surface, points);
    const int lc = std::max(surface.level(), 1);
    const int levels = surface.cage_quads() > 0 ? lc : lc - 1;  // as bspline_patches() descends
    const int per_face = (grid + 1) * (grid + 1);
    double worst = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const int face = static_cast<int>(i) / per_face, k = static_cast<int>(i) % per_face;
        const subdiv::FacePoint start =
            subdiv::descend({face, double(k / (grid + 1)) / grid, double(k % (grid + 1)) / grid}, levels);
        const double own = std::sqrt(surface.limit().project_with_distance(points[i], start).distance2);
        worst = std::max(worst, std::min(projected[i], own));
    }
    return worst;
}

void check_export(const std::string& name, int level, int faces) {
    const Case& c = fitted(name, level);
    const fit::FittedSurface& surface = c.fit.fit.surface;
    fit::BSplinePatchOptions po;
    po.diagonal = c.diagonal;
    const fit::BSplinePatches patches = fit::bspline_patches(surface, po);
    const double T = 1e-5 * c.diagonal;
    SCOPED_TRACE(name + " level " + std::to_string(level) + ": " + patches.message);
    const Solid solid = make_solid(patches);
    const SolidReport& r = solid.report();
    std::printf("%s level %d: %s\n  %s\n", name.c_str(), level, patches.message.c_str(),
                r.to_json(-1).c_str());
    EXPECT_TRUE(patches.tolerance_met);
    EXPECT_EQ(r.faces, faces);
    EXPECT_EQ(r.edges, 2 * faces);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.valid);
    EXPECT_LE(r.sewing_tolerance, T);
    EXPECT_LE(r.max_tolerance, T);
    EXPECT_LE(r.max_deviation, T);
    EXPECT_LE(r.max_deviation_regular, 1e-10 * c.diagonal);  // "to rounding"
    EXPECT_LE(r.max_normal_jump_regular_deg, 0.01);
    EXPECT_LE(r.max_normal_jump_corner_deg, 1.0);
    if (c.genus == 1) {
        EXPECT_TRUE(patches.exact_everywhere);
        EXPECT_LE(r.max_deviation, 1e-10 * c.diagonal);
    }

    const fs::path dir = test::scratch_dir("cad_" + name);
    const std::string step = (dir / "surface.step").string();
    write_step(solid, step);
    const int grid = 6;  // grid + 1 samples along each side of a face
    const ReadBack back = read_back(step, grid);
    EXPECT_EQ(back.solids, 1);
    EXPECT_EQ(back.faces, faces);
    EXPECT_EQ(back.free_edges, 0);
    EXPECT_TRUE(back.closed);
    EXPECT_TRUE(back.valid);
    // Points of the file's faces lie on the limit surface (within T).
    const double worst = worst_distance_to_surface(surface, back, grid);
    std::printf(
        "  read back: %d solid(s), %d faces, %d free edges, valid %d; %zu points, max distance %.3g (%.3g of "
        "the diagonal)\n",
        back.solids, back.faces, back.free_edges, back.valid, back.samples.size() * (grid + 1) * (grid + 1),
        worst, worst / c.diagonal);
    EXPECT_LE(worst, T);
    // Area and volume against the limit surface's tessellation.
    const auto [area, volume] = limit_area_volume(surface, std::max(2, 32 >> std::max(level, 1)));
    std::printf("  area %.9g vs tessellation %.9g (%.2g), volume %.9g vs %.9g (%.2g)\n", back.area, area,
                std::abs(back.area / area - 1), back.volume, volume, std::abs(back.volume / volume - 1));
    EXPECT_NEAR(back.area / area, 1.0, 1e-4);
    EXPECT_NEAR(back.volume / volume, 1.0, 1e-4);
    EXPECT_NEAR(r.volume / back.volume, 1.0, 1e-9);
    fs::remove_all(dir);
}

TEST(CadExport, IcosphereIsOneValidSolidOfSixFaces) {
    check_export("icosphere", 2, 6);
}
TEST(CadExport, TorusIsOneValidSolidOfFourFacesExactEverywhere) {
    check_export("torus", 2, 4);
}
TEST(CadExport, EightIsOneValidSolidOfTenFaces) {
    check_export("eight", 2, 10);
}
TEST(CadExport, GenusThreePlateIsOneValidSolidOfTwentyFaces) {
    check_export("plate3", 1, 20);
}

TEST(CadExport, EightAtLevelThreeRoundTripsThroughIges) {
    const Case& c = fitted("eight", 3);
    fit::BSplinePatchOptions po;
    po.diagonal = c.diagonal;
    const fit::BSplinePatches patches = fit::bspline_patches(c.fit.fit.surface, po);
    const Solid solid = make_solid(patches);
    const fs::path dir = test::scratch_dir("cad_iges");
    const std::string iges = (dir / "surface.igs").string();
    write_iges(solid, iges);
    const ReadBack back = read_back(iges, 4, 1e-5 * c.diagonal);
    std::printf(
        "eight level 3 IGES: %d solid(s), %d shells, %d faces, %d free edges, valid %d, volume %.9g vs "
        "%.9g\n",
        back.solids, back.shells, back.faces, back.free_edges, back.valid, back.volume,
        solid.report().volume);
    EXPECT_EQ(back.faces, 10);
    EXPECT_EQ(back.free_edges, 0);
    EXPECT_TRUE(back.closed);
    EXPECT_TRUE(back.valid);
    EXPECT_NEAR(back.volume / solid.report().volume, 1.0, 1e-6);
    EXPECT_LE(worst_distance_to_surface(c.fit.fit.surface, back, 4), 1e-5 * c.diagonal);
    fs::remove_all(dir);
}

TEST(CadExport, ReadBackRejectsWhatIsNotStepOrIges) {
    const fs::path dir = test::scratch_dir("cad_bad");
    write_text_file((dir / "x.step").string(), "not a step file\n");
    EXPECT_THROW(read_back((dir / "x.step").string()), InvalidInput);
    EXPECT_THROW(read_back((dir / "x.obj").string()), InvalidInput);
    EXPECT_THROW(make_solid(fit::BSplinePatches{}), InvalidInput);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace quadcage::cad

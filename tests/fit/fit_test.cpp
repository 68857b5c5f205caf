#include "quadcage/fit/fit.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <utility>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"
#include "quadcage/fit/outputs.h"
#include "quadcage/layout/quad_layout.h"
#include "support/files.h"
#include "support/fit_layouts.h"
#include "support/names.h"

namespace quadcage::fit {
namespace {

namespace fs = std::filesystem;

// Small and fast: a few thousand data points, 20k error samples.
FitOptions fast_options() {
    FitOptions o;
    o.area_samples = 3000;
    o.error_samples = 20000;
    o.measure_unfitted = true;
    return o;
}

// fast_options() at level 3, without the unfitted measurement.
FitOptions level3_options() {
    FitOptions o = fast_options();
    o.measure_unfitted = false;
    o.mode = FitMode::Level;
    o.level = 3;
    return o;
}

FitResult fit_level(const layout::QuadLayout& layout, int level) {
    FitOptions o = fast_options();
    o.mode = FitMode::Level;
    o.level = level;
    return fit_surface(layout, o);
}

std::string describe(const LevelReport& l) {
    std::ostringstream s;
    s << "level " << l.level << ": relative rms " << l.relative.rms << ", hausdorff " << l.relative.hausdorff
      << ", unfitted rms " << l.unfitted_relative_rms << ", " << l.iterations << " rounds (" << l.stop_reason << ")";
    return s.str();
}

// Fits level 0, then up to max_level (level mode fits levels 1, 2, ... in turn), and checks the
// issue's requirements: errors do not increase with level, the fit beats the unfitted surface 3x at
// every level, and the accuracy level. A fit to a lower level ends with the same fit as that level
// here: what `quadcage fit --level K` gives for each K.
void check_levels(const layout::QuadLayout& layout, int max_level, int accuracy_level) {
    const FitResult r0 = fit_level(layout, 0), r = fit_level(layout, max_level);
    ASSERT_EQ(r0.levels.size(), 1u);
    ASSERT_EQ(r.levels.size(), static_cast<size_t>(max_level));
    EXPECT_EQ(r.surface.level(), max_level);
    std::vector<LevelReport> reports{r0.levels[0]};
    reports.insert(reports.end(), r.levels.begin(), r.levels.end());
    for (int level = 0; level <= max_level; ++level) {
        const LevelReport& l = reports[level];
        std::cout << "  " << describe(l) << "\n";
        EXPECT_EQ(l.level, level);
        EXPECT_GT(l.unfitted_relative_rms, 0);
        EXPECT_LE(l.relative.rms, l.unfitted_relative_rms / 3) << describe(l);
        EXPECT_NEAR(l.relative.rms * l.diagonal, l.absolute.rms, 1e-12 * l.diagonal);
        EXPECT_GE(l.relative.hausdorff, l.relative.rms);
        if (level > 0) {
            // A level that kept the previous fit refined has the previous level's surface, measured
            // again at its own search level: its figures may differ from the previous level's by
            // rounding (the torus's Hausdorff distance at level 4: 4e-13 relative above level 3's on
            // one machine, the same point's distance), so they are compared to within 1e-9 there.
            const bool same_surface = l.stop_reason.find("kept the refined previous fit") != std::string::npos;
            const double slack = same_surface ? 1 + 1e-9 : 1;
            EXPECT_LE(l.relative.rms, slack * reports[level - 1].relative.rms) << describe(l);
            EXPECT_LE(l.relative.hausdorff, slack * reports[level - 1].relative.hausdorff) << describe(l);
        }
    }
    EXPECT_LE(reports[accuracy_level].relative.rms, 2e-3);
    EXPECT_LE(reports[accuracy_level].relative.hausdorff, 2e-2);
    const FitResult lower = fit_level(layout, max_level - 1);
    ASSERT_EQ(lower.levels.size(), static_cast<size_t>(max_level - 1));
    EXPECT_EQ(lower.levels.back().relative.rms, reports[max_level - 1].relative.rms);
    EXPECT_EQ(lower.levels.back().relative.hausdorff, reports[max_level - 1].relative.hausdorff);
}

TEST(FitSurface, TorusErrorsFallWithLevelAndBeatTheUnfittedSurface) {
    // Genus 1: the issue asks for its accuracy at level 4.
    // 8192 vertices: much finer than the 1024 control points of level 4, so the fit is not at the
    // resolution of the input yet (on a 64 x 32 torus levels 2-4 all sit at its facets' ~2e-4 and
    // their order is noise).
    check_levels(test::torus_layout(128, 64), 4, 4);
}

TEST(FitSurface, SphereErrorsFallWithLevelAndBeatTheUnfittedSurface) {
    check_levels(test::cube_sphere_layout(12), 3, 3);
}

TEST(FitSurface, ControlPointCountsFollowTheLevel) {
    const layout::QuadLayout layout = test::cube_sphere_layout(6);
    // Level 0: the 8 cube corners; level 1: V + E + F = 8 + 12 + 6; level 2: 26 + 48 + 24.
    const int expected[] = {8, 26, 98};
    for (int level = 0; level <= 2; ++level) {
        const FitResult r = fit_level(layout, level);
        ASSERT_EQ(r.levels.size(), static_cast<size_t>(std::max(level, 1)));
        EXPECT_EQ(r.levels.back().control_points, expected[level]);
        EXPECT_EQ(r.surface.level(), level);
        EXPECT_EQ(r.surface.control_mesh().num_quads(), 6 << (2 * std::max(level, 1)));
    }
}

TEST(FitSurface, LevelZeroCornersRefineToTheFittedControlMesh) {
    const layout::QuadLayout layout = test::torus_layout(16, 8);
    const FitResult r = fit_level(layout, 0);
    ASSERT_EQ(r.fitted_corners.size(), 4u);
    subdiv::Cage cage = layout.cage;
    cage.points = r.fitted_corners;
    const subdiv::QuadMesh level1 = subdiv::refine_cage(cage).level1;
    ASSERT_EQ(level1.points.size(), r.surface.control_mesh().points.size());
    for (size_t i = 0; i < level1.points.size(); ++i)
        EXPECT_LT(norm(level1.points[i] - r.surface.control_mesh().points[i]), 1e-12);
    // The corners moved: the level-0 fit is not the parametric start.
    double moved = 0;
    for (int c = 0; c < 4; ++c) moved = std::max(moved, norm(r.fitted_corners[c] - layout.cage.points[c]));
    EXPECT_GT(moved, 1e-3);
}

TEST(FitSurface, ToleranceModeStopsAtTheFirstLevelThatMeetsIt) {
    const layout::QuadLayout layout = test::cube_sphere_layout(12);
    FitOptions o = fast_options();
    o.mode = FitMode::Tolerance;
    o.tolerance = 5e-4;
    const FitResult r = fit_surface(layout, o);
    ASSERT_TRUE(r.tolerance_met) << r.message;
    ASSERT_GE(r.levels.size(), 2u) << "level 0 of a cube cannot be that close to a sphere";
    EXPECT_LE(r.levels.back().relative.rms, 5e-4);
    for (size_t i = 0; i + 1 < r.levels.size(); ++i) {
        EXPECT_EQ(r.levels[i].level, static_cast<int>(i));
        EXPECT_GT(r.levels[i].relative.rms, 5e-4);
        EXPECT_LE(r.levels[i + 1].relative.rms, r.levels[i].relative.rms);
    }
    EXPECT_EQ(r.surface.level(), r.levels.back().level);
    EXPECT_NE(r.message.find("met at level " + std::to_string(r.levels.back().level)), std::string::npos) << r.message;
}

TEST(FitSurface, ToleranceModeReportsAnUnreachableTolerance) {
    // No surface meets 1e-9 on a faceted torus of 288 vertices. The search ends either at
    // max_level or, when a level measures worse than the one before even from the refined previous
    // fit (the fit has reached the input's resolution), at that level; either way the report says
    // which and keeps the best level.
    const layout::QuadLayout layout = test::torus_layout(24, 12);
    FitOptions o = fast_options();
    o.mode = FitMode::Tolerance;
    o.tolerance = 1e-9;
    o.max_level = 4;
    const FitResult r = fit_surface(layout, o);
    std::cout << "  " << r.message << "\n";
    EXPECT_FALSE(r.tolerance_met);
    for (size_t i = 1; i < r.levels.size(); ++i) EXPECT_LE(r.levels[i].relative.rms, r.levels[i - 1].relative.rms);
    EXPECT_EQ(r.surface.level(), r.levels.back().level);
    const auto report = nlohmann::json::parse(fit_report(r, o).to_json());
    if (r.rejected_level) {
        EXPECT_EQ(r.rejected_level->level, r.levels.back().level + 1);
        EXPECT_GT(r.rejected_level->relative.rms, r.levels.back().relative.rms);
        EXPECT_NE(r.message.find("did not improve"), std::string::npos) << r.message;
        EXPECT_EQ(report["rejected_level"]["level"], r.rejected_level->level);
    } else {
        EXPECT_EQ(r.levels.back().level, o.max_level);
        EXPECT_NE(r.message.find("not met by max_level " + std::to_string(o.max_level)), std::string::npos)
            << r.message;
    }
}

TEST(FitSurface, DeterministicAndIndependentOfTheThreadCount) {
    const layout::QuadLayout layout = test::cube_sphere_layout(8);
    FitOptions o = fast_options();
    o.level = 2;
    o.threads = 2;
    const FitResult a = fit_surface(layout, o), b = fit_surface(layout, o);
    o.threads = 1;
    const FitResult c = fit_surface(layout, o);
    EXPECT_EQ(a.levels.back().relative.rms, b.levels.back().relative.rms);
    EXPECT_EQ(a.surface.control_mesh().points, b.surface.control_mesh().points);
    EXPECT_NEAR(a.levels.back().relative.rms, c.levels.back().relative.rms, 1e-9);
    for (size_t i = 0; i < a.surface.control_mesh().points.size(); ++i)
        EXPECT_LT(norm(a.surface.control_mesh().points[i] - c.surface.control_mesh().points[i]), 1e-9);
}

// level1_fit_score() (the layout's S-cycle choice in fit_cage() and the CLI): the relative RMS of
// the level-1 fit with the given options, whatever their level, mode and progress, with the
// score's own rounds, tangential weight and points; bad options are refused when the score is
// made, not when a layout is scored.
TEST(FitSurface, LevelOneFitScoreIsTheLevelOneRms) {
    const layout::QuadLayout layout = test::cube_sphere_layout(8);
    FitOptions o = fast_options();
    o.mode = FitMode::Tolerance;
    o.level = 3;
    int said = 0;
    o.progress = [&said](const std::string&) { ++said; };
    const auto score = level1_fit_score(o);
    const double s = score(layout);
    EXPECT_EQ(said, 0);
    FitOptions one = fast_options();
    one.level = 1;
    one.extra_rounds = 0;
    one.tangential_weight = kScoreTangentialWeight;
    one.turned_over_weight = kScoreTurnedOverWeight;
    one.data_points_per_face = one.surface_samples_per_face = kScorePointsPerFace;
    one.error_samples = kScoreErrorSamples;
    const FitResult r = fit_surface(layout, one);
    ASSERT_EQ(r.levels.back().level, 1);
    EXPECT_EQ(s, r.levels.back().relative.rms);
    EXPECT_GT(s, 0);
    FitOptions bad;
    bad.outer_iterations = 0;
    EXPECT_THROW(level1_fit_score(bad), InvalidInput);
}

// level2_fit_score() (the tie-break of that choice): the relative RMS of the level-2 fit with the
// given options, whatever their level, mode and progress, without extra rounds; finer than the
// level-1 score.
TEST(FitSurface, LevelTwoFitScoreIsTheLevelTwoRms) {
    const layout::QuadLayout layout = test::cube_sphere_layout(8);
    FitOptions o = fast_options();
    o.level = 4;
    o.mode = FitMode::Tolerance;
    int said = 0;
    o.progress = [&said](const std::string&) { ++said; };
    const double s2 = level2_fit_score(o)(layout), s1 = level1_fit_score(o)(layout);
    EXPECT_EQ(said, 0);
    FitOptions two = fast_options();
    two.level = 2;
    two.extra_rounds = 0;
    two.turned_over_weight = kScoreTurnedOverWeight;
    const FitResult r = fit_surface(layout, two);
    ASSERT_EQ(r.levels.back().level, 2);
    EXPECT_EQ(s2, r.levels.back().relative.rms);
    EXPECT_GT(s2, 0);
    EXPECT_LT(s2, s1);
    FitOptions bad;
    bad.outer_iterations = 0;
    EXPECT_THROW(level2_fit_score(bad), InvalidInput);
}

TEST(FitSurface, TheDirectSolverEndsWhereCeresEnds) {
    // Both take one damped Gauss-Newton step per round; the direct solver factorises the normal
    // equations itself, with the analysis kept for the level. Rounding apart, the fits agree.
    const layout::QuadLayout layout = test::torus_layout(32, 16);
    FitOptions o = fast_options();
    o.level = 3;
    o.solver = FitSolver::Direct;
    const FitResult direct = fit_surface(layout, o);
    o.solver = FitSolver::Ceres;
    const FitResult ceres = fit_surface(layout, o);
    ASSERT_EQ(direct.levels.size(), ceres.levels.size());
    for (size_t k = 0; k < direct.levels.size(); ++k) {
        const LevelReport &a = direct.levels[k], &b = ceres.levels[k];
        std::cout << "  direct " << describe(a) << "\n  ceres  " << describe(b) << "\n";
        EXPECT_EQ(a.iterations, b.iterations);
        EXPECT_NEAR(a.relative.rms, b.relative.rms, 0.01 * b.relative.rms);
        EXPECT_NEAR(a.relative.hausdorff, b.relative.hausdorff, 0.02 * b.relative.hausdorff);
    }
    const auto& pa = direct.surface.control_mesh().points;
    const auto& pb = ceres.surface.control_mesh().points;
    ASSERT_EQ(pa.size(), pb.size());
    double worst = 0;
    for (size_t i = 0; i < pa.size(); ++i) worst = std::max(worst, norm(pa[i] - pb[i]));
    EXPECT_LT(worst, 1e-3 * direct.levels.back().diagonal);
}

TEST(FitSurface, FittedSurfaceEvaluatesOnCageCoordinates) {
    const layout::QuadLayout layout = test::cube_sphere_layout(8);
    const FitResult r = fit_level(layout, 2);
    const FittedSurface& s = r.surface;
    // Centre of cube face 0 = centre of its level-2 grid: a corner of 4 faces; a sphere of radius 1.
    const subdiv::LimitPoint p = s.evaluate_on_cage({0, 0.5, 0.5});
    EXPECT_NEAR(norm(p.position), 1.0, 1e-2);  // between the facets of the 8 x 8 input
    EXPECT_GT(dot(p.normal, p.position), 0.99);
    const subdiv::FacePoint f = s.from_cage({0, 0.3, 0.7});
    EXPECT_LT(norm(s.evaluate(f).position - s.evaluate_on_cage({0, 0.3, 0.7}).position), 1e-15);
    EXPECT_THROW(s.evaluate_on_cage({6, 0.5, 0.5}), InvalidInput);
    EXPECT_THROW(FittedSurface().limit(), InvalidInput);
}

TEST(FitSurface, MeasureFindsNoErrorAgainstTheSurfaceItself) {
    const layout::QuadLayout layout = test::cube_sphere_layout(6);
    const FitResult r = fit_level(layout, 1);
    // A fine tessellation of the fitted surface as the "input": distances are its chord errors.
    const subdiv::LimitTessellation t = r.surface.limit().tessellate(24);
    MeasureOptions mo;
    mo.samples = 20000;
    const ErrorMeasurement m = measure_fit_error(t.mesh, r.surface, mo);
    LimitPlyOptions po;
    const TessellationChoice chord = tessellation_error(r.surface, 24, po);
    EXPECT_LE(m.absolute.rms, 2 * chord.rms_error + 1e-12);
    EXPECT_LE(m.relative.rms, 1e-4);
    EXPECT_EQ(m.within_tolerance, 1.0);
    // Against the input with the samples fit_surface() measured with (seed + 101), it is the
    // reported fit error again.
    MeasureOptions same;
    same.samples = fast_options().error_samples;
    same.seed = FitOptions{}.seed + 101;
    const ErrorMeasurement again = measure_fit_error(layout.mesh, r.surface, same);
    EXPECT_NEAR(again.relative.rms, r.levels.back().relative.rms, 1e-12);
    EXPECT_NEAR(again.relative.hausdorff, r.levels.back().relative.hausdorff, 1e-12);
}

TEST(FitSurface, MeasuredDistancesAreNoLongerThanToAKnownPointOfTheSurface) {
    // A level-4 surface over a torus cage (the issue fits genus 0 and 1 at level 4), rippled at
    // the scale of two control faces, as a fit that has not settled leaves it. Each point lies off
    // a known surface point along its normal, so its distance to the surface is at most that
    // offset. A projection seeded from 2 segments a face (face_segments() at level 4) started in
    // the wrong basin for 8 of these points and reported up to 5.5% more; torus.obj's level-4 fit
    // reported a Hausdorff distance of 1.28e-3 where check_fit.py measures 6.7e-4. Seeded from
    // kSeedSegments, none is over by 1% (33 still are by 0.1%: a seed is not a global search).
    constexpr int kLevel = 4;
    const subdiv::QuadMesh cage = test::torus_quads(4, 4);
    subdiv::QuadMesh fine = subdiv::refine_uniform(cage, kLevel);
    for (Vec3& p : fine.points) p = p * (1 + 0.06 * std::sin(30 * p[0]) * std::sin(30 * p[1]) * std::cos(30 * p[2]));
    const FittedSurface surface(fine, kLevel, cage.num_quads());
    std::vector<Vec3> points;
    std::vector<double> offsets;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 50000; ++i) {
        const subdiv::FacePoint f{static_cast<int>(unit(rng) * fine.num_quads()) % fine.num_quads(), unit(rng),
                                  unit(rng)};
        const subdiv::LimitPoint at = surface.evaluate(f);
        const double offset = 0.04 * (2 * unit(rng) - 1);
        points.push_back(at.position + at.normal * offset);
        offsets.push_back(std::abs(offset));
    }
    const std::vector<double> d = distances_to_surface(surface, points);
    int longer = 0;
    double worst = 0;
    for (size_t i = 0; i < d.size(); ++i) {
        longer += d[i] > 1.01 * offsets[i] + 1e-9;
        worst = std::max(worst, d[i] / (offsets[i] + 1e-9));
    }
    EXPECT_EQ(longer, 0) << "the worst measured " << worst << " times its known distance";
}

TEST(FitSurface, RejectsBadInput) {
    const layout::QuadLayout layout = test::cube_sphere_layout(4);
    FitOptions o;
    o.level = -1;
    EXPECT_THROW(fit_surface(layout, o), InvalidInput);
    o = FitOptions{};
    o.tolerance = 0;
    EXPECT_THROW(fit_surface(layout, o), InvalidInput);
    o = FitOptions{};
    o.huber_scale = -1;
    EXPECT_NE(o.validate(), "");
    for (const double mu : {-0.1, 1.5}) {
        o = FitOptions{};
        o.tangential_weight = mu;
        EXPECT_NE(o.validate(), "") << mu;
    }
    for (const double w : {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        o = FitOptions{};
        o.turned_over_weight = w;
        EXPECT_NE(o.validate(), "") << w;
    }
    layout::QuadLayout broken = layout;
    broken.triangle_patch.pop_back();
    EXPECT_THROW(fit_surface(broken, FitOptions{}), InvalidInput);
    broken = layout;
    broken.triangle_patch[3] = 6;
    EXPECT_THROW(fit_surface(broken, FitOptions{}), InvalidInput);
    broken = layout;
    broken.corner_uv[0][1] = {1.5, 0.0};
    EXPECT_THROW(fit_surface(broken, FitOptions{}), InvalidInput);
    broken = layout;
    broken.cage.quads[0].edges[0] = broken.cage.quads[0].edges[1];
    EXPECT_THROW(fit_surface(broken, FitOptions{}), InvalidInput);
    MeasureOptions mo;
    mo.samples = 0;
    EXPECT_THROW(measure_fit_error(layout.mesh, FittedSurface(), MeasureOptions{}), InvalidInput);
    EXPECT_NE(mo.validate(), "");
}

// ---------------------------------------------------------------------------------------------
// Writers and the independent checker

int run_shell(const std::string& command) {
    const int status = std::system(command.c_str());
    if (status == -1) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path scratch_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path dir = fs::temp_directory_path() /
                         ("quadcage_fit_test_" + std::to_string(::getpid()) + "_" +
                          test::identifier(std::string(info->test_suite_name()) + "_" + info->name()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string python_unavailable() {
    if (!fs::exists("/usr/bin/python3")) return "/usr/bin/python3 is missing";
    if (run_shell("/usr/bin/python3 -c 'import numpy, scipy' >/dev/null 2>&1") != 0)
        return "/usr/bin/python3 cannot import numpy and scipy";
    if (!fs::exists(fs::path(QUADCAGE_SHARED_DIR) / "tools" / "check_fit.py")) return "check_fit.py is missing";
    return "";
}

// Writes the outputs of a fit and compares the report with check_fit.py's independent measurement.
void check_outputs_against_checker(const layout::QuadLayout& layout, int level, const std::string& name) {
    FitOptions o = fast_options();
    o.level = level;
    o.error_samples = 100000;  // as many as the checker takes
    const FitResult r = fit_surface(layout, o);
    const fs::path dir = scratch_dir() / name;
    const FitOutputs out = write_fit_outputs(dir.string(), layout.mesh, r, o);
    ASSERT_EQ(out.files.size(), 4u);
    for (const auto& f : out.files) EXPECT_TRUE(fs::exists(f)) << f;
    EXPECT_TRUE(out.tessellation.met) << "tessellation error " << out.tessellation.rms_error << " > " << out.tessellation.target;
    EXPECT_LE(out.tessellation.rms_error, 0.1 * r.levels.back().absolute.rms);

    // report.json has the fields the bench reads.
    const auto report = nlohmann::json::parse(slurp(dir / "report.json"));
    // Every level from 1 up to the one asked for, in order; the last is the fitted surface's.
    ASSERT_EQ(report["levels"].size(), static_cast<size_t>(level));
    for (int k = 1; k <= level; ++k) EXPECT_EQ(report["levels"][k - 1]["level"], k);
    const auto& l = report["levels"][level - 1];
    EXPECT_EQ(report["level"], level);
    EXPECT_EQ(l["control_points"], r.levels.back().control_points);
    EXPECT_DOUBLE_EQ(l["relative"]["rms"].get<double>(), r.levels.back().relative.rms);
    for (const char* key : {"parameterization", "evaluation", "closest_points", "solve", "total"})
        EXPECT_TRUE(l["seconds"].contains(key)) << key;
    for (const char* dir_key : {"input_to_surface", "surface_to_input"})
        for (const char* stat : {"rms", "mean", "max"}) EXPECT_TRUE(l["absolute"][dir_key].contains(stat));

    // The files read back: fitted cage (quads fan-split by the reader), limit and deviation meshes.
    const Mesh cage = read_mesh((dir / "fitted_cage.obj").string());
    EXPECT_EQ(cage.num_triangles(), 2 * r.surface.control_mesh().num_quads());
    const Mesh deviation = read_mesh((dir / "deviation.ply").string());
    EXPECT_EQ(deviation.num_vertices(), layout.mesh.num_vertices());
    const Mesh limit = read_mesh((dir / "limit.ply").string());
    EXPECT_EQ(limit.num_triangles(), out.tessellation.triangles);
    // The folds of the surface written and of the input, in the report; a smooth shape fitted
    // through a layout of even patches has none, and neither has its input.
    EXPECT_NEAR(out.tessellation.folded_area_fraction, folded_area_fraction(limit), 1e-9);
    EXPECT_EQ(report["limit_tessellation"]["folded_area_fraction"].get<double>(), out.tessellation.folded_area_fraction);
    EXPECT_EQ(report["limit_tessellation"]["input_folded_area_fraction"].get<double>(), 0.0);
    EXPECT_EQ(out.tessellation.folded_area_fraction, 0.0) << name;
    EXPECT_EQ(report["limit_tessellation"]["inverted_area_fraction"].get<double>(), out.tessellation.inverted_area_fraction);
    EXPECT_EQ(out.tessellation.inverted_area_fraction, 0.0) << name;

    const std::string why = python_unavailable();
    if (!why.empty()) GTEST_SKIP() << "check_fit.py not run: " << why;
    write_ply((dir / "input.ply").string(), layout.mesh);
    const fs::path log = dir / "check_fit.txt";
    const std::string checker = (fs::path(QUADCAGE_SHARED_DIR) / "tools" / "check_fit.py").string();
    ASSERT_EQ(run_shell("'" + checker + "' --input '" + (dir / "input.ply").string() + "' --surface '" +
                        (dir / "limit.ply").string() + "' > '" + log.string() + "' 2>&1 </dev/null"),
              0)
        << slurp(log);
    const std::string text = slurp(log);
    const auto measured = nlohmann::json::parse(text.substr(0, text.find('\n')));
    const double rms = measured["relative"]["rms"], hausdorff = measured["relative"]["hausdorff"];
    const LevelReport& fin = r.levels.back();
    std::cout << "  " << name << " level " << level << ": ours rms " << fin.relative.rms << " hausdorff "
              << fin.relative.hausdorff << "; check_fit.py rms " << rms << " hausdorff " << hausdorff << "\n";
    EXPECT_NEAR(fin.relative.rms, rms, 0.2 * rms);
    EXPECT_NEAR(fin.relative.hausdorff, hausdorff, 0.2 * hausdorff);
}

TEST(FitOutputs, TorusReportAgreesWithCheckFit) { check_outputs_against_checker(test::torus_layout(32, 16), 3, "torus"); }

TEST(FitOutputs, SphereReportAgreesWithCheckFit) { check_outputs_against_checker(test::cube_sphere_layout(12), 2, "sphere"); }

TEST(FitOutputs, TessellationErrorFallsQuadratically) {
    const FitResult r = fit_level(test::cube_sphere_layout(6), 1);
    const TessellationChoice a = tessellation_error(r.surface, 4), b = tessellation_error(r.surface, 8);
    EXPECT_GT(a.rms_error, 0);
    EXPECT_NEAR(b.rms_error / a.rms_error, 0.25, 0.08);
    const TessellationChoice c = choose_tessellation(r.surface, a.rms_error);  // target a / 10
    EXPECT_TRUE(c.met);
    EXPECT_LE(c.rms_error, c.target);
    EXPECT_GT(c.segments, 4);
    EXPECT_THROW(choose_tessellation(r.surface, 0.0), InvalidInput);
    // A bound on the max error too: finer than the RMS target alone, and the bound holds.
    LimitPlyOptions bounded;
    const double diagonal = r.levels.back().diagonal;
    bounded.max_error_relative = 0.25 * c.max_error / diagonal;
    const TessellationChoice d = choose_tessellation(r.surface, a.rms_error, bounded, diagonal);
    EXPECT_TRUE(d.met);
    EXPECT_LE(d.max_error, bounded.max_error_relative * diagonal);
    EXPECT_GT(d.segments, c.segments);
    EXPECT_THROW(choose_tessellation(r.surface, a.rms_error, bounded), InvalidInput);  // no diagonal
}

// The turned-over share compares the surface's orientation with the input's at the closest input
// points: against the same input with every triangle turned over, all of a good fit counts.
TEST(FitOutputs, TurnedOverAreaIsMeasuredAgainstTheInputsOrientation) {
    const layout::QuadLayout layout = test::cube_sphere_layout(8);
    FitOptions o = fast_options();
    o.level = 1;
    const FitResult r = fit_surface(layout, o);
    Mesh turned = layout.mesh;
    for (Triangle& t : turned.triangles) std::swap(t[1], t[2]);
    const FitOutputs same = write_fit_outputs((scratch_dir() / "same").string(), layout.mesh, r, o);
    const FitOutputs against = write_fit_outputs((scratch_dir() / "turned").string(), turned, r, o);
    EXPECT_EQ(same.tessellation.inverted_area_fraction, 0.0);
    EXPECT_EQ(against.tessellation.inverted_area_fraction, 1.0);
    // Folds are the surface's own: the same both ways.
    EXPECT_EQ(same.tessellation.folded_area_fraction, against.tessellation.folded_area_fraction);
}

// A body with three small handles in a row (`generate handles -g 3 --in-a-row -r 2`, laid out with
// the library's defaults): at level 2 without the turned-over term 3.1% of the limit surface lay
// turned over against the input, the middle sheets of pleats; 0.13% with the term at 0.1, the RMS
// 1% higher (measured in development). The default weight, too, must turn most of them back.
// Both solvers take the term alike.
TEST(FitTurnedOver, TheTermTurnsThePleatsBackWithEitherSolver) {
    shapes::HandleBodyOptions body;
    body.handles = 3;
    body.in_a_row = true;
    body.resolution = 2;
    const layout::QuadLayout layout = layout::build_quad_layout(shapes::body_with_handles(body));
    auto turned_over = [&layout](double weight, FitSolver solver) {
        FitOptions o;
        o.mode = FitMode::Level;
        o.level = 2;
        o.turned_over_weight = weight;
        o.solver = solver;
        const FitResult r = fit_surface(layout, o);
        const FitOutputs out = write_fit_outputs((scratch_dir() / "turned_over").string(), layout.mesh, r, o);
        std::cout << "  weight " << weight << (solver == FitSolver::Ceres ? " (ceres)" : "") << ": "
                  << describe(r.levels.back()) << ", turned over " << out.tessellation.inverted_area_fraction
                  << ", on folds " << out.tessellation.folded_area_fraction << "\n";
        return std::pair{r.levels.back(), out.tessellation.inverted_area_fraction};
    };
    const auto [without, turned_without] = turned_over(0.0, FitSolver::Direct);
    const auto [with, turned_with] = turned_over(0.1, FitSolver::Direct);
    EXPECT_GT(turned_without, 0.005);
    EXPECT_LT(turned_with, 0.2 * turned_without);
    EXPECT_LT(with.relative.rms, 1.2 * without.relative.rms);
    const auto [ceres, turned_ceres] = turned_over(0.1, FitSolver::Ceres);
    EXPECT_NEAR(ceres.relative.rms, with.relative.rms, 0.02 * with.relative.rms);
    EXPECT_LT(turned_ceres, 0.2 * turned_without);
    const auto [by_default, turned_by_default] = turned_over(FitOptions{}.turned_over_weight, FitSolver::Direct);
    EXPECT_LT(turned_by_default, 0.3 * turned_without);
    EXPECT_LT(by_default.relative.rms, 1.2 * without.relative.rms);

    // The layout's scores fit without the term (kScoreTurnedOverWeight), whatever their options
    // say, though on this layout the term changes the level-1 fit they are.
    FitOptions heavy;
    heavy.turned_over_weight = 0.1;
    const double score = level1_fit_score(heavy)(layout);
    EXPECT_EQ(score, level1_fit_score(FitOptions{})(layout));
    FitOptions one;
    one.mode = FitMode::Level;
    one.level = 1;
    one.extra_rounds = 0;
    one.tangential_weight = kScoreTangentialWeight;
    one.data_points_per_face = one.surface_samples_per_face = kScorePointsPerFace;
    one.error_samples = kScoreErrorSamples;
    one.turned_over_weight = kScoreTurnedOverWeight;
    EXPECT_EQ(score, fit_surface(layout, one).levels.back().relative.rms);
    one.turned_over_weight = 0.1;
    EXPECT_NE(score, fit_surface(layout, one).levels.back().relative.rms);
}

TEST(FitOutputs, QuadObjAndReportWithoutTessellation) {
    const layout::QuadLayout layout = test::cube_sphere_layout(4);
    FitOptions o = fast_options();
    o.mode = FitMode::Tolerance;
    o.tolerance = 0.5;  // level 0 already meets it
    o.turned_over_weight = 0.03;
    const FitResult r = fit_surface(layout, o);
    ASSERT_TRUE(r.tolerance_met);
    const auto report = nlohmann::json::parse(fit_report(r, o).to_json());
    EXPECT_EQ(report["mode"], "tolerance");
    // The weights that made the surface, from the options.
    EXPECT_EQ(report["weights"]["turned_over"], 0.03);
    EXPECT_EQ(report["weights"]["tangential"], o.tangential_weight);
    EXPECT_EQ(report["weights"]["surface_to_input"], o.surface_to_input_weight);
    EXPECT_EQ(report["tolerance_met"], true);
    EXPECT_EQ(report["level"], 0);
    EXPECT_FALSE(report.contains("limit_tessellation"));
    const fs::path dir = scratch_dir();
    write_quad_obj((dir / "cage.obj").string(), r.surface.control_mesh());
    const Mesh back = read_mesh((dir / "cage.obj").string());
    ASSERT_EQ(back.num_vertices(), r.surface.control_mesh().num_vertices());
    for (int v = 0; v < back.num_vertices(); ++v) EXPECT_EQ(back.points[v], r.surface.control_mesh().points[v]);
    EXPECT_THROW(write_fit_outputs((dir / "x").string(), layout.mesh, FitResult{}, o), InvalidInput);
}

// A plate with square holes has sharp convex edges all round. The closest input points of the
// surface samples near them lie on those edges: measured along the normal of the triangle found,
// the surface could bulge past an edge unseen. Measured along the offset from the edge, it fits the
// plate closer at its largest distance (level 2, with the tangential weight 0.02: 2.4e-2 -> 1.5e-2
// when measured in development, 1.86e-2 -> 1.28e-2 on dab065b). The weight 0.002 lets the rounds
// slide the surface further and bulge less either way (1.42e-2 -> 1.23e-2 on dab065b): the offsets
// still fit closer there, though by less than a fifth, and no worse than at 0.02. Those figures are
// without the turned-over term, which this test keeps off to see the offsets alone. With the
// default term (0.01) the planes-only fit no longer bulges either (1.22e-2 at 0.02 and 1.20e-2 at
// 0.002 on d2efc77, against 1.28e-2 and 1.20e-2 with the offsets): the bulge was partly a sheet
// turned over. With every default the offsets must do no harm.
TEST(FitSurface, OffsetsAtEdgesKeepTheSurfaceFromBulgingPastCreases) {
    shapes::PlateOptions plate;
    plate.resolution = 4;
    const layout::QuadLayout layout = layout::build_quad_layout(shapes::plate_with_holes(2, plate));
    // Level 2 with and without the offsets at the creases.
    auto with_and_without = [&layout](double weight, double turned_over_weight) {
        FitOptions o;  // the default data points: with fast_options()' fewer, 2.1e-2 -> 1.8e-2
        o.mode = FitMode::Level;
        o.level = 2;
        o.tangential_weight = weight;
        o.turned_over_weight = turned_over_weight;
        const LevelReport edges = fit_surface(layout, o).levels.back();
        o.surface_feature_feet = false;
        const LevelReport planes = fit_surface(layout, o).levels.back();
        std::cout << "  tangential weight " << weight << ", turned-over weight " << turned_over_weight
                  << ", offsets at edges: " << describe(edges) << "\n  planes only: " << describe(planes) << "\n";
        EXPECT_LT(edges.relative.rms, 1.02 * planes.relative.rms) << weight;
        return std::pair{edges, planes};
    };
    const auto [edges_then, planes_then] = with_and_without(0.02, 0);
    EXPECT_LT(edges_then.relative.hausdorff, 0.8 * planes_then.relative.hausdorff);
    const auto [edges_small, planes_small] = with_and_without(0.002, 0);
    EXPECT_LT(edges_small.relative.hausdorff, planes_small.relative.hausdorff);
    EXPECT_LE(edges_small.relative.hausdorff, edges_then.relative.hausdorff);
    const FitOptions defaults;
    const auto [edges_now, planes_now] = with_and_without(defaults.tangential_weight, defaults.turned_over_weight);
    EXPECT_LE(edges_now.relative.hausdorff, 1.02 * planes_now.relative.hausdorff);
    EXPECT_LE(edges_now.relative.hausdorff, edges_then.relative.hausdorff);
}

// The rounds a level takes by default bring the fit of a real layout, whose patch maps are far from
// isometric, close to where more rounds end. The smoothness schedule takes 16
// (FitOptions::outer_iterations); at the level asked for, the rounds then go on at the final weight
// while each still gains (FitOptions::extra_rounds). Measured on fertility at level 3, relative RMS
// (our report): 1.88e-4 without the extra rounds, 1.72e-4 with them (36 rounds in all); with this
// test's fewer data points 2.10e-4 and 1.95e-4 (35 rounds), and all 32 extra rounds 1.93e-4. On botijo
// decimated to 10k vertices, where the surface must slide into a small knob inside one big patch,
// 5.29e-4 / Hausdorff 1.17e-2 without them and 3.07e-4 / 7.4e-3 with them (README, "Rounds that go
// on while they gain").
TEST(FitSurface, TheRoundsGoOnWhileTheyGainAtTheLevelAskedFor) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    const layout::QuadLayout layout = layout::build_quad_layout(test::load_shared("fertility.off"));
    const FitOptions o = level3_options();
    const FitResult standard = fit_surface(layout, o);
    FitOptions none = o;
    none.extra_rounds = 0;
    const LevelReport without = fit_surface(layout, none).levels.back();
    const LevelReport& last = standard.levels.back();
    std::cout << "  default: " << describe(last) << "\n  without the extra rounds: " << describe(without) << "\n";
    ASSERT_EQ(last.level, 3);
    for (size_t k = 0; k + 1 < standard.levels.size(); ++k)
        EXPECT_LE(standard.levels[k].iterations, o.outer_iterations) << describe(standard.levels[k]);
    EXPECT_GT(last.iterations, o.outer_iterations);
    EXPECT_LE(last.iterations, o.outer_iterations + o.extra_rounds);
    EXPECT_LE(without.iterations, o.outer_iterations);
    EXPECT_LE(last.relative.rms, 0.97 * without.relative.rms);
    // Issue 20's fit targets at level 3.
    EXPECT_LE(last.relative.rms, 1e-3);
    EXPECT_LE(last.relative.hausdorff, 1e-2);
}

// At the closest feet the tangential part of a data residual is zero, so its weight decides how
// fast the rounds let the surface slide along itself, not where they would end: with the default
// the rounds gain longer before they stall, and end closer than with the weight it replaced.
TEST(FitSurface, ASmallTangentialWeightSlidesTheSurfaceFurther) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not found";
    const layout::QuadLayout layout = layout::build_quad_layout(test::load_shared("eight.off"));
    const FitOptions o = level3_options();
    const LevelReport now = fit_surface(layout, o).levels.back();
    FitOptions before = o;
    before.tangential_weight = 0.02;
    const LevelReport then = fit_surface(layout, before).levels.back();
    std::cout << "  tangential weight " << o.tangential_weight << ": " << describe(now) << "\n  0.02: " << describe(then)
              << "\n";
    EXPECT_LT(o.tangential_weight, before.tangential_weight);
    EXPECT_LE(now.relative.rms, 0.98 * then.relative.rms);
    EXPECT_LE(now.relative.hausdorff, then.relative.hausdorff);
}

}  // namespace
}  // namespace quadcage::fit

// End-to-end tests of the quadcage executable: exit codes, messages and JSON output.

#include <gtest/gtest.h>

#include "support/names.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"

namespace {

namespace fs = std::filesystem;

struct Outcome {
    int code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path scratch_dir() {
    const fs::path dir = fs::temp_directory_path() / ("quadcage_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

// Runs the CLI with `args` (already shell-quoted where needed).
Outcome quadcage(const std::string& args) {
    const fs::path dir = scratch_dir();
    const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    const std::string cmd = std::string("'") + QUADCAGE_CLI + "' " + args + " >'" + out.string() + "' 2>'" +
                            err.string() + "' </dev/null";
    const int status = std::system(cmd.c_str());
    Outcome r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

std::string shared_mesh(const std::string& name) {
    return std::string(QUADCAGE_SHARED_DIR) + "/data/meshes/" + name;
}

template <class Case>
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    return quadcage::test::identifier(info.param.file);
}

bool have_shared() { return fs::exists(shared_mesh("eight.off")); }

int count_lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

struct GenusCase {
    const char* file;
    int genus;
};

class CliInfoValid : public ::testing::TestWithParam<GenusCase> {};

TEST_P(CliInfoValid, ReportsTheDocumentedGenus) {
    if (!have_shared()) GTEST_SKIP() << "shared meshes not found";
    const Outcome r = quadcage("info --json '" + shared_mesh(GetParam().file) + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["components"].size(), 1u);
    EXPECT_EQ(j["components"][0]["genus"], GetParam().genus);
    EXPECT_EQ(j["components"][0]["closed"], true);
    EXPECT_EQ(j["components"][0]["manifold"], true);
    EXPECT_EQ(j["components"][0]["orientable"], true);
    const int g = GetParam().genus;
    EXPECT_EQ(j["minimal_quads"], g == 0 ? 6 : (g == 1 ? 4 : 10 * g - 10));
    EXPECT_EQ(j["quaddable"], true);
    EXPECT_GT(j["bbox_diagonal"].get<double>(), 0.0);
    EXPECT_GT(j["triangles"].get<int>(), 0);
    EXPECT_GT(j["vertices"].get<int>(), 0);
    EXPECT_TRUE(r.err.empty()) << r.err;
}

INSTANTIATE_TEST_SUITE_P(Shared, CliInfoValid,
                         ::testing::Values(GenusCase{"bunny.obj", 0}, GenusCase{"igea.ply", 0},
                                           GenusCase{"kitten.off", 1}, GenusCase{"torus.obj", 1},
                                           GenusCase{"eight.off", 2}, GenusCase{"skull.obj", 2},
                                           GenusCase{"3holes.off", 3}, GenusCase{"fertility.off", 4},
                                           GenusCase{"botijo.off", 5}, GenusCase{"input_wheel.off", 11},
                                           GenusCase{"boot.obj", 12}),
                         case_name<GenusCase>);

struct BadCase {
    const char* file;
    const char* problem;  // must appear in the one-line error
};

class CliInfoInvalid : public ::testing::TestWithParam<BadCase> {};

TEST_P(CliInfoInvalid, ExitsThreeAndNamesTheProblem) {
    if (!have_shared()) GTEST_SKIP() << "shared meshes not found";
    const std::string path = shared_mesh(GetParam().file);
    const Outcome r = quadcage("info '" + path + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(GetParam().file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(GetParam().problem), std::string::npos) << r.err;
    // The full description still goes to stdout, and --json is valid JSON saying why.
    EXPECT_NE(r.out.find("cannot be quadded"), std::string::npos);
    const Outcome j = quadcage("info --json '" + path + "'");
    EXPECT_EQ(j.code, 3);
    const nlohmann::json doc = nlohmann::json::parse(j.out);
    EXPECT_EQ(doc["quaddable"], false);
    EXPECT_FALSE(doc["issues"].empty());
}

INSTANTIATE_TEST_SUITE_P(Shared, CliInfoInvalid,
                         ::testing::Values(BadCase{"stanford-bunny.obj", "open"},
                                           BadCase{"cow.obj", "pinched"},
                                           BadCase{"truck.obj", "non-manifold"}),
                         case_name<BadCase>);

TEST(CliInfo, TruckReportsItsComponents) {
    if (!have_shared()) GTEST_SKIP() << "shared meshes not found";
    const Outcome r = quadcage("info --json '" + shared_mesh("truck.obj") + "'");
    EXPECT_EQ(r.code, 3);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["components"].size(), 50u);
    EXPECT_GT(j["counts"]["non_manifold_edges"].get<int>(), 0);
    EXPECT_GT(j["counts"]["boundary_loops"].get<int>(), 0);
}

TEST(CliInfo, TruncatedBinaryPlyExitsThree) {
    const fs::path dir = scratch_dir();
    const fs::path good = dir / "sphere.ply", bad = dir / "truncated.ply";
    quadcage::write_ply(good.string(), quadcage::shapes::icosphere(3));
    const std::string bytes = slurp(good);
    std::ofstream(bad, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
    const Outcome r = quadcage("info '" + bad.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("truncated.ply"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
}

TEST(CliInfo, EmptyFileExitsThree) {
    const fs::path empty = scratch_dir() / "empty.obj";
    std::ofstream(empty).close();
    const Outcome r = quadcage("info '" + empty.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("empty.obj"), std::string::npos) << r.err;
}

TEST(CliInfo, MissingFileExitsThree) {
    const Outcome r = quadcage("info '" + (scratch_dir() / "no-such-file.off").string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_NE(r.err.find("no-such-file.off"), std::string::npos) << r.err;
}

TEST(CliInfo, NanCoordinatesExitThree) {
    const fs::path nan = scratch_dir() / "nan.obj";
    std::ofstream(nan) << "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const Outcome r = quadcage("info '" + nan.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("NaN"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nan.obj"), std::string::npos) << r.err;
}

TEST(CliInfo, GeneratedPlatesHaveTheirGenus) {
    const fs::path dir = scratch_dir();
    for (int g : {0, 2, 7}) {
        const fs::path file = dir / ("plate" + std::to_string(g) + ".obj");
        const Outcome gen = quadcage("generate plate --genus " + std::to_string(g) + " -o '" + file.string() + "'");
        ASSERT_EQ(gen.code, 0) << gen.err;
        const Outcome r = quadcage("info --json '" + file.string() + "'");
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(nlohmann::json::parse(r.out)["components"][0]["genus"], g);
    }
}

// `generate wheel -g G`: the axle's hole and G - 1 holes round it, with or without ribs; a wheel
// needs its axle, so genus 0 is refused, naming the option, and no file is written.
TEST(CliInfo, GeneratedWheelsHaveTheirGenus) {
    const fs::path dir = scratch_dir();
    for (const std::string ribs : {"", " --ribs 8"})
        for (int g : {1, 4}) {
            const fs::path file = dir / ("wheel" + std::to_string(g) + ".obj");
            const Outcome gen = quadcage("generate wheel -r 2 --genus " + std::to_string(g) + ribs + " -o '" +
                                         file.string() + "'");
            ASSERT_EQ(gen.code, 0) << gen.err;
            const Outcome r = quadcage("info --json '" + file.string() + "'");
            ASSERT_EQ(r.code, 0) << r.err;
            EXPECT_EQ(nlohmann::json::parse(r.out)["components"][0]["genus"], g) << ribs;
        }
    const fs::path none = dir / "wheel0.obj";
    const Outcome r = quadcage("generate wheel --genus 0 -o '" + none.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_NE(r.err.find("--genus"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(none));
}

// `generate limbs|handles --fins F` reaches the generators: the fins change the figure (more area,
// the same vertex count, the same genus); more than 16 is bad usage (exit 2) and writes nothing.
TEST(CliGenerate, TheFinsFlagReachesLimbsAndHandles) {
    const fs::path dir = scratch_dir();
    for (const std::string shape : {"limbs --limbs 1 -r 3", "handles -g 1 -r 2"}) {
        nlohmann::json info[2];
        for (int fins : {0, 2}) {
            const fs::path file = dir / ("fins" + std::to_string(fins) + ".obj");
            const Outcome gen =
                quadcage("generate " + shape + " --fins " + std::to_string(fins) + " -o '" + file.string() + "'");
            ASSERT_EQ(gen.code, 0) << gen.err;
            const Outcome r = quadcage("info --json '" + file.string() + "'");
            ASSERT_EQ(r.code, 0) << r.err;
            info[fins / 2] = nlohmann::json::parse(r.out);
        }
        EXPECT_EQ(info[0]["components"][0]["genus"], info[1]["components"][0]["genus"]) << shape;
        EXPECT_EQ(info[0]["components"][0]["vertices"], info[1]["components"][0]["vertices"]) << shape;
        EXPECT_GT(info[1]["components"][0]["area"].get<double>(), 1.05 * info[0]["components"][0]["area"].get<double>())
            << shape;
    }
    const fs::path bad = dir / "fins17.obj";
    EXPECT_EQ(quadcage("generate limbs --fins 17 -o '" + bad.string() + "'").code, 2);
    EXPECT_FALSE(fs::exists(bad));
}

// generate and subdivide write OBJ or PLY by the output's extension; any other name is refused
// before any work, with exit code 3 and no file, instead of OBJ text under another format's name.
TEST(CliGenerate, RefusesAnOutputNamedForAnotherFormat) {
    const fs::path dir = scratch_dir();
    for (const char* name : {"plate.off", "plate.stl", "plate"}) {
        const fs::path file = dir / name;
        const Outcome r = quadcage("generate plate -g 2 -o '" + file.string() + "'");
        EXPECT_EQ(r.code, 3) << name;
        EXPECT_NE(r.err.find(".obj or .ply"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(file)) << name;
    }
    const fs::path upper = dir / "plate.PLY";
    ASSERT_EQ(quadcage("generate plate -g 2 -o '" + upper.string() + "'").code, 0);
    const Outcome info = quadcage("info --json '" + upper.string() + "'");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_EQ(nlohmann::json::parse(info.out)["format"].get<std::string>().rfind("ply", 0), 0u) << info.out;
    const fs::path sub = dir / "sub.off";
    EXPECT_EQ(quadcage("subdivide '" + upper.string() + "' -o '" + sub.string() + "'").code, 3);
    EXPECT_FALSE(fs::exists(sub));
}

// render writes PNG: any other output name is refused (exit 3, no file) instead of PNG bytes under
// a .jpg name.
TEST(CliRender, RefusesAnOutputNotNamedPng) {
    const fs::path dir = scratch_dir();
    const fs::path mesh = dir / "plate.obj";
    ASSERT_EQ(quadcage("generate plate -g 2 -o '" + mesh.string() + "'").code, 0);
    const fs::path jpg = dir / "plate.jpg";
    const Outcome r = quadcage("render '" + mesh.string() + "' -q -o '" + jpg.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_NE(r.err.find(".png"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(jpg));
    EXPECT_EQ(quadcage("render '" + mesh.string() + "' -q -o '" + (dir / "plate.PNG").string() + "'").code,
              0);
}

TEST(CliUsage, BadUsageExitsTwo) {
    EXPECT_EQ(quadcage("").code, 2);
    EXPECT_EQ(quadcage("frobnicate").code, 2);
    EXPECT_EQ(quadcage("info").code, 2);
    EXPECT_EQ(quadcage("info a.off --no-such-flag").code, 2);
    EXPECT_EQ(quadcage("generate cube -o x.obj").code, 2);
}

// --choose-s-cycles: by default a level-1 fit scores each S-cycle construction built and the best
// is kept; `shape` keeps the rule on patch areas and corner angles, which on this body with two
// small handles chooses another layout, in `fit` as in `layout`. Any other value is bad usage.
TEST(CliLayout, TheSCyclesAreChosenByALevelOneFitUnlessAskedOtherwise) {
    const fs::path dir = scratch_dir();
    const std::string mesh = (dir / "handles2.obj").string();
    ASSERT_EQ(quadcage("generate handles -g 2 -r 2 -o '" + mesh + "'").code, 0);
    const Outcome by_fit = quadcage("layout '" + mesh + "' -o '" + (dir / "by_fit").string() + "'");
    ASSERT_EQ(by_fit.code, 0) << by_fit.err;
    const Outcome by_shape =
        quadcage("layout '" + mesh + "' --choose-s-cycles shape -o '" + (dir / "by_shape").string() + "'");
    ASSERT_EQ(by_shape.code, 0) << by_shape.err;
    EXPECT_NE(by_fit.err.find("; scores "), std::string::npos) << by_fit.err;
    EXPECT_EQ(by_shape.err.find("; scores "), std::string::npos) << by_shape.err;
    EXPECT_NE(slurp(dir / "by_fit" / "layout.ply"), slurp(dir / "by_shape" / "layout.ply"));
    const Outcome fit_by_shape = quadcage("fit '" + mesh + "' --level 0 --choose-s-cycles shape -o '" +
                                          (dir / "fit_by_shape").string() + "'");
    ASSERT_EQ(fit_by_shape.code, 0) << fit_by_shape.err;
    EXPECT_EQ(fit_by_shape.err.find("; scores "), std::string::npos) << fit_by_shape.err;
    EXPECT_EQ(slurp(dir / "fit_by_shape" / "layout.ply"), slurp(dir / "by_shape" / "layout.ply"));
    const Outcome bad = quadcage("layout '" + mesh + "' --choose-s-cycles best -o '" + (dir / "bad").string() + "'");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--choose-s-cycles"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "bad"));
}

TEST(CliUsage, HelpExitsZeroAndListsCommands) {
    const Outcome r = quadcage("--help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("info"), std::string::npos);
    EXPECT_NE(r.out.find("Exit codes"), std::string::npos);
}

TEST(CliVersion, EveryLibraryAnswers) {
    const Outcome r = quadcage("version");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* lib : {"OpenMesh", "OpenSubdiv", "Embree", "Ceres", "Eigen", "OpenCASCADE"})
        EXPECT_NE(r.out.find(lib), std::string::npos) << lib << " missing in:\n" << r.out;
    EXPECT_EQ(r.out.find("FAILED"), std::string::npos) << r.out;
}

}  // namespace

namespace {

// Two closed components side by side: a genus-2 plate and a torus.
quadcage::Mesh two_components() {
    quadcage::Mesh m = quadcage::shapes::plate_with_holes(2);
    const quadcage::Mesh t = quadcage::shapes::torus(16, 8);
    const int base = m.num_vertices();
    for (const quadcage::Vec3& p : t.points) m.points.push_back(p + quadcage::Vec3{20, 0, 0});
    for (const quadcage::Triangle& f : t.triangles) m.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
    return m;
}

TEST(CliCycles, SeveralComponentsGetADirectoryEach) {
    const fs::path dir = scratch_dir();
    const fs::path in = dir / "two.ply", out = dir / "two_out";
    quadcage::write_ply(in.string(), two_components());
    const Outcome r = quadcage("cycles -q '" + in.string() + "' -o '" + out.string() + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json top = nlohmann::json::parse(slurp(out / "report.json"));
    ASSERT_EQ(top["components"].size(), 2u);
    const int genus[2] = {2, 1};
    for (int c = 0; c < 2; ++c) {
        const fs::path sub = out / ("component_" + std::to_string(c));
        const nlohmann::json cycles = nlohmann::json::parse(slurp(sub / "cycles.json"));
        EXPECT_EQ(cycles["orthogonal_system"].size(), 2u * genus[c]);
        EXPECT_EQ(top["components"][c]["genus"], genus[c]);
        EXPECT_TRUE(fs::exists(sub / "layout.ply"));
    }
}

TEST(CliCycles, InvalidInputWritesNothing) {
    if (!have_shared()) GTEST_SKIP() << "shared meshes not found";
    const fs::path out = scratch_dir() / "cow_out";
    const Outcome r = quadcage("cycles -q '" + shared_mesh("cow.obj") + "' -o '" + out.string() + "'");
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("pinched"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliCycles, UnwritableOutputExitsThree) {
    const fs::path dir = scratch_dir();
    const fs::path in = dir / "plate.ply", blocker = dir / "not_a_dir";
    quadcage::write_ply(in.string(), quadcage::shapes::plate_with_holes(2));
    std::ofstream(blocker) << "a file where the output directory should go";
    const Outcome r = quadcage("cycles -q '" + in.string() + "' -o '" + (blocker / "out").string() + "'");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("not_a_dir"), std::string::npos) << r.err;
}

}  // namespace

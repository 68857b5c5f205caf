// `quadcage export` and `fit --step/--iges` as a user runs them (issue 22).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <system_error>

#include "quadcage/cad/cad_export.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"
#include "support/files.h"

namespace quadcage::cad {
namespace {

namespace fs = std::filesystem;
using test::run_logged;
using test::shell_quoted;

const std::string kCli = QUADCAGE_CLI;
const std::string kEight = std::string(QUADCAGE_DATA_DIR) + "/eight.off";

// Removes the shared scratch directory when the test program ends.
struct RemoveAtExit {
    fs::path dir;
    ~RemoveAtExit() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

// One level-1 fit of eight for every test here (the fit is not what they test).
const fs::path& eight_fit() {
    static const RemoveAtExit cleanup{fs::temp_directory_path() /
                                      ("qc_export_cli_" + std::to_string(::getpid()))};
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / ("qc_export_cli_" + std::to_string(::getpid()));
        fs::remove_all(d);
        std::string log;
        fs::create_directories(d);
        const int code =
            run_logged(kCli + " fit " + shell_quoted(kEight) + " --level 1 -q -o " + shell_quoted(d / "fit"),
                       d / "fit.log", &log);
        EXPECT_EQ(code, 0) << log;
        return d;
    }();
    return dir;
}

TEST(ExportCli, WritesAValidStepAndItsReport) {
    const fs::path fit = eight_fit() / "fit";
    fs::remove(fit / "surface.step");
    std::string log;
    ASSERT_EQ(run_logged(kCli + " export -q " + shell_quoted(fit), eight_fit() / "export.log", &log), 0)
        << log;
    EXPECT_NE(log.find("valid closed solid, 10 faces"), std::string::npos) << log;
    const ReadBack back = read_back((fit / "surface.step").string());
    EXPECT_EQ(back.solids, 1);
    EXPECT_EQ(back.faces, 10);
    EXPECT_TRUE(back.valid);
    EXPECT_TRUE(back.closed);
    const nlohmann::json r = nlohmann::json::parse(test::slurp(fit / "export.json"));
    EXPECT_EQ(r["faces"], 10);
    EXPECT_EQ(r["free_edges"], 0);
    EXPECT_TRUE(r["valid"].get<bool>());
    EXPECT_LE(r["relative_max_deviation"].get<double>(), 1e-5);
    EXPECT_NEAR(r["volume"].get<double>() / back.volume, 1.0, 1e-9);
}

TEST(ExportCli, BadInputExitsThreeWithOneLineAndWritesNothing) {
    const fs::path base = eight_fit();
    std::string log;
    fs::create_directories(base / "empty");
    EXPECT_EQ(run_logged(kCli + " export -q " + shell_quoted(base / "empty"), base / "e1.log", &log), 3)
        << log;
    EXPECT_NE(log.find("report.json: missing"), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
    EXPECT_TRUE(fs::is_empty(base / "empty"));
    // A fitted cage from another fit: the counts disagree.
    fs::remove_all(base / "mixed");
    fs::create_directories(base / "mixed");
    fs::copy_file(base / "fit" / "report.json", base / "mixed" / "report.json");
    write_text_file((base / "mixed" / "fitted_cage.obj").string(),
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    EXPECT_EQ(run_logged(kCli + " export -q " + shell_quoted(base / "mixed"), base / "e2.log", &log), 3)
        << log;
    EXPECT_NE(log.find("fitted_cage.obj: 4 vertices, but"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(base / "mixed" / "surface.step"));
    EXPECT_FALSE(fs::exists(base / "mixed" / "export.json"));
}

// What `fit --cage CAGE --level 0` writes for a cage of triangles (the icosahedron): fitted_cage.obj
// holds CAGE's own faces, and the export has one face per quad of CAGE refined once.
TEST(ExportCli, CageFitWithTrianglesExportsOneFacePerQuadOfItsRefinement) {
    const fs::path dir = eight_fit() / "ico_cage";
    fs::create_directories(dir);
    const Mesh ico = shapes::icosphere(0, 1.0);
    std::string obj = "# icosahedron\n";
    for (const Vec3& p : ico.points)
        obj += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (const Triangle& t : ico.triangles)
        obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
               std::to_string(t[2] + 1) + "\n";
    write_text_file((dir / "fitted_cage.obj").string(), obj);
    const nlohmann::json report = {
        {"command", "fit"},
        {"cage", "ico.obj"},
        {"level", 0},
        {"diagonal", 2.0},
        {"control_mesh", {{"faces", 20}, {"vertices", 12}}},
        {"fitted_cage", {{"vertices", 12 + 30 + 20}, {"quads", 60}, {"level0_faces", 20}}}};
    write_text_file((dir / "report.json").string(), report.dump(2));
    std::string log;
    ASSERT_EQ(
        run_logged(kCli + " export -q " + shell_quoted(dir) + " --iges " + shell_quoted(dir / "ico.igs"),
                   dir / "x.log", &log),
        0)
        << log;
    EXPECT_NE(log.find("valid closed solid, 60 faces"), std::string::npos) << log;
    const ReadBack back = read_back((dir / "ico.igs").string());
    EXPECT_EQ(back.faces, 60);
    EXPECT_TRUE(back.closed);
    EXPECT_TRUE(back.valid);
    EXPECT_FALSE(fs::exists(dir / "surface.step"));  // only the file asked for
}

TEST(ExportCli, ToleranceBelowTheFloorIsAUsageErrorAndAnUnreachableOneExitsThree) {
    const fs::path fit = eight_fit() / "fit";
    const fs::path out = eight_fit() / "t.step";
    std::string log;
    EXPECT_EQ(run_logged(kCli + " export -q " + shell_quoted(fit) + " --step " + shell_quoted(out) +
                             " --cad-tolerance 1e-10",
                         eight_fit() / "t1.log", &log),
              2)
        << log;
    EXPECT_EQ(run_logged(kCli + " export -q " + shell_quoted(fit) + " --step " + shell_quoted(out) +
                             " --cad-tolerance 1e-9",
                         eight_fit() / "t2.log", &log),
              3)
        << log;
    EXPECT_NE(log.find("cannot be reached"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(out));
}

TEST(ExportCli, FitWithStepWritesEverythingOrNothing) {
    const fs::path base = eight_fit();
    std::string log;
    EXPECT_EQ(
        run_logged(kCli + " fit " + shell_quoted(kEight) + " --level 1 -q -o " + shell_quoted(base / "one") +
                       " --step " + shell_quoted(base / "one" / "eight.step") + " --iges " +
                       shell_quoted(base / "eight.igs"),
                   base / "f1.log", &log),
        0)
        << log;
    EXPECT_EQ(read_back((base / "one" / "eight.step").string()).faces, 10);
    EXPECT_EQ(read_back((base / "eight.igs").string()).faces, 10);
    const nlohmann::json r = nlohmann::json::parse(test::slurp(base / "one" / "report.json"));
    EXPECT_EQ(r["cad"]["faces"], 10);
    EXPECT_EQ(
        run_logged(kCli + " fit " + shell_quoted(kEight) + " --level 1 -q -o " + shell_quoted(base / "two") +
                       " --step " + shell_quoted(base / "two.step") + " --cad-tolerance 1e-9",
                   base / "f2.log", &log),
        3)
        << log;
    EXPECT_FALSE(fs::exists(base / "two"));
    EXPECT_FALSE(fs::exists(base / "two.step"));
}

}  // namespace
}  // namespace quadcage::cad

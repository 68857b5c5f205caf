// Failure isolation and result collection of run_bench(), with a fake child (tests/bench/fake_child.cpp)
// standing in for the layout and fit commands and for Blender; pictures come from the real CLI.

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "quadcage/bench/bench_runner.h"
#include "quadcage/bench/tables.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"
#include "quadcage/render/image.h"

namespace {

namespace fs = std::filesystem;
using namespace quadcage;
using namespace quadcage::bench;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class BenchRunner : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("quadcage_bench_test_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "in");
    }
    void TearDown() override {
        if (!HasFailure() && !std::getenv("QUADCAGE_KEEP_TEST_OUTPUT")) fs::remove_all(dir_);
    }

    // A small sphere saved under a name that tells the fake child how to behave.
    BenchInput mesh(const std::string& name) {
        const std::string path = (dir_ / "in" / (name + ".ply")).string();
        write_ply(path, shapes::icosphere(2));
        return {path, name, name};
    }

    BenchOptions options() {
        BenchOptions o;
        o.output_dir = (dir_ / "out").string();
        o.executable = FAKE_CHILD;
        o.levels = {0, 1};
        o.timeout_seconds = 20;
        o.jobs = 2;
        o.commands.render = {QUADCAGE_CLI, "render", "{input}", "-o", "{png}", "--kind", "{kind}", "--size", "600x300",
                             "-q"};
        o.blender = FAKE_CHILD;
        o.peer_script = FAKE_CHILD;  // any existing file; the fake ignores it
        o.commands.peer = {"{blender}", "quadriflow", "{mesh}", "{out}", "{faces}", "{seed}"};
        return o;
    }

    fs::path dir_;
};

const MeshResult& by_name(const BenchResult& r, const std::string& name) {
    for (const MeshResult& m : r.meshes)
        if (m.input.name == name) return m;
    throw std::runtime_error("no mesh " + name);
}

TEST_F(BenchRunner, CrashTimeoutRejectionAndErrorsAreRecordedAndTheRunGoesOn) {
    std::vector<BenchInput> inputs = {mesh("good"), mesh("crash"), mesh("segv"), mesh("sleep"),
                                      mesh("reject"), mesh("fail"), mesh("fitdies"), mesh("unverified")};
    BenchOptions o = options();
    o.timeout_seconds = 3;
    o.pictures = false;
    std::vector<std::string> lines;
    o.progress = [&](const std::string& l) { lines.push_back(l); };
    const BenchResult r = run_bench(inputs, o);
    ASSERT_EQ(r.meshes.size(), inputs.size());
    EXPECT_EQ(by_name(r, "good").status, "ok");
    EXPECT_EQ(by_name(r, "crash").status, "failed: crashed (signal " + std::to_string(SIGABRT) + ")");
    EXPECT_EQ(by_name(r, "crash").stage, "layout");
    EXPECT_EQ(by_name(r, "segv").status, "failed: crashed (signal " + std::to_string(SIGSEGV) + ")");
    EXPECT_EQ(by_name(r, "sleep").status, "failed: timeout after 3 s");
    EXPECT_EQ(by_name(r, "reject").status, "rejected");
    EXPECT_EQ(by_name(r, "reject").stage, "info");
    EXPECT_NE(by_name(r, "reject").reason.find("cannot be quadded: 3 boundary edges"), std::string::npos)
        << by_name(r, "reject").reason;
    EXPECT_EQ(by_name(r, "fail").status, "failed: internal error: fake layout failure");
    EXPECT_EQ(by_name(r, "unverified").status, "failed: the layout verifier rejected the layout");
    // A fit that crashes at level 1 keeps level 0.
    const MeshResult& fd = by_name(r, "fitdies");
    EXPECT_EQ(fd.stage, "fit");
    ASSERT_EQ(fd.levels.size(), 2u);
    EXPECT_EQ(fd.levels[0].status, "ok");
    EXPECT_EQ(fd.levels[0].control_points, 8);
    EXPECT_EQ(fd.levels[1].status, "failed: crashed (signal " + std::to_string(SIGSEGV) + ")");
    // A failed layout runs no fit.
    EXPECT_TRUE(by_name(r, "crash").levels.empty());

    // The timed-out child's grandchild was killed with its process group (gone or a zombie).
    const std::string pid_text = slurp(dir_ / "out" / "meshes" / "sleep" / "grandchild.pid");
    ASSERT_FALSE(pid_text.empty());
    const std::string stat = slurp("/proc/" + std::to_string(std::stoi(pid_text)) + "/stat");
    if (!stat.empty()) {
        EXPECT_NE(stat.find(") Z"), std::string::npos) << stat;
    }

    // Each mesh's log holds its stages' stderr.
    EXPECT_NE(slurp(dir_ / "out" / "meshes" / "fail" / "log.txt").find("fake layout failure"), std::string::npos);
    // Progress: one line per stage start and one per mesh end, in the documented form.
    bool saw = false;
    for (const std::string& l : lines) saw = saw || l.rfind("bench [2/8] crash: layout (", 0) == 0;
    EXPECT_TRUE(saw);

    // The same statuses in bench.json and bench.csv.
    write_bench_tables(o.output_dir, r);
    const auto j = nlohmann::json::parse(slurp(dir_ / "out" / "bench.json"));
    EXPECT_EQ(j["summary"]["ok"], 1);
    EXPECT_EQ(j["summary"]["rejected"], 1);
    EXPECT_EQ(j["summary"]["failed"], 6);
    EXPECT_EQ(j["meshes"][3]["status"], "failed: timeout after 3 s");
    EXPECT_EQ(j["meshes"][1]["levels"].size(), 0u);
    const std::string csv = slurp(dir_ / "out" / "bench.csv");
    EXPECT_NE(csv.find("crash,"), std::string::npos);
    EXPECT_NE(csv.find(",failed: crashed (signal " + std::to_string(SIGABRT) + "),layout,"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",rejected,info,"), std::string::npos);
}

TEST_F(BenchRunner, ReadsTheChildReportsDrawsPicturesAndTheRmsPlot) {
    const BenchInput good = mesh("good");
    const BenchResult r = run_bench({good}, options());
    ASSERT_EQ(r.meshes.size(), 1u);
    const MeshResult& m = r.meshes[0];
    EXPECT_EQ(m.status, "ok") << m.reason;
    EXPECT_EQ(m.triangles, shapes::icosphere(2).num_triangles());
    EXPECT_EQ(m.genus, "0");
    EXPECT_EQ(m.minimal_quads, 6);
    EXPECT_EQ(m.quads, 8);
    EXPECT_EQ(m.corners, 6);
    EXPECT_EQ(m.corner_degrees, (std::map<int, int>{{4, 6}}));
    EXPECT_EQ(m.verified, true);
    EXPECT_DOUBLE_EQ(m.layout_seconds.value_or(-1), 0.25);
    ASSERT_EQ(m.levels.size(), 2u);
    EXPECT_EQ(m.levels[1].control_points, 32);
    EXPECT_DOUBLE_EQ(m.levels[1].relative_rms.value_or(-1), 0.005);
    EXPECT_DOUBLE_EQ(m.levels[1].relative_hausdorff.value_or(-1), 0.02);
    EXPECT_DOUBLE_EQ(m.levels[1].fit_seconds.value_or(-1), 1.5);
    EXPECT_GT(m.peak_memory_mib.value_or(0), 0);

    // Pictures drawn by `quadcage render` children: real PNGs of the requested size.
    ASSERT_EQ(m.layout_png, "meshes/good/layout.png");
    const render::Image layout = render::read_png((fs::path(options().output_dir) / m.layout_png).string());
    EXPECT_EQ(layout.width(), 600);
    ASSERT_EQ(m.levels[0].deviation_png, "meshes/good/level0/deviation.png");
    EXPECT_TRUE(fs::exists(fs::path(options().output_dir) / m.levels[1].deviation_png));
    ASSERT_EQ(r.plot_png, "plot.png");
    EXPECT_GT(render::read_png((fs::path(options().output_dir) / "plot.png").string()).width(), 0);

    // Peer at each level: QuadriFlow at our control-face count (8 quads * 4^K), the remesh fitted at
    // level 0 by the fit --cage command; its figures and the ratios ours / peer.
    ASSERT_EQ(m.peers.size(), 2u);
    for (int k = 0; k < 2; ++k) {
        const PeerResult& p = m.peers[k];
        SCOPED_TRACE("level " + std::to_string(k));
        EXPECT_EQ(p.level, k);
        EXPECT_EQ(p.target_faces, 8 << (2 * k));
        EXPECT_EQ(p.status, "ok");
        ASSERT_EQ(p.attempts.size(), 1u);
        EXPECT_EQ(p.attempts[0].seed, 0);
        EXPECT_EQ(p.attempts[0].outcome, "ok");
        EXPECT_EQ(p.control_points, m.levels[k].control_points);  // the fake's box has as many vertices as asked
        EXPECT_EQ(p.faces, p.control_points.value_or(0) - 2);
        EXPECT_NEAR(p.relative_rms.value_or(-1), 0.02 / std::sqrt(8 << (2 * k)), 1e-12);
        EXPECT_NEAR(p.relative_hausdorff.value_or(-1), 0.1 / std::sqrt(8 << (2 * k)), 1e-12);
        EXPECT_DOUBLE_EQ(p.fit_seconds.value_or(-1), 0.25);
        EXPECT_DOUBLE_EQ(p.quadriflow_seconds.value_or(-1), 0.5);
        EXPECT_EQ(p.cage, "meshes/good/peer/level" + std::to_string(k) + "/quadriflow_" + std::to_string(8 << (2 * k)) +
                              "_seed0.obj");
        const PeerComparison c = compare_with_peer(m.levels[k], &p);
        ASSERT_TRUE(c.counted()) << c.note;
        EXPECT_NEAR(*c.rms_ratio, *m.levels[k].relative_rms / *p.relative_rms, 1e-12);
        EXPECT_NEAR(*c.rms_ratio, std::sqrt(2.0), 1e-9);  // 0.01 / 2^K against 0.02 / (sqrt(8) 2^K)
        EXPECT_NEAR(*c.hausdorff_ratio, 0.04 * std::sqrt(8.0) / 0.1, 1e-9);
    }
    // bench.md links the pictures relative to its folder.
    write_bench_tables(options().output_dir, r);
    const std::string md = slurp(fs::path(options().output_dir) / "bench.md");
    EXPECT_NE(md.find("](meshes/good/layout.png)"), std::string::npos);
    EXPECT_NE(md.find("](meshes/good/level1/deviation.png)"), std::string::npos);
    EXPECT_NE(md.find("](plot.png)"), std::string::npos);
    EXPECT_NE(md.find("| good | 1 | 32 / 32 |"), std::string::npos) << md;
    // The summary line carries the ratios over the two counted rows.
    EXPECT_NE(summary_line(r).find("ours / QuadriFlow over 2 rows: RMS worst 1.41 median 1.41, Hausdorff worst 1.13 "
                                   "median 1.13"),
              std::string::npos)
        << summary_line(r);
}

TEST_F(BenchRunner, PeerStatusWithoutBlenderWhenDisabledAndWhenItFails) {
    const BenchInput a = mesh("good");
    BenchOptions o = options();
    o.pictures = false;
    o.levels = {0, 1};
    o.blender = (dir_ / "no-such-blender").string();
    BenchResult r = run_bench({a}, o);
    ASSERT_EQ(r.meshes[0].peers.size(), 2u);
    EXPECT_EQ(r.meshes[0].peers[0].status, "not installed");
    EXPECT_EQ(r.meshes[0].peers[1].status, "not installed");
    EXPECT_TRUE(r.meshes[0].peers[0].attempts.empty());
    EXPECT_EQ(r.meshes[0].status, "ok");
    EXPECT_EQ(compare_with_peer(r.meshes[0].levels[0], &r.meshes[0].peers[0]).note, "n/a (peer not installed)");
    EXPECT_EQ(summary_line(r).find("QuadriFlow"), std::string::npos) << summary_line(r);
    write_bench_tables(o.output_dir, r);
    const auto j = nlohmann::json::parse(slurp(dir_ / "out" / "bench.json"));
    EXPECT_EQ(j["meshes"][0]["peer"][1]["status"], "not installed");
    EXPECT_TRUE(j["meshes"][0]["peer"][1]["rms_ratio"].is_null());

    o.peer = false;
    r = run_bench({a}, o);
    EXPECT_EQ(r.meshes[0].peers[0].status, "disabled");

    // QuadriFlow failing every time: each attempt recorded (seeds 1 and 2, then nearby targets: 8 +-5%
    // rounds to 8, already tried with seed 0, so 8 + 10% -> 9).
    o = options();
    o.pictures = false;
    o.levels = {0};
    r = run_bench({mesh("peerbroken")}, o);
    EXPECT_EQ(r.meshes[0].status, "ok");  // the peer failing is not our failure
    const PeerResult& p = r.meshes[0].peers.at(0);
    EXPECT_EQ(p.status, "failed: quadriflow: error: QuadriFlow failed: the mesh is unchanged");
    ASSERT_EQ(p.attempts.size(), 4u);
    const std::pair<int, int> expected[] = {{8, 0}, {8, 1}, {8, 2}, {8, 0}};
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(p.attempts[i].target_faces, expected[i].first);
        EXPECT_EQ(p.attempts[i].seed, expected[i].second);
        EXPECT_EQ(p.attempts[i].outcome, p.status);
    }
    EXPECT_EQ(p.attempts[3].target_faces, 9);
    EXPECT_EQ(p.attempts[3].seed, 0);
    EXPECT_EQ(p.attempts[3].outcome, p.status);
    EXPECT_FALSE(p.control_points.has_value());
    EXPECT_EQ(summary_line(r).substr(summary_line(r).find(';', summary_line(r).find("wall"))),
              "; ours / QuadriFlow: no row at equal control points");
}

// A first remesh that is unusable (wrong genus, empty, open, refused by our fitter) is recorded with
// its reason, and the next seed is tried.
TEST_F(BenchRunner, PeerRetriesAnUnusableRemeshWithAnotherSeed) {
    BenchOptions o = options();
    o.pictures = false;
    o.levels = {1};
    const BenchResult r =
        run_bench({mesh("peergenus"), mesh("peerempty"), mesh("peeropen"), mesh("peerfitrefuse")}, o);
    const std::pair<const char*, const char*> cases[] = {
        {"peergenus", "wrong genus 1 (input 0)"},
        {"peerempty", "empty output (no faces)"},
        {"peeropen", "open (4 boundary edges)"},
        {"peerfitrefuse", "fit rejected: "}};
    for (const auto& [name, reason] : cases) {
        SCOPED_TRACE(name);
        const MeshResult& m = by_name(r, name);
        ASSERT_EQ(m.peers.size(), 1u);
        const PeerResult& p = m.peers[0];
        EXPECT_EQ(p.status, "ok");
        ASSERT_EQ(p.attempts.size(), 2u);
        EXPECT_EQ(p.attempts[0].target_faces, 32);
        EXPECT_EQ(p.attempts[0].seed, 0);
        EXPECT_EQ(p.attempts[0].outcome.rfind(reason, 0), 0u) << p.attempts[0].outcome;
        EXPECT_EQ(p.attempts[1].target_faces, 32);
        EXPECT_EQ(p.attempts[1].seed, 1);
        EXPECT_EQ(p.attempts[1].outcome, "ok");
        EXPECT_EQ(p.control_points, 32);
        EXPECT_EQ(p.cage, "meshes/" + std::string(name) + "/peer/level1/quadriflow_32_seed1.obj");
        EXPECT_TRUE(compare_with_peer(m.levels.at(0), &p).counted());
    }
    EXPECT_NE(by_name(r, "peerfitrefuse").peers[0].attempts[0].outcome.find("the cage is far from the mesh"),
              std::string::npos);
    // The failed attempts are listed in bench.md and bench.json.
    write_bench_tables(o.output_dir, r);
    const std::string md = slurp(dir_ / "out" / "bench.md");
    EXPECT_NE(md.find("- peergenus level 1, 32 faces, seed 0: wrong genus 1 (input 0) (16 faces)"), std::string::npos)
        << md;
    const auto j = nlohmann::json::parse(slurp(dir_ / "out" / "bench.json"));
    EXPECT_EQ(j["meshes"][1]["peer"][0]["attempts"][0]["outcome"], "empty output (no faces)");
    EXPECT_EQ(j["meshes"][1]["peer"][0]["attempts"][1]["seed"], 1);
}

// A remesh with half the vertices asked for: the next attempt asks for twice the faces and matches.
TEST_F(BenchRunner, PeerRetargetsWhenTheCountIsOff) {
    BenchOptions o = options();
    o.pictures = false;
    o.levels = {1};
    const BenchResult r = run_bench({mesh("peerhalf")}, o);
    const PeerResult& p = r.meshes[0].peers.at(0);
    EXPECT_EQ(p.status, "ok");
    ASSERT_EQ(p.attempts.size(), 2u);
    EXPECT_EQ(p.attempts[0].vertices, 16);
    EXPECT_EQ(p.attempts[0].outcome, "control points 16 not within 10% of ours 32");
    EXPECT_EQ(p.attempts[1].target_faces, 64);
    EXPECT_EQ(p.attempts[1].seed, 0);
    EXPECT_EQ(p.control_points, 32);
    EXPECT_TRUE(compare_with_peer(r.meshes[0].levels.at(0), &p).counted());
}

// A remesh that never reaches our count is fitted (the closest one) but its ratios do not count.
TEST_F(BenchRunner, PeerRatioIsSuppressedWhenTheCountsDifferByMoreThanTenPercent) {
    BenchOptions o = options();
    o.pictures = false;
    o.levels = {0, 1};
    const BenchResult r = run_bench({mesh("peercoarse")}, o);
    const MeshResult& m = r.meshes[0];
    ASSERT_EQ(m.peers.size(), 2u);
    EXPECT_TRUE(compare_with_peer(m.levels[0], &m.peers[0]).counted());  // a cube is right at level 0 (8 points)
    const PeerResult& p = m.peers[1];
    EXPECT_EQ(p.status, "ok");
    ASSERT_EQ(p.attempts.size(), 4u);
    for (const PeerAttempt& a : p.attempts) EXPECT_EQ(a.vertices, 8);
    EXPECT_EQ(p.attempts[1].target_faces, 128);  // 32 * 32 / 8
    EXPECT_EQ(p.attempts[0].outcome, "control points 8 not within 10% of ours 32 (fitted: the closest count)");
    EXPECT_EQ(p.control_points, 8);
    ASSERT_TRUE(p.relative_rms.has_value());
    const PeerComparison c = compare_with_peer(m.levels[1], &p);
    EXPECT_FALSE(c.counted());
    EXPECT_FALSE(c.hausdorff_ratio.has_value());
    EXPECT_EQ(c.note, "n/a (32 vs 8 control points)");
    EXPECT_NE(summary_line(r).find("ours / QuadriFlow over 1 row: "), std::string::npos) << summary_line(r);
    write_bench_tables(o.output_dir, r);
    const std::string csv = slurp(dir_ / "out" / "bench.csv");
    EXPECT_NE(csv.find(",n/a (32 vs 8 control points),"), std::string::npos) << csv;
    const std::string md = slurp(dir_ / "out" / "bench.md");
    EXPECT_NE(md.find("| n/a (32 vs 8 control points) | n/a (32 vs 8 control points) |"), std::string::npos) << md;
    const auto j = nlohmann::json::parse(slurp(dir_ / "out" / "bench.json"));
    EXPECT_TRUE(j["meshes"][0]["peer"][1]["rms_ratio"].is_null());
    EXPECT_EQ(j["meshes"][0]["peer"][1]["ratio_note"], "n/a (32 vs 8 control points)");
    EXPECT_EQ(j["summary"]["peer_ratios"]["rows"], 1);
}

TEST_F(BenchRunner, ToleranceIsPassedToFit) {
    // The fit template echoes its argv into the log through a shell.
    BenchOptions o = options();
    o.pictures = false;
    o.peer = false;
    o.levels = {2};
    o.tolerance = 0.001;
    o.commands.fit = {"/bin/sh", "-c", "echo fit-args: \"$@\" >&2", "sh", "{mesh}", "--level", "{level}"};
    const BenchResult r = run_bench({mesh("good")}, o);
    const std::string log = slurp(dir_ / "out" / "meshes" / "good" / "log.txt");
    EXPECT_NE(log.find("--level 2 --tolerance 0.001"), std::string::npos) << log;
    EXPECT_EQ(r.meshes[0].levels[0].status, "failed: no readable report.json");
}

/// A stage command that logs its argv ("TAG: args") through a shell, then runs it ($0: the fake child).
std::vector<std::string> logged(const char* tag, std::vector<std::string> argv) {
    argv.insert(argv.begin(), {"/bin/sh", "-c", std::string("echo ") + tag + ": \"$@\" >&2; exec \"$0\" \"$@\""});
    return argv;
}

/// The line of `log` that starts with "TAG:", or "" if none does.
std::string logged_line(const std::string& log, const std::string& tag) {
    const size_t at = log.find(tag + ":");
    return at == std::string::npos ? std::string() : log.substr(at, log.find('\n', at) - at);
}

TEST_F(BenchRunner, LayoutFlagsReachTheLayoutAndOurFitsButNotThePeersFit) {
    BenchOptions o = options();
    o.pictures = false;
    o.levels = {0};
    o.layout_flags = {"--embedding-iterations", "30", "--embedding-extract"};
    o.commands.layout = logged("layout-args", {"{exe}", "layout", "{mesh}", "-o", "{dir}"});
    o.commands.fit = logged("fit-args", {"{exe}", "fit", "{mesh}", "-o", "{dir}", "--level", "{level}"});
    o.commands.peer_fit = logged(
        "peer-fit-args", {"{exe}", "fit", "{mesh}", "--cage", "{cage}", "--level", "0", "-o", "{dir}"});
    const BenchResult r = run_bench({mesh("good")}, o);
    ASSERT_EQ(r.meshes[0].status, "ok");
    const std::string log = slurp(dir_ / "out" / "meshes" / "good" / "log.txt");
    const auto line = [&](const std::string& tag) { return logged_line(log, tag); };
    EXPECT_NE(line("layout-args").find("--embedding-iterations 30 --embedding-extract"), std::string::npos)
        << log;
    EXPECT_NE(line("fit-args").find("--level 0 --embedding-iterations 30 --embedding-extract"),
              std::string::npos)
        << log;
    ASSERT_NE(line("peer-fit-args"), "") << log;
    EXPECT_EQ(line("peer-fit-args").find("--embedding"), std::string::npos) << log;
    write_bench_tables(o.output_dir, r);
    const auto j = nlohmann::json::parse(slurp(dir_ / "out" / "bench.json"));
    EXPECT_EQ(j["layout_flags"], nlohmann::json({"--embedding-iterations", "30", "--embedding-extract"}));
    EXPECT_NE(slurp(dir_ / "out" / "bench.md").find("`--embedding-iterations 30 --embedding-extract`"),
              std::string::npos);
}

/// One bench run of `input` (a mesh named "good") at level 0 into `out`, with both fit commands
/// logged; returns the mesh's log and the run's bench.json and bench.md (tables written).
struct LoggedFits {
    std::string log, md;
    nlohmann::json json;
};
LoggedFits run_logged_fits(BenchOptions o, const BenchInput& input, const fs::path& out) {
    o.pictures = false;
    o.levels = {0};
    o.output_dir = out.string();
    o.commands.fit = logged("fit-args", {"{exe}", "fit", "{mesh}", "-o", "{dir}", "--level", "{level}"});
    o.commands.peer_fit =
        logged("peer-fit-args", {"{exe}", "fit", "{mesh}", "--cage", "{cage}", "--level", "0", "-o", "{dir}"});
    const BenchResult r = run_bench({input}, o);
    EXPECT_EQ(r.meshes[0].status, "ok");
    write_bench_tables(o.output_dir, r);
    return {slurp(out / "meshes" / "good" / "log.txt"), slurp(out / "bench.md"),
            nlohmann::json::parse(slurp(out / "bench.json"))};
}

TEST_F(BenchRunner, RoundsReachOurFitsAndThePeersFit) {
    // Both fits of a level must use the same fitter settings: the ratios compare the cages.
    BenchOptions o = options();
    o.fit_rounds = 5;
    const LoggedFits with = run_logged_fits(o, mesh("good"), dir_ / "out");
    EXPECT_NE(logged_line(with.log, "fit-args").find("--level 0 --rounds 5"), std::string::npos) << with.log;
    EXPECT_NE(logged_line(with.log, "peer-fit-args").find("--level 0 -o"), std::string::npos) << with.log;
    EXPECT_NE(logged_line(with.log, "peer-fit-args").find("--rounds 5"), std::string::npos) << with.log;
    EXPECT_EQ(with.json["fit_rounds"], 5);
    EXPECT_NE(with.md.find("`--rounds 5`"), std::string::npos);

    // Without it, neither fit gets the flag and the tables say null.
    o.fit_rounds = 0;
    const LoggedFits without = run_logged_fits(o, mesh("good"), dir_ / "out2");
    EXPECT_EQ(without.log.find("--rounds"), std::string::npos);
    EXPECT_TRUE(without.json["fit_rounds"].is_null());
}

TEST_F(BenchRunner, TheTurnedOverWeightReachesOurFitsAndThePeersFit) {
    BenchOptions o = options();
    o.turned_over_weight = 0.01;
    const LoggedFits with = run_logged_fits(o, mesh("good"), dir_ / "out");
    EXPECT_NE(logged_line(with.log, "fit-args").find("--level 0 --turned-over-weight 0.01"), std::string::npos) << with.log;
    EXPECT_NE(logged_line(with.log, "peer-fit-args").find("--turned-over-weight 0.01"), std::string::npos) << with.log;
    EXPECT_EQ(with.json["turned_over_weight"], 0.01);
    EXPECT_NE(with.md.find("`--turned-over-weight 0.01`"), std::string::npos);

    // 0 is passed too (the term off on both sides); unset, neither fit gets the flag.
    o.turned_over_weight = 0.0;
    const LoggedFits off = run_logged_fits(o, mesh("good"), dir_ / "out0");
    EXPECT_NE(logged_line(off.log, "fit-args").find("--turned-over-weight 0"), std::string::npos) << off.log;
    EXPECT_NE(logged_line(off.log, "peer-fit-args").find("--turned-over-weight 0"), std::string::npos) << off.log;
    EXPECT_EQ(off.json["turned_over_weight"], 0.0);

    o.turned_over_weight.reset();
    const LoggedFits unset = run_logged_fits(o, mesh("good"), dir_ / "out2");
    EXPECT_EQ(unset.log.find("--turned-over-weight"), std::string::npos);
    EXPECT_TRUE(unset.json["turned_over_weight"].is_null());
}

TEST_F(BenchRunner, AMissingStageCommandIsAFailureNotAnAbort) {
    BenchOptions o = options();
    o.pictures = false;
    o.peer = false;
    o.commands.layout = {(dir_ / "missing-layout-tool").string(), "{mesh}"};
    const BenchResult r = run_bench({mesh("good")}, o);
    EXPECT_EQ(r.meshes[0].stage, "layout");
    EXPECT_NE(r.meshes[0].status.find("failed: cannot run"), std::string::npos) << r.meshes[0].status;
}

TEST(BenchOptionsValidate, RejectsBadValues) {
    BenchOptions o;
    o.output_dir = "/tmp/x";
    o.executable = "/bin/true";
    EXPECT_EQ(o.validate(), "");
    o.jobs = 0;
    EXPECT_NE(o.validate(), "");
    o.jobs = 1;
    o.fit_rounds = -1;
    EXPECT_NE(o.validate().find("rounds"), std::string::npos);
    o.fit_rounds = 1001;
    EXPECT_NE(o.validate().find("rounds"), std::string::npos);
    o.fit_rounds = 0;
    o.turned_over_weight = -0.1;
    EXPECT_NE(o.validate().find("turned-over"), std::string::npos);
    o.turned_over_weight = std::nan("");
    EXPECT_NE(o.validate().find("turned-over"), std::string::npos);
    o.turned_over_weight = 0.0;
    EXPECT_EQ(o.validate(), "");
    o.turned_over_weight.reset();
    o.levels = {0, 0};
    EXPECT_NE(o.validate().find("twice"), std::string::npos);
    o.levels = {9};
    EXPECT_NE(o.validate().find("outside"), std::string::npos);
    o.levels = {};
    o.timeout_seconds = 0;
    EXPECT_NE(o.validate(), "");
    EXPECT_THROW(run_bench({}, o), InvalidInput);
}

// The real quadcage executable: info works today; layout/fit may not exist yet, which must be a
// recorded failure of that stage (or, once they exist, success).
TEST_F(BenchRunner, RealQuadcageOnTheBundledMesh) {
    BenchOptions o = options();
    o.executable = QUADCAGE_CLI;
    o.commands = StageCommands{};
    o.peer = false;
    o.levels = {0};
    const BenchInput eight{std::string(QUADCAGE_DATA_DIR) + "/eight.off", "eight", "eight"};
    const BenchResult r = run_bench({eight}, o);
    const MeshResult& m = r.meshes[0];
    EXPECT_EQ(m.triangles, 1536);
    EXPECT_EQ(m.genus, "2");
    EXPECT_EQ(m.minimal_quads, 10);
    EXPECT_EQ(m.components, 1);
    if (m.status != "ok") {
        EXPECT_EQ(m.status.rfind("failed: ", 0), 0u) << m.status;
        EXPECT_TRUE(m.stage == "layout" || m.stage == "fit") << m.stage;
        EXPECT_GT(m.status.size(), std::string("failed: ").size());
    }
}

}  // namespace

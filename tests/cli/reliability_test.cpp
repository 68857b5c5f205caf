// Issue 23 end to end: hostile inputs give exit 3 with one line naming the file, outputs never
// replace an input (exit 2), and a run that fails leaves the output directory as it was. Every input
// is built here.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"
#include "support/files.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;
using test::shell_quoted;
using test::slurp;

struct CliRun {
    int code = -1;
    std::string out, err;
    double seconds = 0;
};

class CliReliability : public testing::Test {
protected:
    void SetUp() override { dir_ = test::scratch_dir("quadcage_cli_rel_"); }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    // Runs the CLI with `args` (each shell-quoted here).
    CliRun cli(const std::vector<std::string>& args) const {
        std::string cmd = shell_quoted(QUADCAGE_CLI);
        for (const std::string& a : args) cmd += " " + shell_quoted(a);
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const auto t0 = std::chrono::steady_clock::now();
        CliRun r;
        r.code = test::run_shell(cmd + " >" + shell_quoted(out) + " 2>" + shell_quoted(err) + " </dev/null");
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r.out = slurp(out);
        r.err = slurp(err);
        fs::remove(out);
        fs::remove(err);
        return r;
    }

    std::string write_bytes(const fs::path& p, const std::string& bytes) const {
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }

    fs::path dir_;
};

// Every entry under `root` (relative path -> "dir" or "file:<contents>").
std::map<std::string, std::string> snapshot(const fs::path& root) {
    std::map<std::string, std::string> out;
    if (!fs::exists(root)) return out;
    for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it)
        out[it->path().lexically_relative(root).string()] = it->is_directory() ? "dir" : "file:" + slurp(it->path());
    return out;
}

// One line on stderr, "quadcage: error: <path>...<expected>...".
void expect_one_line(const CliRun& r, const std::string& path, const std::string& expected, int code = 3) {
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("quadcage: error: " + path, 0), 0u) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.err;
    EXPECT_LT(r.seconds, 20.0) << r.err;  // by hand each takes well under a second (see the note)
}

Mesh scaled(Mesh m, double s) {
    for (Vec3& p : m.points) p = p * s;
    return m;
}

Mesh two_spheres() {
    Mesh m = shapes::icosphere(1);
    const Mesh b = shapes::icosphere(1);
    const int base = m.num_vertices();
    for (const Vec3& p : b.points) m.points.push_back(p + Vec3{4, 0, 0});
    for (Triangle t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return m;
}

TEST_F(CliReliability, HostileMeshesGiveExit3WithOneLineNamingTheFileInInfoAndLayout) {
    const fs::path in = dir_ / "in";
    std::vector<std::pair<std::string, std::string>> cases;  // path, expected part of the message
    cases.push_back({write_bytes(in / "hang.ply", "ply\nformat ascii 1.0\nelement a 9223372036854775807\nend_header\n"),
                     "contains no triangles"});
    cases.push_back({write_bytes(in / "count.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 2147483648\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n0 0 0\n"),
                     "can hold at most 1"});
    const std::string tet_faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    cases.push_back({write_bytes(in / "equal.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nv 1 1 1\n" + tet_faces),
                     "degenerate: component 0 has zero area"});
    cases.push_back({write_bytes(in / "coplanar.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n" + tet_faces),
                     "degenerate: component 0 encloses no volume"});
    cases.push_back({write_bytes(in / "huge.obj", "v -1e308 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\n" + tet_faces),
                     "the bounding-box diagonal overflows"});
    write_obj((in / "tiny.obj").string(), scaled(shapes::icosphere(1), 1e-150));
    cases.push_back({(in / "tiny.obj").string(), "outside the supported range [1e-30, 1e30]; rescale"});
    write_obj((in / "big.obj").string(), scaled(shapes::icosphere(1), 1e150));
    cases.push_back({(in / "big.obj").string(), "outside the supported range [1e-30, 1e30]; rescale"});
    cases.push_back({write_bytes(in / "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\n"),
                     "line 8: face corner 5 refers to a vertex that does not exist (the file defines 4 vertices"});
    {
        // A closed icosahedron as an unwelded OBJ triangle soup: 20 open components.
        const Mesh cube = scaled(shapes::icosphere(0), 1.0);
        std::string soup;
        int n = 0;
        for (const Triangle& t : cube.triangles) {
            for (int v : t)
                soup += "v " + std::to_string(cube.points[v].x) + " " + std::to_string(cube.points[v].y) + " " +
                        std::to_string(cube.points[v].z) + "\n";
            soup += "f " + std::to_string(n + 1) + " " + std::to_string(n + 2) + " " + std::to_string(n + 3) + "\n";
            n += 3;
        }
        cases.push_back({write_bytes(in / "soup.obj", soup), "merge coincident vertices first"});
    }
    const std::string fifo = (in / "pipe.off").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    cases.push_back({fifo, "is a FIFO (named pipe), not a regular file"});
    cases.push_back({"/dev/zero", "is a device, not a regular file"});
    cases.push_back({(in / "folder.obj").string(), "is a directory, not a mesh file"});
    fs::create_directories(in / "folder.obj");

    for (const auto& [path, expected] : cases) {
        SCOPED_TRACE(path);
        expect_one_line(cli({"info", path}), path, expected);
        const fs::path out = dir_ / "out";
        expect_one_line(cli({"layout", path, "-o", out.string(), "-q"}), path, expected);
        EXPECT_FALSE(fs::exists(out));
        EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // no staging left
    }
}

TEST_F(CliReliability, ANaNPatchIsRejectedByRenderNamingTheFile) {
    const std::string p = write_bytes(dir_ / "nan.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                      "property float patch\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 nan\n");
    expect_one_line(cli({"render", p, "-o", (dir_ / "x.png").string(), "-q"}), p, "property 'patch' is NaN");
    EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(CliReliability, AnOutputThatWouldReplaceAnInputIsRefusedWithExit2) {
    const fs::path d = dir_ / "D";
    const Mesh sphere = shapes::icosphere(1);
    const struct {
        const char* command;
        const char* input;
    } cases[] = {{"layout", "cage.obj"}, {"layout", "layout.ply"}, {"layout", "report.json"},
                 {"fit", "fitted_cage.obj"}, {"fit", "limit.ply"}, {"cycles", "layout.ply"}};
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.command) + " " + c.input);
        fs::remove_all(d);
        const fs::path input = d / c.input;
        fs::create_directories(d);
        if (input.extension() == ".ply") write_ply(input.string(), sphere);
        else write_obj(input.string(), sphere);  // report.json: an OBJ by content
        const auto before = snapshot(d);
        expect_one_line(cli({c.command, input.string(), "-o", d.string(), "-q"}), d.string(),
                        "would replace the input " + input.string(), 2);
        EXPECT_EQ(snapshot(d), before);
    }
    // Single-file outputs.
    const std::string mesh = (d / "m.obj").string();
    write_obj(mesh, sphere);
    const auto before = snapshot(d);
    expect_one_line(cli({"subdivide", mesh, "-o", mesh}), mesh, "would replace the input", 2);
    expect_one_line(cli({"render", mesh, "-o", mesh, "-q"}), mesh, "would replace the input", 2);
    expect_one_line(cli({"subdivide", mesh, "-o", (d / "." / "m.obj").string()}), (d / "." / "m.obj").string(),
                    "would replace the input", 2);
    EXPECT_EQ(snapshot(d), before);
}

// Each output name in turn taken by a directory: the run fails (before any work) and DIR is as it was.
TEST_F(CliReliability, AFailureAtAnyOutputFileLeavesTheDirectoryAsItWas) {
    const std::string mesh = (dir_ / "sphere.obj").string();
    write_obj(mesh, shapes::icosphere(1));
    const fs::path d = dir_ / "D";
    const std::map<std::string, std::vector<std::string>> outputs = {
        {"layout", {"layout.ply", "cage.obj", "cage_level1.obj", "cage.json", "cycles.json", "report.json"}},
        {"cycles", {"layout.ply", "cycles.json", "report.json"}},
        {"fit", {"layout.ply", "cage.obj", "fitted_cage.obj", "limit.ply", "deviation.ply", "report.json"}}};
    for (const auto& [command, names] : outputs)
        for (const std::string& name : names) {
            SCOPED_TRACE(command + " with " + name + " a directory");
            fs::remove_all(d);
            write_bytes(d / "keep.txt", "mine");
            if (name != "cage.json") write_bytes(d / "cage.json", "an old output");
            fs::create_directories(d / name / "inside");
            const auto before = snapshot(d);
            const CliRun r = cli({command, mesh, "-o", d.string(), "-q"});
            expect_one_line(r, (d / name).string(), "is a directory");
            EXPECT_EQ(snapshot(d), before);
            EXPECT_TRUE(r.out.empty()) << r.out;  // no success summary
        }
    // A file where a component's folder goes (a mesh of two components).
    const std::string two = (dir_ / "two.obj").string();
    write_obj(two, two_spheres());
    fs::remove_all(d);
    write_bytes(d / "component_1", "a file");
    const auto before = snapshot(d);
    expect_one_line(cli({"layout", two, "-o", d.string(), "-q"}), (d / "component_1").string(), "exists and is not a directory");
    EXPECT_EQ(snapshot(d), before);
    // DIR itself a file.
    const std::string file = write_bytes(dir_ / "plain_file", "x");
    expect_one_line(cli({"layout", mesh, "-o", file, "-q"}), file, "exists and is not a directory");
    EXPECT_EQ(slurp(file), "x");
}

TEST_F(CliReliability, ASuccessfulRunReplacesItsOutputsAndLeavesOtherFilesAlone) {
    const std::string two = (dir_ / "two.obj").string();
    write_obj(two, two_spheres());
    const fs::path d = dir_ / "D";
    write_bytes(d / "keep.txt", "mine");
    write_bytes(d / "report.json", "old");
    write_bytes(d / "component_0" / "cage.obj", "old");
    write_bytes(d / "component_0" / "notes.txt", "mine too");
    const CliRun r = cli({"layout", two, "-o", d.string(), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto after = snapshot(d);
    EXPECT_EQ(after.at("keep.txt"), "file:mine");
    EXPECT_EQ(after.at("component_0/notes.txt"), "file:mine too");
    EXPECT_NE(after.at("report.json"), "file:old");
    EXPECT_EQ(after.at("component_0/cage.obj").rfind("file:# quadcage level-0 cage: 6 quads", 0), 0u);
    for (const char* name : {"layout.ply", "cage.obj", "cage_level1.obj", "cage.json", "cycles.json", "report.json"})
        for (const char* c : {"component_0/", "component_1/"}) EXPECT_EQ(after.count(std::string(c) + name), 1u) << c << name;
    EXPECT_EQ(after.size(), 17u);  // keep.txt, report.json, 2 folders, 6 outputs + notes.txt, 6 outputs
    // No staging folder left beside D.
    for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().find(".quadcage"), std::string::npos);
}

}  // namespace
}  // namespace quadcage

// A stand-in for the quadcage executable (and for Blender) in the bench tests: it answers the stage
// commands `info MESH --json`, `layout MESH -o DIR`, `fit MESH -o DIR --level K`,
// `fit MESH --cage CAGE --level 0 -o DIR` and `quadriflow IN OUT FACES [SEED]`, and misbehaves on
// purpose when the mesh's file name says so:
//   reject  - info exits 3 with a reason          crash   - layout aborts (SIGABRT)
//   segv    - layout raises SIGSEGV               sleep   - layout sleeps (with a grandchild) for 60 s
//   fail    - layout exits 1 with a message       unverified - layout reports verified: false
//   fitdies  - fit raises SIGSEGV at level >= 1    peerbroken - quadriflow exits 1
//   peergenus - quadriflow with seed 0 returns a quad torus (genus 1)
//   peerempty - quadriflow with seed 0 writes an OBJ without faces
//   peeropen  - quadriflow with seed 0 returns a box with a face missing
//   peerhalf  - quadriflow returns about half the vertices asked for
//   peercoarse - quadriflow always returns a cube (8 vertices)
//   peerfitrefuse - fit --cage exits 3 for a cage made with seed 0
// Otherwise it writes outputs in the documented formats (report.json, layout.ply with a 'patch'
// face property, deviation.ply with a 'distance' vertex property). Our fit at level K reports
// 8 * 4^K control points, relative RMS 0.01 / 2^K and Hausdorff 0.04 / 2^K; a --cage fit reports the
// cage's vertices N as control points, RMS 0.02 / sqrt(N) and Hausdorff 0.1 / sqrt(N).

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <unistd.h>
#include <utility>

#include "quadcage/core/io.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool has(const std::string& path, const char* word) {
    return fs::path(path).filename().string().find(word) != std::string::npos;
}

std::string option(int argc, char** argv, const std::string& name) {
    for (int i = 0; i + 1 < argc; ++i)
        if (argv[i] == name) return argv[i + 1];
    return {};
}

int info(const std::string& mesh_path) {
    if (has(mesh_path, "reject")) {
        std::printf("{\"triangles\": 12, \"components\": [{\"genus\": null, \"closed\": false}], \"minimal_quads\": null}\n");
        std::fprintf(stderr, "quadcage: error: %s: cannot be quadded: 3 boundary edges (an open surface)\n",
                     mesh_path.c_str());
        return 3;
    }
    const quadcage::Mesh mesh = quadcage::read_mesh(mesh_path);
    std::set<std::pair<int, int>> edges;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    const int chi = mesh.num_vertices() - static_cast<int>(edges.size()) + mesh.num_triangles();
    const int genus = (2 - chi) / 2;
    const int minimal = genus == 0 ? 6 : genus == 1 ? 4 : 10 * genus - 10;
    json j{{"triangles", mesh.num_triangles()},
           {"components", json::array({json{{"genus", genus}}})},
           {"minimal_quads", minimal}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
}

int layout(const std::string& mesh_path, const std::string& dir) {
    std::fprintf(stderr, "quadcage: [   0.0 s] loading %s\n", mesh_path.c_str());
    if (has(mesh_path, "crash")) std::abort();
    if (has(mesh_path, "segv")) std::raise(SIGSEGV);
    if (has(mesh_path, "sleep")) {
        // A grandchild in the same process group: the timeout must kill it too.
        const pid_t child = fork();
        if (child == 0) {
            sleep(60);
            _exit(0);
        }
        std::ofstream(dir + "/grandchild.pid") << child << "\n";
        sleep(60);
        return 0;
    }
    if (has(mesh_path, "fail")) {
        std::fprintf(stderr, "quadcage: internal error: fake layout failure\n");
        return 1;
    }
    const quadcage::Mesh mesh = quadcage::read_mesh(mesh_path);
    // Patches: the octant of each triangle's centroid (a sphere gets 8 patches, 6 corners of degree 4).
    quadcage::PlyExtras extras;
    extras.face_int_name = "patch";
    for (const auto& t : mesh.triangles) {
        const quadcage::Vec3 c = (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]) / 3.0;
        extras.face_ints.push_back((c.x > 0) + 2 * (c.y > 0) + 4 * (c.z > 0));
    }
    fs::create_directories(dir);
    quadcage::write_ply(dir + "/layout.ply", mesh, extras);
    json report{{"command", "layout"},
                {"genus", 0},
                {"components", 1},
                {"quads", 8},
                {"corners", 6},
                {"edges", 12},
                {"degree_histogram", {{"4", 6}}},
                {"verified", !has(mesh_path, "unverified")},
                {"quality", {{"patch_area_max_over_min", 1.0}}},
                {"seconds", {{"total", 0.25}}},
                {"peak_memory_mib", 12.5}};
    quadcage::write_text_file(dir + "/report.json", report.dump(2));
    return 0;
}

int fit(const std::string& mesh_path, const std::string& dir, int level) {
    if (has(mesh_path, "fitdies") && level >= 1) std::raise(SIGSEGV);
    const quadcage::Mesh mesh = quadcage::read_mesh(mesh_path);
    quadcage::PlyExtras extras;
    extras.vertex_float_name = "distance";
    for (const auto& p : mesh.points) extras.vertex_floats.push_back(static_cast<float>(std::abs(p.x) * 0.01 / (1 << level)));
    fs::create_directories(dir);
    quadcage::write_ply(dir + "/deviation.ply", mesh, extras);
    const int control_points = 8 << (2 * level);
    json entry{{"level", level},
               {"control_points", control_points},
               {"relative", {{"rms", 0.01 / (1 << level)}, {"hausdorff", 0.04 / (1 << level)}}},
               {"absolute", {{"rms", 0.02 / (1 << level)}}},
               {"seconds", {{"total", 0.5 + level}}}};
    json report{{"command", "fit"}, {"genus", 0}, {"quads", 8}, {"levels", json::array({entry})},
                {"seconds", {{"total", 0.5 + level}}}, {"peak_memory_mib", 20.0}};
    quadcage::write_text_file(dir + "/report.json", report.dump(2));
    return 0;
}

int fit_cage(const std::string& cage_path, const std::string& dir) {
    if (cage_path.find("peerfitrefuse") != std::string::npos && has(cage_path, "seed0")) {
        std::fprintf(stderr, "quadcage: error: %s: the cage is far from the mesh\n", cage_path.c_str());
        return 3;
    }
    const quadcage::PolygonMesh cage = quadcage::read_polygon_mesh(cage_path);
    const int n = static_cast<int>(cage.points.size());
    json entry{{"level", 0},
               {"control_points", n},
               {"relative", {{"rms", 0.02 / std::sqrt(n)}, {"hausdorff", 0.1 / std::sqrt(n)}}},
               {"seconds", {{"total", 0.25}}}};
    json report{{"command", "fit"}, {"cage", cage_path}, {"levels", json::array({entry})},
                {"seconds", {{"fit", 0.25}, {"total", 0.25}}}};
    fs::create_directories(dir);
    quadcage::write_text_file(dir + "/report.json", report.dump(2));
    return 0;
}

// A closed quad box of 1 x 1 x L cells: 4L + 2 faces, 4L + 4 vertices (L = 1: a cube, 8 vertices of
// valence 3). Without `top`, one end face is missing (an open box).
std::string quad_box(int L, bool top = true) {
    std::string obj;
    for (int k = 0; k <= L; ++k)
        for (int i = 0; i < 4; ++i)
            obj += "v " + std::to_string(i == 1 || i == 2) + " " + std::to_string(i >= 2) + " " + std::to_string(k) + "\n";
    auto id = [](int k, int i) { return std::to_string(4 * k + (i % 4) + 1); };
    obj += "f " + id(0, 0) + " " + id(0, 3) + " " + id(0, 2) + " " + id(0, 1) + "\n";  // bottom, facing -z
    if (top) obj += "f " + id(L, 0) + " " + id(L, 1) + " " + id(L, 2) + " " + id(L, 3) + "\n";
    for (int k = 0; k < L; ++k)
        for (int i = 0; i < 4; ++i) obj += "f " + id(k, i) + " " + id(k, i + 1) + " " + id(k + 1, i + 1) + " " + id(k + 1, i) + "\n";
    return obj;
}

// An n x n quad torus grid (genus 1).
std::string quad_torus(int n) {
    std::string obj;
    for (int i = 0; i < n * n; ++i) obj += "v " + std::to_string(i / n) + " " + std::to_string(i % n) + " 0\n";
    auto id = [n](int i, int j) { return std::to_string((i % n) * n + (j % n) + 1); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) obj += "f " + id(i, j) + " " + id(i + 1, j) + " " + id(i + 1, j + 1) + " " + id(i, j + 1) + "\n";
    return obj;
}

// QuadriFlow's output: a box with about `faces` vertices (as many control points as a genus-1
// remesh of that many faces), or what the mesh's name asks for.
int quadriflow(const std::string& in, const std::string& out, int faces, int seed) {
    // The input is DIR/meshes/<name>/peer/input.obj: the mesh's name is in the path.
    auto named = [&in](const char* word) { return in.find(word) != std::string::npos; };
    if (named("peerbroken")) {
        std::fprintf(stderr, "quadriflow: error: QuadriFlow failed: the mesh is unchanged\n");
        return 1;
    }
    const int wanted = named("peerhalf") ? faces / 2 : faces;
    const int L = named("peercoarse") ? 1 : std::max(1, static_cast<int>(std::lround((wanted - 4) / 4.0)));
    std::string obj = quad_box(L);
    if (seed == 0 && named("peergenus")) obj = quad_torus(4);
    if (seed == 0 && named("peerempty")) obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    if (seed == 0 && named("peeropen")) obj = quad_box(L, false);
    quadcage::write_text_file(out, obj);
    quadcage::write_text_file(out + ".json", json{{"seconds", 0.5}, {"target_faces", faces}, {"seed", seed}}.dump());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) return 2;
    const std::string cmd = argv[1], mesh = argv[2];
    try {
        if (cmd == "info") return info(mesh);
        if (cmd == "layout") return layout(mesh, option(argc, argv, "-o"));
        if (cmd == "fit" && !option(argc, argv, "--cage").empty()) return fit_cage(option(argc, argv, "--cage"), option(argc, argv, "-o"));
        if (cmd == "fit") return fit(mesh, option(argc, argv, "-o"), std::atoi(option(argc, argv, "--level").c_str()));
        if (cmd == "quadriflow" && (argc == 5 || argc == 6))
            return quadriflow(mesh, argv[3], std::atoi(argv[4]), argc == 6 ? std::atoi(argv[5]) : 0);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fake: error: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr, "fake: unknown command %s\n", cmd.c_str());
    return 2;
}

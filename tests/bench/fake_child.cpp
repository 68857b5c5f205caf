// A stand-in for the quadcage executable (and for Blender) in the bench tests: it answers the stage
// commands `info MESH --json`, `layout MESH -o DIR`, `fit MESH -o DIR --level K` and
// `quadriflow IN OUT FACES`, and misbehaves on purpose when the mesh's file name says so:
//   reject  - info exits 3 with a reason          crash   - layout aborts (SIGABRT)
//   segv    - layout raises SIGSEGV               sleep   - layout sleeps (with a grandchild) for 60 s
//   fail    - layout exits 1 with a message       unverified - layout reports verified: false
//   fitdies  - fit raises SIGSEGV at level >= 1    peerbroken - quadriflow exits 1
// Otherwise it writes outputs in the documented formats (report.json, layout.ply with a 'patch'
// face property, deviation.ply with a 'distance' vertex property).

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

// A quad cube (6 quads, 8 vertices of valence 3) as QuadriFlow's output.
int quadriflow(const std::string& in, const std::string& out, int faces) {
    if (in.find("peerbroken") != std::string::npos) {  // the input is DIR/meshes/<name>/peer/input.obj
        std::fprintf(stderr, "quadriflow: error: QuadriFlow failed: the mesh is unchanged\n");
        return 1;
    }
    std::string obj;
    for (int i = 0; i < 8; ++i) obj += "v " + std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " + std::to_string(i >> 2) + "\n";
    obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    quadcage::write_text_file(out, obj);
    quadcage::write_text_file(out + ".json", json{{"seconds", 0.5}, {"target_faces", faces}}.dump());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) return 2;
    const std::string cmd = argv[1], mesh = argv[2];
    try {
        if (cmd == "info") return info(mesh);
        if (cmd == "layout") return layout(mesh, option(argc, argv, "-o"));
        if (cmd == "fit") return fit(mesh, option(argc, argv, "-o"), std::atoi(option(argc, argv, "--level").c_str()));
        if (cmd == "quadriflow" && argc == 5) return quadriflow(mesh, argv[3], std::atoi(argv[4]));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fake: error: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr, "fake: unknown command %s\n", cmd.c_str());
    return 2;
}

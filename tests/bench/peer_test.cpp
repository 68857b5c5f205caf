// Statistics of QuadriFlow's polygon output: quads, genus, irregular vertices; empty and broken files.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "quadcage/bench/peer.h"
#include "quadcage/core/errors.h"

namespace {

namespace fs = std::filesystem;
using quadcage::bench::peer_cage_problem;
using quadcage::bench::polygon_obj_stats;

fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = fs::temp_directory_path() / ("quadcage_peer_test_" + std::to_string(::getpid()) + name);
    std::ofstream(p) << text;
    return p;
}

// An n x m quad torus grid: genus 1, every vertex of valence 4.
std::string quad_torus(int n, int m) {
    std::string s;
    for (int i = 0; i < n * m; ++i) s += "v " + std::to_string(i) + " 0 0\n";
    auto id = [&](int i, int j) { return std::to_string(((i % n) * m + (j % m)) + 1); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) s += "f " + id(i, j) + "/1/1 " + id(i + 1, j) + " " + id(i + 1, j + 1) + " " + id(i, j + 1) + "\n";
    return s;
}

TEST(PolygonObjStats, QuadTorusIsRegularGenusOne) {
    const auto st = polygon_obj_stats(write("torus.obj", quad_torus(6, 4)).string());
    EXPECT_EQ(st.faces, 24);
    EXPECT_EQ(st.quads, 24);
    EXPECT_EQ(st.vertices, 24);
    EXPECT_EQ(st.edges, 48);
    EXPECT_EQ(st.components, 1);
    EXPECT_EQ(st.genus, 1);
    EXPECT_EQ(st.irregular_vertices, 0);
}

TEST(PolygonObjStats, CubeHasEightIrregularCornersAndNegativeIndicesWork) {
    std::string s;
    for (int i = 0; i < 8; ++i) s += "v " + std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " + std::to_string(i >> 2) + "\n";
    s += "f -8 -6 -5 -7\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    const auto st = polygon_obj_stats(write("cube.obj", s).string());
    EXPECT_EQ(st.quads, 6);
    EXPECT_EQ(st.genus, 0);
    EXPECT_EQ(st.irregular_vertices, 8);
}

std::string cube(const std::string& faces) {
    std::string s;
    for (int i = 0; i < 8; ++i) s += "v " + std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " + std::to_string(i >> 2) + "\n";
    return s + faces;
}
const std::string kCubeFaces = "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

TEST(PolygonObjStats, ClosedManifoldQuadMeshesPassThePeerCheck) {
    const auto torus = polygon_obj_stats(write("torus2.obj", quad_torus(5, 4)).string());
    EXPECT_TRUE(torus.closed_manifold());
    EXPECT_EQ(peer_cage_problem(torus, 1, 1), "");
    EXPECT_EQ(peer_cage_problem(torus, 2, 1), "wrong genus 1 (input 2)");
    EXPECT_EQ(peer_cage_problem(torus, 1, 2), "wrong component count 1 (input 2)");
    const auto c = polygon_obj_stats(write("cube2.obj", cube(kCubeFaces)).string());
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(peer_cage_problem(c, 0, 1), "");
}

// Each check of the peer's remesh rejects the broken mesh it is for.
TEST(PolygonObjStats, OpenNonManifoldMisorientedAndNonQuadRemeshesAreRejected) {
    // One face missing: its 4 edges are boundary edges.
    const auto open = polygon_obj_stats(write("open.obj", cube("f 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")).string());
    EXPECT_EQ(open.boundary_edges, 4);
    EXPECT_FALSE(open.closed_manifold());
    EXPECT_EQ(peer_cage_problem(open, 0, 1), "open (4 boundary edges)");
    // A face given twice: its 4 edges are in 3 faces.
    const auto doubled = polygon_obj_stats(write("doubled.obj", cube(kCubeFaces + "f 1 3 4 2\n")).string());
    EXPECT_EQ(doubled.nonmanifold_edges, 4);
    EXPECT_EQ(peer_cage_problem(doubled, 0, 1), "non-manifold (4 edges in more than 2 faces)");
    // One face turned round: its 4 edges run the same way in both faces.
    const auto flipped = polygon_obj_stats(write("flipped.obj", cube("f 1 2 4 3\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")).string());
    EXPECT_EQ(flipped.misoriented_edges, 4);
    EXPECT_EQ(peer_cage_problem(flipped, 0, 1), "inconsistently oriented (4 edges)");
    // A quad split into two triangles.
    const auto tri = polygon_obj_stats(write("tri.obj", cube("f 1 3 4\nf 1 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")).string());
    EXPECT_TRUE(tri.closed_manifold());
    EXPECT_EQ(peer_cage_problem(tri, 0, 1), "not all quads (2 of 7 faces are not)");
    // A face with a repeated vertex.
    const auto degenerate = polygon_obj_stats(write("degenerate.obj", cube(kCubeFaces + "f 1 2 1 3\n")).string());
    EXPECT_EQ(degenerate.degenerate_faces, 1);
    EXPECT_NE(peer_cage_problem(degenerate, 0, 1), "");
    // No faces.
    EXPECT_EQ(peer_cage_problem(polygon_obj_stats(write("none.obj", "v 0 0 0\n").string()), 0, 1),
              "empty output (no faces)");
}

TEST(PolygonObjStats, EmptyAndBrokenFiles) {
    EXPECT_EQ(polygon_obj_stats(write("empty.obj", "# nothing\n").string()).faces, 0);
    EXPECT_THROW(polygon_obj_stats(write("bad.obj", "v 0 0 0\nf 1 2 3\n").string()), quadcage::InvalidInput);
    EXPECT_THROW(polygon_obj_stats("/nonexistent/x.obj"), quadcage::InvalidInput);
}

}  // namespace

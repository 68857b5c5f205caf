// Statistics of QuadriFlow's polygon output: quads, genus, irregular vertices; empty and broken files.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "quadcage/bench/peer.h"
#include "quadcage/core/errors.h"

namespace {

namespace fs = std::filesystem;
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

TEST(PolygonObjStats, EmptyAndBrokenFiles) {
    EXPECT_EQ(polygon_obj_stats(write("empty.obj", "# nothing\n").string()).faces, 0);
    EXPECT_THROW(polygon_obj_stats(write("bad.obj", "v 0 0 0\nf 1 2 3\n").string()), quadcage::InvalidInput);
    EXPECT_THROW(polygon_obj_stats("/nonexistent/x.obj"), quadcage::InvalidInput);
}

}  // namespace

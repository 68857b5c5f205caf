// read_ply_with_extras(): the 'patch' face and 'distance' vertex properties written by write_ply()
// come back, in ascii and binary, also for polygons; read_mesh() is unaffected.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/shapes.h"

namespace {

namespace fs = std::filesystem;
using namespace quadcage;

fs::path temp(const std::string& name) {
    return fs::temp_directory_path() / ("quadcage_io_extras_" + std::to_string(::getpid()) + "_" + name);
}

class PlyExtrasRoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(PlyExtrasRoundTrip, ValuesComeBack) {
    const Mesh mesh = shapes::torus(8, 5);
    PlyExtras out;
    out.face_int_name = "patch";
    out.vertex_float_name = "distance";
    for (int t = 0; t < mesh.num_triangles(); ++t) out.face_ints.push_back(t % 7 - 2);
    for (int v = 0; v < mesh.num_vertices(); ++v) out.vertex_floats.push_back(0.25f * v);
    const fs::path p = temp(GetParam() ? "a.ply" : "b.ply");
    write_ply(p.string(), mesh, out, GetParam());

    PlyExtras in;
    in.face_int_name = "patch";
    in.vertex_float_name = "distance";
    const Mesh back = read_ply_with_extras(p.string(), in);
    EXPECT_EQ(back.triangles, mesh.triangles);
    EXPECT_EQ(in.face_ints, out.face_ints);
    EXPECT_EQ(in.vertex_floats, out.vertex_floats);
    EXPECT_EQ(read_mesh(p.string()).points, back.points);  // read_mesh skips the properties

    PlyExtras other;
    other.face_int_name = "region";  // not in the file
    read_ply_with_extras(p.string(), other);
    EXPECT_TRUE(other.face_ints.empty());
    EXPECT_TRUE(other.vertex_floats.empty());
    fs::remove(p);
}

INSTANTIATE_TEST_SUITE_P(AsciiAndBinary, PlyExtrasRoundTrip, ::testing::Bool(),
                         [](const auto& info) { return info.param ? std::string("ascii") : std::string("binary"); });

TEST(PlyExtras, PolygonValueRepeatsOnItsTrianglesAndNonPlyIsRejected) {
    const fs::path p = temp("quad.ply");
    std::ofstream(p) << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                        "element face 2\nproperty int patch\nproperty list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n9 4 0 1 2 3\n4 3 0 1 4\n";
    PlyExtras e;
    e.face_int_name = "patch";
    const Mesh m = read_ply_with_extras(p.string(), e);
    ASSERT_EQ(m.num_triangles(), 3);
    EXPECT_EQ(e.face_ints, (std::vector<int>{9, 9, 4}));
    const fs::path obj = temp("x.obj");
    write_obj(obj.string(), m);
    EXPECT_THROW(read_ply_with_extras(obj.string(), e), InvalidInput);
    fs::remove(p);
    fs::remove(obj);
}

}  // namespace

#include "quadcage/core/io.h"

#include <gtest/gtest.h>

#include "support/names.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include <unistd.h>

#include "quadcage/core/errors.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;

const std::string kMeshDir = std::string(QUADCAGE_SHARED_DIR) + "/data/meshes/";

// Each test gets its own directory (pid + test name), so parallel ctest runs do not collide.
class IoTest : public testing::Test {
protected:
    void SetUp() override {
        const auto* test = testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(testing::TempDir()) /
               ("quadcage_io_" + std::to_string(::getpid()) + "_" + test->test_suite_name() + "_" + test->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    std::string write_bytes(const std::string& name, const std::string& bytes) const {
        const std::string p = path(name);
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        EXPECT_TRUE(out.good()) << p;
        return p;
    }

    fs::path dir_;
};

std::string read_bytes(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Appends the bytes of v, little- or big-endian regardless of the host.
template <class T>
void put(std::string& out, T v, bool big_endian) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    const bool host_little = first == 1;
    if (host_little == big_endian) std::reverse(b, b + sizeof(T));
    out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

template <class T>
T get_le(const std::string& bytes, size_t offset) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, bytes.data() + offset, sizeof(T));
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    if (first != 1) std::reverse(b, b + sizeof(T));
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

// Unit cube, outward-facing triangles: the STL tests weld its 36 corners back to 8 vertices.
Mesh cube() {
    Mesh m;
    for (int i = 0; i < 8; ++i) m.points.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return m;
}

// Coordinates that only survive a writer/reader pair that keeps every bit.
Mesh awkward_mesh() {
    Mesh m;
    m.points = {{1.0 / 3.0, -2.0 / 7.0, 1e-300},
                {std::nextafter(1.0, 2.0), -0.0, 123456789.123456789},
                {std::numeric_limits<double>::denorm_min(), 0.1, -1e22},
                {std::acos(-1.0), std::exp(1.0), -std::sqrt(2.0)}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    return m;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
    ASSERT_EQ(a.num_vertices(), b.num_vertices());
    ASSERT_EQ(a.num_triangles(), b.num_triangles());
    for (int i = 0; i < a.num_vertices(); ++i) {
        // memcmp, so that -0.0 vs 0.0 would be caught too.
        EXPECT_EQ(0, std::memcmp(&a.points[i], &b.points[i], sizeof(Vec3))) << "vertex " << i;
    }
    for (int t = 0; t < a.num_triangles(); ++t) EXPECT_EQ(a.triangles[t], b.triangles[t]) << "triangle " << t;
}

bool indices_in_range(const Mesh& m) {
    for (const Triangle& t : m.triangles)
        for (int v : t)
            if (v < 0 || v >= m.num_vertices()) return false;
    return true;
}

std::string error_of(const std::string& p) {
    try {
        read_mesh(p);
    } catch (const InvalidInput& e) {
        return e.what();
    }
    return "(no InvalidInput thrown)";
}

// ------------------------------------------------------------------------------------------------
// The shared real meshes

struct SharedMesh {
    const char* file;
    const char* format;
    int triangles;
    int vertices_in_file;
};

class IoShared : public testing::TestWithParam<SharedMesh> {};

TEST_P(IoShared, LoadsWithReadmeCounts) {
    const SharedMesh& s = GetParam();
    LoadInfo info;
    const Mesh m = read_mesh(kMeshDir + s.file, &info);
    EXPECT_EQ(m.num_triangles(), s.triangles);
    EXPECT_EQ(m.num_vertices(), s.vertices_in_file);
    EXPECT_EQ(info.format, s.format);
    EXPECT_EQ(info.polygons_split, 0);
    EXPECT_EQ(info.dropped_faces, 0);
    EXPECT_EQ(info.welded_vertices, 0);
    EXPECT_TRUE(indices_in_range(m));
    for (const Vec3& p : m.points) ASSERT_TRUE(is_finite(p));
}

// Counts from data/meshes/README.md; "vertices" there counts used vertices, which equals the
// file's count except for stanford-bunny.obj (35,947 in the file, 1,113 unused).
INSTANTIATE_TEST_SUITE_P(IoMeshes, IoShared,
                         testing::Values(SharedMesh{"eight.off", "off", 1536, 766},
                                         SharedMesh{"kitten.off", "off", 3700, 1850},
                                         SharedMesh{"torus.obj", "obj", 4608, 2304},
                                         SharedMesh{"bunny.obj", "obj", 6598, 3301},
                                         SharedMesh{"3holes.off", "off", 7200, 3596},
                                         SharedMesh{"fertility.off", "off", 9000, 4494},
                                         SharedMesh{"input_wheel.off", "off", 55890, 27925},
                                         SharedMesh{"botijo.off", "off", 82332, 41158},
                                         SharedMesh{"skull.obj", "obj", 100002, 49999},
                                         SharedMesh{"igea.ply", "ply-binary-le", 268686, 134345},
                                         SharedMesh{"boot.obj", "obj", 39906, 19931},
                                         SharedMesh{"stanford-bunny.obj", "obj", 69451, 35947},
                                         SharedMesh{"cow.obj", "obj", 5804, 2903},
                                         SharedMesh{"truck.obj", "obj", 4770, 2956}),
                         [](const testing::TestParamInfo<SharedMesh>& p) {
                             return quadcage::test::identifier(p.param.file);
                         });

std::uint64_t edge_key(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }

TEST(IoRead, IgeaStripsGiveConsistentlyOrientedClosedMesh) {
    const Mesh m = read_mesh(kMeshDir + "igea.ply");
    std::unordered_set<std::uint64_t> directed;
    directed.reserve(3 * m.triangles.size());
    for (const Triangle& t : m.triangles) {
        EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        for (int k = 0; k < 3; ++k)
            ASSERT_TRUE(directed.insert(edge_key(t[k], t[(k + 1) % 3])).second)
                << "directed edge " << t[k] << "->" << t[(k + 1) % 3] << " used twice";
    }
    // The README says igea is closed: then every directed edge has its twin.
    for (const Triangle& t : m.triangles)
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(directed.count(edge_key(t[(k + 1) % 3], t[k])));
}

TEST(IoRead, BunnyObjWithSlashNormalFaces) {
    const Mesh m = read_mesh(kMeshDir + "bunny.obj");
    ASSERT_EQ(m.num_triangles(), 6598);
    // First face in the file: "f 1//1 2//1 3//1".
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

// ------------------------------------------------------------------------------------------------
// OBJ

using IoObj = IoTest;

TEST_F(IoObj, AllCornerFormsNegativeIndicesPolygonsAndIgnoredStatements) {
    const std::string p = write_bytes("forms.obj",
                                      "# comment\r\n"
                                      "mtllib x.mtl\n"
                                      "o thing\n"
                                      "v 0 0 0\n"
                                      "v 1 0 0 1.0\n"         // w
                                      "v 1 1 0 0.5 0.5 0.5\n"  // colour
                                      "v +0 1 0\n"
                                      "vt 0 0\nvn 0 0 1\nvp 0.5\ng grp\ns 1\nusemtl red\n"
                                      "f 1 2 3\n"
                                      "f 1/1 3/1 4/1\r\n"
                                      "f 1//1 2//1 3//1 # trailing comment\n"
                                      "f 1/1/1 2/1/1 3/1/1 4/1/1\n"  // quad: split
                                      "f -4 -3 -2\n"                  // relative: 1 2 3
                                      "f 1 2\n"                       // dropped
                                      "l 1 2\n"
                                      "v 5 5 5\n"
                                      "f -1 -2 -3 -4 -5\n");  // pentagon relative to 5 vertices
    LoadInfo info;
    const Mesh m = read_mesh(p, &info);
    EXPECT_EQ(info.format, "obj");
    ASSERT_EQ(m.num_vertices(), 5);
    EXPECT_EQ(m.points[1], (Vec3{1, 0, 0}));
    EXPECT_EQ(m.points[3], (Vec3{0, 1, 0}));
    const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {0, 1, 2}, {0, 1, 2}, {0, 2, 3},
                                            {0, 1, 2}, {4, 3, 2}, {4, 2, 1}, {4, 1, 0}};
    EXPECT_EQ(m.triangles, expected);
    EXPECT_EQ(info.polygons_split, 2);
    EXPECT_EQ(info.dropped_faces, 1);
}

// OBJ indices that name no vertex are errors in the file's own numbering (issue 23); the other
// formats number from 0 as stored, so they keep such indices for validate() (IoOff, IoPly below).
TEST_F(IoObj, IndicesThatNameNoVertexAreReportedAsWritten) {
    const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const struct {
        const char* face;
        const char* expected;
    } cases[] = {{"f 1 2 9\n", "line 4: face corner 9 refers to a vertex that does not exist (the file defines 3 vertices"},
                 {"f 0 2 3\n", "line 4: face corner 0 is not a vertex index (OBJ indices count from 1"},
                 {"f -7 1 2\n", "line 4: face corner -7 refers to a vertex that does not exist (the file has defined 3 vertices so far"},
                 {"f 1/1/1 2//2 4/4\n", "line 4: face corner 4 refers"}};
    for (const auto& c : cases) {
        const std::string p = write_bytes("range.obj", head + c.face);
        try {
            read_mesh(p);
            ADD_FAILURE() << c.face << ": no exception";
        } catch (const InvalidInput& e) {
            EXPECT_NE(std::string(e.what()).find(p + ", " + c.expected), std::string::npos) << e.what();
        }
    }
    // A face may name vertices defined after it (positive indices).
    const Mesh m = read_mesh(write_bytes("forward.obj", "f 1 2 3\n" + head));
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

// ------------------------------------------------------------------------------------------------
// PLY

using IoPly = IoTest;

TEST_F(IoPly, BigEndianWithMixedScalarTypesAndPolygon) {
    std::string data =
        "ply\n"
        "format binary_big_endian 1.0\n"
        "comment mixed types\n"
        "obj_info made by hand\n"
        "element vertex 4\n"
        "property float32 x\n"
        "property uchar red\n"
        "property double y\n"
        "property list uint8 float normals\n"
        "property short z\n"
        "element face 2\n"
        "property int flags\n"
        "property list uint8 uint vertex_index\n"
        "end_header\n";
    const double ys[4] = {0.1, 0.25, -3.5, 1e10};
    for (int i = 0; i < 4; ++i) {
        put<float>(data, 1.5f * float(i), true);
        put<std::uint8_t>(data, 200, true);
        put<double>(data, ys[i], true);
        put<std::uint8_t>(data, 2, true);
        put<float>(data, 7.f, true);
        put<float>(data, 8.f, true);
        put<std::int16_t>(data, static_cast<std::int16_t>(-300 * i), true);
    }
    put<std::int32_t>(data, 42, true);
    put<std::uint8_t>(data, 4, true);  // a quad
    for (std::uint32_t v : {0u, 1u, 2u, 3u}) put<std::uint32_t>(data, v, true);
    put<std::int32_t>(data, 43, true);
    put<std::uint8_t>(data, 3, true);
    for (std::uint32_t v : {3u, 2u, 1u}) put<std::uint32_t>(data, v, true);

    LoadInfo info;
    const Mesh m = read_mesh(write_bytes("be.ply", data), &info);
    EXPECT_EQ(info.format, "ply-binary-be");
    ASSERT_EQ(m.num_vertices(), 4);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(m.points[i], (Vec3{1.5 * i, ys[i], -300.0 * i})) << i;
    const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {3, 2, 1}};
    EXPECT_EQ(m.triangles, expected);
    EXPECT_EQ(info.polygons_split, 1);
}

// An element the reader does not know, with list properties, between vertices and faces.
std::string ply_with_unknown_element(bool binary) {
    std::string data = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                       " 1.0\n"
                       "element vertex 3\n"
                       "property double x\nproperty double y\nproperty double z\n"
                       "element material 2\n"
                       "property list uchar float values\n"
                       "property int id\n"
                       "property list int short tags\n"
                       "element face 1\n"
                       "property list uchar int vertex_indices\n"
                       "property uchar quality\n"
                       "end_header\n";
    const double pts[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}};
    if (binary) {
        for (const auto& p : pts)
            for (double c : p) put<double>(data, c, false);
        for (int k = 0; k < 2; ++k) {
            put<std::uint8_t>(data, 3, false);
            for (int j = 0; j < 3; ++j) put<float>(data, 0.5f * j, false);
            put<std::int32_t>(data, k, false);
            put<std::int32_t>(data, 2, false);
            put<std::int16_t>(data, 7, false);
            put<std::int16_t>(data, 8, false);
        }
        put<std::uint8_t>(data, 3, false);
        for (int v : {2, 1, 0}) put<std::int32_t>(data, v, false);
        put<std::uint8_t>(data, 99, false);
    } else {
        data += "0 0 0\n1 0 0\n0 1 0.5\n"
                "3 0 0.5 1 0 2 7 8\n"
                "0 1 0\n"
                "3 2 1 0 99\n";
    }
    return data;
}

TEST_F(IoPly, SkipsUnknownElementWithListsBinary) {
    LoadInfo info;
    const Mesh m = read_mesh(write_bytes("unknown_bin.ply", ply_with_unknown_element(true)), &info);
    EXPECT_EQ(info.format, "ply-binary-le");
    ASSERT_EQ(m.num_vertices(), 3);
    EXPECT_EQ(m.points[2], (Vec3{0, 1, 0.5}));
    ASSERT_EQ(m.num_triangles(), 1);
    EXPECT_EQ(m.triangles[0], (Triangle{2, 1, 0}));
}

TEST_F(IoPly, SkipsUnknownElementWithListsAscii) {
    LoadInfo info;
    const Mesh m = read_mesh(write_bytes("unknown_ascii.ply", ply_with_unknown_element(false)), &info);
    EXPECT_EQ(info.format, "ply-ascii");
    ASSERT_EQ(m.num_vertices(), 3);
    EXPECT_EQ(m.points[2], (Vec3{0, 1, 0.5}));
    ASSERT_EQ(m.num_triangles(), 1);
    EXPECT_EQ(m.triangles[0], (Triangle{2, 1, 0}));
}

TEST_F(IoPly, TriangleStripsAlternateOrientationAndRestart) {
    const std::string p = write_bytes("strips.ply",
                                      "ply\nformat ascii 1.0\n"
                                      "element vertex 7\nproperty float x\nproperty float y\nproperty float z\n"
                                      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                                      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n2 2 0\n"
                                      // strip 0 1 2 3 4, a degenerate joint 4 4, restart, strip 4 5 6
                                      "10 0 1 2 3 4 4 -1 4 5 6\n");
    const Mesh m = read_mesh(p);
    const std::vector<Triangle> expected = {{0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {4, 5, 6}};
    EXPECT_EQ(m.triangles, expected);
}

// ------------------------------------------------------------------------------------------------
// OFF

using IoOff = IoTest;

TEST_F(IoOff, ColourHeaderCountsOnHeaderLineCommentsAndFaceColours) {
    const std::string p = write_bytes("c.off",
                                      "# made by hand\n"
                                      "COFF 5 2 0\n"
                                      "0 0 0 255 0 0 255\n"
                                      "1 0 0 255 0 0 255  # a comment\n"
                                      "\n"
                                      "# between vertices\n"
                                      "1 1 0 0 0 255 255\n"
                                      "0 1 0 0 0 255 255\n"
                                      "0.5 0.5 1e-3 0 0 0 0\n"
                                      "4 0 1 2 3 0.5 0.5 0.5\n"
                                      "3 3 2 4\n");
    LoadInfo info;
    const Mesh m = read_mesh(p, &info);
    EXPECT_EQ(info.format, "off");
    ASSERT_EQ(m.num_vertices(), 5);
    EXPECT_EQ(m.points[4], (Vec3{0.5, 0.5, 1e-3}));
    const std::vector<Triangle> expected = {{0, 1, 2}, {0, 2, 3}, {3, 2, 4}};
    EXPECT_EQ(m.triangles, expected);
    EXPECT_EQ(info.polygons_split, 1);
}

TEST_F(IoOff, NoffHeader) {
    const Mesh m = read_mesh(write_bytes("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"));
    EXPECT_EQ(m.num_vertices(), 3);
    EXPECT_EQ(m.num_triangles(), 1);
}

// ------------------------------------------------------------------------------------------------
// STL

using IoStl = IoTest;

std::string cube_stl_ascii() {
    const Mesh c = cube();
    std::ostringstream s;
    s << "solid cube exported by hand\n";
    for (const Triangle& t : c.triangles) {
        s << "  facet normal 0 0 0\n    outer loop\n";
        for (int v : t) s << "      vertex " << c.points[v].x << ' ' << c.points[v].y << ' ' << c.points[v].z << '\n';
        s << "    endloop\n  endfacet\n";
    }
    s << "endsolid cube\n";
    return s.str();
}

std::string cube_stl_binary(const std::string& header_text) {
    const Mesh c = cube();
    std::string data = header_text;
    data.resize(80, ' ');
    put<std::uint32_t>(data, static_cast<std::uint32_t>(c.triangles.size()), false);
    for (const Triangle& t : c.triangles) {
        for (int k = 0; k < 3; ++k) put<float>(data, 0.f, false);
        for (int v : t) {
            put<float>(data, float(c.points[v].x), false);
            put<float>(data, float(c.points[v].y), false);
            put<float>(data, float(c.points[v].z), false);
        }
        put<std::uint16_t>(data, 0, false);
    }
    return data;
}

// The reader welds STL corners into vertices in order of first use; map them back by position.
void expect_cube(const Mesh& m) {
    const Mesh c = cube();
    ASSERT_EQ(m.num_vertices(), 8);
    ASSERT_EQ(m.num_triangles(), 12);
    for (int t = 0; t < 12; ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.points[m.triangles[t][k]], c.points[c.triangles[t][k]]);
}

TEST_F(IoStl, AsciiCubeWelds) {
    LoadInfo info;
    const Mesh m = read_mesh(write_bytes("cube.stl", cube_stl_ascii()), &info);
    EXPECT_EQ(info.format, "stl-ascii");
    EXPECT_EQ(info.welded_vertices, 36 - 8);
    expect_cube(m);
}

TEST_F(IoStl, BinaryCubeWelds) {
    LoadInfo info;
    const Mesh m = read_mesh(write_bytes("cube_bin.stl", cube_stl_binary("binary cube")), &info);
    EXPECT_EQ(info.format, "stl-binary");
    EXPECT_EQ(info.welded_vertices, 36 - 8);
    expect_cube(m);
}

TEST_F(IoStl, BinaryDetectedBySizeEvenIfHeaderSaysSolid) {
    LoadInfo info;
    // No extension either: the size alone identifies it.
    const Mesh m = read_mesh(write_bytes("cube_solid_header", cube_stl_binary("solid cube")), &info);
    EXPECT_EQ(info.format, "stl-binary");
    expect_cube(m);
}

// ------------------------------------------------------------------------------------------------
// Writers

using IoWrite = IoTest;

TEST_F(IoWrite, BinaryPlyRoundTripWithExtras) {
    const Mesh m = awkward_mesh();
    PlyExtras extras;
    extras.face_int_name = "patch";
    extras.face_ints = {7, -1, 0x12345678, 3};
    extras.vertex_float_name = "distance";
    extras.vertex_floats = {0.5f, -1.25f, 3e-8f, 1e30f};
    const std::string p = path("out.ply");
    write_ply(p, m, extras);
    EXPECT_FALSE(fs::exists(p + ".tmp"));

    LoadInfo info;
    expect_same_mesh(m, read_mesh(p, &info));
    EXPECT_EQ(info.format, "ply-binary-le");

    // The bytes of the extra properties, at the offsets the header implies.
    const std::string bytes = read_bytes(p);
    const size_t body = bytes.find("end_header\n") + std::strlen("end_header\n");
    ASSERT_NE(bytes.find("property float distance\n"), std::string::npos);
    ASSERT_NE(bytes.find("property list uchar int vertex_indices\nproperty int patch\n"), std::string::npos);
    const size_t vertex_size = 3 * 8 + 4;
    const size_t face_size = 1 + 3 * 4 + 4;
    ASSERT_EQ(bytes.size(), body + 4 * vertex_size + 4 * face_size);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(get_le<double>(bytes, body + i * vertex_size), m.points[i].x);
        EXPECT_EQ(get_le<float>(bytes, body + i * vertex_size + 24), extras.vertex_floats[i]);
    }
    const size_t faces = body + 4 * vertex_size;
    for (size_t t = 0; t < 4; ++t) {
        EXPECT_EQ(static_cast<unsigned char>(bytes[faces + t * face_size]), 3u);
        EXPECT_EQ(get_le<std::int32_t>(bytes, faces + t * face_size + 1 + 8), m.triangles[t][2]);
        EXPECT_EQ(get_le<std::int32_t>(bytes, faces + t * face_size + 13), extras.face_ints[t]);
    }
}

TEST_F(IoWrite, AsciiPlyRoundTripWithExtras) {
    const Mesh m = awkward_mesh();
    PlyExtras extras;
    extras.face_int_name = "patch";
    extras.face_ints = {1, 2, 3, -4};
    const std::string p = path("out_ascii.ply");
    write_ply(p, m, extras, /*ascii=*/true);
    LoadInfo info;
    expect_same_mesh(m, read_mesh(p, &info));
    EXPECT_EQ(info.format, "ply-ascii");
    const std::string text = read_bytes(p);
    EXPECT_NE(text.find("\n3 1 3 2 -4\n"), std::string::npos) << text;
}

TEST_F(IoWrite, RealMeshPlyRoundTrip) {
    const Mesh m = read_mesh(kMeshDir + "botijo.off");
    const std::string p = path("botijo.ply");
    write_ply(p, m);
    expect_same_mesh(m, read_mesh(p));
}

TEST_F(IoWrite, ObjRoundTrip) {
    const Mesh m = awkward_mesh();
    const std::string p = path("out.obj");
    write_obj(p, m);
    EXPECT_FALSE(fs::exists(p + ".tmp"));
    LoadInfo info;
    expect_same_mesh(m, read_mesh(p, &info));
    EXPECT_EQ(info.format, "obj");
    EXPECT_NE(read_bytes(p).find("\nf 1 2 3\n"), std::string::npos);
}

TEST_F(IoWrite, ExtrasSizeMismatchThrowsAndWritesNothing) {
    const Mesh m = cube();
    const std::string p = path("bad.ply");
    PlyExtras faces;
    faces.face_int_name = "patch";
    faces.face_ints = {1, 2};
    EXPECT_THROW(write_ply(p, m, faces), InvalidInput);
    PlyExtras verts;
    verts.vertex_float_name = "d";
    verts.vertex_floats.assign(9, 0.f);
    EXPECT_THROW(write_ply(p, m, verts), InvalidInput);
    PlyExtras unnamed;
    unnamed.face_ints.assign(12, 0);
    EXPECT_THROW(write_ply(p, m, unnamed), InvalidInput);
    EXPECT_FALSE(fs::exists(p));
    EXPECT_FALSE(fs::exists(p + ".tmp"));
}

TEST_F(IoWrite, UnwritablePathThrowsNamingIt) {
    const std::string p = path("no_such_dir/out.ply");
    try {
        write_ply(p, cube());
        FAIL() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
    EXPECT_THROW(write_obj(p, cube()), InvalidInput);
    EXPECT_THROW(write_text_file(p, "x"), InvalidInput);
}

TEST_F(IoWrite, TextFileReplacesAtomically) {
    const std::string p = path("report.json");
    write_text_file(p, "old");
    write_text_file(p, "{\"new\": true}\n");
    EXPECT_EQ(read_bytes(p), "{\"new\": true}\n");
    EXPECT_FALSE(fs::exists(p + ".tmp"));
}

// ------------------------------------------------------------------------------------------------
// Format detection

using IoDetect = IoTest;

TEST_F(IoDetect, ContentWinsOverExtension) {
    LoadInfo info;
    read_mesh(write_bytes("really_ply.obj", ply_with_unknown_element(true)), &info);
    EXPECT_EQ(info.format, "ply-binary-le");
    read_mesh(write_bytes("really_off.stl", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), &info);
    EXPECT_EQ(info.format, "off");
    read_mesh(write_bytes("really_obj.ply.txt", "# obj\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), &info);
    EXPECT_EQ(info.format, "obj");
    read_mesh(write_bytes("really_stl.off", cube_stl_ascii()), &info);
    EXPECT_EQ(info.format, "stl-ascii");
}

TEST_F(IoDetect, ExtensionDecidesWhenContentDoesNot) {
    // An OFF without its header, and an OBJ starting with a statement we do not list.
    const Mesh off = read_mesh(write_bytes("headerless.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_EQ(off.num_triangles(), 1);
    const Mesh obj = read_mesh(write_bytes("odd.obj", "cstype bezier\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_EQ(obj.num_triangles(), 1);
}

// ------------------------------------------------------------------------------------------------
// Errors

using IoErrors = IoTest;

// Each message must name the file so that a user knows which input to fix.
void expect_error(const std::string& p, const std::string& also) {
    const std::string msg = error_of(p);
    EXPECT_NE(msg.find(fs::path(p).filename().string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(also), std::string::npos) << msg;
}

TEST_F(IoErrors, EmptyFile) {
    expect_error(write_bytes("empty.obj", ""), "contains no triangles");
    expect_error(write_bytes("blank.off", "  \n\n"), "contains no triangles");
}

TEST_F(IoErrors, NoTriangles) {
    expect_error(write_bytes("points.obj", "v 0 0 0\nv 1 1 1\n"), "contains no triangles");
    expect_error(write_bytes("zero.off", "OFF\n0 0 0\n"), "contains no triangles");
}

TEST_F(IoErrors, NonexistentFile) { expect_error(path("missing.ply"), "cannot open"); }

TEST_F(IoErrors, TruncatedBinaryPly) {
    const std::string igea = read_bytes(kMeshDir + "igea.ply");
    ASSERT_GT(igea.size(), 2'000'000u);
    // Inside the vertices (12 bytes each after the header), and inside the strip list.
    expect_error(write_bytes("cut_vertices.ply", igea.substr(0, 1'000'000)), "expected 134345 'vertex' elements");
    expect_error(write_bytes("cut_strips.ply", igea.substr(0, 2'500'000)), "expected 1 'tristrips' elements, file ends after 0");
    EXPECT_NE(error_of(path("cut_strips.ply")).find("truncated"), std::string::npos);
    expect_error(write_bytes("cut_header.ply", igea.substr(0, 100)), "end_header");
}

TEST_F(IoErrors, TruncatedAsciiFiles) {
    expect_error(write_bytes("cut.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n"),
                 "expected 2 faces, file ends after 1");
    expect_error(write_bytes("cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
                 "expected 1 'face' elements, file ends after 0");
    expect_error(write_bytes("cut.stl", cube_stl_binary("x").substr(0, 84 + 50 * 5 + 20)), "truncated");
}

// Cutting a file anywhere must give either a mesh or InvalidInput: never a crash, another
// exception type, or (for binary PLY, whose every element is required) a silent partial mesh.
TEST_F(IoErrors, EveryTruncationIsCleanlyHandled) {
    write_obj(path("full.obj"), cube());
    write_ply(path("full_bin.ply"), cube());
    write_ply(path("full_ascii.ply"), cube(), {}, true);
    const std::vector<std::pair<std::string, std::string>> files = {
        {"obj", read_bytes(path("full.obj"))},
        {"ply", read_bytes(path("full_bin.ply"))},
        {"ply", read_bytes(path("full_ascii.ply"))},
        {"ply", ply_with_unknown_element(true)},
        {"stl", cube_stl_ascii()},
        {"stl", cube_stl_binary("solid")},
        {"off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 2 3 1\n"}};
    int n = 0;
    for (const auto& [ext, full] : files) {
        const bool binary_ply = full.find("binary_little_endian") != std::string::npos;
        for (size_t cut = 0; cut < full.size(); ++cut) {
            const std::string p = write_bytes("cut" + std::to_string(n++) + "." + ext, full.substr(0, cut));
            try {
                read_mesh(p);
                EXPECT_FALSE(binary_ply) << "binary PLY cut at " << cut << " of " << full.size() << " loaded";
            } catch (const InvalidInput& e) {
                EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
            } catch (const std::exception& e) {
                ADD_FAILURE() << p << ": unexpected exception " << e.what();
            }
            fs::remove(p);
        }
    }
}

TEST_F(IoErrors, ObjMalformedNumberNamesLine) {
    expect_error(write_bytes("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1.5.2 0\nf 1 2 3\n"), "line 3");
    expect_error(write_bytes("bad_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 x3\n"), "line 5");
    expect_error(write_bytes("short.obj", "v 0 0\n"), "line 1");
}

TEST_F(IoErrors, MalformedOffAndPlyNameLine) {
    expect_error(write_bytes("bad.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"), "line 4");
    expect_error(write_bytes("bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                        "property float z\nend_header\n0 nan? 0\n"),
                 "line 8");
    expect_error(write_bytes("badtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"),
                 "line 4");
}

TEST_F(IoErrors, UnknownFormatListsSupported) {
    expect_error(write_bytes("notes.txt", "hello world\nthis is not a mesh\n"), "supported formats");
    expect_error(write_bytes("noext", "1 2 3\n"), "supported formats");
}

}  // namespace
}  // namespace quadcage

namespace quadcage {
namespace {

TEST_F(IoTest, PolygonMeshKeepsQuadsPentagonsAndTrianglesInEveryFormat) {
    // A pentagon, a quad and a triangle, written as OBJ (1-based, one negative index), OFF and
    // ASCII PLY.
    const std::vector<std::vector<int>> faces = {{0, 1, 2, 3, 4}, {0, 5, 6, 1}, {2, 1, 6}};
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                            "f 1 2 3 4 5\nf 1/1 6/1 7/1 2/1\nf 3 2 -1\n";
    std::string off = "OFF\n7 3 0\n0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n0 0 1\n1 0 1\n5 0 1 2 3 4\n4 0 5 6 1\n3 2 1 6\n";
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n0 0 1\n1 0 1\n5 0 1 2 3 4\n4 0 5 6 1\n3 2 1 6\n";
    for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
             {"cage.obj", obj}, {"cage.off", off}, {"cage.ply", ply}}) {
        LoadInfo info;
        const PolygonMesh m = read_polygon_mesh(write_bytes(name, text), &info);
        EXPECT_EQ(m.num_vertices(), 7) << name;
        EXPECT_EQ(m.faces, faces) << name;
        EXPECT_EQ(info.polygons_split, 2) << name;
        // read_mesh() of the same file fan-triangulates: 3 + 2 + 1 triangles.
        EXPECT_EQ(read_mesh(path(name)).num_triangles(), 6) << name;
    }
}

TEST_F(IoTest, PolygonMeshOfBinaryStlIsItsFacets) {
    std::string stl(80, ' ');
    auto put32 = [&](std::uint32_t v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
    auto putf = [&](float v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
    put32(2);
    const float tris[2][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};
    for (const auto& t : tris) {
        for (int k = 0; k < 3; ++k) putf(0);
        for (float x : t) putf(x);
        stl.append(2, '\0');
    }
    const PolygonMesh m = read_polygon_mesh(write_bytes("two.stl", stl));
    EXPECT_EQ(m.num_vertices(), 4);  // welded
    ASSERT_EQ(m.num_faces(), 2);
    EXPECT_EQ(m.faces[0].size(), 3u);
    EXPECT_EQ(m.faces[1].size(), 3u);
}

}  // namespace
}  // namespace quadcage

// Hostile inputs of issue 23 for the readers: counts larger than the file, property-less elements
// with huge counts, non-regular files, non-finite extras. Every input is built here.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "support/names.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;

class IoHostile : public testing::Test {
protected:
    void SetUp() override {
        const auto* test = testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(testing::TempDir()) / ("quadcage_io_hostile_" + std::to_string(::getpid()) + "_" +
                                               test::identifier(std::string(test->name())));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string write_bytes(const std::string& name, const std::string& bytes) const {
        const std::string p = (dir_ / name).string();
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return p;
    }
    fs::path dir_;
};

// The message of the InvalidInput that `f` throws ("" and a test failure if none), and how long it took.
template <class F>
std::string message_of(F&& f, double* seconds = nullptr) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string what;
    try {
        f();
        ADD_FAILURE() << "no InvalidInput thrown";
    } catch (const InvalidInput& e) {
        what = e.what();
    }
    if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return what;
}

const std::string kTriangleBody =
    "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\n";

TEST_F(IoHostile, PropertylessElementWithCount2To63Minus1IsSkippedAtOnce) {
    // The 62-byte file of the issue: nothing but the element.
    const std::string alone =
        write_bytes("alone.ply", "ply\nformat ascii 1.0\nelement a 9223372036854775807\nend_header\n");
    double seconds = 0;
    const std::string what = message_of([&] { read_mesh(alone); }, &seconds);
    EXPECT_NE(what.find(alone + ": contains no triangles"), std::string::npos) << what;
    EXPECT_LT(seconds, 1.0);
    // Beside a real triangle, in both encodings, the element holds nothing and is skipped.
    const std::string ascii = write_bytes(
        "ascii.ply", "ply\nformat ascii 1.0\nelement a 9223372036854775807\n" + kTriangleBody +
                         "element b 9223372036854775807\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_EQ(read_mesh(ascii).num_triangles(), 1);
    std::string bin = "ply\nformat binary_little_endian 1.0\nelement a 9223372036854775807\n" + kTriangleBody + "end_header\n";
    const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    bin += '\3';
    for (std::int32_t v : {0, 1, 2}) bin.append(reinterpret_cast<const char*>(&v), 4);
    if (const std::uint16_t one = 1; *reinterpret_cast<const char*>(&one) == 1) {  // the bytes above are little-endian
        EXPECT_EQ(read_mesh(write_bytes("binary.ply", bin)).num_triangles(), 1);
    }
}

TEST_F(IoHostile, CountsLargerThanTheFileCanHoldAreRejectedBeforeReading) {
    const struct {
        const char* name;
        std::string bytes;
        const char* expected;
    } cases[] = {
        {"vertices.ply",
         "ply\nformat binary_little_endian 1.0\nelement vertex 4294967296\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n" + std::string(12, '\0'),
         "expected 4294967296 'vertex' elements, but the 12 bytes left in the file can hold at most 1"},
        {"faces.ply",
         "ply\nformat ascii 1.0\n" + std::string("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n") +
             "element face 2147483648\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "expected 2147483648 'face' elements, but the 9 bytes left in the file can hold at most 5"},
        {"other.ply",
         "ply\nformat ascii 1.0\nelement junk 9223372036854775807\nproperty uchar a\nend_header\n1 2 3\n",
         "'junk' elements, but the 6 bytes left"},
    };
    for (const auto& c : cases) {
        const std::string p = write_bytes(c.name, c.bytes);
        double seconds = 0;
        const std::string what = message_of([&] { read_mesh(p); }, &seconds);
        EXPECT_NE(what.find(p + ": truncated"), std::string::npos) << what;
        EXPECT_NE(what.find(c.expected), std::string::npos) << what;
        EXPECT_LT(seconds, 1.0) << c.name;
    }
}

TEST_F(IoHostile, AHugeListLengthIsTruncationNotAnOverflow) {
    // A skipped list of 2^31 - 1 doubles (8 bytes each: the byte count overflows 32 bits) in a
    // 3-byte remainder.
    std::string bin = "ply\nformat binary_little_endian 1.0\nelement junk 1\nproperty list int double a\nend_header\n";
    const std::int32_t n = 2147483647;
    bin.append(reinterpret_cast<const char*>(&n), 4);
    bin += "abc";
    const std::string p = write_bytes("list.ply", bin);
    if (const std::uint16_t one = 1; *reinterpret_cast<const char*>(&one) != 1) GTEST_SKIP() << "big-endian host";
    const std::string what = message_of([&] { read_mesh(p); });
    EXPECT_NE(what.find("expected 1 'junk' elements, file ends after 0"), std::string::npos) << what;
}

TEST_F(IoHostile, OnlyRegularFilesAreRead) {
    const std::string fifo = (dir_ / "pipe.obj").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
    const std::string link = (dir_ / "zero.stl").string();
    fs::create_symlink("/dev/zero", link);
    const struct {
        std::string path;
        const char* expected;
    } cases[] = {{fifo, "is a FIFO (named pipe), not a regular file"},
                 {"/dev/zero", "is a device, not a regular file"},
                 {link, "is a device, not a regular file"},
                 {dir_.string(), "is a directory, not a mesh file"},
                 {(dir_ / "missing.obj").string(), "cannot open file (No such file or directory)"}};
    for (const auto& c : cases) {
        double seconds = 0;
        const std::string what = message_of([&] { read_mesh(c.path); }, &seconds);
        EXPECT_EQ(what.rfind(c.path + ": " + c.expected, 0), 0u) << what;
        EXPECT_LT(seconds, 1.0) << c.path;
        PlyExtras extras;
        EXPECT_THROW(read_ply_with_extras(c.path, extras), InvalidInput) << c.path;
        EXPECT_THROW(read_polygon_mesh(c.path), InvalidInput) << c.path;
    }
}

TEST_F(IoHostile, NonFiniteOrOutOfRangeExtrasAreRejectedNamingTheFile) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property double distance\nelement face 1\nproperty list uchar int vertex_indices\nproperty double patch\n"
        "end_header\n";
    const struct {
        const char* d0;
        const char* d1;
        const char* d2;
        const char* patch;
        const char* expected;
    } cases[] = {{"0", "0", "0", "nan", "PLY element 'face' 0: property 'patch' is NaN"},
                 {"0", "0", "0", "-inf", "PLY element 'face' 0: property 'patch' is infinite"},
                 {"0", "0", "0", "3e9", "PLY element 'face' 0: property 'patch' = 3e+09 is out of the range of an int"},
                 {"0", "nan", "0", "1", "PLY element 'vertex' 1: property 'distance' is NaN"},
                 {"0", "0", "1e300", "1", "PLY element 'vertex' 2: property 'distance' = 1e+300 is out of the range of a float"}};
    for (const auto& c : cases) {
        const std::string body = std::string("0 0 0 ") + c.d0 + "\n1 0 0 " + c.d1 + "\n0 1 0 " + c.d2 + "\n3 0 1 2 " +
                                 c.patch + "\n";
        const std::string p = write_bytes("extras.ply", head + body);
        PlyExtras extras;
        extras.face_int_name = "patch";
        extras.vertex_float_name = "distance";
        const std::string what = message_of([&] { read_ply_with_extras(p, extras); });
        EXPECT_EQ(what.rfind(p + ": " + c.expected, 0), 0u) << what;
    }
}

}  // namespace
}  // namespace quadcage

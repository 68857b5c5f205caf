// Expansion of bench PATH arguments: files, folders, manifests, duplicates and name collisions.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "quadcage/bench/inputs.h"
#include "quadcage/core/errors.h"

namespace {

namespace fs = std::filesystem;
using quadcage::InvalidInput;
using quadcage::bench::expand_inputs;

class BenchInputs : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("quadcage_inputs_test_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "set" / "sub");
        for (const char* f : {"set/b.off", "set/a.obj", "set/c.STL", "set/notes.md", "set/sub/a.ply", "other.ply"})
            std::ofstream(dir_ / f) << "x\n";
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(BenchInputs, FolderGivesItsMeshesSortedByName) {
    const auto in = expand_inputs({(dir_ / "set").string()});
    ASSERT_EQ(in.size(), 3u);
    EXPECT_EQ(fs::path(in[0].path).filename(), "a.obj");
    EXPECT_EQ(fs::path(in[1].path).filename(), "b.off");
    EXPECT_EQ(fs::path(in[2].path).filename(), "c.STL");
    EXPECT_EQ(in[0].name, "a");
}

TEST_F(BenchInputs, ManifestPathsAreRelativeToTheManifestAndNamesAreMadeUnique) {
    std::ofstream(dir_ / "list.txt") << "# comment\n\nset/sub/a.ply\r\n  set/a.obj  \n" << (dir_ / "other.ply").string()
                                     << "\nset/a.obj\n";
    const auto in = expand_inputs({(dir_ / "list.txt").string()});
    ASSERT_EQ(in.size(), 3u);  // set/a.obj listed twice: kept once
    EXPECT_EQ(in[0].name, "a");
    EXPECT_EQ(in[1].name, "a_2");
    EXPECT_EQ(in[2].name, "other");
    EXPECT_TRUE(fs::exists(in[1].path));
}

TEST_F(BenchInputs, OddNamesGetSafeFolderNames) {
    std::ofstream(dir_ / "we ird,name.obj") << "x\n";
    const auto in = expand_inputs({(dir_ / "we ird,name.obj").string()});
    ASSERT_EQ(in.size(), 1u);
    EXPECT_EQ(in[0].name, "we ird,name");
    EXPECT_EQ(in[0].dir_name, "we_ird_name");
}

TEST_F(BenchInputs, ErrorsNameThePath) {
    try {
        expand_inputs({(dir_ / "missing.obj").string()});
        FAIL() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("missing.obj: no such file or folder"), std::string::npos) << e.what();
    }
    fs::create_directories(dir_ / "empty");
    EXPECT_THROW(expand_inputs({(dir_ / "empty").string()}), InvalidInput);
    std::ofstream(dir_ / "self.txt") << "self.txt\n";
    EXPECT_THROW(expand_inputs({(dir_ / "self.txt").string()}), InvalidInput);
    std::ofstream(dir_ / "bad.txt") << "set/a.obj\nnope.off\n";
    try {
        expand_inputs({(dir_ / "bad.txt").string()});
        FAIL() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("bad.txt:2:"), std::string::npos) << e.what();
    }
    EXPECT_THROW(expand_inputs({}), InvalidInput);
}

}  // namespace

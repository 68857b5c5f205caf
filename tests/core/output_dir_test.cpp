// OutputDir: all-or-nothing outputs, checked before the work, never replacing an input (issue 23).

#include "quadcage/core/output_dir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "support/names.h"

namespace quadcage {
namespace {

namespace fs = std::filesystem;

// Every entry under `root` (relative path -> "dir", "file:<contents>" or "link:<target>").
std::map<std::string, std::string> snapshot(const fs::path& root) {
    std::map<std::string, std::string> out;
    if (!fs::exists(fs::symlink_status(root))) return out;
    for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
        const std::string rel = it->path().lexically_relative(root).string();
        if (it->is_symlink()) out[rel] = "link:" + fs::read_symlink(it->path()).string();
        else if (it->is_directory()) out[rel] = "dir";
        else {
            std::ifstream in(it->path(), std::ios::binary);
            std::stringstream s;
            s << in.rdbuf();
            out[rel] = "file:" + s.str();
        }
    }
    return out;
}

class OutputDirTest : public testing::Test {
protected:
    void SetUp() override {
        const auto* test = testing::UnitTest::GetInstance()->current_test_info();
        base_ = fs::path(testing::TempDir()) / ("quadcage_outdir_" + std::to_string(::getpid()) + "_" +
                                                test::identifier(std::string(test->name())));
        fs::remove_all(base_);
        fs::create_directories(base_);
        dir_ = base_ / "out";
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(base_, ec);
    }
    void put(const fs::path& p, const std::string& text) const {
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
    }
    // The outputs of a run: two at the top, two in a component folder.
    static void stage(OutputDir& out, const std::string& tag) {
        write_text_file(out.path("a.txt"), "a " + tag);
        write_text_file(out.path("report.json"), "{} " + tag);
        write_text_file(out.path("component_1/b.txt"), "b " + tag);
        write_text_file(out.folder("component_1") + "/c.txt", "c " + tag);
    }
    // Nothing but `dir_` itself (if at all) in base_: no staging folder left behind.
    void expect_no_leftovers() const {
        for (const auto& e : fs::directory_iterator(base_)) EXPECT_EQ(e.path(), dir_) << "left behind: " << e.path();
    }
    fs::path base_, dir_;
};

TEST_F(OutputDirTest, CommitReplacesItsOutputsAndLeavesOtherFilesAlone) {
    put(dir_ / "a.txt", "old a");
    put(dir_ / "keep.txt", "mine");
    put(dir_ / "component_1" / "keep.txt", "mine too");
    {
        OutputDir out(dir_.string());
        out.expect({"a.txt", "report.json", "component_1/b.txt", "component_1/c.txt"});
        stage(out, "new");
        EXPECT_EQ(snapshot(dir_).at("a.txt"), "file:old a");  // nothing moves before commit()
        out.commit();
    }
    const auto after = snapshot(dir_);
    const std::map<std::string, std::string> expected = {
        {"a.txt", "file:a new"},         {"keep.txt", "file:mine"},          {"report.json", "file:{} new"},
        {"component_1", "dir"},          {"component_1/b.txt", "file:b new"}, {"component_1/c.txt", "file:c new"},
        {"component_1/keep.txt", "file:mine too"}};
    EXPECT_EQ(after, expected);
    expect_no_leftovers();
}

TEST_F(OutputDirTest, CommitCreatesAMissingDirectoryAndItsParents) {
    dir_ = base_ / "deep" / "er" / "out";
    {
        OutputDir out(dir_.string() + "/");
        stage(out, "x");
        EXPECT_FALSE(fs::exists(base_ / "deep"));
        out.commit();
    }
    EXPECT_EQ(snapshot(dir_).size(), 5u);
    EXPECT_EQ(std::distance(fs::directory_iterator(base_), fs::directory_iterator()), 1);
}

TEST_F(OutputDirTest, WithoutCommitNothingChanges) {
    put(dir_ / "a.txt", "old a");
    const auto before = snapshot(base_);
    {
        OutputDir out(dir_.string());
        stage(out, "new");
    }
    EXPECT_EQ(snapshot(base_), before);
    // A directory that did not exist is not created either.
    const fs::path fresh = base_ / "fresh";
    {
        OutputDir out(fresh.string());
        stage(out, "new");
    }
    EXPECT_FALSE(fs::exists(fresh));
    EXPECT_EQ(snapshot(base_), before);
}

// A failure at any move of the commit leaves the directory exactly as it was: the moves already
// made are undone and replaced files come back.
TEST_F(OutputDirTest, AFailedMoveAtAnyFileLeavesTheDirectoryAsItWas) {
    put(dir_ / "a.txt", "old a");
    put(dir_ / "component_1" / "b.txt", "old b");
    put(dir_ / "keep.txt", "mine");
    const auto before = snapshot(base_);
    int moves = 0;
    {
        OutputDirOptions count;
        count.rename = [&](const std::string& from, const std::string& to) {
            ++moves;
            return std::rename(from.c_str(), to.c_str());
        };
        OutputDir probe((base_ / "probe").string(), count);
        stage(probe, "x");
        probe.commit();
    }
    fs::remove_all(base_ / "probe");
    ASSERT_EQ(moves, 4);
    // With a.txt and b.txt present there are 6 moves (two set the old files aside); fail each in turn.
    for (int fail_at = 0; fail_at < 6; ++fail_at) {
        int k = 0;
        OutputDirOptions options;
        options.rename = [&](const std::string& from, const std::string& to) {
            if (k++ == fail_at) {
                errno = EIO;
                return -1;
            }
            return std::rename(from.c_str(), to.c_str());
        };
        {
            OutputDir out(dir_.string(), options);
            stage(out, "new");
            try {
                out.commit();
                ADD_FAILURE() << "commit did not fail at move " << fail_at;
            } catch (const InvalidInput& e) {
                EXPECT_NE(std::string(e.what()).find("the output directory was left as it was"), std::string::npos) << e.what();
            }
        }
        EXPECT_EQ(snapshot(base_), before) << "failure at move " << fail_at;
    }
}

TEST_F(OutputDirTest, AnUnusableDirectoryIsRefusedUpFront) {
    put(base_ / "file", "x");
    EXPECT_THROW(OutputDir((base_ / "file").string()), InvalidInput);
    EXPECT_THROW(OutputDir((base_ / "file" / "below").string()), InvalidInput);
    EXPECT_THROW(OutputDir(""), InvalidInput);
    // Output names taken by directories, or folders on the way taken by files.
    fs::create_directories(dir_ / "cage.obj");
    put(dir_ / "component_1", "a file");
    OutputDir out(dir_.string());
    try {
        out.expect({"layout.ply", "cage.obj"});
        ADD_FAILURE() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("cage.obj: is a directory"), std::string::npos) << e.what();
    }
    try {
        out.expect({"component_1/layout.ply"});
        ADD_FAILURE() << "no exception";
    } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find("component_1: exists and is not a directory"), std::string::npos) << e.what();
    }
    EXPECT_THROW(out.expect({"../escape.txt"}), InvalidInput);
    EXPECT_THROW(out.path("/etc/passwd"), InvalidInput);
}

TEST_F(OutputDirTest, AnOutputThatWouldReplaceAnInputIsAConflict) {
    put(dir_ / "cage.obj", "the input");
    const fs::path hard = base_ / "hard_link.obj";
    fs::create_hard_link(dir_ / "cage.obj", hard);
    for (const fs::path& input : {dir_ / "cage.obj", dir_ / ".." / "out" / "cage.obj", hard}) {
        OutputDir out(dir_.string());
        EXPECT_THROW(out.expect({"layout.ply", "cage.obj"}, {input.string()}), OutputConflict) << input;
        // Not an output name: no conflict.
        EXPECT_NO_THROW(out.expect({"layout.ply"}, {}));
    }
    // commit() checks again, whatever expect() was told.
    {
        OutputDir out(dir_.string());
        out.expect({}, {hard.string()});
        write_text_file(out.path("cage.obj"), "an output");
        EXPECT_THROW(out.commit(), OutputConflict);
    }
    EXPECT_EQ(snapshot(dir_).at("cage.obj"), "file:the input");
}

}  // namespace
}  // namespace quadcage

/* semloc tests — StagedDirectory: complete output or none. */
#include <gtest/gtest.h>
#include <semloc/io/StagedDirectory.h>

#include <filesystem>
#include <fstream>

TEST(StagedDirectory, CommitReplacesErrorLeavesNothing)
{
    namespace fs = std::filesystem;
    const fs::path base = fs::path(SEMLOC_TEST_OUT) / "staged";
    fs::remove_all(base);
    const fs::path target = base / "a" / "out";
    {
        semloc::StagedDirectory d(target.string());
        std::ofstream(d.path("x.txt")) << "1";
        EXPECT_FALSE(fs::exists(target));
        d.commit();
    }
    EXPECT_TRUE(fs::exists(target / "x.txt"));
    {
        semloc::StagedDirectory d(target.string());
        std::ofstream(d.path("y.txt")) << "2";
        d.commit();
    }
    EXPECT_FALSE(fs::exists(target / "x.txt")) << "replaced as a whole";
    EXPECT_TRUE(fs::exists(target / "y.txt"));
    {
        semloc::StagedDirectory d((base / "b").string());
        std::ofstream(d.path("z.txt")) << "3";
        // no commit: an error happened
    }
    EXPECT_FALSE(fs::exists(base / "b"));
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(base))
    {
        entries++;
        EXPECT_EQ(e.path().filename(), "a") << "no staging directory left behind";
    }
    EXPECT_EQ(entries, 1u);
}

/* semloc tests — semloc-localize on a long log: memory bounded by the work, not the log's
 * length (the rawlog is streamed, each step written to steps.csv as it is run). */
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "LongLog.h"
#include "ProcessRun.h"
#include "TestHelpers.h"

namespace fs = std::filesystem;

namespace
{
const std::string kSrc = SEMLOC_SOURCE_DIR;
const std::string kBin = SEMLOC_BIN_DIR;

/** Peak resident set of semloc-localize on a 300 000-step log with 20 particles [MiB]. */
[[maybe_unused]] constexpr double kBudget_MiB = 400;

size_t lineCount(const fs::path& p)
{
    std::ifstream f(p);
    size_t n = 0;
    for (std::string line; std::getline(f, line);)
    {
        n++;
    }
    return n;
}

/** semloc-localize (config/localize/semantic.ini, 20 particles, one thread) on a `steps`-step log;
 * its peak resident set [MiB]. */
double localizeLongLog(size_t steps)
{
    const fs::path d = fs::path(SEMLOC_TEST_OUT) / ("long_log_" + std::to_string(steps));
    fs::remove_all(d);
    fs::create_directories(d);
    const auto world = semloc::World::FromFile(kSrc + "/maps/paper_50x50.yaml");
    semloc::test::writeLongLog(world, steps, (d / "long.rawlog").string(),
                               (d / "long_gt.txt").string());
    double rss = 0;
    const int rc = semloc::test::runMeasured(
        {kBin + "/semloc-localize", kSrc + "/config/localize/semantic.ini",
         (d / "long.rawlog").string(), "-o", (d / "out").string(), "-n", "20", "-t", "1", "-q"},
        d / "localize.log", rss);
    EXPECT_EQ(rc, 0) << semloc::test::readText(d / "localize.log");
    EXPECT_EQ(lineCount(d / "out" / "steps.csv"), steps + 1) << "a row per step and the header";
    const std::string summary = semloc::test::readText(d / "out" / "summary.yaml");
    EXPECT_NE(summary.find("\nsteps_with_ground_truth: " + std::to_string(steps) + "\n"),
              std::string::npos)
        << summary;
    std::cout << "semloc-localize, " << steps << " steps: peak RSS " << rss << " MiB\n";
    if (!::testing::Test::HasFailure())
    {
        fs::remove_all(d);
    }
    return rss;
}
}  // namespace

TEST(LongLog, LocalizeMemoryDoesNotGrowWithTheLogsLength)
{
#ifdef SEMLOC_SANITIZED
    // The sanitizers' shadow memory and quarantine count as resident, so the sizes say nothing
    // there; the shorter log runs the same code for memory errors.
    localizeLongLog(30000);
#else
    const double rssShort = localizeLongLog(30000);
    const double rssLong = localizeLongLog(300000);
    EXPECT_LT(rssLong, kBudget_MiB);
    // Ten times the steps: what grows is the step times kept for the ground truth (8 bytes a
    // step), a few MB, not the rawlog or the records.
    EXPECT_LT(rssLong - rssShort, 40) << rssShort << " MiB at 30 000 steps";
#endif
}

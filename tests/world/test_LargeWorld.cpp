/* semloc tests — a 20 x 20 km world with 300 objects, simulated and localized by the tools
 * (semloc-simulate, semloc-localize with config/localize/semantic.ini) within a memory budget: what
 * a run keeps per unit of area is bounded (the free-space raster, the object index, the visibility
 * tables, the ray caster's grid), so the peak resident set of each tool stays near that of the 50 x
 * 50 m paper world (about 110 MB). */
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "LargeWorld.h"
#include "ProcessRun.h"
#include "TestHelpers.h"

namespace fs = std::filesystem;

namespace
{
const std::string kSrc = SEMLOC_SOURCE_DIR;
const std::string kBin = SEMLOC_BIN_DIR;

/** Peak resident set allowed to each tool on the 20 km world [MiB] (docs/design.md, "Large
 *  worlds"). A raster of the world at the 0.1 m of small worlds would take 40 GB, at 1 m 400 MB. */
[[maybe_unused]] constexpr long kBudget_MiB = 256;  // unused when sanitized

using semloc::test::readText;

/** Runs `args` (args[0] in the build's bin directory): semloc::test::runMeasured. */
int run(std::vector<std::string> args, const fs::path& log, double& maxRss_MiB)
{
    args[0] = kBin + "/" + args[0];
    return semloc::test::runMeasured(args, log, maxRss_MiB);
}

/** `ini` with each `key = value` line of `keys` replaced (each key must be there). */
std::string withKeys(std::string ini, const std::vector<std::pair<std::string, std::string>>& keys)
{
    for (const auto& [k, v] : keys)
    {
        const size_t p = ini.find("\n" + k + " ");
        EXPECT_NE(p, std::string::npos) << k;
        if (p != std::string::npos)
        {
            std::string line = k;
            line += " = ";
            line += v;
            ini.replace(p + 1, ini.find('\n', p + 1) - p - 1, line);
        }
    }
    return ini;
}

/** The value of `key: ` in summary.yaml text. */
std::string summaryValue(const std::string& yaml, const std::string& key)
{
    const size_t p = yaml.find("\n" + key + ": ");
    if (p == std::string::npos)
    {
        return "";
    }
    const size_t b = p + key.size() + 3;
    return yaml.substr(b, yaml.find('\n', b) - b);
}
}  // namespace

TEST(LargeWorld, A20kmWorldIsSimulatedAndLocalizedWithinTheMemoryBudget)
{
    const fs::path d = fs::path(SEMLOC_TEST_OUT) / "large_world";
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "large.yaml") << semloc::test::largeWorldYaml();

    // A 200-step survey (1 m/s, 1 s steps) in the middle of the world.
    std::ofstream(d / "sim.ini") << withKeys(
        readText(kSrc + "/config/simulate/simulate.ini"),
        {{"world_file", (d / "large.yaml").string()}, {"max_steps", "200"}});
    double rss = 0;
    ASSERT_EQ(
        run({"semloc-simulate", (d / "sim.ini").string(), "-o", (d / "large.rawlog").string()},
            d / "simulate.log", rss),
        0)
        << readText(d / "simulate.log");
    std::cout << "semloc-simulate: peak RSS " << rss << " MiB\n";
#ifndef SEMLOC_SANITIZED  // the sanitizers' shadow memory and quarantine count as resident
    EXPECT_LT(rss, kBudget_MiB);
#endif

    const std::string semantic = semloc::test::resolvedIni(kSrc + "/config/localize/semantic.ini");
    // Global localization (config/localize/semantic.ini as shipped: 10000 particles uniform over
    // the free space of 400 km2): the first cloud and every free-space test at this scale.
    std::ofstream(d / "global.ini")
        << withKeys(semantic, {{"map_file", (d / "large.yaml").string()}});
    ASSERT_EQ(run({"semloc-localize", (d / "global.ini").string(), (d / "large.rawlog").string(),
                   "-o", (d / "global").string(), "-q"},
                  d / "global.log", rss),
              0)
        << readText(d / "global.log");
    std::cout << "semloc-localize, global: peak RSS " << rss << " MiB\n";
#ifndef SEMLOC_SANITIZED
    EXPECT_LT(rss, kBudget_MiB);
#endif
    const std::string g = readText(d / "global" / "summary.yaml");
    EXPECT_EQ(summaryValue(g, "steps"), "200") << g;
    EXPECT_EQ(summaryValue(g, "nonfinite_likelihoods"), "0") << g;

    // Localization from a 100 x 100 m box around the start (the survey's first 10 m lie in
    // it): converges to the simulated truth.
    std::ofstream(d / "box.ini") << withKeys(semantic, {{"map_file", (d / "large.yaml").string()},
                                                        {"init_PDF_mode", "1"},
                                                        {"init_PDF_min_x", "9850"},
                                                        {"init_PDF_max_x", "9950"},
                                                        {"init_PDF_min_y", "9950"},
                                                        {"init_PDF_max_y", "10050"}});
    ASSERT_EQ(run({"semloc-localize", (d / "box.ini").string(), (d / "large.rawlog").string(), "-o",
                   (d / "box").string(), "-q"},
                  d / "box.log", rss),
              0)
        << readText(d / "box.log");
    std::cout << "semloc-localize, box: peak RSS " << rss << " MiB\n";
#ifndef SEMLOC_SANITIZED
    EXPECT_LT(rss, kBudget_MiB);
#endif
    const std::string b = readText(d / "box" / "summary.yaml");
    EXPECT_EQ(summaryValue(b, "converged"), "true") << b;
    EXPECT_LT(std::atof(summaryValue(b, "final_err_m").c_str()), 1.0) << b;
    EXPECT_LT(std::atof(summaryValue(b, "mean_err_after_conv_m").c_str()), 1.0) << b;
}

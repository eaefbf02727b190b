/* semloc tests — range-only acoustic beacons (LBL) end to end: a dataset of
 * config/simulate/simulate_lbl.ini localized by config/localize/semantic_lbl.ini (MRPT's
 * CBeaconMap beside the semantic map), from a uniform start with 10000 particles (with 2000,
 * the first ranges leave a handful of particles, at the right place with random headings),
 * the same for 1 and 2 threads; the shipped lbl files against their bases. */
#include <gtest/gtest.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/Simulator.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <unistd.h>

#include "TestHelpers.h"
#include "experiment/LocalizeRun.h"

namespace fs = std::filesystem;
using semloc::LocalizationExperiment;
using semloc::test::readText;
using semloc::test::stepsWithoutTiming;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "localize_beacons";
const std::string kConfig = SEMLOC_SOURCE_DIR "/config/";

/** `variant` (a file of config/localize/, its base resolved) started uniformly over the free
 *  space of the lbl world, written to the test's output directory. */
std::string uniformStart(const std::string& variant)
{
    const std::string text = semloc::test::withKeys(
        semloc::config::readIniText(kConfig + "localize/" + variant + ".ini"), variant,
        {{"init_PDF_mode", "0"}, {"map_file", SEMLOC_SOURCE_DIR "/maps/paper_50x50_lbl.yaml"}});
    const fs::path path = kOut / (variant + "_uniform.ini");
    std::ofstream(path) << text;
    return path.string();
}

/** "[section] key" -> value of every key of an ini file, its bases resolved. */
std::map<std::string, std::string> keysOf(const std::string& file)
{
    const semloc::config::IniFileInMemory ini(file);
    std::vector<std::string> sections;
    ini.getAllSections(sections);
    std::map<std::string, std::string> keys;
    for (const auto& section : sections)
    {
        std::vector<std::string> names;
        ini.getAllKeys(section, names);
        for (const auto& k : names)
        {
            std::string name = "[" + section;
            name += "] " + k;
            keys[name] = ini.read_string(section, k, "");
        }
    }
    return keys;
}

LocalizationExperiment::TResult localize(const std::string& ini, const std::string& rawlog,
                                         const std::string& name, int threads)
{
    return semloc::test::localizeRun(ini, rawlog, (kOut / name).string(), 10000, threads);
}
}  // namespace

TEST(LocalizeBeacons, TheBeaconVariantLocalizesFromAUniformStartWhateverTheThreads)
{
    fs::create_directories(kOut);
    // The first 60 steps of simulate_lbl.ini (the paper's dataset plus the LBL ranges) with a
    // detector that sees 6 m far (config/benchmark/lbl/short_range.ini): few detections.
    auto options = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate_lbl.ini");
    options.simulation.max_steps = 60;
    options.detector.max_range_m = 6;
    const semloc::Simulator sim(options);
    const auto data = sim.run();
    EXPECT_EQ(data.pings, 60u);
    const std::string rawlog = (kOut / ("lbl_" + std::to_string(::getpid()) + ".rawlog")).string();
    sim.writeDataset(data, rawlog);

    const std::string lbl = uniformStart("semantic_lbl");
    const auto one = localize(lbl, rawlog, "lbl_1", 1);
    const auto two = localize(lbl, rawlog, "lbl_2", 2);
    EXPECT_EQ(one.variant, "semantic_lbl");
    EXPECT_TRUE(one.metrics.converged);
    EXPECT_LT(one.metrics.convergence_step, 15);
    EXPECT_LT(one.metrics.mean_err_after_conv_m, 0.5);
    EXPECT_EQ(stepsWithoutTiming(kOut / "lbl_1"), stepsWithoutTiming(kOut / "lbl_2"));
    EXPECT_EQ(two.metrics.convergence_step, one.metrics.convergence_step);

    // The same filter without the beacon map (semantic_lbl's filter is semantic_norecovery's),
    // on the same frames, the ranges unscored.
    const auto semantic = localize(uniformStart("semantic_norecovery"), rawlog, "semantic_1", 1);
    EXPECT_TRUE(!semantic.metrics.converged ||
                semantic.metrics.convergence_step > one.metrics.convergence_step + 10)
        << semantic.metrics.convergence_step;
}

TEST(ShippedConfigs, TheLblFilesAddTheBeaconsToTheirBaseAndNothingElse)
{
    // semantic_lbl.ini: semantic.ini with the lbl world, no recovery (nor re-seeding) and a beacon
    // map whose rangeStd is the simulated ranges' standard deviation.
    auto expected = keysOf(kConfig + "localize/semantic.ini");
    EXPECT_NE(readText(kConfig + "localize/semantic_lbl.ini").find("\nbase = semantic.ini\n"),
              std::string::npos);
    expected["[LocalizationExperiment] map_file"] = "../../maps/paper_50x50_lbl.yaml";
    expected["[LocalizationExperiment] logOutput_dir"] = "results/semantic_lbl";
    expected["[LocalizationExperiment] variant"] = "semantic_lbl";
    expected["[Recovery] trigger"] = "off";
    expected["[Recovery] lost_var_xy_m2"] = "0";  // re-seeding is part of the recovery
    expected["[MetricMap] beaconMap_count"] = "1";
    expected["[MetricMap_beaconMap_00_likelihoodOpts] rangeStd"] = "0.5";
    EXPECT_EQ(keysOf(kConfig + "localize/semantic_lbl.ini"), expected);
    // Its filter is semantic_norecovery.ini's.
    auto norecovery = keysOf(kConfig + "localize/semantic_norecovery.ini");
    for (const auto& [key, value] : norecovery)
    {
        if (key.rfind("[PF_options]", 0) == 0 || key.rfind("[Recovery]", 0) == 0 ||
            key.rfind("[MotionModel]", 0) == 0)
        {
            EXPECT_EQ(expected[key], value) << key;
        }
    }

    // simulate_lbl.ini: simulate.ini in the lbl world with the ranging on.
    auto sim = keysOf(kConfig + "simulate/simulate.ini");
    sim["[Simulation] world_file"] = "../../maps/paper_50x50_lbl.yaml";
    sim["[Simulation] output_rawlog"] = "dataset_lbl.rawlog";
    sim["[BeaconRanging] enabled"] = "true";
    EXPECT_EQ(keysOf(kConfig + "simulate/simulate_lbl.ini"), sim);
    EXPECT_EQ(std::stod(sim["[BeaconRanging] range_std_m"]),
              std::stod(expected["[MetricMap_beaconMap_00_likelihoodOpts] rangeStd"]));
}

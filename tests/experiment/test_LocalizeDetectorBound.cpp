/* semloc tests — the detector's Cramér–Rao bound semloc-localize reports in summary.yaml: on a
 * simulated dataset, with the filter configured with the simulator's detector, it is the bound
 * semloc-benchmark computes from the simulator (with and without outlines that hide objects);
 * another configured detector gives another bound; null without ground truth; a gap in the
 * ground truth leaves its steps out. */
#include <gtest/gtest.h>
#include <mrpt/containers/yaml.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/simulator/DetectorBound.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "TestHelpers.h"
#include "experiment/LocalizeRun.h"

namespace fs = std::filesystem;
using semloc::LocalizationExperiment;
using semloc::test::readText;
using semloc::test::withKeys;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "localize_bound";
const std::string kConfig = SEMLOC_SOURCE_DIR "/config/";

/** A simulated dataset on disk, its world file and the simulator's bound of each step. */
struct Dataset
{
    std::string rawlog, world;
    std::vector<semloc::TDetectorBoundStep> bound;
};

/** 150 steps of config/simulate/simulate.ini on the paper's world (its objects made points when
 *  `points`: nothing hides them), the odometry's heading drifting 2 deg/min, as `name`. */
Dataset simulate(const std::string& name, bool points)
{
    fs::create_directories(kOut);
    auto world = semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    if (points)
    {
        for (auto& o : world.objects)
        {
            o.shape = semloc::ShapeType::Point;
            o.points.clear();
        }
    }
    // ctest runs each test as its own process, in parallel: one file set per process.
    const std::string stem = (kOut / (name + "_" + std::to_string(::getpid()))).string();
    Dataset d;
    d.world = stem + "_world.yaml";
    world.saveToFile(d.world);
    auto options = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    options.simulation.max_steps = 150;
    options.odometry.heading_drift_deg_per_min = 2;
    const semloc::Simulator sim(semloc::World::FromFile(d.world), options);
    const auto data = sim.run();
    d.rawlog = stem + ".rawlog";
    sim.writeDataset(data, d.rawlog);
    d.bound = semloc::detectorCramerRaoBound(sim, data);
    return d;
}

/** config/localize/semantic.ini (the simulator's detector, a heading drift state) with `keys`
 *  replaced and map_file = `world`, written as kOut/<name>.ini. */
std::string config(const std::string& world, const std::string& name,
                   std::vector<std::pair<std::string, std::string>> keys = {})
{
    keys.emplace_back("map_file", world);
    const std::string out = withKeys(semloc::test::resolvedIni(kConfig + "localize/semantic.ini"),
                                     "semantic.ini", keys);
    const auto path = kOut / (name + ".ini");
    std::ofstream(path) << out;
    return path.string();
}

/** Runs `ini` on `rawlog` into kOut/<name> with 2000 particles, keeping the records. */
LocalizationExperiment::TResult localize(const std::string& ini, const std::string& rawlog,
                                         const std::string& name)
{
    return semloc::test::localizeRun(ini, rawlog, (kOut / name).string(), 2000, 2);
}

/** The simulator's bound `d` averaged as the benchmark does over the steps of `res`: every
 *  step with ground truth (first), from the convergence step on (second). */
std::pair<double, double> simulatorBound(const Dataset& d,
                                         const LocalizationExperiment::TResult& res)
{
    semloc::Benchmark::TRunResult r;
    r.records = res.records;
    r.metrics = res.metrics;
    r.detectorBound = d.bound;
    double sum = 0;
    size_t n = 0;
    for (const auto& s : res.records)
    {
        if (s.gt)
        {
            sum += d.bound.at(s.step).mean_err_xy_m;
            n++;
        }
    }
    return {n ? sum / static_cast<double>(n) : NAN, r.detectorBoundAfterConvergence()};
}

/** The value of `key` in kOut/<name>/summary.yaml as written ("null", a number). */
std::string summaryValue(const std::string& name, const std::string& key)
{
    std::istringstream in(readText(kOut / name / "summary.yaml"));
    std::string line;
    while (std::getline(in, line))
    {
        if (line.rfind(key + ": ", 0) == 0)
        {
            return line.substr(key.size() + 2);
        }
    }
    return "missing";
}

/** Localizes `d` with the simulator's detector as `name` and checks that the bound in
 *  summary.yaml is the simulator's, after convergence and over every step. The same model at
 *  the same increments and objects (the rawlog's actions carry the simulator's motion
 *  model): only rounding differs (about 1e-9 here), so 1e-6 rather than a few per cent. */
void expectTheSimulatorsBound(const Dataset& d, const std::string& name)
{
    const auto res = localize(config(d.world, name), d.rawlog, name);
    ASSERT_TRUE(res.metrics.converged);
    ASSERT_EQ(res.metrics.steps_with_ground_truth, d.bound.size());
    const auto [simAll, simAfter] = simulatorBound(d, res);
    EXPECT_NEAR(res.detector_bound_mean_m, simAll, 1e-6 * simAll);
    EXPECT_NEAR(res.detector_bound_after_conv_m, simAfter, 1e-6 * simAfter);
    const auto y = mrpt::containers::yaml::FromFile((kOut / name / "summary.yaml").string());
    EXPECT_NEAR(y["detector_bound_mean_m"].as<double>(), res.detector_bound_mean_m, 1e-12);
    EXPECT_NEAR(y["detector_bound_after_conv_m"].as<double>(), res.detector_bound_after_conv_m,
                1e-12);
    EXPECT_NEAR(y["error_over_bound_after_conv"].as<double>(),
                res.metrics.mean_err_after_conv_m / res.detector_bound_after_conv_m, 1e-9);
}
}  // namespace

TEST(LocalizeDetectorBound, IsTheSimulatorsBoundForTheSameDetector)
{
    expectTheSimulatorsBound(simulate("points", true), "points");
}

TEST(LocalizeDetectorBound, IsTheSimulatorsBoundWithTheSameOutlinesHidingObjects)
{
    expectTheSimulatorsBound(simulate("outlines", false), "outlines");
}

TEST(LocalizeDetectorBound, AnotherConfiguredDetectorGivesAnotherBound)
{
    // The filter told of a detector half as precise: the bound it reports is that detector's,
    // far above the simulated one's.
    const auto d = simulate("other", true);
    const auto res =
        localize(config(d.world, "other", {{"sigma_range_m", "1"}, {"sigma_bearing_deg", "6"}}),
                 d.rawlog, "other");
    const double simAll = simulatorBound(d, res).first;
    EXPECT_GT(res.detector_bound_mean_m, 1.5 * simAll);
}

TEST(LocalizeDetectorBound, IsNullWithoutGroundTruth)
{
    const auto d = simulate("nogt", true);
    fs::remove(semloc::GroundTruthFile::PathFor(d.rawlog));
    const auto res = localize(config(d.world, "nogt"), d.rawlog, "nogt");
    EXPECT_EQ(res.metrics.steps_with_ground_truth, 0u);
    EXPECT_TRUE(std::isnan(res.detector_bound_mean_m));
    EXPECT_TRUE(std::isnan(res.detector_bound_after_conv_m));
    for (const char* key :
         {"detector_bound_after_conv_m", "detector_bound_mean_m", "error_over_bound_after_conv"})
    {
        EXPECT_EQ(summaryValue("nogt", key), "null") << key;
    }
}

TEST(LocalizeDetectorBound, AGapInTheGroundTruthLeavesItsStepsOut)
{
    // Steps 60..79 lose their ground truth: the bound is over the others, predicted across the
    // gap by the odometry; without the gap's detections it is no lower than the simulator's
    // there, and back to it within a few steps.
    const auto d = simulate("gap", true);
    const std::string gt = semloc::GroundTruthFile::PathFor(d.rawlog);
    auto rows = semloc::GroundTruthFile::Read(gt);
    rows.erase(rows.begin() + 60, rows.begin() + 80);
    semloc::GroundTruthFile::Write(rows, gt);
    const auto res = localize(config(d.world, "gap"), d.rawlog, "gap");
    ASSERT_EQ(res.metrics.steps_with_ground_truth, d.bound.size() - 20);
    const double simAll = simulatorBound(d, res).first;
    EXPECT_GE(res.detector_bound_mean_m, 0.99 * simAll);
    EXPECT_LT(res.detector_bound_mean_m, 1.2 * simAll);
}

/* semloc tests — detections.csv (semloc-localize --trace-detections): one row per detection
 * the semantic map uses, each detection's gain at the estimate and at the true pose and the
 * object it is most like; a wrong estimate shows in the gains; refused without a semantic
 * map. */
#include <gtest/gtest.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "TestHelpers.h"
#include "experiment/LocalizeRun.h"

namespace fs = std::filesystem;
using semloc::LocalizationExperiment;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "detections_trace";
const std::string kConfig = SEMLOC_SOURCE_DIR "/config/";

/** The first 30 steps of the paper's dataset (config/simulate/simulate.ini), saved. */
std::string dataset()
{
    fs::create_directories(kOut);
    auto options = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    options.simulation.max_steps = 30;
    const semloc::Simulator sim(options);
    const std::string rawlog =
        (kOut / ("paper_" + std::to_string(::getpid()) + ".rawlog")).string();
    sim.writeDataset(sim.run(), rawlog);
    return rawlog;
}

/** semantic_norecovery.ini with its particles started around (x, y, 0) within 0.05 m. */
std::string startedAt(double x, double y, const std::string& name)
{
    const std::string text = semloc::test::withKeys(
        semloc::config::readIniText(kConfig + "localize/semantic_norecovery.ini"), name,
        {{"init_PDF_mode", "2"},
         {"init_PDF_mean_x", std::to_string(x)},
         {"init_PDF_mean_y", std::to_string(y)},
         {"init_PDF_mean_yaw_deg", "0"},
         {"init_PDF_std_xy", "0.05"},
         {"init_PDF_std_yaw_deg", "1"},
         {"map_file", SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml"}});
    const fs::path path = kOut / (name + ".ini");
    std::ofstream(path) << text;
    return path.string();
}

struct Row
{
    int step = 0, k = 0;
    std::string estObject, gtObject;
    double estGain = 0, gtGain = 0;
};

/** The rows of a run's detections.csv; its header in `header`. */
std::vector<Row> rowsOf(const fs::path& dir, std::string& header)
{
    std::istringstream in(semloc::test::readText(dir / "detections.csv"));
    std::getline(in, header);
    std::vector<Row> rows;
    for (std::string line; std::getline(in, line);)
    {
        std::vector<std::string> c;
        std::stringstream ls(line);
        for (std::string f; std::getline(ls, f, ',');)
        {
            c.push_back(f);
        }
        c.resize(12);
        rows.push_back(
            {std::stoi(c[0]), std::stoi(c[2]), c[6], c[9], std::stod(c[8]), std::stod(c[11])});
    }
    return rows;
}

LocalizationExperiment::TResult localize(const std::string& ini, const std::string& rawlog,
                                         const std::string& name)
{
    return semloc::test::localizeRun(ini, rawlog, (kOut / name).string(), 2000, std::nullopt, true);
}
}  // namespace

TEST(DetectionsTrace, TrackingItsGainsAreTheTruthsAndAWrongEstimateShows)
{
    const std::string rawlog = dataset();
    // Started at the true start (3, 4, 0): the estimate stays on the truth, so the two sides
    // of every row agree closely.
    localize(startedAt(3, 4, "at_truth"), rawlog, "at_truth");
    std::string header;
    const auto rows = rowsOf(kOut / "at_truth", header);
    EXPECT_EQ(header,
              "step,t,k,label,range_m,bearing_deg,est_object,est_d2,est_gain,gt_object,gt_d2,"
              "gt_gain");
    ASSERT_GT(rows.size(), 30u);  // a few detections per scan
    std::set<std::pair<int, int>> seen;
    size_t sameObject = 0, withObject = 0;
    double sumGt = 0;
    for (const Row& r : rows)
    {
        EXPECT_TRUE(seen.insert({r.step, r.k}).second) << "step " << r.step << " k " << r.k;
        EXPECT_TRUE(std::isfinite(r.estGain) && std::isfinite(r.gtGain));
        if (!r.gtObject.empty())
        {
            withObject++;
            sameObject += r.estObject == r.gtObject ? 1 : 0;
        }
        sumGt += r.gtGain;
    }
    EXPECT_GT(withObject, rows.size() / 2);
    EXPECT_GT(sameObject, withObject * 9 / 10);
    EXPECT_GT(sumGt / static_cast<double>(rows.size()), 0);  // detections favour the truth

    // Started 6 m off, without recovery: at the first steps the detections explain the truth
    // far better than the wrong estimate, detection by detection.
    localize(startedAt(9, 4, "off"), rawlog, "off");
    const auto off = rowsOf(kOut / "off", header);
    double gap = 0;
    size_t first = 0;
    for (const Row& r : off)
    {
        if (r.step < 3)
        {
            gap += r.gtGain - r.estGain;
            first++;
        }
    }
    ASSERT_GT(first, 0u);
    EXPECT_GT(gap / static_cast<double>(first), 1.0);
}

TEST(DetectionsTrace, RefusedWithoutASemanticMapNamingTheKey)
{
    const std::string rawlog = dataset();
    LocalizationExperiment::TOverrides ov;
    ov.rawlog_file = rawlog;
    ov.logOutput_dir = (kOut / "geometric").string();
    ov.detections_trace = true;
    try
    {
        (void)LocalizationExperiment::FromConfigFile(kConfig + "localize/geometric.ini", ov);
        FAIL() << "a trace without a semantic map was accepted";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("detections_trace"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(kOut / "geometric"));
}

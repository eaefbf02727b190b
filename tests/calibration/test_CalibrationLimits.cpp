/* semloc tests — semloc-calibrate's fits kept to what semloc-localize accepts: degenerate
 * datasets (a noise-free detector, one that sees everything or nothing far, no clutter, one
 * scan, a still vehicle) give an ini that loads, with every clamp and every fit left out said in
 * its comment and on stderr; a detector's bias and a map offset reported, warned and not taken
 * into the sigmas; a base ini semloc-localize would refuse refused first. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using semloc::GroundTruthFile;
using semloc::SensorCalibration;
using semloc::Simulator;
using semloc::TCalibrationFit;
using semloc::TCalibrationResult;
using semloc::TSimulatorOptions;
#include "TestHelpers.h"

namespace fs = std::filesystem;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kSemanticIni = SEMLOC_SOURCE_DIR "/config/localize/semantic.ini";
const std::string kLik = "MetricMap_semanticMap_00_likelihoodOpts";

using semloc::test::readText;

TSimulatorOptions paperRun(uint32_t seed)
{
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.simulation.seed = seed;
    o.simulation.time_step_s = 0.5;
    return o;
}

/** Every semantic observation of `log` changed by `f`. */
void editScans(mrpt::obs::CRawlog& log, const std::function<void(semloc::CObservationSemantic&)>& f)
{
    for (size_t i = 0; i < log.size(); i++)
    {
        if (log.getType(i) != mrpt::obs::CRawlog::etSensoryFrame)
        {
            continue;
        }
        const auto sf = log.getAsObservations(i);
        for (size_t k = 0; k < sf->size(); k++)
        {
            if (auto obs = std::dynamic_pointer_cast<semloc::CObservationSemantic>(
                    sf->getObservationByIndex(k)))
            {
                f(*obs);
            }
        }
    }
}

/** Every detection's range moved by `dr` [m] (a detector that reads too far). */
void shiftRanges(mrpt::obs::CRawlog& log, double dr)
{
    editScans(log,
              [&](semloc::CObservationSemantic& obs)
              {
                  for (auto& d : obs.detections)
                  {
                      d.range_m = std::min(obs.maxRange_m, d.range_m + dr);
                  }
              });
}

/** The ground truth moved by (dx, dy) and turned by dtheta [rad] about (cx, cy): the map is
 *  then offset from it by the inverse. */
std::vector<semloc::GroundTruthRow> moved(std::vector<semloc::GroundTruthRow> gt, double dx,
                                          double dy, double dtheta, double cx, double cy)
{
    for (auto& r : gt)
    {
        const double x = r.x - cx, y = r.y - cy;
        r.x = cx + std::cos(dtheta) * x - std::sin(dtheta) * y + dx;
        r.y = cy + std::sin(dtheta) * x + std::cos(dtheta) * y + dy;
        r.phi = std::remainder(r.phi + dtheta, 2 * M_PI);
    }
    return gt;
}

/** What one run of the tool gave. */
struct ToolRun
{
    int status = -1;
    fs::path ini;
    std::string out, err, iniText;
};

/** semloc-calibrate on the dataset of `o` (written to `dir`), base `base`; the ini it writes
 *  is then loaded as semloc-localize loads it (LocalizationExperiment::FromConfigFile with
 *  the rawlog and an output directory). */
ToolRun calibrateTool(const std::string& name, const TSimulatorOptions& o,
                      const std::string& base = kSemanticIni,
                      const std::function<void(mrpt::obs::CRawlog&)>& edit = {})
{
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / ("calibrate_limits_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const Simulator sim(o);
    const std::string rawlog = (dir / "data.rawlog").string();
    auto res = sim.run();
    if (edit)
    {
        edit(res.rawlog);
    }
    sim.writeDataset(res, rawlog);
    ToolRun t;
    t.ini = dir / "out.ini";
    const std::string cmd = std::string(SEMLOC_BIN_DIR) + "/semloc-calibrate " + rawlog +
                            " --world " + kPaper + " --ground-truth " +
                            GroundTruthFile::PathFor(rawlog) + " --base " + base + " -o " +
                            t.ini.string() + " --consistency-seeds 0 > " +
                            (dir / "stdout").string() + " 2> " + (dir / "stderr").string();
    t.status = std::system(cmd.c_str());
    t.out = readText(dir / "stdout");
    t.err = readText(dir / "stderr");
    t.iniText = readText(t.ini);
    if (t.status == 0)
    {
        semloc::LocalizationExperiment::TOverrides ov;
        ov.rawlog_file = rawlog;
        ov.logOutput_dir = (dir / "loc").string();
        EXPECT_NO_THROW((void)semloc::LocalizationExperiment::FromConfigFile(t.ini.string(), ov))
            << name << ": semloc-localize refuses the calibrated ini:\n"
            << t.iniText;
    }
    return t;
}

/** The line of `key` in `ini`'s text (the first line that starts with it and a blank). */
std::string lineOf(const std::string& ini, const std::string& key)
{
    std::istringstream in(ini);
    for (std::string line; std::getline(in, line);)
    {
        if (line.rfind(key + " ", 0) == 0)
        {
            return line;
        }
    }
    return "";
}

bool has(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}

/** What the stdout summary `out` gives for `key` (p_detect_near and p_detect_far: the two ends
 *  of `p_detect A .. B`): the text after the key up to the next ", " or "; " outside brackets. */
std::string printed(const std::string& out, const std::string& key)
{
    const bool far = key == "p_detect_far";
    const std::string name = key.rfind("p_detect_", 0) == 0 ? "p_detect" : key;
    size_t b = out.find(" " + name + " ");
    if (b == std::string::npos)
    {
        return "";
    }
    b += name.size() + 2;
    std::string text;
    int depth = 0;
    for (size_t i = b; i < out.size(); i++)
    {
        const char c = out[i];
        depth += c == '(' ? 1 : c == ')' ? -1 : 0;
        if (depth == 0 && (out.compare(i, 2, ", ") == 0 || out.compare(i, 2, "; ") == 0))
        {
            break;
        }
        if (depth == 0 && out.compare(i, 4, " .. ") == 0)
        {
            if (!far)
            {
                break;
            }
            text.clear();
            i += 3;
            continue;
        }
        text += c;
    }
    return text;
}

/** Each value the summary line prints is the one the ini writes, with why where it is not the
 *  fit: the base's value kept, a clamp. */
void expectPrintedAsWritten(const ToolRun& t)
{
    const auto c = semloc::test::iniText(t.iniText);
    for (const char* key : {"sigma_range_m", "sigma_bearing_deg", "p_detect_near", "p_detect_far",
                            "clutter_per_scan", "p_confusion", "p_range_outlier"})
    {
        const std::string shown = printed(t.out, key), line = lineOf(t.iniText, key);
        const std::string value = c.read_string(kLik, key, "?");
        EXPECT_EQ(shown.substr(0, shown.find(' ')), value) << key << " printed: " << t.out;
        if (has(line, "not fitted, too little data ("))
        {
            EXPECT_TRUE(has(shown, " (not fitted, too little data (") &&
                        has(shown, "): the base ini's value kept)"))
                << key << ": " << shown;
        }
        if (has(line, "clamped to the"))
        {
            EXPECT_TRUE(has(shown, "clamped to the")) << key << ": " << shown;
        }
        if (has(line, "// calibrated: n = "))
        {
            EXPECT_EQ(shown, value) << key << ": a fit as made needs no why";
        }
    }
}
}  // namespace

TEST(CalibrationLimits, NoiseFreeDetectorSigmasClampedToTheSmallestTheFilterTakes)
{
    auto o = paperRun(21);
    o.simulation.max_steps = 200;
    o.detector.range_noise_std_m = 0;
    o.detector.bearing_noise_std_deg = 0;
    const auto t = calibrateTool("noise_free", o);
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText);
    const auto lo = semloc::CSemanticMap::TLikelihoodOptions::range("sigma_range_m").lo;
    EXPECT_EQ(c.read_double(kLik, "sigma_range_m", 0), lo);
    EXPECT_TRUE(has(lineOf(t.iniText, "sigma_range_m"),
                    "clamped to the smallest value the "
                    "filter takes"))
        << lineOf(t.iniText, "sigma_range_m");
    EXPECT_TRUE(has(t.err, "warning: sigma_range_m: fitted ")) << t.err;
    EXPECT_TRUE(has(t.err, "warning: sigma_bearing_deg: fitted ")) << t.err;
    expectPrintedAsWritten(t);
}

TEST(CalibrationLimits, DetectorThatSeesNothingFar)
{
    // None detected beyond 20 m of the 30 m the scans claim to cover (a camera rated further
    // than it sees): P_D's line crosses 0 before max range, clamped into the filter's range
    // with the counts that made it in the comment.
    auto o = paperRun(22);
    o.simulation.max_steps = 300;
    o.detector.p_detect_near = 1.0;
    o.detector.p_detect_far = 0.0;
    const auto t = calibrateTool(
        "near_all_far_none", o, kSemanticIni,
        [](mrpt::obs::CRawlog& log)
        { editScans(log, [](semloc::CObservationSemantic& obs) { obs.maxRange_m = 30; }); });
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText);
    const auto far = semloc::CSemanticMap::TLikelihoodOptions::range("p_detect_far");
    EXPECT_GE(c.read_double(kLik, "p_detect_far", -1), far.lo);
    EXPECT_LE(c.read_double(kLik, "p_detect_near", 2), far.hi);
    const std::string farLine = lineOf(t.iniText, "p_detect_far");
    EXPECT_TRUE(has(farLine, "// calibrated: fitted 0 (0 detections of ") &&
                has(farLine, " in-view objects beyond 20 m), clamped to the smallest value"))
        << farLine;
    EXPECT_TRUE(has(t.err, "warning: p_detect_far: fitted 0 (0 detections of ")) << t.err;
}

TEST(CalibrationLimits, DetectorThatSeesEverything)
{
    auto o = paperRun(28);
    o.simulation.max_steps = 300;
    o.detector.p_detect_near = 1.0;
    o.detector.p_detect_far = 1.0;
    const auto t = calibrateTool("sees_everything", o);
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText);
    const auto range = semloc::CSemanticMap::TLikelihoodOptions::range("p_detect_near");
    EXPECT_EQ(c.read_double(kLik, "p_detect_near", -1), range.hi);
    EXPECT_TRUE(has(t.err, "warning: p_detect_near: fitted 1")) << t.err;
    EXPECT_TRUE(has(lineOf(t.iniText, "p_detect_near"), "clamped to the largest value"))
        << lineOf(t.iniText, "p_detect_near");
    expectPrintedAsWritten(t);
}

TEST(CalibrationLimits, NoClutterClampedToTheSmallestRateTheFilterTakes)
{
    auto o = paperRun(23);
    o.simulation.max_steps = 200;
    o.detector.false_positives_per_scan = 0;
    o.detector.p_confusion = 0;
    o.detector.range_noise_std_m = 0.1;
    o.detector.bearing_noise_std_deg = 0.5;
    const auto t = calibrateTool("no_clutter", o);
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText);
    EXPECT_EQ(c.read_double(kLik, "clutter_per_scan", 0),
              semloc::CSemanticMap::TLikelihoodOptions::range("clutter_per_scan").lo);
    EXPECT_TRUE(has(lineOf(t.iniText, "clutter_per_scan"),
                    "fitted 0 (0 detections matching no in-view object in 200 scans)"))
        << lineOf(t.iniText, "clutter_per_scan");
    EXPECT_TRUE(has(t.err, "warning: clutter_per_scan: fitted 0")) << t.err;
}

TEST(CalibrationLimits, OneScanKeepsTheBasesValues)
{
    auto o = TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini");
    o.simulation.max_steps = 1;
    o.simulation.seed = 2;
    const auto t = calibrateTool("one_scan", o);
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText), base(semloc::test::resolvedIni(kSemanticIni));
    for (const char* key : {"sigma_range_m", "sigma_bearing_deg", "p_detect_near", "p_detect_far",
                            "clutter_per_scan", "p_confusion"})
    {
        EXPECT_EQ(c.read_double(kLik, key, -1), base.read_double(kLik, key, -2)) << key;
        EXPECT_TRUE(has(lineOf(t.iniText, key), "not fitted, too little data (") &&
                    has(lineOf(t.iniText, key), "the base ini's value kept"))
            << lineOf(t.iniText, key);
        EXPECT_TRUE(has(t.err, std::string("warning: ") + key + ": not fitted, too little data"))
            << key << "\n"
            << t.err;
    }
    EXPECT_TRUE(has(t.err, "warning: [MotionModel]: not fitted, too little data")) << t.err;
    // A key the base does not set keeps its default.
    ASSERT_FALSE(base.keyExists(kLik, "p_detect_edge_ratio"));
    EXPECT_EQ(c.read_double(kLik, "p_detect_edge_ratio", -1), 1.0);
    EXPECT_TRUE(has(lineOf(t.iniText, "p_detect_edge_ratio"),
                    "the default kept (the base ini does not set it)"))
        << lineOf(t.iniText, "p_detect_edge_ratio");
}

TEST(CalibrationLimits, OneScanPrintsTheBasesValuesItWritesAndWhy)
{
    // Too little data for any fit: the summary on stdout gives the values the ini keeps, not
    // those the few samples would have fitted, each with why.
    auto o = TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini");
    o.simulation.max_steps = 1;
    o.simulation.seed = 2;
    const auto t = calibrateTool("one_scan_summary", o);
    ASSERT_EQ(t.status, 0) << t.err;
    const auto base = semloc::test::iniText(semloc::test::resolvedIni(kSemanticIni));
    EXPECT_EQ(printed(t.out, "sigma_range_m"),
              base.read_string(kLik, "sigma_range_m", "?") +
                  " (not fitted, too little data (2 matched range residuals, fewer than the 10 a "
                  "sigma needs): the base ini's value kept)")
        << t.out;
    EXPECT_TRUE(has(printed(t.out, "p_detect_far"), "the base ini's value kept)")) << t.out;
    EXPECT_TRUE(has(t.out,
                    ", [MotionModel] the base ini's (not fitted, too little data (the "
                    "vehicle moved in 0 of 0 odometry increments"))
        << t.out;
    expectPrintedAsWritten(t);
}

TEST(CalibrationLimits, StillVehicleKeepsTheBasesMotionModel)
{
    // A vehicle that does not move (5 micrometres a step) and odometry without noise: every
    // motion noise would fit 0; the base's [MotionModel] is kept and the reason given.
    auto o = paperRun(24);
    o.simulation.max_steps = 100;
    o.simulation.speed_mps = 1e-5;
    o.odometry.xy_std_per_m = 0;
    o.odometry.phi_std_deg_per_m = 0;
    o.odometry.phi_std_per_rad = 0;
    o.odometry.min_xy_std_m = 0;
    o.odometry.min_phi_std_deg = 0;
    const auto t = calibrateTool("still", o);
    ASSERT_EQ(t.status, 0) << t.err;
    mrpt::config::CConfigFileMemory c(t.iniText), base(semloc::test::resolvedIni(kSemanticIni));
    for (const char* key : {"a1", "a3", "a4", "minStdXY", "minStdPHI"})
    {
        EXPECT_EQ(c.read_double("MotionModel", key, -1), base.read_double("MotionModel", key, -2))
            << key;
    }
    EXPECT_EQ(c.read_string("MotionModel", "source", ""), "rawlog");
    EXPECT_TRUE(has(t.iniText,
                    "// semloc-calibrate: not fitted, too little data (the vehicle "
                    "moved in 0 of 99 odometry increments"))
        << t.iniText;
    EXPECT_TRUE(has(t.err,
                    "warning: [MotionModel]: not fitted, too little data (the vehicle "
                    "moved in 0 of 99"))
        << t.err;
}

TEST(CalibrationLimits, BaseThatLocalizeRefusesIsRefusedFirst)
{
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "calibrate_limits_base";
    fs::create_directories(dir);
    std::string text = semloc::test::resolvedIni(kSemanticIni);
    text.replace(text.find("\nsigma_range_m "), 15, "\nsigma_rnage_m ");
    {
        std::ofstream(dir / "base.ini") << text;
    }
    auto o = paperRun(25);
    o.simulation.max_steps = 20;
    const auto t = calibrateTool("base_unknown_key", o, (dir / "base.ini").string());
    EXPECT_NE(t.status, 0);
    EXPECT_TRUE(has(t.err, "ini '" + (dir / "base.ini").string() + "': [" + kLik +
                               "] sigma_rnage_m: unknown key"))
        << t.err;
    EXPECT_FALSE(fs::exists(t.ini));
}

TEST(CalibrationLimits, RangeBiasReportedWarnedAndCoveredByTheSigma)
{
    // Every range read 0.3 m too far (sigma 0.5): found as a range bias (0.3 m on the axis
    // and at both edges, within 0.1 m), taken off the ranges (their mean residual then about
    // 0, the sigma written the noise's 0.5 m), reported and warned.
    auto o = paperRun(26);
    const Simulator sim(o);
    auto res = sim.run();
    shiftRanges(res.rawlog, 0.3);
    const auto r = SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(),
                                               res.groundTruth, SensorCalibration::TOptions());
    std::cout << SensorCalibration::BiasText(r);
    ASSERT_EQ(r.rangeBias_m.size(), 4U);
    const auto& c = r.rangeBias_m;
    EXPECT_NEAR(c[0], 0.3, 0.05);
    EXPECT_NEAR(c[0] - c[1] + c[2] - c[3], 0.3, 0.1);
    EXPECT_NEAR(c[0] + c[1] + c[2] + c[3], 0.3, 0.1);
    EXPECT_NEAR(r.bias.range_m, 0, 0.05);
    EXPECT_NEAR(r.bias.sigmaRangeAround_m, 0.5, 0.05);
    EXPECT_NEAR(r.sigma_range_m.value, 0.5, 0.05);
    EXPECT_GT(r.sigmaRangeUncorrected_m, 0.5);
    EXPECT_NEAR(r.bias.bearing_deg, 0, 0.5);
    EXPECT_TRUE(has(SensorCalibration::BiasText(r), "range bias by bearing: 0."));
    const auto w = SensorCalibration::Warnings(r);
    std::string all;
    for (const auto& s : w)
    {
        all += s + "\n";
    }
    EXPECT_TRUE(has(all, "the detector's ranges read 0.")) << all;
    EXPECT_TRUE(has(all, "taken off each detection (range_bias_m)")) << all;
    EXPECT_FALSE(has(all, "the range residuals' mean")) << all;
    EXPECT_FALSE(has(all, "the bearing residuals' mean")) << all;
    EXPECT_FALSE(has(all, "the map is offset")) << all;
}

TEST(CalibrationLimits, MapOffsetReportedWarnedAndNotTakenIntoTheSigmas)
{
    // The map 1.5 m and 2 degrees off the ground truth: the offset is fitted (the ground truth
    // moved by the opposite), warned of, and the sigmas are the detector's (0.5 m, 3 deg),
    // not the 1.5 m the offset spreads the residuals by at the ground truth as given.
    auto o = paperRun(27);
    const Simulator sim(o);
    const auto res = sim.run();
    const double cx = 25, cy = 25, th = 2 * M_PI / 180;
    const auto gt = moved(res.groundTruth, -1.5, 0.4, -th, cx, cy);
    const auto r = SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(), gt,
                                               SensorCalibration::TOptions());
    std::cout << SensorCalibration::BiasText(r);
    ASSERT_TRUE(r.mapOffset.fitted);
    EXPECT_TRUE(r.mapOffset.removed);
    EXPECT_NEAR(r.mapOffset.dtheta_deg, 2.0, 0.3);
    // The transform at the objects' centroid is the ground truth's move undone there.
    const double ux = r.mapOffset.cx_m - cx, uy = r.mapOffset.cy_m - cy;
    const double gx = cx + std::cos(-th) * ux - std::sin(-th) * uy - 1.5;
    const double gy = cy + std::sin(-th) * ux + std::cos(-th) * uy + 0.4;
    EXPECT_NEAR(r.mapOffset.dx_m, r.mapOffset.cx_m - gx, 0.1);
    EXPECT_NEAR(r.mapOffset.dy_m, r.mapOffset.cy_m - gy, 0.1);
    EXPECT_NEAR(r.sigma_range_m.value, 0.5, 0.05);
    EXPECT_NEAR(r.sigma_bearing_deg.value, 3.0, 0.3);
    EXPECT_GT(r.bias.sigmaRangeAtTruth_m, 0.8);
    std::string all;
    for (const auto& s : SensorCalibration::Warnings(r))
    {
        all += s + "\n";
    }
    EXPECT_TRUE(has(all, "the map is offset from the ground truth by dx ")) << all;
    // Without an offset: none fitted large, none warned, nothing removed.
    const auto clean = SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(),
                                                   res.groundTruth, SensorCalibration::TOptions());
    EXPECT_FALSE(clean.mapOffset.removed);
    EXPECT_LT(clean.mapOffset.rms_m, 0.1);
    for (const auto& s : SensorCalibration::Warnings(clean))
    {
        EXPECT_FALSE(has(s, "the map is offset")) << s;
    }
}

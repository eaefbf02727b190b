/* semloc tests — semloc-calibrate's consistency stage: the filter run on the calibration run
 * widens a model that is too sure of itself, deterministically, and says so in the ini. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/simulator/Simulator.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "TestHelpers.h"

using semloc::GroundTruthFile;
using semloc::SensorCalibration;
using semloc::Simulator;
using semloc::TCalibrationFit;
using semloc::TCalibrationResult;
using semloc::TSimulatorOptions;

namespace
{
namespace fs = std::filesystem;
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

/** config/localize/semantic.ini with 1000 particles (the stage runs the filter several times). */
std::string smallBase()
{
    return semloc::test::withKeys(
        semloc::test::resolvedIni(SEMLOC_SOURCE_DIR "/config/localize/semantic.ini"),
        "semantic.ini", {{"particles_count", "1000"}});
}

/** A simulated run of the paper's world, written to `dir`, and its fits. */
struct Run
{
    std::string rawlog, groundTruth;
    TCalibrationResult fits;
};

Run simulatedRun(const fs::path& dir)
{
    fs::remove_all(dir);
    fs::create_directories(dir);
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.simulation.seed = 5;
    o.simulation.max_steps = 160;
    const Simulator sim(o);
    const auto res = sim.run();
    Run r;
    r.rawlog = (dir / "run.rawlog").string();
    sim.writeDataset(res, r.rawlog);
    r.groundTruth = GroundTruthFile::PathFor(r.rawlog);
    r.fits = SensorCalibration::Estimate(res.rawlog, r.rawlog, sim.world(), res.groundTruth,
                                         SensorCalibration::TOptions());
    return r;
}

SensorCalibration::TConsistencyOptions fewTrials()
{
    SensorCalibration::TConsistencyOptions o;
    o.seeds = {1};
    o.sensorScales = {1, 4};
    o.motionScales = {1, 4};
    return o;
}

/** The fits made `k` times surer of themselves (every sigma and motion noise divided). */
TCalibrationResult overconfident(TCalibrationResult r, double k)
{
    for (TCalibrationFit* f : {&r.sigma_range_m, &r.sigma_bearing_deg, &r.a1, &r.a2, &r.a3, &r.a4,
                               &r.minStdXY, &r.minStdPHI})
    {
        f->value /= k;
    }
    return r;
}
}  // namespace

TEST(CalibrationConsistency, WidensAnOverconfidentModelAndSaysSoInTheIni)
{
    const auto run = simulatedRun(fs::path(SEMLOC_TEST_OUT) / "consistency_widens");
    const auto tight = overconfident(run.fits, 8);
    const std::string base = smallBase();
    const auto out = SensorCalibration::Consistency(tight, base, "semantic.ini", kPaper, run.rawlog,
                                                    run.groundTruth, fewTrials());
    const auto& c = out.consistency;
    ASSERT_FALSE(c.trials.empty());
    EXPECT_EQ(c.trials.front().sensorScale, 1);
    EXPECT_EQ(c.trials.front().motionScale, 1);
    const auto& chosen = c.trials[c.chosen];
    for (const auto& t : c.trials)
    {
        std::cout << "x" << t.sensorScale << " / x" << t.motionScale << ": " << 100 * t.insideShare
                  << " % inside, mean NEES " << t.neesMean << ", error " << t.meanErr_m << " m, "
                  << t.converged << " of " << t.runs << " converged\n";
    }
    std::cout << "as given: " << 100 * c.trials.front().insideShare << " % inside; written: x"
              << chosen.sensorScale << " / x" << chosen.motionScale << ", "
              << 100 * chosen.insideShare << " % inside\n";
    // Eight times too sure, the filter loses the vehicle: the stage widens until it holds.
    EXPECT_TRUE(chosen.sensorScale > 1 || chosen.motionScale > 1);
    EXPECT_EQ(chosen.converged, chosen.runs);
    EXPECT_LT(chosen.meanErr_m, c.trials.front().meanErr_m);
    EXPECT_DOUBLE_EQ(out.sigma_range_m.value, tight.sigma_range_m.value * chosen.sensorScale);
    EXPECT_DOUBLE_EQ(out.sigma_range_m.widenedBy, chosen.sensorScale);
    EXPECT_DOUBLE_EQ(out.minStdXY.value, tight.minStdXY.value * chosen.motionScale);
    const std::string ini = SensorCalibration::ApplyToIni(base, "semantic.ini", out, kPaper);
    EXPECT_NE(ini.find("widened x"), std::string::npos);
    EXPECT_NE(SensorCalibration::ConsistencyText(out).find("consistency: as fitted, NEES inside"),
              std::string::npos);
    // The same inputs, the same trials.
    const auto again = SensorCalibration::Consistency(tight, base, "semantic.ini", kPaper,
                                                      run.rawlog, run.groundTruth, fewTrials());
    ASSERT_EQ(again.consistency.trials.size(), c.trials.size());
    for (size_t i = 0; i < c.trials.size(); i++)
    {
        EXPECT_EQ(again.consistency.trials[i].insideShare, c.trials[i].insideShare) << i;
        EXPECT_EQ(again.consistency.trials[i].meanErr_m, c.trials[i].meanErr_m) << i;
    }
}

TEST(CalibrationConsistency, NothingFittedNothingRun)
{
    TCalibrationResult r;
    for (TCalibrationFit* f : {&r.sigma_range_m, &r.sigma_bearing_deg, &r.minStdXY, &r.minStdPHI})
    {
        f->status = TCalibrationFit::Status::TooLittleData;
    }
    const auto out = SensorCalibration::Consistency(r, smallBase(), "semantic.ini", kPaper,
                                                    "none.rawlog", "none.txt", fewTrials());
    EXPECT_TRUE(out.consistency.trials.empty());
    EXPECT_EQ(SensorCalibration::ConsistencyText(out), "");
}

TEST(CalibrationConsistency, WidenedKeepsEachValueInItsRange)
{
    TCalibrationResult r;
    r.sigma_range_m.value = 0.5;
    r.minStdPHI.value = 1;
    r.a1.value = 0;  // left out of the fit: stays 0
    const auto w = SensorCalibration::Widened(r, 1e9, 3);
    const auto hi = semloc::CSemanticMap::TLikelihoodOptions::range("sigma_range_m").hi;
    EXPECT_EQ(w.sigma_range_m.value, hi);
    EXPECT_DOUBLE_EQ(w.sigma_range_m.widenedBy, hi / 0.5);
    EXPECT_DOUBLE_EQ(w.minStdPHI.value, 3);
    EXPECT_EQ(w.a1.value, 0);
    EXPECT_EQ(w.a1.widenedBy, 1);
}

TEST(CalibrationConsistency, ATemperingIsWrittenAsAFactorOnTheBasesPowFactor)
{
    TCalibrationResult r;
    r.sigma_range_m.value = 0.5;
    const auto w = SensorCalibration::Widened(r, 2, 1, 0.25);
    EXPECT_EQ(w.temper, 0.25);
    EXPECT_DOUBLE_EQ(w.sigma_range_m.value, 1.0);
    const auto powFactor = [](const std::string& ini)
    {
        mrpt::config::CConfigFileMemory c(ini);
        return c.read_double("PF_options", "powFactor", -1);
    };
    const std::string base = smallBase();
    EXPECT_DOUBLE_EQ(powFactor(SensorCalibration::ApplyToIni(base, "semantic.ini", w, kPaper)),
                     0.25);
    const std::string halved = semloc::test::withKeys(base, "semantic.ini", {{"powFactor", "0.5"}});
    const std::string ini = SensorCalibration::ApplyToIni(halved, "semantic.ini", w, kPaper);
    EXPECT_DOUBLE_EQ(powFactor(ini), 0.125);
    EXPECT_NE(ini.find("tempered x0.25 by the consistency stage"), std::string::npos);
    // Not tempered: the base's value stays as it was.
    EXPECT_DOUBLE_EQ(powFactor(SensorCalibration::ApplyToIni(
                         halved, "semantic.ini", SensorCalibration::Widened(r, 2, 1), kPaper)),
                     0.5);
}

TEST(CalibrationConsistency, ConsistentAllowsTheSharesSamplingError)
{
    // 95 % asked for over 4000 steps: two standard errors are 0.69 %.
    semloc::TConsistencyTrial t;
    t.runs = t.converged = 2;
    t.steps = 4000;
    t.insideShare = 0.9435;
    EXPECT_TRUE(SensorCalibration::Consistent(t, 0.95));
    t.insideShare = 0.9425;
    EXPECT_FALSE(SensorCalibration::Consistent(t, 0.95));
    t.steps = 400;  // fewer steps, a wider tolerance (2.2 %)
    EXPECT_TRUE(SensorCalibration::Consistent(t, 0.95));
    t.converged = 1;  // a run that did not converge is never consistent
    EXPECT_FALSE(SensorCalibration::Consistent(t, 0.95));
    t.converged = 2;
    t.steps = 0;  // no step with ground truth: nothing to judge by
    t.insideShare = 1;
    EXPECT_FALSE(SensorCalibration::Consistent(t, 0.95));
}

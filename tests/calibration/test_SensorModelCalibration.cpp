/* semloc — SensorModelCalibration: the side-scan's, the compass's, the fixes' and the DVL's
 * noise recovered from a simulated AUV survey whose noise is known, and the fits in the ini. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/calibration/SensorModelCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "calibration/SensorModelFits.h"

namespace
{
using semloc::SensorModelCalibration;
using semloc::TCalibrationFit;
using semloc::TModelFits;

const std::string kSim = SEMLOC_SOURCE_DIR "/config/simulate/simulate_auv.ini";
const std::string kWorld = SEMLOC_SOURCE_DIR "/maps/seabed_200x200.yaml";
const std::string kBase = SEMLOC_SOURCE_DIR "/config/localize/auv/sidescan_usbl.ini";

/** A simulated survey (the whole lawnmower, 1388 steps) with the noise of simulate_auv.ini; its
 *  rawlog path. */
std::string survey(const semloc::TSimulatorOptions& o, const std::string& name)
{
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "sensor_model_calibration";
    fs::create_directories(dir);
    const semloc::Simulator sim(o);
    std::string rawlog = (dir / (name + ".rawlog")).string();
    sim.writeDataset(sim.run(), rawlog);
    return rawlog;
}

semloc::TSimulatorOptions auvRun()
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSim);
    o.simulation.seed = 3;
    return o;
}

/** The fits by model name and key. */
std::map<std::string, std::map<std::string, TCalibrationFit>> byName(
    const std::vector<TModelFits>& fits)
{
    std::map<std::string, std::map<std::string, TCalibrationFit>> m;
    for (const auto& f : fits)
    {
        for (const auto& [k, v] : f.keys)
        {
            m[f.name][k] = v;
        }
    }
    return m;
}

std::vector<TModelFits> estimate(const std::string& rawlog)
{
    const auto gt = semloc::GroundTruthFile::Read(semloc::GroundTruthFile::PathFor(rawlog));
    return SensorModelCalibration::Estimate(rawlog, semloc::config::readIniText(kBase), kBase,
                                            kWorld, gt, 0.05, 3.0);
}

TEST(SensorModelCalibration, RecoversTheSimulatedNoise)
{
    auto o = auvRun();
    o.auv.compass.deviation_deg = 0;  // white noise: the fit is the simulated sigma
    const auto fits = byName(estimate(survey(o, "white")));
    ASSERT_EQ(fits.count("sideScanMap 'sidescan'"), 1u);
    const auto& ss = fits.at("sideScanMap 'sidescan'");
    // About 100 matched detections, 250 objects in view and 280 false alarms: tolerances of
    // 2.5 standard errors, and each fit's own 95 % interval holding the simulated value.
    const auto expectFit = [](const TCalibrationFit& f, double truth, double tol)
    {
        EXPECT_NEAR(f.value, truth, tol);
        EXPECT_GT(f.ci95, 0);
        EXPECT_LE(std::abs(f.value - truth), 1.5 * f.ci95) << f.method;
    };
    expectFit(ss.at("sigma_range_m"), o.auv.sidescan.range_noise_std_m, 0.09);
    expectFit(ss.at("p_detect_near"), o.auv.sidescan.p_detect_near, 0.18);
    expectFit(ss.at("p_detect_far"), o.auv.sidescan.p_detect_far, 0.12);
    expectFit(ss.at("clutter_per_scan"), o.auv.sidescan.clutter_per_scan, 0.04);
    EXPECT_EQ(ss.count("sigma_bearing_deg"), 0u) << "a side-scan measures no bearing";

    const auto& compass = fits.at("compassMap");
    EXPECT_NEAR(compass.at("sigma_deg").value, o.auv.compass.sigma_deg, 0.2);
    EXPECT_LT(compass.at("p_outlier").value, 0.01);

    const auto& fix = fits.at("poseFixMap");
    EXPECT_NEAR(fix.at("sigma_m").value, o.auv.usbl.sigma_m, 0.8);
    EXPECT_LT(fix.at("p_outlier").value, 0.15);

    const auto& dvl = fits.at("[MotionModel] dvl");
    // Each axis' noise per metre plus the scale error, both shares of the distance.
    const double a1 = std::sqrt(o.auv.dvl.xy_std_per_m * o.auv.dvl.xy_std_per_m +
                                0.5 * o.auv.dvl.scale_error * o.auv.dvl.scale_error);
    EXPECT_NEAR(dvl.at("a1").value, a1, 0.3 * a1);
}

TEST(SensorModelCalibration, ALastingDeviationWidensTheCompass)
{
    // The residual deviation (1 deg x cos(heading)) lasts a survey leg: the readings of a leg
    // share it, and the fit must not let them average it away.
    const auto fits = byName(estimate(survey(auvRun(), "deviation")));
    EXPECT_GT(fits.at("compassMap").at("sigma_deg").value, 3.0);
}

TEST(SensorModelCalibration, AutocorrelationTime)
{
    std::mt19937 rng(1);
    std::normal_distribution<double> n(0, 1);
    std::vector<double> white(20000), ar(20000);
    double x = 0;
    for (size_t i = 0; i < white.size(); i++)
    {
        white[i] = n(rng);
        x = 0.9 * x + n(rng);
        ar[i] = x;
    }
    EXPECT_NEAR(semloc::detail::autocorrelationTime(white, 1000), 1.0, 0.1);
    // AR(1) with rho 0.9: (1 + rho) / (1 - rho) = 19.
    EXPECT_NEAR(semloc::detail::autocorrelationTime(ar, 1000), 19.0, 3.0);
    EXPECT_EQ(semloc::detail::autocorrelationTime({1, 1, 1, 1}, 10), 1.0);
}

TEST(SensorModelCalibration, FitsInTheIni)
{
    TModelFits f;
    f.section = "MetricMap_compassMap_00_likelihoodOpts";
    f.name = "compassMap";
    f.keys.emplace_back("sigma_deg", semloc::detail::fitValue(2.5, 100, 0.1, "RMS", 10, 1e-6, 180));
    f.keys.emplace_back("p_outlier", semloc::detail::fitValue(0.5, 3, 0, "share", 20, 0, 1));
    const std::string base =
        "[MetricMap]\ncompassMap_count = 1\n\n"
        "[MetricMap_compassMap_00_likelihoodOpts]\nsigma_deg = 4\n";
    const std::string ini = SensorModelCalibration::ApplyToIni(base, "base.ini", {f});
    const mrpt::config::CConfigFileMemory c(ini);
    EXPECT_EQ(c.read_double(f.section, "sigma_deg", 0), 2.5);
    EXPECT_FALSE(c.keyExists(f.section, "p_outlier")) << "a fit from too little data is not set";
    EXPECT_NE(ini.find("p_outlier not fitted, too little data"), std::string::npos) << ini;
    const auto w = SensorModelCalibration::Warnings({f});
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("compassMap p_outlier"), std::string::npos);
    EXPECT_EQ(semloc::detail::fitValue(-1, 100, 0, "m", 10, 0, 1).status,
              TCalibrationFit::Status::Clamped);
}
}  // namespace

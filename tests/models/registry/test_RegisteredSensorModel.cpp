/* semloc tests — a sensor model defined only in the tests (CPositionFixMap), registered there
 * and run from an ini by semloc-localize's own code (apps/semloc-localize/main.cpp built with
 * it): created by name from [MetricMap], its options read strictly and written back, its
 * variant named, its bad fixes refused, and a vehicle with drifting odometry localized by its
 * fixes alone. The stock semloc-localize, which does not have it, refuses the same ini. */
#include <gtest/gtest.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "ProcessRun.h"
#include "TestHelpers.h"

namespace fs = std::filesystem;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "registered_sensor_model";

/** A 300-step drive (0.2 m a step, turning 1 deg a step) whose odometry reads the turns 10 %
 *  short, with a position fix (sigma 0.5 m) at every step; the fix of step `badFixAt` (if
 *  < 300) is NaN. Writes the rawlog and its `_gt.txt`; returns the rawlog's path. */
std::string writeDrive(const std::string& name, size_t badFixAt = 1000)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(7);
    mrpt::obs::CRawlog log;
    std::ofstream gt(kOut / (name + "_gt.txt"));
    gt.precision(17);
    mrpt::poses::CPose2D truth(2, 3, 0);
    const mrpt::poses::CPose2D step(0.2, 0, mrpt::DEG2RAD(1.0)), odo(0.2, 0, mrpt::DEG2RAD(0.9));
    for (size_t k = 0; k < 300; k++)
    {
        truth = truth + step;
        const double t = 1.0 + static_cast<double>(k);
        gt << t << ' ' << truth.x() << ' ' << truth.y() << ' ' << truth.phi() << '\n';
        auto acts = semloc::test::gaussianOdometry(odo);
        log.insert(acts);
        mrpt::obs::CSensoryFrame sf;
        {
            auto fix = mrpt::obs::CObservationRobotPose::Create();
            fix->timestamp = mrpt::Clock::fromDouble(t);
            fix->pose.mean =
                mrpt::poses::CPose3D(truth.x() + 0.5 * rng.drawGaussian1D_normalized(),
                                     truth.y() + 0.5 * rng.drawGaussian1D_normalized(), 0, 0, 0, 0);
            fix->pose.cov.setIdentity();
            if (k == badFixAt)
            {
                fix->pose.mean.x(std::numeric_limits<double>::quiet_NaN());
            }
            sf.insert(fix);
        }
        log.insert(sf);
    }
    const fs::path rawlog = kOut / (name + ".rawlog");
    EXPECT_TRUE(log.saveToRawLogFile(rawlog.string()));
    return rawlog.string();
}

/** The ini: the shipped filter with the position-fix map only, a start within a few metres
 *  and tens of degrees of the first pose. */
std::string writeIni(const std::string& name, const std::string& sigma)
{
    const fs::path path = kOut / (name + ".ini");
    std::ofstream(path) << "base = " SEMLOC_SOURCE_DIR "/config/localize/filter.ini\n"
                        << "[LocalizationExperiment]\n"
                           "map_file =\n"
                           "particles_count = 2000\n"
                           "init_PDF_mode = 2\n"
                           "init_PDF_mean_x = 3\ninit_PDF_mean_y = 2\n"
                           "init_PDF_mean_yaw_deg = 20\n"
                           "init_PDF_std_xy = 2\ninit_PDF_std_yaw_deg = 30\n"
                           "[MetricMap]\n"
                           "positionFixMap_count = 1\n"
                           "[MetricMap_positionFixMap_00_likelihoodOpts]\n"
                           "sigma_m = "
                        << sigma << "\n";
    return path.string();
}

int localize(const std::string& tool, const std::string& ini, const std::string& rawlog,
             const std::string& out, std::string& log)
{
    double rss = 0;
    const fs::path logFile = kOut / (out + ".log");
    const int rc = semloc::test::runMeasured(
        {tool, ini, rawlog, "-o", (kOut / out).string(), "-q", "-s", "1"}, logFile, rss);
    log = semloc::test::readText(logFile);
    return rc;
}

double summaryNumber(const std::string& summary, const std::string& key)
{
    const auto at = summary.find(key + ": ");
    if (at == std::string::npos)
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    return std::stod(summary.substr(at + key.size() + 2));
}
}  // namespace

TEST(RegisteredSensorModel, RunsFromAnIniThroughTheLocalizeTool)
{
    fs::create_directories(kOut);
    const std::string rawlog = writeDrive("drive");
    std::string log;
    ASSERT_EQ(localize(SEMLOC_PLUGGED_LOCALIZE, writeIni("fix", "1"), rawlog, "fix", log), 0)
        << log;
    const std::string summary = semloc::test::readText(kOut / "fix" / "summary.yaml");
    EXPECT_NE(summary.find("variant: \"position_fix\""), std::string::npos) << summary;
    // Fixes of 0.5 m every 0.2 m, scored as 1 m ones, and a heading told only by the fixes'
    // track: within 0.5 m.
    const double err = summaryNumber(summary, "mean_err_after_conv_m");
    EXPECT_LT(err, 0.5) << summary;
    // Its options are written back as read, through its kind.
    const std::string config = semloc::test::readText(kOut / "fix" / "config.ini");
    EXPECT_NE(config.find("[MetricMap_positionFixMap_00_likelihoodOpts]"), std::string::npos);
    EXPECT_NE(config.find("sigma_m"), std::string::npos) << config;
}

TEST(RegisteredSensorModel, ItsOptionsAndFixesAreChecked)
{
    fs::create_directories(kOut);
    std::string log;
    const std::string rawlog = writeDrive("drive_bad", 100);
    // A bad value of its own key: refused, naming the section and key.
    EXPECT_NE(
        localize(SEMLOC_PLUGGED_LOCALIZE, writeIni("bad_sigma", "-1"), rawlog, "bad_sigma", log),
        0);
    EXPECT_NE(log.find("[MetricMap_positionFixMap_00_likelihoodOpts] sigma_m"), std::string::npos)
        << log;
    EXPECT_FALSE(fs::exists(kOut / "bad_sigma"));
    // A NaN fix: left out and counted, as its kind refuses it.
    ASSERT_EQ(localize(SEMLOC_PLUGGED_LOCALIZE, writeIni("nan_fix", "1"), rawlog, "nan_fix", log),
              0)
        << log;
    const std::string summary = semloc::test::readText(kOut / "nan_fix" / "summary.yaml");
    EXPECT_EQ(summaryNumber(summary, "observations_invalid"), 1) << summary;
}

TEST(RegisteredSensorModel, TheStockToolDoesNotKnowIt)
{
    fs::create_directories(kOut);
    std::string log;
    EXPECT_NE(localize(SEMLOC_BIN_DIR "/semloc-localize", writeIni("stock", "0.5"),
                       writeDrive("drive_stock"), "stock", log),
              0);
    EXPECT_NE(log.find("unknown map 'positionFixMap'"), std::string::npos) << log;
}

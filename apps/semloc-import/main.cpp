/* semloc-import: a vehicle's dataset in plain-text CSV files (odometry, detections, optional
 * ground truth and landmarks) as a semantic rawlog semloc-localize runs on:
 *   semloc-import -o run.rawlog --odometry odom.csv --detections det.csv \
 *                 --ground-truth gt.csv --landmarks lm.csv
 * writes run.rawlog, run_gt.txt (with --ground-truth) and run_world.yaml (with --landmarks).
 * Each file may be gz-compressed. The summary line counts what real logs bring (repeated
 * times, a scan's readings milliseconds apart, detections of no landmark, ground-truth gaps)
 * and a warning says where a rule may have made the result wrong. The format: docs/tools.md,
 * "semloc-import". */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/system/filesystem.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd(
    "semloc-import: a CSV dataset (odometry, detections, ground truth, "
    "landmarks; plain or gz-compressed) as a semantic rawlog",
    ' ', "0.1");
TCLAP::ValueArg<std::string> argOut("o", "output", "Rawlog to write", true, "", "out.rawlog", cmd);
TCLAP::ValueArg<std::string> argOdometry("", "odometry", "Odometry CSV: t,x,y,phi or t,v,w", true,
                                         "", "odom.csv", cmd);
TCLAP::ValueArg<std::string> argDetections(
    "", "detections", "Detections CSV: t,label,range_m,bearing_rad[,id][,confidence]", true, "",
    "det.csv", cmd);
TCLAP::ValueArg<std::string> argGroundTruth("", "ground-truth", "Ground truth CSV: t,x,y,phi",
                                            false, "", "gt.csv", cmd);
TCLAP::ValueArg<std::string> argLandmarks("", "landmarks",
                                          "Landmarks CSV: id,label,x,y[,sigma_x_m,sigma_y_m]",
                                          false, "", "lm.csv", cmd);
TCLAP::ValueArg<double> argMaxRange("", "max-range-m", "Detector's maximum range [m] (default 20)",
                                    false, 20.0, "R", cmd);
TCLAP::ValueArg<double> argFov("", "fov-deg",
                               "Detector's horizontal field of view [deg] (default 120)", false,
                               120.0, "F", cmd);
TCLAP::ValueArg<std::string> argSensorPose(
    "", "sensor-pose", "Detector's pose on the vehicle [m, m, deg] (default 0,0,0)", false, "0,0,0",
    "x,y,yaw_deg", cmd);
TCLAP::ValueArg<double> argMaxStep("", "max-step-s",
                                   "Longest step without detections [s] (default 0.5)", false, 0.5,
                                   "S", cmd);
TCLAP::ValueArg<double> argMargin("", "margin-m", "World bounds margin [m] (default 10)", false,
                                  10.0, "M", cmd);
TCLAP::ValueArg<double> argScanWindow(
    "", "scan-window-s",
    "Detection rows at most this long after a scan's first row are of that scan [s] (default "
    "0.01; 0: only rows of one time)",
    false, semloc::kDefaultScanWindow_s, "W", cmd);
TCLAP::ValueArg<double> argGtMaxGap(
    "", "gt-max-gap-s",
    "Longest ground-truth gap interpolated across [s]; steps inside a longer one have no ground "
    "truth (default: the larger of 1 s and 10 times the ground truth's median period)",
    false, 0.0, "G", cmd);

/** `x,y,yaw_deg` as a pose (yaw in radians). */
mrpt::math::TPose2D sensorPose(const std::string& text)
{
    std::istringstream ss(text);
    double v[3];
    char comma1 = 0, comma2 = 0;
    if (!(ss >> v[0] >> comma1 >> v[1] >> comma2 >> v[2]) || comma1 != ',' || comma2 != ',' ||
        !(ss >> std::ws).eof())
    {
        THROW_EXCEPTION("--sensor-pose '" + text + "': expected x,y,yaw_deg (three numbers)");
    }
    return {v[0], v[1], mrpt::DEG2RAD(v[2])};
}

bool isWorldFile(const std::string& p)
{
    try
    {
        (void)semloc::World::FromFile(p);
        return true;
    }
    catch (const std::exception&)
    {
        return false;
    }
}

void printSummary(const std::string& out, const semloc::TDatasetImportStats& s,
                  const std::vector<std::string>& written)
{
    const std::string counts = semloc::DatasetImport::summaryCounts(s);
    std::cout << "semloc-import: " << out << ": " << s.steps << " steps (" << s.scans << " scans, "
              << s.odometryOnlySteps << " odometry-only), " << s.detections << " detections"
              << (counts.empty() ? "" : ", " + counts) << "; wrote";
    for (const auto& f : written)
    {
        std::cout << " " << f;
    }
    std::cout << "\n";
    for (const auto& w : s.warnings)
    {
        std::cerr << "semloc-import: warning: " << w << "\n";
    }
    if (s.scansOutsideOdometry > 0)
    {
        std::cerr << "semloc-import: warning: " << s.scansOutsideOdometry
                  << " scans outside the odometry's time span were skipped\n";
    }
    if (s.detectionsOutsideCoverage > 0)
    {
        std::cerr << "semloc-import: warning: " << s.detectionsOutsideCoverage
                  << " detections lie beyond --max-range-m or outside --fov-deg (semloc-localize "
                     "skips them as detections_invalid)\n";
    }
}

void run()
{
    using semloc::DatasetImport;
    semloc::TDatasetImportOptions o;
    o.maxRange_m = argMaxRange.getValue();
    o.fov_deg = argFov.getValue();
    o.sensorPose = sensorPose(argSensorPose.getValue());
    o.maxStep_s = argMaxStep.getValue();
    o.margin_m = argMargin.getValue();
    o.scanWindow_s = argScanWindow.getValue();
    o.gtMaxGap_s = argGtMaxGap.getValue();
    o.check();
    const std::string out = argOut.getValue(), gtIn = argGroundTruth.getValue(),
                      lmIn = argLandmarks.getValue();
    const std::string gtOut = semloc::GroundTruthFile::PathFor(out);
    const std::filesystem::path op(out);
    const std::string worldOut = (op.parent_path() / (op.stem().string() + "_world.yaml")).string();
    const std::vector<std::string> inputs = {argOdometry.getValue(), argDetections.getValue(), gtIn,
                                             lmIn};
    if (gtOut == out || worldOut == out)
    {
        THROW_EXCEPTION("output rawlog '" + out +
                        "' collides with its ground-truth or world file name (give it an "
                        "extension such as .rawlog)");
    }
    semloc::checkOutputFile(out, inputs, semloc::RawlogReader::IsSemlocRawlog);
    std::vector<std::string> outputs = {out};
    if (!gtIn.empty())
    {
        semloc::checkOutputFile(gtOut, inputs, semloc::GroundTruthFile::IsGroundTruthFile);
        outputs.push_back(gtOut);
    }
    else if (std::filesystem::exists(gtOut))
    {
        std::cerr << "semloc-import: warning: '" << gtOut
                  << "' (a previous ground truth) stays; semloc-localize would take it for "
                     "this rawlog's\n";
    }
    if (!lmIn.empty())
    {
        semloc::checkOutputFile(worldOut, inputs, isWorldFile);
        outputs.push_back(worldOut);
    }

    // Everything is read and checked before anything is written.
    semloc::TDatasetImportStats stats;
    const auto odometry = DatasetImport::readOdometry(argOdometry.getValue(), &stats);
    const auto scans =
        DatasetImport::readDetections(argDetections.getValue(), o.scanWindow_s, &stats);
    const auto gt = gtIn.empty() ? std::vector<semloc::GroundTruthRow>{}
                                 : DatasetImport::readGroundTruth(gtIn, &stats);
    const auto landmarks =
        lmIn.empty() ? semloc::LandmarkSet{} : DatasetImport::readLandmarkSet(lmIn);
    const auto steps = DatasetImport::steps(scans, odometry, o.maxStep_s, stats,
                                            argOdometry.getValue(), argDetections.getValue());
    const auto gtRows =
        gt.empty() ? gt : DatasetImport::groundTruthAtSteps(gt, steps, gtIn, o.gtMaxGap_s, &stats);
    DatasetImport::checkLandmarkSet(steps, scans, landmarks, stats);
    const auto world = landmarks.empty() ? semloc::World{}
                                         : DatasetImport::makeWorldFrame(landmarks, gt, o.margin_m,
                                                                         op.stem().string());

    // Ctrl-C: exit 130, the temporary files removed, the outputs as they were.
    semloc::installInterruptHandlers();
    semloc::writeOutputFiles(outputs,
                             [&](const std::vector<std::string>& tmp)
                             {
                                 // Entry by entry: memory holds the parsed files only.
                                 DatasetImport::writeRawlog(steps, scans, odometry, o, stats,
                                                            tmp[0]);
                                 size_t next = 1;
                                 if (!gtRows.empty())
                                 {
                                     semloc::GroundTruthFile::Write(gtRows, tmp[next++]);
                                 }
                                 if (!landmarks.empty())
                                 {
                                     world.saveToFile(tmp[next], landmarks.objectList());
                                 }
                             });
    printSummary(out, stats, outputs);
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-import", run);
}

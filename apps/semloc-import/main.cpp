/* semloc-import: a vehicle's dataset in plain-text CSV files (odometry, detections, optional
 * ground truth, landmarks, depth, heading and position fixes) as a semantic rawlog
 * semloc-localize runs on:
 *   semloc-import -o run.rawlog --odometry odom.csv --detections det.csv \
 *                 --ground-truth gt.csv --landmarks lm.csv
 * writes run.rawlog, run_gt.txt (with --ground-truth) and run_world.yaml (with --landmarks).
 * Each file may be gz-compressed. The summary line counts what real logs bring (repeated
 * times, a scan's readings milliseconds apart, detections of no landmark, ground-truth gaps,
 * readings superseded by later ones) and a warning says where a rule may have made the result
 * wrong. The format: docs/tools.md, "semloc-import". */
#include <mrpt/3rdparty/tclap/CmdLine.h>
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
#include <string>
#include <vector>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd(
    "semloc-import: a CSV dataset (odometry, detections, ground truth, landmarks, depth, heading, "
    "position fixes; plain or gz-compressed) as a semantic rawlog",
    ' ', "0.1");
TCLAP::ValueArg<std::string> argOut("o", "output", "Rawlog to write", true, "", "out.rawlog", cmd);
TCLAP::ValueArg<std::string> argOdometry("", "odometry",
                                         "Odometry CSV: t,x,y,phi, t,v,w or t,vx,vy,w", true, "",
                                         "odom.csv", cmd);
TCLAP::ValueArg<std::string> argDetections(
    "", "detections",
    "Detections CSV: t,label,range_m,bearing_rad[,id][,confidence][,sensor][,side] (range_m "
    "empty: bearing-only; side port/starboard: a side-scan's, bearing_rad empty)",
    true, "", "det.csv", cmd);
TCLAP::ValueArg<std::string> argGroundTruth("", "ground-truth", "Ground truth CSV: t,x,y,phi",
                                            false, "", "gt.csv", cmd);
TCLAP::ValueArg<std::string> argLandmarks("", "landmarks",
                                          "Landmarks CSV: id,label,x,y[,sigma_x_m,sigma_y_m]",
                                          false, "", "lm.csv", cmd);
TCLAP::ValueArg<std::string> argDepth("", "depth",
                                      "Depth CSV: t,depth_m[,altitude_m] (CObservationDepth "
                                      "'depth')",
                                      false, "", "depth.csv", cmd);
TCLAP::ValueArg<std::string> argHeading("", "heading",
                                        "Heading CSV: t,heading_rad (CObservationIMU 'compass')",
                                        false, "", "heading.csv", cmd);
TCLAP::ValueArg<std::string> argFixes(
    "", "fixes",
    "Position fixes CSV: t,x,y[,z][,sigma_m | ,sigma_x_m,sigma_y_m] (CObservationRobotPose "
    "'usbl')",
    false, "", "fixes.csv", cmd);
TCLAP::MultiArg<std::string> argMaxRange(
    "", "max-range-m", "Detectors' maximum range [m] (default 20); NAME=R: of the sensor NAME only",
    false, "[NAME=]R", cmd);
TCLAP::MultiArg<std::string> argFov(
    "", "fov-deg",
    "Detectors' horizontal field of view [deg] (default 120); NAME=F: of the sensor NAME only",
    false, "[NAME=]F", cmd);
TCLAP::MultiArg<std::string> argSensorPose(
    "", "sensor-pose",
    "Detectors' pose on the vehicle: forward, to port [m], yaw [deg], height up [m] (default "
    "0,0,0, z 0); NAME=...: of the sensor NAME only",
    false, "[NAME=]x,y,yaw_deg[,z_m]", cmd);
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
                  << " detections lie beyond --max-range-m or outside --fov-deg"
                  << (s.semanticWithoutRange == 0
                          ? std::string()
                          : " or, " + std::to_string(s.semanticWithoutRange) +
                                " of them of sensor SEMANTIC, have no range (the semantic "
                                "models need one)")
                  << " (semloc-localize skips them as detections_invalid)\n";
    }
}

/** The depth, heading and fixes files given (the fixes' default z from the depth). */
semloc::VehicleReadings readVehicleReadings(semloc::TDatasetImportStats& stats)
{
    using semloc::DatasetImport;
    semloc::VehicleReadings r;
    if (!argDepth.getValue().empty())
    {
        r.depth = DatasetImport::readDepth(argDepth.getValue(), &stats);
    }
    if (!argHeading.getValue().empty())
    {
        r.heading = DatasetImport::readHeading(argHeading.getValue(), &stats);
    }
    if (!argFixes.getValue().empty())
    {
        r.fixes = DatasetImport::readFixes(argFixes.getValue(), r.depth, &stats);
    }
    return r;
}

/** The options of the command line, checked. */
semloc::TDatasetImportOptions importOptions()
{
    semloc::TDatasetImportOptions o;
    o.setSensorOption("--max-range-m", argMaxRange.getValue());
    o.setSensorOption("--fov-deg", argFov.getValue());
    o.setSensorOption("--sensor-pose", argSensorPose.getValue());
    o.maxStep_s = argMaxStep.getValue();
    o.margin_m = argMargin.getValue();
    o.scanWindow_s = argScanWindow.getValue();
    o.gtMaxGap_s = argGtMaxGap.getValue();
    o.check();
    return o;
}

/** The files to write: the rawlog `out`, then `gtOut` with a ground truth and `worldOut` with
 *  landmarks, each checked against the inputs (semloc::checkOutputFile). */
std::vector<std::string> outputFiles(const std::string& out, const std::string& gtOut,
                                     const std::string& worldOut)
{
    const std::string gtIn = argGroundTruth.getValue(), lmIn = argLandmarks.getValue();
    const std::vector<std::string> inputs = {
        argOdometry.getValue(), argDetections.getValue(), gtIn, lmIn, argDepth.getValue(),
        argHeading.getValue(),  argFixes.getValue()};
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
    return outputs;
}

void run()
{
    using semloc::DatasetImport;
    const semloc::TDatasetImportOptions o = importOptions();
    const std::string out = argOut.getValue(), gtIn = argGroundTruth.getValue(),
                      lmIn = argLandmarks.getValue();
    const std::string gtOut = semloc::GroundTruthFile::PathFor(out);
    const std::filesystem::path op(out);
    const std::string worldOut = (op.parent_path() / (op.stem().string() + "_world.yaml")).string();
    const std::vector<std::string> outputs = outputFiles(out, gtOut, worldOut);

    // Everything is read and checked before anything is written.
    semloc::TDatasetImportStats stats;
    const auto odometry = DatasetImport::readOdometry(argOdometry.getValue(), &stats);
    const auto scans =
        DatasetImport::readDetections(argDetections.getValue(), o.scanWindow_s, &stats);
    const auto gt = gtIn.empty() ? std::vector<semloc::GroundTruthRow>{}
                                 : DatasetImport::readGroundTruth(gtIn, &stats);
    const auto landmarks =
        lmIn.empty() ? semloc::LandmarkSet{} : DatasetImport::readLandmarkSet(lmIn);
    const auto readings = readVehicleReadings(stats);
    DatasetImport::checkSensors(scans, o, stats);
    const auto steps =
        DatasetImport::steps(scans, odometry, o.maxStep_s, stats, argOdometry.getValue(),
                             argDetections.getValue(), o.scanWindow_s);
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
                                 DatasetImport::writeRawlog(steps, scans, odometry, readings, o,
                                                            stats, tmp[0]);
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

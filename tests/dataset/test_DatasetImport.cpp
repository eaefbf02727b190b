/* semloc tests — DatasetImport and semloc-import: the steps and rawlog made of CSV files, and a
 * simulated dataset exported as CSV, imported by the tool and localized by semloc-localize. */
#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "TestHelpers.h"

namespace
{
namespace fs = std::filesystem;
using semloc::DatasetImport;
using semloc::test::readText;

const std::string kSrc = SEMLOC_SOURCE_DIR;
const std::string kBin = SEMLOC_BIN_DIR;

fs::path freshDir(const std::string& name)
{
    fs::path d = fs::path(SEMLOC_TEST_OUT) / "dataset_import" / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string write(const fs::path& p, const std::string& text)
{
    std::ofstream(p) << text;
    return p.string();
}

using semloc::test::errorOf;

TEST(DatasetImport, OdometryPosesOrSpeeds)
{
    const auto d = freshDir("odometry");
    const auto poses =
        DatasetImport::readOdometry(write(d / "p.csv", "phi,t,x,y\n0,10,0,0\n1.5,12,2,1\n"));
    const auto mid = poses.at(11);
    EXPECT_DOUBLE_EQ(mid.x, 1);
    EXPECT_DOUBLE_EQ(mid.y, 0.5);
    EXPECT_DOUBLE_EQ(mid.phi, 0.75);
    // A quarter circle of radius 2: v = pi/2 m/s, w = pi/4 rad/s for 2 s.
    const auto arc = DatasetImport::readOdometry(write(
        d / "s.csv", "# speeds\nt,v,w\n0,1.5707963267948966,0.7853981633974483\n2,0,0\n3,0,0\n"));
    EXPECT_NEAR(arc.pose[1].x, 2, 1e-12);
    EXPECT_NEAR(arc.pose[1].y, 2, 1e-12);
    EXPECT_NEAR(arc.pose[1].phi, M_PI / 2, 1e-12);
    EXPECT_NE(errorOf([&] { DatasetImport::readOdometry(write(d / "m.csv", "t,x,y\n1,0,0\n")); })
                  .find("m.csv:1: missing column 'phi'"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { DatasetImport::readOdometry(write(d / "b.csv", "t,v\n1,0\n2,0\n")); })
                  .find("b.csv:1: missing column 'w'"),
              std::string::npos);
}

TEST(DatasetImport, DetectionsFormScansAndEmptyScans)
{
    const auto d = freshDir("detections");
    const auto scans = DatasetImport::readDetections(
        write(d / "det.csv",
              "t,label,range_m,bearing_rad,id,confidence\n1,buoy,3,0.1,4,0.9\n1,rock,5,-0.2,,\n"
              "2,,,,,\n3,buoy,2,0,-1,\n"));
    ASSERT_EQ(scans.size(), 3u);
    ASSERT_EQ(scans[0].detections.size(), 2u);
    EXPECT_EQ(scans[0].detections[0].object_id, 4);
    EXPECT_DOUBLE_EQ(scans[0].detections[0].confidence, 0.9);
    EXPECT_EQ(scans[0].detections[1].object_id, -1);
    EXPECT_DOUBLE_EQ(scans[0].detections[1].confidence, 1.0);
    EXPECT_TRUE(scans[1].detections.empty());
    EXPECT_EQ(scans[2].detections.size(), 1u);
    const std::string mixed = errorOf(
        [&]
        {
            DatasetImport::readDetections(
                write(d / "x.csv", "t,label,range_m,bearing_rad\n1,buoy,3,0\n1,,,\n"));
        });
    EXPECT_NE(mixed.find("x.csv:3: column 2 'label': the scan at time 1 is marked empty"),
              std::string::npos)
        << mixed;
    const std::string label = errorOf(
        [&]
        {
            DatasetImport::readDetections(
                write(d / "l.csv", "t,label,range_m,bearing_rad\n1,oil rig,3,0\n"));
        });
    EXPECT_NE(label.find("l.csv:2: column 2 'label':"), std::string::npos) << label;
}

TEST(DatasetImport, StepsAtScansWithOdometryOnlyStepsInLongGaps)
{
    semloc::OdometryTrack odo;
    odo.t = {0.5, 10};
    odo.pose = {{0, 0, 0}, {9.5, 0, 0}};
    std::vector<semloc::DetectionScan> scans = {{0.2, {}}, {1, {}}, {1.4, {}}, {3, {}}, {11, {}}};
    semloc::TDatasetImportStats stats;
    const auto steps = DatasetImport::steps(scans, odo, 0.5, stats);
    // 1 and 1.4 (0.4 apart), then 1.4 .. 3 in 4 gaps of 0.4 s.
    const std::vector<double> t = {1, 1.4, 1.8, 2.2, 2.6, 3};
    ASSERT_EQ(steps.size(), t.size());
    for (size_t k = 0; k < t.size(); k++)
    {
        EXPECT_NEAR(steps[k].t, t[k], 1e-12);
    }
    EXPECT_EQ(steps[0].scan, 1);
    EXPECT_EQ(steps[2].scan, -1);
    EXPECT_EQ(steps[5].scan, 3);
    EXPECT_EQ(stats.scansOutsideOdometry, 2u);

    semloc::TDatasetImportOptions o;
    const auto log = DatasetImport::makeRawlog(steps, scans, odo, o, stats);
    ASSERT_EQ(log.size(), 12u);
    EXPECT_EQ(stats.odometryOnlySteps, 3u);
    EXPECT_EQ(stats.scans, 3u);
    EXPECT_EQ(log.getAsObservations(1)->size(), 1u);  // a scan: its (empty) observation
    EXPECT_EQ(log.getAsObservations(5)->size(), 0u);  // odometry only: nothing
    const auto move = log.getAsAction(4)->getBestMovementEstimation();
    ASSERT_TRUE(move);
    EXPECT_NEAR(move->poseChange->getMeanVal().x(), 0.4, 1e-12);
    EXPECT_GT(move->poseChange->getCovariance()(0, 0), 0);
}

TEST(DatasetImport, LandmarksCarryTheirSigmasAndRejectDuplicateIds)
{
    const auto d = freshDir("landmarks");
    const auto lm = DatasetImport::readLandmarks(write(
        d / "lm.csv", "label,id,x,y,sigma_x_m,sigma_y_m\nbuoy,3,1,2,0.5,1.0\nrock,7,4,5,,\n"));
    ASSERT_EQ(lm.size(), 2u);
    EXPECT_EQ(lm[1].object.id, 7);
    EXPECT_DOUBLE_EQ(lm[0].sigma_x_m, 0.5);
    EXPECT_TRUE(std::isnan(lm[1].sigma_x_m));
    // The world's isotropic sigma of the same total variance; none without them.
    EXPECT_DOUBLE_EQ(lm[0].object.sigma_m, std::sqrt((0.25 + 1.0) / 2));
    EXPECT_EQ(lm[1].object.sigma_m, 0.0);
    auto landmarksError = [&](const char* name, const char* text)
    { return errorOf([&] { DatasetImport::readLandmarks(write(d / name, text)); }); };
    const std::string half = landmarksError("h.csv", "id,label,x,y,sigma_x_m\n3,a,0,0,0.5\n");
    EXPECT_NE(half.find("h.csv:2: column 5 'sigma_x_m': given without sigma_y_m"),
              std::string::npos)
        << half;
    EXPECT_NE(half.find("give both standard deviations or neither"), std::string::npos) << half;
    const std::string huge =
        landmarksError("u.csv", "id,label,x,y,sigma_x_m,sigma_y_m\n3,a,0,0,1,1e300\n");
    EXPECT_NE(huge.find("u.csv:2: column 6 'sigma_y_m': a standard deviation must be in [0, 1e7]"),
              std::string::npos)
        << huge;
    const std::string dup = landmarksError("d.csv", "id,label,x,y\n3,a,0,0\n3,b,1,1\n");
    EXPECT_NE(dup.find("d.csv:3: column 1 'id': duplicate id 3 (first on line 2)"),
              std::string::npos)
        << dup;
    // The first repeat in file order, named with the row it repeats; an error in an earlier
    // row comes first.
    const std::string later =
        landmarksError("r.csv", "id,label,x,y\n5,a,0,0\n4,a,0,0\n4,b,1,1\n5,c,2,2\n");
    EXPECT_NE(later.find("r.csv:4: column 1 'id': duplicate id 4 (first on line 3)"),
              std::string::npos)
        << later;
    const std::string first =
        landmarksError("f.csv", "id,label,x,y\n5,a,0,0\n6,a,nan,0\n5,b,1,1\n");
    EXPECT_NE(first.find("f.csv:3: column 3 'x': 'nan' is not a finite number"), std::string::npos)
        << first;
    // An id is decimal digits: what strtod reads as a number is not one.
    for (const std::string id : {"0x10", "1e3", "16.0", "+5"})
    {
        const std::string e = landmarksError("i.csv", ("id,label,x,y\n" + id + ",a,0,0\n").c_str());
        EXPECT_NE(e.find("i.csv:2: column 1 'id': '" + id +
                         "' is not an integer of decimal digits in [1, 2147483647]"),
                  std::string::npos)
            << e;
    }
    EXPECT_EQ(DatasetImport::readLandmarks(write(d / "z.csv", "id,label,x,y\n007,a,0,0\n"))
                  .at(0)
                  .object.id,
              7);
}

// The readers with their default arguments, as readError's `reader`.
void readOdometryFile(const std::string& p)
{
    DatasetImport::readOdometry(p);
}
void readGroundTruthFile(const std::string& p)
{
    DatasetImport::readGroundTruth(p);
}
void readDetectionsFile(const std::string& p)
{
    DatasetImport::readDetections(p);
}
void readLandmarksFile(const std::string& p)
{
    DatasetImport::readLandmarks(p);
}

/** The message reading `text` as `name` with `reader` (readOdometryFile...). */
template <typename Reader>
std::string readError(const fs::path& d, const char* name, const std::string& text, Reader reader)
{
    return errorOf([&] { reader(write(d / name, text)); });
}

TEST(DatasetImport, AbsurdValuesAreRefusedNamingTheCell)
{
    const auto d = freshDir("bounds");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {readError(d, "o.csv", "t,x,y,phi\n1,0,0,0\n2,1e308,0,0\n", readOdometryFile),
         "o.csv:3: column 2 'x': x 1e+308 is beyond +-1e+07 m"},
        {readError(d, "p.csv", "t,x,y,phi\n1,0,0,1e300\n2,1,0,0\n", readOdometryFile),
         "p.csv:2: column 4 'phi': phi 1e+300 is beyond +-1e+06 rad"},
        {readError(d, "v.csv", "t,v,w\n1,1e300,0\n2,0,0\n", readOdometryFile),
         "v.csv:2: column 2 'v': v 1e+300 is beyond +-100 m/s"},
        {readError(d, "w.csv", "t,v,w\n1,0,0\n2,0,-500\n", readOdometryFile),
         "w.csv:3: column 3 'w': w -500 is beyond +-100 rad/s"},
        {readError(d, "i.csv", "t,v,w\n1,100,0\n1e6,0,0\n", readOdometryFile),
         "i.csv:3: column 1 't': the speeds integrated to this row's time reach (99999900, 0) m"},
        {readError(d, "g.csv", "t,x,y,phi\n1,0,-2e7,0\n", readGroundTruthFile),
         "g.csv:2: column 3 'y': y -2e+07 is beyond +-1e+07 m"},
        {readError(d, "l.csv", "id,label,x,y\n1,buoy,1e300,0\n", readLandmarksFile),
         "l.csv:2: column 3 'x': x 1e+300 is beyond +-1e+07 m"},
        {readError(d, "r.csv", "t,label,range_m,bearing_rad\n1,buoy,1e300,0\n", readDetectionsFile),
         "r.csv:2: column 3 'range_m': range_m 1e+300 is beyond +-1e+07 m"},
        {readError(d, "n.csv", "t,label,range_m,bearing_rad\n1.7e18,buoy,1,0\n",
                   readDetectionsFile),
         "n.csv:2: column 1 't': time 1.7e+18 is beyond +-1e11 s (3170 years): are the times in "
         "nanoseconds? semloc-import takes seconds"},
        {readError(d, "u.csv", "t,x,y,phi\n1700000000000000,0,0,0\n", readGroundTruthFile),
         "are the times in microseconds?"},
        {readError(d, "m.csv", "t,x,y,phi\n1700000000000,0,0,0\n", readGroundTruthFile),
         "are the times in milliseconds?"},
    };
    for (const auto& [error, expected] : cases)
    {
        EXPECT_NE(error.find(expected), std::string::npos) << error << "\nexpected: " << expected;
    }
}

TEST(DatasetImport, BearingsBeyondPiLookLikeDegrees)
{
    const auto d = freshDir("degrees");
    const char* header = "t,label,range_m,bearing_rad\n";
    for (const char* b : {"3.2", "-45", "90"})
    {
        const std::string e =
            readError(d, "b.csv", header + std::string("1,buoy,3,0.1\n2,buoy,3,") + b + "\n",
                      readDetectionsFile);
        EXPECT_NE(e.find("b.csv:3: column 4 'bearing_rad': bearing " + std::string(b) +
                         " is outside [-pi, pi]: are the bearings in degrees? semloc-import takes "
                         "radians"),
                  std::string::npos)
            << e;
    }
    EXPECT_EQ(readError(d, "ok.csv", header + std::string("1,buoy,3,3.14159\n2,buoy,3,-3.14159\n"),
                        readDetectionsFile),
              "");
}

/** An odometry track and scans at `times` (a straight line, 1 m/s). */
std::pair<semloc::OdometryTrack, std::vector<semloc::DetectionScan>> track(
    const std::vector<double>& times)
{
    semloc::OdometryTrack odo;
    std::vector<semloc::DetectionScan> scans;
    for (const double t : times)
    {
        odo.t.push_back(t);
        odo.pose.emplace_back(t - times.front(), 0, 0);
        scans.push_back({t, {}});
    }
    return {odo, scans};
}

TEST(DatasetImport, TimesThatLookLikeMillisecondsAreRefused)
{
    std::vector<double> ms;
    for (int k = 0; k < 79; k++)
    {
        ms.push_back(1000.0 * (k + 1));  // 79 scans a second apart, in milliseconds
    }
    // Not a structured binding: the lambdas below capture them (C++17).
    const auto tracked = track(ms);
    const auto& odo = tracked.first;
    const auto& scans = tracked.second;
    semloc::TDatasetImportStats stats;
    const std::string e =
        errorOf([&] { DatasetImport::steps(scans, odo, 0.5, stats, "odom.csv", "det.csv"); });
    EXPECT_NE(e.find("times of 'odom.csv' and 'det.csv' (1000 to 79000): the median time between "
                     "consecutive rows is 1000 s, more than 10 s: are the times in milliseconds? "
                     "semloc-import takes seconds"),
              std::string::npos)
        << e;
    EXPECT_STREQ(DatasetImport::likelyTimeUnit(1e5), "microseconds");
    EXPECT_STREQ(DatasetImport::likelyTimeUnit(1e8), "nanoseconds");
    // In seconds, 10 s apart: imported.
    std::vector<double> s;
    for (int k = 0; k < 10; k++)
    {
        s.push_back(1700000000.0 + 10 * k);
    }
    const auto [odo10, scans10] = track(s);
    EXPECT_EQ(DatasetImport::steps(scans10, odo10, 0.5, stats).size(), 9u * 20 + 1);
}

TEST(DatasetImport, TooManyStepsAreRefusedBeforeAnyIsMade)
{
    std::vector<double> t;
    for (int k = 0; k <= 3600; k++)
    {
        t.push_back(1700000000.0 + k);  // an hour at 1 Hz
    }
    const auto tracked = track(t);  // not a structured binding: a lambda captures them
    const auto& odo = tracked.first;
    const auto& scans = tracked.second;
    semloc::TDatasetImportStats stats;
    const auto start = std::chrono::steady_clock::now();
    const std::string e =
        errorOf([&] { DatasetImport::steps(scans, odo, 1e-4, stats, "odom.csv", "det.csv"); });
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
    EXPECT_NE(e.find("detections 'det.csv': times span 3600 s (from 1700000000 to 1700003600): "
                     "36000001 steps at --max-step-s 1e-04, more than the 10000000 allowed"),
              std::string::npos)
        << e;
}

TEST(DatasetImport, RawlogWrittenEntryByEntryHasTheBytesOfTheWholeOne)
{
    const auto d = freshDir("streamed");
    const auto [odo, scans0] = track({1, 2, 3, 6});
    auto scans = scans0;
    semloc::TSemanticDetection det;
    det.label = "buoy";
    det.range_m = 3;
    det.bearing_rad = 0.25;
    scans[1].detections = {det, det};
    semloc::TDatasetImportStats stats, streamedStats;
    const auto steps = DatasetImport::steps(scans, odo, 0.5, stats);
    semloc::TDatasetImportOptions o;
    semloc::saveRawlog(DatasetImport::makeRawlog(steps, scans, odo, o, stats),
                       (d / "whole.rawlog").string(), "semloc-import");
    DatasetImport::writeRawlog(steps, scans, odo, o, streamedStats,
                               (d / "streamed.rawlog").string());
    EXPECT_EQ(readText(d / "streamed.rawlog"), readText(d / "whole.rawlog"));
    EXPECT_EQ(streamedStats.steps, stats.steps);
    EXPECT_EQ(streamedStats.detections, 2u);
}

TEST(DatasetImport, ReadersTakeAStreamNamedInTheirMessages)
{
    std::istringstream odometry("t,x,y,phi\n1,0,0,0\n2,1,0,0\n");
    EXPECT_EQ(DatasetImport::readOdometry(odometry, "odom.csv").pose[1].x, 1.0);
    std::istringstream detections("t,label,range_m,bearing_rad\n1,buoy,3,0\n");
    EXPECT_EQ(DatasetImport::readDetections(detections, "det.csv").at(0).detections.size(), 1u);
    std::istringstream groundTruth("t,x,y,phi\n1,2,3,0\n");
    EXPECT_EQ(DatasetImport::readGroundTruth(groundTruth, "gt.csv").at(0).y, 3.0);
    std::istringstream landmarks("id,label,x,y\n1,buoy,2,3\n");
    EXPECT_EQ(DatasetImport::readLandmarks(landmarks, "lm.csv").at(0).object.label, "buoy");
    std::istringstream bad("t,x,y,phi\n1,0,0,0\n2,far,0,0\n");
    const std::string e = errorOf([&] { DatasetImport::readOdometry(bad, "odom.csv"); });
    EXPECT_NE(e.find("odom.csv:3: column 2 'x': 'far' is not a number"), std::string::npos) << e;
    std::istringstream empty("");
    const std::string none = errorOf([&] { DatasetImport::readLandmarks(empty, "lm.csv"); });
    EXPECT_NE(none.find("'lm.csv' has no header row"), std::string::npos) << none;
}

// ------------------------------------------------------------------ end to end

int runTool(const std::string& commandLine, const fs::path& log)
{
    const int status = std::system((commandLine + " >" + log.string() + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/** A simulated paper dataset (detector 0.5 m ahead, yawed 10 deg) as CSV files: dead-reckoned
 *  odometry, every third scan left out (gaps of 2 s: odometry-only steps), empty scans marked,
 *  ground truth and landmarks. */
void exportSimulation(const fs::path& d)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate.ini");
    o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
    o.detector.sensor_x_m = 0.5;
    o.detector.sensor_yaw_deg = 10;
    const semloc::Simulator sim(o);
    const auto res = sim.run();
    std::ostringstream odo, det, gt, lm;
    odo.precision(17);
    det.precision(17);
    gt.precision(17);
    odo << "t,x,y,phi\n";
    det << "# a simulated detector\nt,label,range_m,bearing_rad,id,confidence\n";
    gt << "t,x,y,phi\n";
    lm << "id,label,x,y,sigma_x_m,sigma_y_m\n";
    mrpt::poses::CPose2D dead(0, 0, 0);
    for (size_t i = 0, k = 0; i + 1 < res.rawlog.size(); i += 2, k++)
    {
        const auto acts = res.rawlog.getAsAction(i);
        dead = dead + acts->getBestMovementEstimation()->poseChange->getMeanVal();
        const double t = mrpt::Clock::toDouble(acts->get(0)->timestamp);
        odo << t << ',' << dead.x() << ',' << dead.y() << ',' << dead.phi() << '\n';
        const auto sem = res.rawlog.getAsObservations(i + 1)
                             ->getObservationByClass<semloc::CObservationSemantic>();
        if (k % 3 == 1)
        {
            continue;
        }
        for (const auto& x : sem->detections)
        {
            det << t << ',' << x.label << ',' << x.range_m << ',' << x.bearing_rad << ','
                << x.object_id << ',' << x.confidence << '\n';
        }
        if (sem->detections.empty())
        {
            det << t << ",,,,,\n";
        }
    }
    for (const auto& r : res.groundTruth)
    {
        gt << r.t << ',' << r.x << ',' << r.y << ',' << r.phi << '\n';
    }
    for (const auto& ob : sim.world().objects)
    {
        lm << ob.id << ',' << ob.label << ',' << ob.center.x << ',' << ob.center.y << ",0.1,0.1\n";
    }
    write(d / "odom.csv", odo.str());
    write(d / "det.csv", det.str());
    write(d / "gt.csv", gt.str());
    write(d / "lm.csv", lm.str());
}

/** config/localize/semantic.ini on the imported dataset, `particles` particles. */
void writeIni(const fs::path& d, int particles)
{
    std::string ini = semloc::test::resolvedIni(kSrc + "/config/localize/semantic.ini");
    const std::vector<std::pair<std::string, std::string>> keys = {
        {"map_file", "run_world.yaml"},
        {"ground_truth_path_file", "run_gt.txt"},
        {"logOutput_dir", "loc"},
        {"particles_count", std::to_string(particles)}};
    for (const auto& [k, v] : keys)
    {
        std::string pattern = "\n";
        pattern += k;
        pattern += " *=[^\n]*";
        std::string line = "\n";
        line += k;
        line += " = ";
        line += v;
        ini = std::regex_replace(ini, std::regex(pattern), line);
    }
    write(d / "loc.ini", ini);
}

TEST(DatasetImport, SimulatedDatasetImportedAndLocalized)
{
    const auto d = freshDir("end_to_end");
    exportSimulation(d);
    const std::string import = "cd " + d.string() + " && " + kBin +
                               "/semloc-import -o run.rawlog --odometry odom.csv --detections "
                               "det.csv --ground-truth gt.csv --landmarks lm.csv "
                               "--max-range-m 20 --fov-deg 120 --sensor-pose 0.5,0,10";
    ASSERT_EQ(runTool(import, d / "import.log"), 0) << readText(d / "import.log");
    const std::string summary = readText(d / "import.log");
    // 431 scans, 144 of them left out: 287 scans, 143 gaps of 2 s with 3 odometry-only steps
    // each and 143 gaps of 1 s with 1.
    EXPECT_NE(summary.find("run.rawlog: 859 steps (287 scans, 572 odometry-only)"),
              std::string::npos)
        << summary;
    for (const char* f : {"run.rawlog", "run_gt.txt", "run_world.yaml"})
    {
        EXPECT_TRUE(fs::exists(d / f)) << f;
    }
    // The landmarks' standard deviations (0.1 m in x and y) are the map's sigma_m.
    const semloc::World world = semloc::World::FromFile((d / "run_world.yaml").string());
    ASSERT_FALSE(world.objects.empty());
    for (const auto& ob : world.objects)
    {
        EXPECT_DOUBLE_EQ(ob.sigma_m, 0.1) << ob.id;
    }
    writeIni(d, 3000);
    ASSERT_EQ(runTool("cd " + d.string() + " && " + kBin + "/semloc-localize loc.ini run.rawlog -q",
                      d / "localize.log"),
              0)
        << readText(d / "localize.log");
    const std::string yaml = readText(d / "loc" / "summary.yaml");
    EXPECT_NE(yaml.find("steps: 859\n"), std::string::npos) << yaml;
    // Every step is timed, the odometry-only ones by their action, and has ground truth.
    EXPECT_NE(yaml.find("steps_with_ground_truth: 859\n"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("converged: true"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("detections_invalid: 0\n"), std::string::npos) << yaml;
    const std::regex finalErr("final_err_m: ([0-9.e-]+)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(yaml, m, finalErr)) << yaml;
    EXPECT_LT(std::stod(m[1]), 1.0) << yaml;
    // The same import again replaces its own outputs; an input as the output is refused.
    EXPECT_EQ(runTool(import, d / "again.log"), 0) << readText(d / "again.log");
    EXPECT_NE(runTool("cd " + d.string() + " && " + kBin +
                          "/semloc-import -o odom.csv --odometry odom.csv --detections det.csv",
                      d / "refused.log"),
              0);
    EXPECT_NE(readText(d / "refused.log").find("is the input"), std::string::npos);
}

TEST(DatasetImport, GroundTruthGapLeavesItsStepsWithoutErrorEndToEnd)
{
    // The simulated dataset with 100 s of its ground truth removed: the steps inside the gap
    // get no row of run_gt.txt, and semloc-localize gives them no error.
    const auto d = freshDir("gt_gap");
    exportSimulation(d);
    std::istringstream in(readText(d / "gt.csv"));
    std::string gt, line;
    double first = -1;
    while (std::getline(in, line))
    {
        const double t = line[0] == 't' ? -1 : std::stod(line);
        first = first < 0 && t >= 0 ? t : first;
        gt += t >= 0 && t > first + 100 && t < first + 200 ? "" : line + "\n";
    }
    write(d / "gt.csv", gt);
    const std::string import = "cd " + d.string() + " && " + kBin +
                               "/semloc-import -o run.rawlog --odometry odom.csv --detections "
                               "det.csv --ground-truth gt.csv --landmarks lm.csv "
                               "--max-range-m 20 --fov-deg 120 --sensor-pose 0.5,0,10";
    ASSERT_EQ(runTool(import, d / "import.log"), 0) << readText(d / "import.log");
    const std::string log = readText(d / "import.log");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        log, m, std::regex("([0-9]+) steps without ground truth in 1 gap over 10 s")))
        << log;
    const int inGap = std::stoi(m[1]);
    EXPECT_GT(inGap, 180) << log;  // ~2 steps a second for ~100 s
    EXPECT_NE(log.find("warning: ground truth 'gt.csv': 1 gap longer than 10 s"), std::string::npos)
        << log;
    std::istringstream rows(readText(d / "run_gt.txt"));
    int gtRows = 0;
    while (std::getline(rows, line))
    {
        gtRows += line.empty() || line[0] == '#' ? 0 : 1;
    }
    EXPECT_EQ(gtRows, 859 - inGap);
    writeIni(d, 300);
    ASSERT_EQ(runTool("cd " + d.string() + " && " + kBin + "/semloc-localize loc.ini run.rawlog -q",
                      d / "localize.log"),
              0)
        << readText(d / "localize.log");
    const std::string yaml = readText(d / "loc" / "summary.yaml");
    EXPECT_NE(yaml.find("steps: 859\n"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("steps_with_ground_truth: " + std::to_string(859 - inGap) + "\n"),
              std::string::npos)
        << yaml;
}

}  // namespace

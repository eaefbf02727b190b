/* semloc tests — DatasetImport on an AUV's logs: the DVL's body-frame velocities (t,vx,vy,w),
 * detections of several sensors (side-scan sides, a bearing-only camera) and their per-sensor
 * coverage, and the depth, heading and fixes files placed in the steps' frames. */
#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/observation/CObservationDepth.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "TestHelpers.h"

namespace
{
namespace fs = std::filesystem;
using semloc::DatasetImport;
using semloc::TDatasetImportOptions;
using semloc::TDatasetImportStats;

fs::path dir()
{
    fs::path d = fs::path(SEMLOC_TEST_OUT) / "dataset_import_auv";
    fs::create_directories(d);
    return d;
}

std::string write(const std::string& name, const std::string& text)
{
    std::ofstream(dir() / name) << text;
    return (dir() / name).string();
}

using semloc::test::errorOf;

/** Expects `error` (or a summary line) to hold `excerpt`. */
void expectError(const std::string& error, const std::string& excerpt)
{
    EXPECT_NE(error.find(excerpt), std::string::npos) << error << "\nexpected: " << excerpt;
}

bool warned(const TDatasetImportStats& s, const std::string& excerpt)
{
    for (const auto& w : s.warnings)
    {
        if (w.find(excerpt) != std::string::npos)
        {
            return true;
        }
    }
    return false;
}

// ------------------------------------------------------------------ odometry t,vx,vy,w

/** The velocity rows (vx, vy, w from t[k] to t[k + 1]) integrated by Euler steps of 1e-5 s. */
mrpt::math::TPose2D euler(const std::vector<double>& t, const std::vector<double>& vx,
                          const std::vector<double>& vy, const std::vector<double>& w)
{
    double x = 0, y = 0, phi = 0;
    for (size_t k = 0; k + 1 < t.size(); k++)
    {
        const int n = static_cast<int>(std::round((t[k + 1] - t[k]) / 1e-5));
        const double h = (t[k + 1] - t[k]) / n;
        for (int i = 0; i < n; i++)
        {
            const double mid = phi + 0.5 * w[k] * h;  // midpoint: the error O(h^2) per second
            x += (vx[k] * std::cos(mid) - vy[k] * std::sin(mid)) * h;
            y += (vx[k] * std::sin(mid) + vy[k] * std::cos(mid)) * h;
            phi += w[k] * h;
        }
    }
    return {x, y, mrpt::math::wrapToPi(phi)};
}

TEST(DatasetImportAuv, DvlVelocitiesIntegrateAsAFineEulerIntegration)
{
    const std::vector<double> t = {10, 11.5, 12, 14, 14.25, 17};
    const std::vector<double> vx = {1.5, 1.4, 0.3, -0.2, 2, 0};
    const std::vector<double> vy = {0.2, -0.4, 0, 0.7, 0.1, 0};
    const std::vector<double> w = {0.05, -0.3, 0.8, 0, 1e-12, 0};
    std::ostringstream csv;
    csv.precision(17);
    csv << "t,vx,vy,w\n";
    for (size_t k = 0; k < t.size(); k++)
    {
        csv << t[k] << ',' << vx[k] << ',' << vy[k] << ',' << w[k] << '\n';
    }
    const auto odo = DatasetImport::readOdometry(write("dvl.csv", csv.str()));
    ASSERT_EQ(odo.t, t);
    for (size_t k = 1; k < t.size(); k++)
    {
        const std::vector<double> tk(t.begin(), t.begin() + static_cast<long>(k) + 1);
        const auto ref = euler(tk, vx, vy, w);
        EXPECT_NEAR(odo.pose[k].x, ref.x, 1e-6) << k;
        EXPECT_NEAR(odo.pose[k].y, ref.y, 1e-6) << k;
        EXPECT_NEAR(odo.pose[k].phi, ref.phi, 1e-9) << k;
    }
}

TEST(DatasetImportAuv, ACrabbingVehicleMovesSidewaysAlongItsArc)
{
    // Straight: 1 m/s to port for 2 s from heading 0 is 2 m along y.
    const auto side =
        DatasetImport::readOdometry(write("crab.csv", "t,vx,vy,w\n0,0,1,0\n2,0,0,0\n"));
    EXPECT_NEAR(side.pose[1].x, 0, 1e-15);
    EXPECT_NEAR(side.pose[1].y, 2, 1e-15);
    // Turning a quarter in 1 s while moving 1 m/s to port: its world velocity (-sin, cos) of the
    // heading integrates to (-2/pi, 2/pi).
    const auto arc = DatasetImport::readOdometry(
        write("crab_arc.csv", "t,vx,vy,w\n0,0,1,1.5707963267948966\n1,0,0,0\n"));
    EXPECT_NEAR(arc.pose[1].x, -2 / M_PI, 1e-12);
    EXPECT_NEAR(arc.pose[1].y, 2 / M_PI, 1e-12);
    EXPECT_NEAR(arc.pose[1].phi, M_PI / 2, 1e-12);
    // Forward 1 m/s and 0.5 m/s to port in a 20 deg crab: the track runs 26.57 deg off the
    // heading.
    const auto crab =
        DatasetImport::readOdometry(write("crab_track.csv", "t,vx,vy,w\n0,1,0.5,0\n10,0,0,0\n"));
    EXPECT_NEAR(std::atan2(crab.pose[1].y, crab.pose[1].x), std::atan(0.5), 1e-12);
    EXPECT_NEAR(std::hypot(crab.pose[1].x, crab.pose[1].y), 10 * std::hypot(1, 0.5), 1e-12);
}

TEST(DatasetImportAuv, SpeedsFormIsTheDvlFormWithoutSwayToTheBit)
{
    const std::string rows[] = {"1,1.5,0.3\n", "2.5,0.7,-0.9\n", "3,1.1,0\n", "7,0,0\n"};
    std::string speeds = "t,v,w\n", dvl = "t,vx,vy,w\n";
    for (const auto& r : rows)
    {
        speeds += r;
        const size_t c = r.find(',', r.find(',') + 1);
        dvl += r.substr(0, c) + ",0" + r.substr(c);
    }
    const auto a = DatasetImport::readOdometry(write("sp.csv", speeds));
    const auto b = DatasetImport::readOdometry(write("sp_dvl.csv", dvl));
    ASSERT_EQ(a.pose.size(), b.pose.size());
    // The speeds' form as it always was: the arc of radius v / w, to the bit.
    const double t[] = {1, 2.5, 3, 7}, v[] = {1.5, 0.7, 1.1}, w[] = {0.3, -0.9, 0};
    mrpt::math::TPose2D p(0, 0, 0);
    for (size_t k = 0; k < a.pose.size(); k++)
    {
        if (k > 0)
        {
            const double dt = t[k] - t[k - 1], dphi = w[k - 1] * dt;
            if (std::abs(dphi) < 1e-9)
            {
                p.x += v[k - 1] * dt * std::cos(p.phi + 0.5 * dphi);
                p.y += v[k - 1] * dt * std::sin(p.phi + 0.5 * dphi);
            }
            else
            {
                const double r = v[k - 1] / w[k - 1];
                p.x += r * (std::sin(p.phi + dphi) - std::sin(p.phi));
                p.y -= r * (std::cos(p.phi + dphi) - std::cos(p.phi));
            }
            p.phi = mrpt::math::wrapToPi(p.phi + dphi);
        }
        EXPECT_EQ(a.pose[k].x, p.x) << k;
        EXPECT_EQ(a.pose[k].y, p.y) << k;
        EXPECT_EQ(a.pose[k].phi, p.phi) << k;
        EXPECT_EQ(a.pose[k].x, b.pose[k].x);
        EXPECT_EQ(a.pose[k].y, b.pose[k].y);
        EXPECT_EQ(a.pose[k].phi, b.pose[k].phi);
    }
}

TEST(DatasetImportAuv, DvlColumnsAreBothOrNeitherAndOneFormOnly)
{
    auto err = [](const char* name, const char* text)
    { return errorOf([&] { DatasetImport::readOdometry(write(name, text)); }); };
    expectError(err("vx.csv", "t,vx,w\n1,1,0\n2,1,0\n"),
                "vx.csv:1: missing column 'vy' (odometry is t,x,y,phi, t,v,w or t,vx,vy,w)");
    expectError(err("vy.csv", "# a DVL\nt,vy,w\n1,1,0\n2,1,0\n"), "vy.csv:2: missing column 'vx'");
    expectError(err("vvx.csv", "t,v,vx,vy,w\n1,1,1,0,0\n2,1,1,0,0\n"),
                "vvx.csv:1: column 'v': odometry is t,x,y,phi, t,v,w or t,vx,vy,w, one form, not "
                "several (the DVL's forward speed is vx)");
    expectError(err("xvx.csv", "t,x,y,phi,vy\n1,0,0,0,0\n2,1,0,0,0\n"),
                "xvx.csv:1: column 'vy': odometry is t,x,y,phi, t,v,w or t,vx,vy,w");
    expectError(err("big.csv", "t,vx,vy,w\n1,1,0,0\n2,1,-101,0\n"),
                "big.csv:3: column 3 'vy': vy -101 is beyond +-100 m/s");
    expectError(err("empty.csv", "t,vx,vy,w\n1,1,,0\n2,1,0,0\n"),
                "empty.csv:2: column 3 'vy': empty (a number is required)");
}

// ------------------------------------------------------------------ detections of sensors

const char* kAuvDetections =
    "t,sensor,label,range_m,bearing_rad,side,id\n"
    "100,sidescan,boulder,12.5,,port,\n"
    "100.004,camera,tyre,,0.2,,\n"                // within the window of sidescan's scan: one step
    "100.006,sidescan,boulder,30,,Starboard,4\n"  // sidescan's scan of 100
    "101,,wreck,8,0.1,,\n"                        // SEMANTIC
    "101,sidescan,,,,,\n"                         // an empty scan of sidescan
    "102.5,camera,tyre,,-0.3,,7\n"
    "102.5,camera,tyre,,0.35,,\n";

TEST(DatasetImportAuv, DetectionsFormScansPerSensorInTheOrderOfTheirFirstRows)
{
    TDatasetImportStats stats;
    const auto scans =
        DatasetImport::readDetections(write("auv_det.csv", kAuvDetections), 0.01, &stats);
    ASSERT_EQ(scans.size(), 5u);
    const std::vector<std::string> sensors = {"sidescan", "camera", "SEMANTIC", "sidescan",
                                              "camera"};
    const std::vector<double> times = {100, 100.004, 101, 101, 102.5};
    const std::vector<size_t> counts = {2, 1, 1, 0, 2};
    for (size_t k = 0; k < sensors.size(); k++)
    {
        EXPECT_EQ(scans[k].sensor, sensors[k]) << k;
        EXPECT_EQ(scans[k].t, times[k]) << k;
        EXPECT_EQ(scans[k].detections.size(), counts[k]) << k;
    }
    EXPECT_EQ(stats.detectionsGrouped, 1u);  // sidescan's row of 100.006
    // The side-scan's sides are bearings of +-pi/2; the camera's rows have no range.
    EXPECT_EQ(scans[0].detections[0].bearing_rad, M_PI / 2);
    EXPECT_EQ(scans[0].detections[1].bearing_rad, -M_PI / 2);
    EXPECT_EQ(scans[0].detections[1].object_id, 4);
    EXPECT_TRUE(std::isnan(scans[1].detections[0].range_m));
    EXPECT_DOUBLE_EQ(scans[1].detections[0].bearing_rad, 0.2);
    EXPECT_EQ(scans[2].detections[0].range_m, 8);
}

TEST(DatasetImportAuv, SideAndSensorCellsAreChecked)
{
    auto err = [](const char* name, const std::string& rows)
    {
        return errorOf(
            [&]
            {
                DatasetImport::readDetections(
                    write(name, "t,label,range_m,bearing_rad,side,sensor\n" + rows));
            });
    };
    expectError(err("s1.csv", "1,boulder,3,0.2,port,\n"),
                "s1.csv:2: column 4 'bearing_rad': a side-scan row (side 'port') has its bearing "
                "from its side: bearing_rad must be empty");
    expectError(err("s2.csv", "1,boulder,3,,aft,\n"),
                "s2.csv:2: column 5 'side': 'aft' is no side: port or left (bearing +pi/2), "
                "starboard or right (-pi/2), or empty");
    expectError(err("s3.csv", "1,,,,left,\n"),
                "s3.csv:2: column 5 'side': a row without a label marks a scan with no detections");
    expectError(err("s4.csv", "1,boulder,3,0.1,,side scan\n"),
                "s4.csv:2: column 6 'sensor': sensor label 'side scan' holds a blank or control "
                "character");
    expectError(err("s5.csv", "1,boulder,,,,\n"), "s5.csv:2: column 4 'bearing_rad': empty");
    expectError(err("s6.csv", "1,boulder,3,0.1,,cam\n1,,,,,cam\n"),
                "s6.csv:3: column 2 'label': the scan at time 1 of sensor cam is marked empty");
    // A row of another sensor is no detection of the empty scan.
    EXPECT_EQ(err("s7.csv", "1,boulder,3,0.1,,cam\n1,,,,,\n2,rock,,,right,\n"), "");
    const auto s = DatasetImport::readDetections(write(
        "s8.csv", "t,label,range_m,bearing_rad,side,sensor\n1,a,3,,LEFT,ss\n1,a,4,,right,ss\n"));
    EXPECT_EQ(s.at(0).detections.at(0).bearing_rad, M_PI / 2);
    EXPECT_EQ(s.at(0).detections.at(1).bearing_rad, -M_PI / 2);
}

TEST(DatasetImportAuv, SensorOptionsNameOneSensorOrEvery)
{
    TDatasetImportOptions o;
    o.setSensorOption("--max-range-m", {"25", "sidescan=40", "camera=8"});
    o.setSensorOption("--fov-deg", {"sidescan=360"});
    o.setSensorOption("--sensor-pose", {"0.5,0,10", "camera=1,-0.2,-90,0.4"});
    o.check();
    const auto def = o.sensor("SEMANTIC");
    EXPECT_EQ(def.maxRange_m, 25);
    EXPECT_EQ(def.fov_deg, 120);
    EXPECT_EQ(def.pose.x, 0.5);
    EXPECT_DOUBLE_EQ(def.pose.phi, mrpt::DEG2RAD(10.0));
    EXPECT_EQ(def.z_m, 0);
    const auto ss = o.sensor("sidescan");
    EXPECT_EQ(ss.maxRange_m, 40);
    EXPECT_EQ(ss.fov_deg, 360);
    EXPECT_EQ(ss.pose.x, 0.5);  // the default pose
    const auto cam = o.sensor("camera");
    EXPECT_EQ(cam.maxRange_m, 8);
    EXPECT_EQ(cam.fov_deg, 120);
    EXPECT_EQ(cam.pose.y, -0.2);
    EXPECT_DOUBLE_EQ(cam.pose.phi, -M_PI / 2);
    EXPECT_EQ(cam.z_m, 0.4);

    auto err = [](const std::string& option, const std::vector<std::string>& values)
    {
        return errorOf(
            [&]
            {
                TDatasetImportOptions p;
                p.setSensorOption(option, values);
                p.check();
            });
    };
    expectError(err("--max-range-m", {"sonar="}),
                "--max-range-m 'sonar=': expected [NAME=]R, R a number [m]");
    expectError(err("--sensor-pose", {"sonar=1,2"}),
                "--sensor-pose 'sonar=1,2': expected [NAME=]x,y,yaw_deg[,z_m] (three or four "
                "numbers)");
    expectError(err("--fov-deg", {"sonar=30", "sonar=40"}),
                "--fov-deg 'sonar=40': given twice for sensor sonar");
    expectError(err("--fov-deg", {"30", "40"}), "--fov-deg '40': given twice for every sensor");
    expectError(err("--fov-deg", {"=30"}), "--fov-deg '=30': sensor label is empty");
    expectError(err("--fov-deg", {"sonar=400"}), "--fov-deg sonar=400: must be in (0, 360] [deg]");
    expectError(err("--max-range-m", {"sonar=nan"}), "--max-range-m 'sonar=nan': expected");
    expectError(err("--max-range-m", {"0"}),
                "--max-range-m 0: must be a finite number in (0, 1e7] [m]");
    expectError(err("--sensor-pose", {"cam=0,0,0,5000"}),
                "--sensor-pose cam: z must be finite and within 1000 m of the vehicle");

    // A NAME= no detection row has: a warning.
    TDatasetImportStats stats;
    std::vector<semloc::DetectionScan> scans = {{1, {}, "sidescan"}, {2, {}, "camera"}};
    o.setSensorOption("--fov-deg", {"sonar=90"});
    DatasetImport::checkSensors(scans, o, stats);
    EXPECT_TRUE(warned(stats,
                       "--fov-deg sonar=: no detection row is of sensor 'sonar' (the "
                       "detections' sensors: camera, sidescan): not used"));
    EXPECT_EQ(stats.warnings.size(), 1u);
}

// ------------------------------------------------------------------ steps and frames

/** A straight odometry track at 1 m/s over [t0, t1]. */
semloc::OdometryTrack straight(double t0, double t1)
{
    semloc::OdometryTrack odo;
    odo.t = {t0, t1};
    odo.pose = {{0, 0, 0}, {t1 - t0, 0, 0}};
    return odo;
}

TEST(DatasetImportAuv, ScansOfSeveralSensorsWithinTheWindowShareAStep)
{
    const auto scans = DatasetImport::readDetections(write("auv_det2.csv", kAuvDetections), 0.01);
    const auto odo = straight(99, 110);
    TDatasetImportStats stats;
    const auto steps = DatasetImport::steps(scans, odo, 0.5, stats, "o", "d", 0.01);
    // 100 (sidescan + camera), 100.5, 101 (SEMANTIC + sidescan), 101.5, 102, 102.5 (camera).
    ASSERT_EQ(steps.size(), 6u);
    EXPECT_EQ(steps[0].scan, 0);
    EXPECT_EQ(steps[0].scanCount, 2u);
    EXPECT_EQ(steps[1].scan, -1);
    EXPECT_EQ(steps[2].scan, 2);
    EXPECT_EQ(steps[2].scanCount, 2u);
    EXPECT_EQ(steps[5].scan, 4);
    EXPECT_EQ(steps[5].scanCount, 1u);
    // Window 0: scans of one time only share a step.
    TDatasetImportStats s0;
    EXPECT_EQ(DatasetImport::steps(scans, odo, 0.5, s0, "o", "d", 0).size(), 7u);

    TDatasetImportOptions o;
    o.setSensorOption("--fov-deg", {"sidescan=360", "camera=80"});
    o.setSensorOption("--max-range-m", {"sidescan=40"});
    o.setSensorOption("--sensor-pose", {"camera=0.5,0,0,-0.3"});
    const auto log = DatasetImport::makeRawlog(steps, scans, odo, o, stats);
    const auto frame = log.getAsObservations(1);
    ASSERT_EQ(frame->size(), 2u);
    const auto ss =
        std::dynamic_pointer_cast<semloc::CObservationSemantic>(frame->getObservationByIndex(0));
    const auto cam =
        std::dynamic_pointer_cast<semloc::CObservationSemantic>(frame->getObservationByIndex(1));
    ASSERT_TRUE(ss && cam);
    EXPECT_EQ(ss->sensorLabel, "sidescan");
    EXPECT_EQ(ss->maxRange_m, 40);
    EXPECT_DOUBLE_EQ(ss->fov_rad, 2 * M_PI);
    EXPECT_EQ(ss->detections.size(), 2u);
    EXPECT_EQ(cam->sensorLabel, "camera");
    EXPECT_EQ(cam->maxRange_m, 20);
    EXPECT_DOUBLE_EQ(cam->fov_rad, mrpt::DEG2RAD(80.0));
    EXPECT_EQ(cam->sensorPose.x(), 0.5);
    EXPECT_EQ(cam->sensorPose.z(), -0.3);
    EXPECT_EQ(mrpt::Clock::toDouble(cam->timestamp), 100.004);
    const auto sem = log.getAsObservations(5);
    ASSERT_EQ(sem->size(), 2u);
    EXPECT_EQ(sem->getObservationByIndex(0)->sensorLabel, "SEMANTIC");
    EXPECT_EQ(sem->getObservationByIndex(1)->sensorLabel, "sidescan");
    EXPECT_EQ(stats.scans, 3u);
    EXPECT_EQ(stats.scanObservations, 5u);
    EXPECT_EQ(stats.stepsOfSeveralScans, 2u);
    EXPECT_EQ(stats.detectionsWithoutRange, 3u);
    // In coverage: the camera's bearing-only detections (their bearings in its 80 deg), the
    // side-scan's 30 m at starboard; out: none.
    EXPECT_EQ(stats.detectionsOutsideCoverage, 0u);
    const std::string summary = DatasetImport::summaryCounts(stats);
    expectError(summary,
                "scans by sensor: SEMANTIC 1, camera 2, sidescan 2 (2 steps hold "
                "several), 3 detections without a range (bearing-only)");
}

TEST(DatasetImportAuv, BearingOnlyCoverageIsTheFieldOfViewAlone)
{
    std::vector<semloc::DetectionScan> scans(2);
    scans[0] = {5, {}, "camera"};
    scans[1] = {5, {}, "SEMANTIC"};
    semloc::TSemanticDetection d;
    d.label = "tyre";
    d.range_m = std::nan("");
    d.bearing_rad = 0.2;
    scans[0].detections = {d, d};
    scans[0].detections[1].bearing_rad = 1.2;  // outside 80 deg
    scans[1].detections = {d};                 // SEMANTIC: the semantic models need a range
    TDatasetImportOptions o;
    o.setSensorOption("--fov-deg", {"camera=80"});
    TDatasetImportStats stats;
    const auto steps = DatasetImport::steps(scans, straight(4, 6), 0.5, stats);
    ASSERT_EQ(steps.size(), 1u);
    DatasetImport::makeRawlog(steps, scans, straight(4, 6), o, stats);
    EXPECT_EQ(stats.detectionsOutsideCoverage, 2u);
    EXPECT_EQ(stats.semanticWithoutRange, 1u);
    EXPECT_EQ(stats.detectionsWithoutRange, 3u);
}

// ------------------------------------------------------------------ depth, heading, fixes

TEST(DatasetImportAuv, DepthHeadingAndFixesAreRead)
{
    TDatasetImportStats stats;
    const auto depth = DatasetImport::readDepth(
        write("depth.csv", "t,depth_m,altitude_m\n1,25.5,4.5\n2,-0.5,\n2,26,5\n4,30,0\n"), &stats);
    ASSERT_EQ(depth.size(), 3u);
    EXPECT_EQ(depth[1].depth_m, 26);  // the later of time 2
    EXPECT_EQ(depth[0].altitude_m, 4.5);
    EXPECT_EQ(stats.depth.repeatedTimes, 1u);
    EXPECT_TRUE(warned(stats, "depth '" + (dir() / "depth.csv").string() +
                                  "': 1 of the 1 repeated times hold another depth"));
    const auto noAlt = DatasetImport::readDepth(write("depth2.csv", "t,depth_m\n1,3\n"));
    EXPECT_TRUE(std::isnan(noAlt.at(0).altitude_m));
    const auto heading = DatasetImport::readHeading(
        write("heading.csv", "t,heading_rad\n1,0.5\n2,7\n3,-3.5\n"), &stats);
    ASSERT_EQ(heading.size(), 3u);
    EXPECT_DOUBLE_EQ(heading[1].heading_rad, 7 - 2 * M_PI);  // wrapped
    EXPECT_DOUBLE_EQ(heading[2].heading_rad, -3.5 + 2 * M_PI);
    // The fixes' z: minus the depth at or before them (the first before any), or z.
    const auto fixes = DatasetImport::readFixes(
        write("fixes.csv", "t,x,y,z,sigma_m\n0.5,1,2,,3\n2,3,4,,2\n3.9,5,6,-12,2\n5,7,8,,1\n"),
        depth, &stats);
    ASSERT_EQ(fixes.size(), 4u);
    EXPECT_EQ(fixes[0].z, -25.5);
    EXPECT_EQ(fixes[1].z, -26);
    EXPECT_EQ(fixes[2].z, -12);
    EXPECT_EQ(fixes[3].z, -30);
    EXPECT_EQ(fixes[1].sigma_x_m, 2);
    EXPECT_EQ(fixes[1].sigma_y_m, 2);
    const auto xy = DatasetImport::readFixes(
        write("fixes_xy.csv", "t,x,y,sigma_x_m,sigma_y_m\n1,1,2,0.5,4\n"), {}, &stats);
    EXPECT_EQ(xy.at(0).z, 0);
    EXPECT_EQ(xy.at(0).sigma_y_m, 4);
    EXPECT_FALSE(warned(stats, "carry no standard deviation"));
    const auto bare =
        DatasetImport::readFixes(write("fixes_bare.csv", "t,x,y\n1,1,2\n"), {}, &stats);
    EXPECT_TRUE(std::isnan(bare.at(0).sigma_x_m));
    EXPECT_TRUE(warned(stats,
                       "fixes_bare.csv' carry no standard deviation (columns sigma_m, or "
                       "sigma_x_m and sigma_y_m): written with a standard deviation of 1 "
                       "m; set sigma_m in the poseFixMap's likelihoodOpts"));
}

TEST(DatasetImportAuv, BadReadingsAreRefusedNamingTheCell)
{
    auto depth = [](const char* name, const char* text)
    { return errorOf([&] { DatasetImport::readDepth(write(name, text)); }); };
    auto heading = [](const char* name, const char* text)
    { return errorOf([&] { DatasetImport::readHeading(write(name, text)); }); };
    auto fixes = [](const char* name, const char* text)
    { return errorOf([&] { DatasetImport::readFixes(write(name, text)); }); };
    expectError(depth("d1.csv", "t,depth_m\n1,abc\n"),
                "d1.csv:2: column 2 'depth_m': 'abc' is not a number");
    expectError(depth("d2.csv", "t,depth_m,altitude_m\n1,3,-1\n"),
                "d2.csv:2: column 3 'altitude_m': altitude -1 m is outside [0, 100000] m");
    expectError(depth("d3.csv", "t,depth_m\n1,-20000\n"),
                "d3.csv:2: column 2 'depth_m': depth -20000 m is outside [-10000, 100000] m");
    expectError(depth("d4.csv", "t,depth_m\n2,3\n1,3\n"),
                "d4.csv:3: column 1 't': time 1 goes back");
    expectError(depth("d5.csv", "t,depth_m\n0,3\n"),
                "d5.csv:2: column 1 't': time 0 is MRPT's 'no timestamp'");
    expectError(depth("d6.csv", "t,depth_m\n"), "d6.csv' holds no depth readings");
    expectError(heading("h1.csv", "t,heading_deg\n1,90\n"),
                "h1.csv:1: column 2 'heading_deg': unknown column (known: t, heading_rad)");
    expectError(heading("h2.csv", "t,heading_rad\n1,1e7\n"),
                "h2.csv:2: column 2 'heading_rad': heading_rad 1e+07 is beyond +-1e+06 rad");
    expectError(
        fixes("f1.csv", "t,x,y,sigma_m\n1,0,0,0\n"),
        "f1.csv:2: column 4 'sigma_m': sigma_m 0 is not a standard deviation in (0, 1e7] m");
    expectError(fixes("f2.csv", "t,x,y,sigma_m,sigma_x_m,sigma_y_m\n1,0,0,1,1,1\n"),
                "f2.csv:1: column 'sigma_x_m': the fixes give sigma_m and sigma_x_m,sigma_y_m: one "
                "form of the standard deviations, not both");
    expectError(fixes("f3.csv", "t,x,y,sigma_y_m\n1,0,0,1\n"),
                "f3.csv:1: column 'sigma_y_m': given without sigma_x_m");
    expectError(fixes("f4.csv", "t,x,y,sigma_x_m,sigma_y_m\n1,0,0,1,\n"),
                "f4.csv:2: column 5 'sigma_y_m': empty (a number is required)");
    expectError(fixes("f5.csv", "t,x,y\n1,2e7,0\n"), "f5.csv:2: column 2 'x': x 2e+07 is beyond");
}

/** The observation classes of a frame, in order ("depth compass usbl sidescan"). */
std::string labels(const mrpt::obs::CSensoryFrame& f)
{
    std::string s;
    for (size_t i = 0; i < f.size(); i++)
    {
        s += (s.empty() ? "" : " ") + f.getObservationByIndex(i)->sensorLabel;
    }
    return s;
}

TEST(DatasetImportAuv, ReadingsGoIntoTheFirstStepAtOrAfterThemDepthFirst)
{
    // Steps: 10 (scan), 10.5, 11 (scan), 11.5, 12 (scan).
    std::vector<semloc::DetectionScan> scans = {
        {10, {}, "sidescan"}, {11, {}, "sidescan"}, {12, {}, "sidescan"}};
    const auto odo = straight(9, 13);
    TDatasetImportStats stats;
    const auto steps = DatasetImport::steps(scans, odo, 0.5, stats);
    ASSERT_EQ(steps.size(), 5u);
    semloc::VehicleReadings r;
    r.depth = {{9.5, 20, 5}, {10, 21, 4}, {10.2, 22, 3}, {10.4, 23, std::nan("")}, {12.5, 24, 1}};
    r.heading = {{10.7, 0.1}, {11.9, 0.2}};
    r.fixes = {{8, 1, 2, -20, 3, 3}, {11.2, 3, 4, -22, 0.5, 2}};
    TDatasetImportOptions o;
    const auto log = DatasetImport::makeRawlog(steps, scans, odo, r, o, stats);
    ASSERT_EQ(log.size(), 10u);
    EXPECT_EQ(labels(*log.getAsObservations(1)), "depth usbl sidescan");  // 10
    EXPECT_EQ(labels(*log.getAsObservations(3)), "depth");                // 10.5: 10.4 last
    EXPECT_EQ(labels(*log.getAsObservations(5)), "compass sidescan");     // 11
    EXPECT_EQ(labels(*log.getAsObservations(7)), "usbl");                 // 11.5
    EXPECT_EQ(labels(*log.getAsObservations(9)), "compass sidescan");     // 12
    const auto d0 = log.getAsObservations(1)->getObservationByClass<semloc::CObservationDepth>();
    EXPECT_EQ(d0->depth_m, 21);  // 9.5 superseded by 10
    EXPECT_EQ(d0->altitude_m, 4);
    EXPECT_EQ(d0->sensorLabel, "depth");
    EXPECT_EQ(mrpt::Clock::toDouble(d0->timestamp), 10);
    const auto d1 = log.getAsObservations(3)->getObservationByClass<semloc::CObservationDepth>();
    EXPECT_EQ(d1->depth_m, 23);
    EXPECT_TRUE(std::isnan(d1->altitude_m));
    const auto imu = log.getAsObservations(5)->getObservationByClass<mrpt::obs::CObservationIMU>();
    ASSERT_TRUE(imu);
    EXPECT_TRUE(imu->has(mrpt::obs::IMU_YAW));
    EXPECT_EQ(imu->get(mrpt::obs::IMU_YAW), 0.1);
    const auto fix =
        log.getAsObservations(7)->getObservationByClass<mrpt::obs::CObservationRobotPose>();
    ASSERT_TRUE(fix);
    EXPECT_EQ(fix->pose.mean.x(), 3);
    EXPECT_EQ(fix->pose.mean.z(), -22);
    EXPECT_EQ(fix->pose.cov(0, 0), 0.25);
    EXPECT_EQ(fix->pose.cov(1, 1), 4);
    EXPECT_EQ(fix->pose.cov(2, 2), 1);
    EXPECT_EQ(fix->pose.cov(3, 3), 100);
    EXPECT_EQ(fix->pose.cov(5, 5), 100);
    EXPECT_EQ(fix->pose.cov(0, 1), 0);
    EXPECT_EQ(stats.depth.written, 2u);
    EXPECT_EQ(stats.depth.superseded, 2u);
    EXPECT_EQ(stats.depth.dropped, 1u);
    EXPECT_EQ(stats.heading.written, 2u);
    EXPECT_EQ(stats.fixes.written, 2u);
    EXPECT_EQ(stats.fixes.superseded, 0u);
    const std::string summary = DatasetImport::summaryCounts(stats);
    expectError(summary,
                "2 depth readings written (2 superseded, 1 after the last step "
                "dropped), 2 heading readings written, 2 fixes written");
}

TEST(DatasetImportAuv, RawlogWithReadingsStreamedHasTheBytesOfTheWholeOne)
{
    const auto scans = DatasetImport::readDetections(write("auv_det3.csv", kAuvDetections), 0.01);
    const auto odo = straight(99, 110);
    TDatasetImportStats stats, streamed;
    const auto steps = DatasetImport::steps(scans, odo, 0.5, stats, "o", "d", 0.01);
    semloc::VehicleReadings r;
    r.depth = {{99.5, 20, 5}, {100.7, 21, 4}, {101, 22, 3}};
    r.heading = {{100, 0.3}};
    r.fixes = {{101.2, 1, 2, -22, 3, 3}};
    TDatasetImportOptions o;
    const fs::path whole = dir() / "whole.rawlog", part = dir() / "streamed.rawlog";
    semloc::saveRawlog(DatasetImport::makeRawlog(steps, scans, odo, r, o, stats), whole.string(),
                       "semloc-import");
    DatasetImport::writeRawlog(steps, scans, odo, r, o, streamed, part.string());
    EXPECT_EQ(semloc::test::readText(part), semloc::test::readText(whole));
    EXPECT_EQ(streamed.depth.written, stats.depth.written);
    EXPECT_EQ(streamed.fixes.written, 1u);
}

// ------------------------------------------------------------------ the tool

int runTool(const std::string& commandLine, const fs::path& log)
{
    const int status = std::system((commandLine + " >" + log.string() + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(DatasetImportAuv, TheToolImportsAnAuvLog)
{
    const fs::path d = dir() / "tool";
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "odom.csv") << "t,vx,vy,w\n1700000000,1.5,0.2,0\n1700000001,1.5,0.2,0.05\n"
                                     "1700000002,1.5,0.1,0\n1700000003,1.5,0,0\n";
    std::ofstream(d / "det.csv") << "t,sensor,label,range_m,bearing_rad,side\n"
                                    "1700000000,sidescan,boulder,12.5,,port\n"
                                    "1700000000.004,camera,tyre,,0.2,\n"
                                    "1700000001,sidescan,,,,\n"
                                    "1700000002,sidescan,boulder,20.1,,starboard\n";
    std::ofstream(d / "depth.csv")
        << "t,depth_m,altitude_m\n1699999999.5,25.1,4.9\n"
           "1700000000.5,25,\n1700000000.7,25.1,5\n1700000000.9,25.2,5.1\n"
           "1700000009,25,5\n";
    std::ofstream(d / "heading.csv") << "t,heading_rad\n1700000000,0.01\n1700000001.5,0.06\n";
    std::ofstream(d / "fixes.csv") << "t,x,y,sigma_m\n1700000001.2,10,5,3\n";
    const std::string cmd = "cd " + d.string() + " && " + SEMLOC_BIN_DIR +
                            "/semloc-import -o auv.rawlog --odometry odom.csv --detections "
                            "det.csv --depth depth.csv --heading heading.csv --fixes fixes.csv "
                            "--max-range-m sidescan=40 --fov-deg sidescan=360 --max-range-m "
                            "camera=8 --fov-deg camera=80 --sensor-pose camera=0.5,0,0,-0.3 "
                            "--sensor-pose sonar=1,0,0";
    ASSERT_EQ(runTool(cmd, d / "import.log"), 0) << semloc::test::readText(d / "import.log");
    const std::string out = semloc::test::readText(d / "import.log");
    EXPECT_NE(out.find("auv.rawlog: 5 steps (3 scans, 2 odometry-only), 3 detections, scans by "
                       "sensor: camera 1, sidescan 3 (1 step holds several), 1 detection without "
                       "a range (bearing-only), 3 depth readings written (1 superseded, 1 after "
                       "the last step dropped), 2 heading readings written, 1 fix written; wrote "
                       "auv.rawlog"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("warning: --sensor-pose sonar=: no detection row is of sensor 'sonar'"),
              std::string::npos)
        << out;
    const auto log = semloc::RawlogReader::Load((d / "auv.rawlog").string());
    ASSERT_EQ(log.size(), 10u);
    EXPECT_EQ(labels(*log.getAsObservations(1)), "depth compass sidescan camera");
    EXPECT_EQ(labels(*log.getAsObservations(3)), "depth");
    EXPECT_EQ(labels(*log.getAsObservations(5)), "depth sidescan");
    EXPECT_EQ(labels(*log.getAsObservations(7)), "compass usbl");
    EXPECT_EQ(labels(*log.getAsObservations(9)), "sidescan");
}

}  // namespace

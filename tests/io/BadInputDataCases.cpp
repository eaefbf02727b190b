/* semloc tests — the bad inputs of docs/bad-input.md's table: rawlogs, ground truth, observations,
 * imports. Each case builds its input in a fresh directory and returns the tool's command line
 * (test_BadInput.cpp runs it and checks the row). */
#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{

/** The rawlog file itself. */
Cases rawlogFileCases()
{
    return {
        {"rawlog-missing",
         [](const fs::path& d) { return localize(d, writeIni(d), d / "nope.rawlog"); }},
        {"rawlog-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "dir.rawlog");
             return localize(d, writeIni(d), d / "dir.rawlog");
         }},
        {"rawlog-empty",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", "");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-not-a-rawlog",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", "t x y phi\n1 2 3 4\n");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
    };
}

/** Truncated and corrupted rawlogs. */
Cases rawlogDamagedCases()
{
    return {
        {"rawlog-truncated-gz",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "full.rawlog");
             const std::string b = readText(d / "full.rawlog");
             fs::remove(d / "full.rawlog");
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated-allowed",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog", {"--allow-truncated"});
         }},
        {"rawlog-truncated-entry-0",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", plainBytes(d).substr(0, 40));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated-entry-0-allowed",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", plainBytes(d).substr(0, 40));
             return localize(d, writeIni(d), d / "data.rawlog", {"--allow-truncated"});
         }},
        {"rawlog-corrupted-gz",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "full.rawlog");
             std::string b = readText(d / "full.rawlog");
             fs::remove(d / "full.rawlog");
             for (size_t i = b.size() / 2; i < b.size() / 2 + 16; i++)
             {
                 b[i] = static_cast<char>(~b[i]);
             }
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-corrupted-entry",
         [](const fs::path& d)
         {
             // The serialization version byte after the 2nd sensory frame's class name.
             std::string b = plainBytes(d);
             const std::string name = "mrpt::obs::CSensoryFrame";
             const auto p = b.find(name, b.find(name) + 1);
             b[p + name.size()] = 99;
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-unknown-class",
         [](const fs::path& d)
         {
             std::string b = plainBytes(d);
             const std::string name = "CObservationSemantic";
             b[b.find(name, b.find(name) + 1) + name.size() - 1] = 'X';
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
    };
}

/** The rawlog's odometry. */
Cases rawlogOdometryCases()
{
    return {
        {"rawlog-no-odometry",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       mrpt::obs::CRawlog obsOnly;
                                       for (size_t i = 0; i < log.size(); i++)
                                       {
                                           if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
                                           {
                                               for (const auto& o : *log.getAsObservations(i))
                                               {
                                                   obsOnly.insert(o);
                                               }
                                           }
                                       }
                                       log.swap(obsOnly);
                                   });
         }},
        {"rawlog-no-usable-observations",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       for (size_t i = 0; i < log.size(); i++)
                                       {
                                           if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
                                           {
                                               auto sf = log.getAsObservations(i);
                                               sf->eraseByLabel("SEMANTIC");
                                           }
                                       }
                                   });
         }},
        {"rawlog-odometry-nan",
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto acts = log.getAsAction(2);
                     auto m = acts->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
                     m->computeFromOdometry(mrpt::poses::CPose2D(kNaN, 0, 0),
                                            m->motionModelConfiguration);
                 });
         }},
        {"rawlog-odometry-very-noisy",
         [](const fs::path& d)
         {
             auto o =
                 semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate.ini");
             o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
             o.simulation.max_steps = 6;
             o.odometry.min_xy_std_m = 5;
             o.odometry.min_phi_std_deg = 60;
             saveGz(semloc::Simulator(o).run().rawlog, d / "data.rawlog");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-odometry-huge-step",  // its covariance as the simulator's model makes it
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto m =
                         log.getAsAction(4)->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
                     m->computeFromOdometry(mrpt::poses::CPose2D(1e6, 0, 0),
                                            m->motionModelConfiguration);
                 });
         }},
    };
}

/** Time: the rawlog's steps and the ground-truth file. */
Cases timeCases()
{
    return {
        {"rawlog-time-repeated",
         [](const fs::path& d)
         {
             return localizeEditedWithGroundTruth(d,
                                                  [](mrpt::obs::CRawlog& log)
                                                  {
                                                      const auto obs = allObservations(log);
                                                      for (const auto& o : obs)
                                                      {
                                                          o->timestamp = obs[0]->timestamp;
                                                      }
                                                  });
         }},
        {"rawlog-time-swapped",  // steps 2 and 3 (entries 4-5 and 6-7) exchanged
         [](const fs::path& d)
         {
             return localizeEditedWithGroundTruth(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     mrpt::obs::CRawlog swapped;
                     for (const size_t i : {0, 1, 2, 3, 6, 7, 4, 5, 8, 9, 10, 11})
                     {
                         swapped.insert(log.getAsGeneric(i));
                     }
                     log.swap(swapped);
                 });
         }},
        // ---- ground truth
        {"gt-missing",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"ground_truth_path_file", (d / "nope.txt").string()}});
         }},
        {"gt-columns", [](const fs::path& d)
         { return localizeWithGroundTruth(d, "# t x y phi\n1 2 3 0\n2 3 4\n"); }},
        {"gt-not-a-number",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n2 3 four 0\n"); }},
        {"gt-nan",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n2 nan 4 0\n"); }},
        {"gt-time-decreasing", [](const fs::path& d)
         { return localizeWithGroundTruth(d, "1 2 3 0\n3 2 3 0\n2 2 3 0\n"); }},
        {"gt-time-repeated",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n1 2 3 0\n"); }},
        {"gt-matches-no-step",  // in milliseconds
         [](const fs::path& d)
         {
             return localizeEditedWithGroundTruth(
                 d, [](mrpt::obs::CRawlog&) {}, 1000);
         }},
    };
}

namespace
{
/** Acoustic beacon ranges beside the semantic map: three frames get ranges that are not
 *  finite (a NaN range, an infinite one, a NaN transducer position), one a fine range. */
std::vector<std::string> beaconRangesInvalid(const fs::path& d)
{
    auto sim = simulate();
    auto sem = observationsOf<semloc::CObservationSemantic>(sim.rawlog);
    auto ranges = [&](size_t frame, float range, double sensorX)
    {
        auto obs = mrpt::obs::CObservationBeaconRanges::Create();
        obs->timestamp = sem[frame]->timestamp;
        obs->maxSensorDistance = 200;
        obs->stdError = 0.5f;
        mrpt::obs::CObservationBeaconRanges::TMeasurement m;
        m.beaconID = 1;
        m.sensedDistance = range;
        m.sensorLocationOnRobot = mrpt::poses::CPoint3D(sensorX, 0, 0);
        obs->sensedData.push_back(m);
        return obs;
    };
    for (size_t i = 0; i < sim.rawlog.size(); i++)
    {
        auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(sim.rawlog.getAsGeneric(i));
        if (!sf || !sf->getObservationByClass<semloc::CObservationSemantic>())
        {
            continue;
        }
        const auto obs = sf->getObservationByClass<semloc::CObservationSemantic>();
        const size_t k = static_cast<size_t>(std::find(sem.begin(), sem.end(), obs) - sem.begin());
        if (k < 4)
        {
            const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                                 std::numeric_limits<float>::infinity(), 30.0f, 30.0f};
            sf->insert(ranges(k, bad[k], k == 2 ? kNaN : 0.0));
        }
    }
    saveGz(sim.rawlog, d / "data.rawlog");
    return localize(d,
                    writeIni(d, "[MetricMap]\nbeaconMap_count = 1\n",
                             {{"map_file", kSrc + "/maps/paper_50x50_lbl.yaml"},
                              {"trigger", "off"},
                              {"lost_var_xy_m2", "0"}}),
                    d / "data.rawlog");
}
}  // namespace

/** Observations: skipped and counted. */
Cases observationCases()
{
    return {
        {"detections-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       auto o = firstObservation<semloc::CObservationSemantic>(log);
                                       for (const double r : {kNaN, kInf, -1.0, 1000.0})
                                       {
                                           semloc::TSemanticDetection det;
                                           det.label = "pillar";
                                           det.range_m = r;
                                           o->detections.push_back(det);
                                       }
                                   });
         }},
        {"beams-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto s = firstObservation<mrpt::obs::CObservation2DRangeScan>(log);
                     const float r[] = {std::numeric_limits<float>::quiet_NaN(),
                                        std::numeric_limits<float>::infinity(), -1.0f,
                                        s->maxRange + 5};
                     for (size_t k = 0; k < 4; k++)
                     {
                         s->setScanRange(k, r[k]);
                         s->setScanRangeValidity(k, true);
                     }
                 });
         }},
        {"observations-geometry-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       auto o = observationsOf<semloc::CObservationSemantic>(log);
                                       o[0]->sensorPose.x(kNaN);
                                       o[1]->sensorPose.y(1e300);
                                       o[2]->maxRange_m = kInf;
                                   });
         }},
        {"beacon-ranges-invalid", beaconRangesInvalid},
        {"scans-geometry-invalid",
         [](const fs::path& d)
         {
             return localizeEditedWith(
                 d, "grid_rt",
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto s = observationsOf<mrpt::obs::CObservation2DRangeScan>(log);
                     s[0]->sensorPose.x(kNaN);
                     s[1]->aperture = std::numeric_limits<float>::quiet_NaN();
                     s[2]->resizeScan(0);
                 });
         }},
        {"scans-one-beam-grid",  // semloc-simulate's [Sonar] beam_count = 1
         [](const fs::path& d)
         {
             return localizeEditedWith(
                 d, "grid_lf",
                 [](mrpt::obs::CRawlog& log)
                 {
                     for (const auto& s : observationsOf<mrpt::obs::CObservation2DRangeScan>(log))
                     {
                         s->resizeScan(1);
                     }
                 });
         }},
    };
}

/** semloc-import-landmarks. */
Cases importCases()
{
    return {
        {"import-truncated",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "in.rawlog", b.substr(0, b.size() / 2));
             return std::vector<std::string>{"semloc-import-landmarks", (d / "in.rawlog").string(),
                                             "-o", (d / "lm.rawlog").string()};
         }},
        {"import-label-blank",
         [](const fs::path& d) {
             return importLandmarks(d, {"--label", "oil rig"});
         }},
        {"import-label-empty",
         [](const fs::path& d) {
             return importLandmarks(d, {"--label", ""});
         }},
        {"import-margin-huge",
         [](const fs::path& d) {
             return importLandmarks(d, {"--margin", "1e300"});
         }},
        {"import-csv-missing-column",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", "t,label,range_m\n1,buoy,3\n"}});
         }},
        {"import-csv-unknown-column",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,x,y,heading\n1,0,0,0\n2,1,0,0\n"}});
         }},
        {"import-csv-not-a-number",
         [](const fs::path& d)
         {
             return importCsv(
                 d, {{"det.csv", "t,label,range_m,bearing_rad\n1,buoy,3,0.1\n2,buoy,far,0\n"}});
         }},
        {"import-csv-nan",
         [](const fs::path& d) {
             return importCsv(d, {{"gt.csv", "t,x,y,phi\n1,5,5,0\n2,nan,5,0\n"}});
         }},
        {"import-csv-time-back",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,x,y,phi\n1,0,0,0\n2,1,0,0\n1.5,2,0,0\n"}});
         }},
        {"import-csv-no-scan-in-odometry",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,x,y,phi\n10,0,0,0\n11,1,0,0\n"}});
         }},
        {"import-csv-out-is-input",
         [](const fs::path& d)
         {
             auto a = importCsv(d, {});
             a[2] = "det.csv";
             return a;
         }},
        {"import-csv-out-not-semloc",
         [](const fs::path& d)
         {
             auto a = importCsv(d, {});
             writeText(d / "notes.txt", "my notes\n");
             a[2] = "notes.txt";
             return a;
         }},
        {"import-csv-landmark-duplicate-id",
         [](const fs::path& d) {
             return importCsv(d, {{"lm.csv", "id,label,x,y\n2,buoy,9,5\n2,rock,12,6\n"}});
         }},
        {"import-csv-landmark-sigma-alone",
         [](const fs::path& d) {
             return importCsv(d,
                              {{"lm.csv", "id,label,x,y,sigma_x_m,sigma_y_m\n1,buoy,9,5,0.5,\n"}});
         }},
        {"import-csv-fov-out-of-range",
         [](const fs::path& d) {
             return importCsv(d, {}, {"--fov-deg", "400"});
         }},
    };
}

std::vector<std::string> calibrate(const fs::path& d, size_t gtRows, const std::string& base,
                                   const std::string& out)
{
    const auto sim = simulate();
    saveGz(sim.rawlog, d / "data.rawlog");
    std::ostringstream gt;
    gt.precision(17);
    for (size_t i = 0; i < gtRows && i < sim.groundTruth.size(); i++)
    {
        const auto& r = sim.groundTruth[i];
        gt << r.t << " " << r.x << " " << r.y << " " << r.phi << "\n";
    }
    writeText(d / "gt.txt", gt.str());
    writeText(d / "base.ini", resolvedIni(kSrc + "/config/localize/" + base + ".ini"));
    return {"semloc-calibrate",
            (d / "data.rawlog").string(),
            "--world",
            kSrc + "/maps/paper_50x50.yaml",
            "--ground-truth",
            (d / "gt.txt").string(),
            "--base",
            (d / "base.ini").string(),
            "-o",
            (d / out).string()};
}

Cases calibrateCases()
{
    return {
        {"calibrate-base-no-semantic-map",
         [](const fs::path& d) { return calibrate(d, 100, "geometric", "out.ini"); }},
        {"calibrate-ground-truth-short",
         [](const fs::path& d) { return calibrate(d, 2, "semantic", "out.ini"); }},
        {"calibrate-gate-not-positive",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             a.insert(a.end(), {"--gate-m", "0"});
             return a;
         }},
        {"calibrate-consistency-seeds-negative",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             a.insert(a.end(), {"--consistency-seeds", "-1"});
             return a;
         }},
        {"calibrate-out-is-input",
         [](const fs::path& d) { return calibrate(d, 100, "semantic", "base.ini"); }},
        {"calibrate-base-unknown-key",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             std::string base = readText(d / "base.ini");
             base.replace(base.find("\nsigma_range_m "), 15, "\nsigma_rnage_m ");
             writeText(d / "base.ini", base);
             return a;
         }},
        {"calibrate-base-bad-value",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             std::string base = readText(d / "base.ini");
             const auto at = base.find("\np_detect_far ");
             base.replace(at, base.find('\n', at + 1) - at, "\np_detect_far = 0");
             writeText(d / "base.ini", base);
             return a;
         }},
        {"calibrate-too-little-data",
         [](const fs::path& d) { return calibrate(d, 100, "semantic", "out.ini"); }},
        {"calibrate-sensor-model-without-readings",
         [](const fs::path& d) { return calibrate(d, 100, "auv/dead_reckoning", "out.ini"); }},
        {"calibrate-out-not-semloc",
         [](const fs::path& d)
         {
             writeText(d / "mytuned.ini", "[PF_options]\nBETA = 0.4\n");
             return calibrate(d, 100, "semantic", "mytuned.ini");
         }},
    };
}

}  // namespace semloc::test::bad_input

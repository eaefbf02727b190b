/* semloc tests — the simulator's AUV sensors ([Depth], [Compass], [USBL], [DVL], [SideScan],
 * [ForwardSonar], [Camera]): each reading's statistics against its options, the geometry the
 * detector models score, the other sensors' data untouched when they are on, and their bad
 * keys refused. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/observation/CObservationDepth.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

using mrpt::math::TPose2D;
using semloc::CObservationDepth;
using semloc::CObservationSemantic;
using semloc::SimulationResult;
using semloc::Simulator;
using semloc::TSimulatorOptions;

namespace
{
const std::string kSeabed = SEMLOC_SOURCE_DIR "/maps/seabed_200x200.yaml";
constexpr double kDeg = M_PI / 180;

TSimulatorOptions survey(int steps)
{
    TSimulatorOptions o;
    o.simulation.world_file = kSeabed;
    o.simulation.max_steps = steps;
    return o;
}

TSimulatorOptions allSensors(int steps)
{
    auto o = survey(steps);
    auto& a = o.auv;
    a.depth.enabled = a.compass.enabled = a.usbl.enabled = a.dvl.enabled = true;
    a.sidescan.enabled = a.fls.enabled = a.camera.enabled = true;
    a.compass.sigma_deg = 1;
    a.compass.deviation_deg = 2;
    a.usbl.period_steps = 5;
    a.dvl.scale_error = 0.01;
    a.camera.max_range_m = 12;
    a.camera.tilt_deg = 60;
    a.camera.vertical_fov_deg = 60;
    a.fls.tilt_deg = 15;
    a.fls.vertical_fov_deg = 20;
    return o;
}

mrpt::obs::CSensoryFrame::Ptr frameOf(const SimulationResult& r, size_t k)
{
    return std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(r.rawlog.getAsGeneric(2 * k + 1));
}
mrpt::obs::CActionRobotMovement2D::Ptr actionOf(const SimulationResult& r, size_t k)
{
    auto acts =
        std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(r.rawlog.getAsGeneric(2 * k));
    return acts->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
}

std::string bytesOf(const mrpt::serialization::CSerializable& obj)
{
    mrpt::io::CMemoryStream m;
    auto ar = mrpt::serialization::archiveFrom(m);
    ar << obj;
    return {static_cast<const char*>(m.getRawBufferData()),
            static_cast<size_t>(m.getTotalBytesCount())};
}

TPose2D truthAt(const SimulationResult& r, size_t k)
{
    const auto& g = r.groundTruth[k];
    return {g.x, g.y, g.phi};
}
}  // namespace

TEST(AuvSensors, ReadingsHaveTheirOptionsStatistics)
{
    const auto o = allSensors(600);
    const Simulator sim(o);
    const auto r = sim.run();
    double depthSum = 0, depthSq = 0, compassSum = 0, compassSq = 0, fixSq = 0;
    size_t depths = 0, compasses = 0, fixes = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto truth = truthAt(r, k);
        const auto sf = frameOf(r, k);
        // The AUV's readings follow the other sensors', the depth first among them.
        ASSERT_TRUE(IS_CLASS(*sf->getObservationByIndex(0), mrpt::obs::CObservation2DRangeScan));
        ASSERT_TRUE(IS_CLASS(*sf->getObservationByIndex(2), CObservationDepth));
        const auto depth = sf->getObservationByClass<CObservationDepth>();
        depthSum += depth->depth_m - 25, depthSq += (depth->depth_m - 25) * (depth->depth_m - 25);
        EXPECT_NEAR(depth->altitude_m, 5, 1);
        depths++;
        const auto imu = sf->getObservationByClass<mrpt::obs::CObservationIMU>();
        ASSERT_TRUE(imu && imu->has(mrpt::obs::IMU_YAW));
        const double e = std::remainder(
            imu->get(mrpt::obs::IMU_YAW) - truth.phi - 2 * kDeg * std::cos(truth.phi), 2 * M_PI);
        compassSum += e, compassSq += e * e, compasses++;
        if (const auto fix = sf->getObservationByClass<mrpt::obs::CObservationRobotPose>())
        {
            EXPECT_EQ(k % 5, 0u);
            EXPECT_EQ(fix->pose.cov(0, 0), 9);
            fixSq += std::pow(fix->pose.mean.x() - truth.x, 2) +
                     std::pow(fix->pose.mean.y() - truth.y, 2);
            fixes++;
        }
    }
    EXPECT_NEAR(depthSum / depths, 0, 0.01);
    EXPECT_NEAR(std::sqrt(depthSq / depths), 0.05, 0.01);
    EXPECT_NEAR(compassSum / compasses, 0, 0.2 * kDeg);
    EXPECT_NEAR(std::sqrt(compassSq / compasses), 1 * kDeg, 0.15 * kDeg);
    EXPECT_EQ(fixes, 119u);
    EXPECT_NEAR(std::sqrt(fixSq / (2 * fixes)), 3, 0.5);
}

TEST(AuvSensors, TheDvlReadsTheBodyFrameIncrementWithItsScaleError)
{
    const auto r = Simulator(allSensors(300)).run();
    double ratio = 0;
    size_t n = 0;
    for (size_t k = 1; k < r.steps; k++)
    {
        const auto a = truthAt(r, k - 1), b = truthAt(r, k);
        const auto inc = mrpt::poses::CPose2D(b) - mrpt::poses::CPose2D(a);
        const auto raw = actionOf(r, k)->rawOdometryIncrementReading;
        if (inc.norm() > 1)
        {
            ratio += raw.norm() / inc.norm();
            n++;
        }
    }
    EXPECT_NEAR(ratio / n, 1.01, 0.003);  // scale_error 0.01, noise 1 % per step averaged
}

/** Every detection is of an object the detector's geometry sees, at its slant range. */
TEST(AuvSensors, DetectionsFollowTheDetectorsGeometry)
{
    const auto o = allSensors(800);
    const Simulator sim(o);
    const auto r = sim.run();
    const auto& objects = sim.world().objects;
    size_t counted[3] = {0, 0, 0}, explained[3] = {0, 0, 0};
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto truth = truthAt(r, k);
        const auto sf = frameOf(r, k);
        for (const auto& obs : *sf)
        {
            const auto* scan = dynamic_cast<const CObservationSemantic*>(obs.get());
            if (!scan || scan->sensorLabel == "SEMANTIC")
            {
                continue;
            }
            const int kind = scan->sensorLabel == "sidescan" ? 0
                             : scan->sensorLabel == "fls"    ? 1
                                                             : 2;
            const auto sensor =
                mrpt::poses::CPose3D(truth.x, truth.y, -25, truth.phi, 0, 0) + scan->sensorPose;
            for (const auto& d : scan->detections)
            {
                counted[kind]++;
                if (kind == 0)
                {
                    EXPECT_EQ(std::abs(d.bearing_rad), M_PI / 2);
                }
                if (kind == 2)
                {
                    EXPECT_TRUE(std::isnan(d.range_m));
                }
                for (const auto& obj : objects)
                {
                    if (obj.label != d.label)
                    {
                        continue;
                    }
                    double u, w, dz;
                    sensor.inverseComposePoint(obj.center.x, obj.center.y, obj.z, u, w, dz);
                    const double slant = std::sqrt(u * u + w * w + dz * dz);
                    const bool ok =
                        kind == 0
                            ? (std::abs(std::asin(u / slant)) <= 2 * kDeg + 1e-9 &&
                               (w > 0) == (d.bearing_rad > 0) && std::abs(d.range_m - slant) < 2)
                            : (std::abs(std::remainder(d.bearing_rad - std::atan2(w, u),
                                                       2 * M_PI)) < 5 * kDeg &&
                               (kind == 2 || std::abs(d.range_m - slant) < 2));
                    if (ok)
                    {
                        explained[kind]++;
                        break;
                    }
                }
            }
        }
    }
    for (int kind = 0; kind < 2; kind++)
    {
        EXPECT_GT(counted[kind], 100u) << kind;
        // All but the false alarms (0.1 a scan) are explained by an object in view.
        EXPECT_GT(explained[kind], counted[kind] - 0.15 * r.steps) << kind;
        EXPECT_GT(explained[kind], counted[kind] / 2) << kind;
    }
    EXPECT_GT(counted[2], 0u);
}

/** The AUV's sensors add observations and leave the others' draws as they were; with the DVL
 *  off the odometry is the same too. */
TEST(AuvSensors, TheOtherSensorsAreUntouched)
{
    auto on = allSensors(200);
    on.auv.dvl.enabled = false;
    const auto a = Simulator(survey(200)).run(), b = Simulator(on).run();
    ASSERT_EQ(a.steps, b.steps);
    for (size_t k = 0; k < a.steps; k++)
    {
        ASSERT_EQ(bytesOf(*actionOf(a, k)), bytesOf(*actionOf(b, k)));
        const auto fa = frameOf(a, k), fb = frameOf(b, k);
        ASSERT_EQ(fa->size(), 2u);
        ASSERT_GT(fb->size(), 2u);
        for (size_t i = 0; i < fa->size(); i++)
        {
            ASSERT_EQ(bytesOf(*fa->getObservationByIndex(i)),
                      bytesOf(*fb->getObservationByIndex(i)));
        }
    }
}

namespace
{
std::string loadError(const std::string& text)
{
    mrpt::config::CConfigFileMemory ini;
    ini.setContent(text);
    TSimulatorOptions o;
    try
    {
        o.auv.loadFromConfigFile(ini);
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}
}  // namespace

TEST(AuvSensors, BadKeysAreNamed)
{
    EXPECT_NE(loadError("[SideScan]\nfov_deg=30\n").find("fov_deg"), std::string::npos);
    EXPECT_NE(loadError("[Camera]\nrange_noise_std_m=1\n").find("range_noise_std_m"),
              std::string::npos);
    EXPECT_NE(loadError("[ForwardSonar]\nmin_range_m=70\n").find("min_range_m"), std::string::npos);
    EXPECT_NE(loadError("[Depth]\ndepth_m=40\nseabed_depth_m=30\n").find("seabed_depth_m"),
              std::string::npos);
    EXPECT_NE(loadError("[USBL]\nperiod_steps=0\n").find("period_steps"), std::string::npos);
    EXPECT_NE(loadError("[DVL]\nscale_error=nan\n").find("scale_error"), std::string::npos);
    EXPECT_NE(loadError("[Compass]\ndeviation=1\n").find("deviation"), std::string::npos);
    EXPECT_EQ(loadError("[SideScan]\nenabled=true\nbeam_width_deg=2\n"), "");
}

TEST(AuvSensors, TheCsvFilesImportBackToTheRawlogsReadings)
{
    namespace fs = std::filesystem;
    auto o = allSensors(150);
    o.detector.enabled = false;  // the AUV's detectors only
    const Simulator sim(o);
    const auto r = sim.run();
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "auv_csv";
    fs::remove_all(dir);
    sim.writeCsvDataset(r, dir.string());
    for (const char* f : {"odometry.csv", "detections.csv", "ground_truth.csv", "landmarks.csv",
                          "depth.csv", "heading.csv", "fixes.csv"})
    {
        EXPECT_TRUE(fs::exists(dir / f)) << f;
    }
    // The DVL's t,vx,vy,w rows integrate back to each step's increment.
    const auto odo = semloc::DatasetImport::readOdometry((dir / "odometry.csv").string());
    ASSERT_EQ(odo.t.size(), r.steps);
    for (size_t k = 1; k < r.steps; k++)
    {
        const mrpt::poses::CPose2D want = actionOf(r, k)->poseChange->getMeanVal();
        const mrpt::poses::CPose2D got =
            mrpt::poses::CPose2D(odo.pose[k]) - mrpt::poses::CPose2D(odo.pose[k - 1]);
        ASSERT_NEAR(got.x(), want.x(), 1e-9) << k;
        ASSERT_NEAR(got.y(), want.y(), 1e-9) << k;
        ASSERT_NEAR(got.phi(), want.phi(), 1e-12) << k;
    }
    // Every detector's scan, with its sensor, its side-scan sides and its camera's missing ranges.
    const auto scans = semloc::DatasetImport::readDetections((dir / "detections.csv").string());
    size_t want = 0, got = 0, semantic = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        for (const auto& obs : *frameOf(r, k))
        {
            if (const auto* s = dynamic_cast<const CObservationSemantic*>(obs.get()))
            {
                want += s->detections.size();
                semantic += s->sensorLabel == "SEMANTIC" ? 1 : 0;
            }
        }
    }
    EXPECT_EQ(semantic, 0u) << "[SemanticDetector] enabled = false: no SEMANTIC scans";
    EXPECT_EQ(scans.size(), 3 * r.steps) << "one scan per detector and step";
    for (const auto& s : scans)
    {
        got += s.detections.size();
        for (const auto& d : s.detections)
        {
            if (s.sensor == o.auv.sidescan.sensor_label)
            {
                EXPECT_EQ(std::abs(d.bearing_rad), M_PI / 2);
            }
            EXPECT_EQ(std::isnan(d.range_m), s.sensor == o.auv.camera.sensor_label);
        }
    }
    EXPECT_EQ(got, want);
    EXPECT_GT(want, 20u);
}

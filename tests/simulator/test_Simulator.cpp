/* semloc tests — Simulator and its models: exact noise-free data, error statistics,
 * determinism, kidnapping, options and atomic output. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/Interrupt.h>
#include <semloc/models/structure/CStructureMap.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/simulator/TrajectoryFollower.h>
#include <semloc/simulator/WorldChanges.h>

#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>

using mrpt::math::TPose2D;
using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CSensoryFrame;
using mrpt::poses::CPose2D;
using semloc::CObservationSemantic;
using semloc::GroundTruthFile;
using semloc::GroundTruthRow;
using semloc::SemanticDetectorModel;
using semloc::SimulatedOdometry;
using semloc::SimulationResult;
using semloc::Simulator;
using semloc::SonarModel;
using semloc::TSimulatorOptions;
using semloc::World;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kOut = SEMLOC_TEST_OUT;

const World& paperWorld()
{
    static const World w = World::FromFile(kPaper);
    return w;
}

/** The paper world with the default noise, for `steps` steps. */
TSimulatorOptions paperRun(int steps)
{
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.simulation.max_steps = steps;
    return o;
}

/** Every noise and error source off; detections carry object ids. */
TSimulatorOptions noiseFree()
{
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.odometry.xy_std_per_m = o.odometry.xy_std_m_per_rad = 0;
    o.odometry.phi_std_deg_per_m = o.odometry.phi_std_per_rad = 0;
    o.odometry.min_xy_std_m = o.odometry.min_phi_std_deg = 0;
    o.sonar.range_noise_std_m = o.sonar.dropout_probability = 0;
    o.detector.range_noise_std_m = o.detector.bearing_noise_std_deg = 0;
    o.detector.p_detect_near = o.detector.p_detect_far = 1;
    o.detector.false_positives_per_scan = o.detector.p_confusion = 0;
    o.detector.report_ids = true;
    return o;
}

/** The step's odometry action, sonar scan and semantic observation. */
struct Step
{
    CActionRobotMovement2D::Ptr odometry;
    CObservation2DRangeScan::Ptr sonar;
    CObservationSemantic::Ptr semantic;
};

Step stepOf(const SimulationResult& r, size_t k)
{
    const auto acts = std::dynamic_pointer_cast<CActionCollection>(r.rawlog.getAsGeneric(2 * k));
    const auto sf = std::dynamic_pointer_cast<CSensoryFrame>(r.rawlog.getAsGeneric(2 * k + 1));
    EXPECT_TRUE(acts && sf);
    Step s;
    s.odometry = acts->getBestMovementEstimation();
    s.sonar = sf->getObservationByClass<CObservation2DRangeScan>();
    s.semantic = sf->getObservationByClass<CObservationSemantic>();
    return s;
}

std::string fileBytes(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/** Sensor pose in the world: vehicle (+) the sensor's 2D pose (as the likelihoods do). */
TPose2D sensorInWorld(const TPose2D& v, double x, double y, double yaw)
{
    return {v.x + std::cos(v.phi) * x - std::sin(v.phi) * y,
            v.y + std::sin(v.phi) * x + std::cos(v.phi) * y, v.phi + yaw};
}

/** Distance along the ray (s, angle) to segment [p, q] within [0, maxT], or +inf, the
 *  segment's ends stretched by `slack` (of its length). An implementation independent of
 *  RayCaster (Cramer's rule, parallel segments ignored). */
double rayHit(const TPose2D& s, double angle, const mrpt::math::TSegment2D& seg, double maxT,
              double slack)
{
    const double ux = std::cos(angle), uy = std::sin(angle);
    const double ex = seg.point2.x - seg.point1.x, ey = seg.point2.y - seg.point1.y;
    const double den = ux * ey - uy * ex;
    if (std::abs(den) < 1e-15)
    {
        return INFINITY;
    }
    const double wx = seg.point1.x - s.x, wy = seg.point1.y - s.y;
    const double t = (wx * ey - wy * ex) / den;
    const double u = (wx * uy - wy * ux) / den;
    return (u >= -slack && u <= 1 + slack && t >= 0 && t <= maxT) ? t : INFINITY;
}

/** Expected detections of an ideal detector, by brute force: visible object index ->
 *  (range, bearing). Objects whose sight line grazes another outline's vertex (occluded
 *  or not depending on the last bit) are `ambiguous` and not checked. */
struct ExpectedView
{
    std::map<size_t, std::pair<double, double>> visible;
    std::set<size_t> ambiguous;
    size_t occluded = 0;
};

ExpectedView expectedView(const World& w, const TPose2D& sensor, double maxRange, double fov)
{
    ExpectedView v;
    for (size_t i = 0; i < w.objects.size(); i++)
    {
        const auto& o = w.objects[i];
        const double dx = o.center.x - sensor.x, dy = o.center.y - sensor.y;
        const double r = std::hypot(dx, dy), angle = std::atan2(dy, dx);
        const double b = mrpt::math::wrapToPi(angle - sensor.phi);
        if (r > maxRange || std::abs(b) > 0.5 * fov)
        {
            continue;
        }
        // Nearest hit on the own outline and on the others', with segments shrunk and
        // stretched by 1e-9: the object is hidden when another outline comes first.
        bool hiddenSure = false, hiddenMaybe = false;
        for (const double slack : {-1e-9, 1e-9})
        {
            double own = INFINITY, other = INFINITY;
            for (size_t j = 0; j < w.objects.size(); j++)
            {
                const auto poly = World::outlinePolygon(w.objects[j]);
                for (size_t k = 0; k < poly.size(); k++)
                {
                    const double t =
                        rayHit(sensor, angle, {poly[k], poly[(k + 1) % poly.size()]}, r, slack);
                    (j == i ? own : other) = std::min(j == i ? own : other, t);
                }
            }
            (slack < 0 ? hiddenSure : hiddenMaybe) = other < own;
        }
        if (hiddenSure != hiddenMaybe)
        {
            v.ambiguous.insert(i);
        }
        else if (hiddenSure)
        {
            v.occluded++;
        }
        else
        {
            v.visible[i] = {r, b};
        }
    }
    return v;
}

/** `k` standard errors of a proportion p estimated from n trials. */
double seProportion(double p, double n)
{
    return std::sqrt(p * (1 - p) / n);
}

constexpr double kSigmas = 4;  // two-sided 6e-5 false alarm per check (seeds are fixed anyway)

}  // namespace

// ------------------------------------------------------------------ trajectory

TEST(TrajectoryFollower, CoversThePolylineAtConstantStep)
{
    const auto& wps = paperWorld().trajectory->waypoints;
    double length = 0;
    for (size_t i = 1; i < wps.size(); i++)
    {
        length += (wps[i] - wps[i - 1]).norm();
    }
    semloc::TrajectoryFollower f(wps, 0.5);
    EXPECT_EQ(f.stepsToEnd(), static_cast<size_t>(std::ceil(length / 0.5 - 1e-9)) + 1);
    EXPECT_EQ(f.pose().x, wps[0].x);
    EXPECT_EQ(f.pose().y, wps[0].y);
    size_t corners = 0;
    while (!f.finished())
    {
        const TPose2D before = f.pose();
        f.step();
        const double d = std::hypot(f.pose().x - before.x, f.pose().y - before.y);
        const bool turned = std::abs(mrpt::math::wrapToPi(f.pose().phi - before.phi)) > 1e-12;
        corners += turned ? 1 : 0;
        if (!f.finished() && !turned)
        {
            EXPECT_NEAR(d, 0.5, 1e-9);  // on a straight leg every step is exact
        }
        EXPECT_LE(d, 0.5 + 1e-9);  // a corner step's chord is shorter
    }
    EXPECT_EQ(corners, wps.size() - 2);  // the heading turns once per corner
    EXPECT_NEAR(f.pose().x, wps.back().x, 1e-12);
    EXPECT_NEAR(f.pose().y, wps.back().y, 1e-12);
}

TEST(TrajectoryFollower, CarriesTheStepAroundACorner)
{
    semloc::TrajectoryFollower f({{0, 0}, {1, 0}, {1, 5}}, 1.5);
    f.step();
    EXPECT_NEAR(f.pose().x, 1.0, 1e-12);
    EXPECT_NEAR(f.pose().y, 0.5, 1e-12);
    EXPECT_NEAR(f.pose().phi, M_PI / 2, 1e-12);  // the whole corner within one step
    EXPECT_THROW(semloc::TrajectoryFollower({{1, 1}, {1, 1}}, 1.0), std::exception);
    EXPECT_THROW(semloc::TrajectoryFollower({{0, 0}, {1, 1}}, 0.0), std::exception);
}

// ------------------------------------------------------------------ noise-free run

class NoiseFreeRun : public ::testing::Test
{
protected:
    static void SetUpTestSuite() { result_ = new SimulationResult(Simulator(noiseFree()).run()); }
    static void TearDownTestSuite() { delete result_; }
    static SimulationResult* result_;
};
SimulationResult* NoiseFreeRun::result_ = nullptr;

TEST_F(NoiseFreeRun, LayoutTimestampsAndWholeTrajectory)
{
    const auto& r = *result_;
    const auto& wps = paperWorld().trajectory->waypoints;
    semloc::TrajectoryFollower f(wps, 0.5 * 1.0);
    ASSERT_EQ(r.steps, f.stepsToEnd());
    ASSERT_EQ(r.groundTruth.size(), r.steps);
    ASSERT_EQ(r.rawlog.size(), 2 * r.steps);
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto s = stepOf(r, k);
        ASSERT_TRUE(s.odometry && s.sonar && s.semantic) << "step " << k;
        const auto sf = std::dynamic_pointer_cast<CSensoryFrame>(r.rawlog.getAsGeneric(2 * k + 1));
        ASSERT_EQ(sf->size(), 2u);
        EXPECT_EQ(sf->getObservationByIndex(0)->sensorLabel, "SONAR");
        EXPECT_EQ(sf->getObservationByIndex(1)->sensorLabel, "SEMANTIC");
        const auto stamp = mrpt::Clock::fromDouble(1.7e9 + static_cast<double>(k));
        EXPECT_EQ(s.odometry->timestamp, stamp);
        EXPECT_EQ(s.sonar->timestamp, stamp);
        EXPECT_EQ(s.semantic->timestamp, stamp);
        EXPECT_EQ(r.groundTruth[k].t, mrpt::Clock::toDouble(stamp));
        EXPECT_EQ(s.odometry->estimationMethod, CActionRobotMovement2D::emOdometry);
        EXPECT_EQ(s.odometry->motionModelConfiguration.modelSelection,
                  CActionRobotMovement2D::mmGaussian);
    }
    EXPECT_NEAR(r.groundTruth.back().x, wps.back().x, 1e-12);
    EXPECT_NEAR(r.groundTruth.back().y, wps.back().y, 1e-12);
    EXPECT_EQ(r.beamsPerScan, 61u);
    EXPECT_EQ(r.meanValidBeams, 61.0);
}

TEST_F(NoiseFreeRun, IntegratedOdometryIsTheGroundTruth)
{
    const auto& r = *result_;
    CPose2D integrated(r.groundTruth[0].pose());
    for (size_t k = 0; k < r.steps; k++)
    {
        integrated = integrated + stepOf(r, k).odometry->rawOdometryIncrementReading;
        const auto& g = r.groundTruth[k];
        ASSERT_NEAR(integrated.x(), g.x, 1e-9) << "step " << k;
        ASSERT_NEAR(integrated.y(), g.y, 1e-9) << "step " << k;
        ASSERT_NEAR(mrpt::math::wrapToPi(integrated.phi() - g.phi), 0, 1e-9) << "step " << k;
    }
}

TEST_F(NoiseFreeRun, SonarRangesAreTheRayCastersForEveryBeam)
{
    const auto& r = *result_;
    const semloc::RayCaster caster(paperWorld().outlineSegments());  // CStructureMap's
    size_t hits = 0, maxReadings = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto& scan = *stepOf(r, k).sonar;
        ASSERT_EQ(scan.getScanSize(), 61u);
        ASSERT_TRUE(scan.rightToLeft);
        const auto s = sensorInWorld(r.groundTruth[k].pose(), scan.sensorPose.x(),
                                     scan.sensorPose.y(), scan.sensorPose.yaw());
        for (size_t b = 0; b < 61; b++)
        {
            const double a = -0.5 * scan.aperture + scan.aperture * static_cast<double>(b) / 60.0;
            const double expected = caster.cast(s.x, s.y, s.phi + a, scan.maxRange);
            ASSERT_TRUE(scan.getScanRangeValidity(b));  // max-range readings are valid too
            ASSERT_EQ(scan.getScanRange(b), static_cast<float>(expected)) << k << " " << b;
            (expected < scan.maxRange ? hits : maxReadings)++;
        }
    }
    EXPECT_GT(hits, 1000u);
    EXPECT_GT(maxReadings, 1000u);
}

TEST_F(NoiseFreeRun, StructureLikelihoodPrefersTheTruePose)
{
    const auto& r = *result_;
    semloc::CStructureMap map;
    map.loadFromWorld(paperWorld());
    for (size_t k = 0; k < r.steps; k += 25)
    {
        const auto& scan = *stepOf(r, k).sonar;
        const TPose2D g = r.groundTruth[k].pose();
        const double atTruth = map.computeLogLikelihood(scan, g);
        for (const TPose2D& d : {TPose2D(0.5, 0, 0), TPose2D(0, 0.5, 0), TPose2D(0, 0, 0.05)})
        {
            EXPECT_GE(atTruth,
                      map.computeLogLikelihood(scan, {g.x + d.x, g.y + d.y, g.phi + d.phi}))
                << "step " << k;
        }
    }
}

TEST_F(NoiseFreeRun, DetectionsAreExactlyTheVisibleObjects)
{
    const auto& r = *result_;
    const World& w = paperWorld();
    size_t detections = 0, occluded = 0, checked = 0, ambiguous = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto& obs = *stepOf(r, k).semantic;
        const auto s = sensorInWorld(r.groundTruth[k].pose(), obs.sensorPose.x(),
                                     obs.sensorPose.y(), obs.sensorPose.yaw());
        const auto view = expectedView(w, s, obs.maxRange_m, obs.fov_rad);
        occluded += view.occluded;
        ambiguous += view.ambiguous.size();
        std::set<size_t> seen;
        for (const auto& d : obs.detections)
        {
            ASSERT_TRUE(obs.isValid(d));
            const int idx = w.indexOfId(d.object_id);
            ASSERT_GE(idx, 0) << "step " << k << ": a detection without a world object";
            seen.insert(static_cast<size_t>(idx));
            if (view.ambiguous.count(static_cast<size_t>(idx)))
            {
                continue;
            }
            ASSERT_TRUE(view.visible.count(static_cast<size_t>(idx)))
                << "step " << k << ": object " << d.object_id << " is not visible";
            EXPECT_EQ(d.label, w.objects[static_cast<size_t>(idx)].label);
            EXPECT_NEAR(d.range_m, view.visible.at(static_cast<size_t>(idx)).first, 1e-12);
            EXPECT_NEAR(d.bearing_rad, view.visible.at(static_cast<size_t>(idx)).second, 1e-12);
            EXPECT_EQ(d.confidence, 1.0);
            checked++;
        }
        for (const auto& [idx, rb] : view.visible)
        {
            EXPECT_TRUE(seen.count(idx) || view.ambiguous.count(idx))
                << "step " << k << ": visible object " << w.objects[idx].id << " not detected";
        }
        detections += obs.detections.size();
    }
    EXPECT_GT(checked, 300u);
    EXPECT_GT(occluded, 0u);  // the trajectory does pass objects hidden behind others
    EXPECT_LT(ambiguous, checked / 100);
    EXPECT_DOUBLE_EQ(r.meanDetections,
                     static_cast<double>(detections) / static_cast<double>(r.steps));
}

TEST(SemanticDetectorModel, OcclusionByOthersNeverBySelf)
{
    const World w = World::FromText(R"(
name: occlusion
bounds: {x_min: -5, x_max: 30, y_min: -10, y_max: 10}
objects:
  - {id: 1, label: pillar, shape: cylinder, center: [5, 0], radius: 0.5}
  - {id: 2, label: wellhead, shape: box, center: [10, 0], size: [1, 1]}
  - {id: 3, label: marker, shape: point, center: [15, 0.2]}
  - {id: 4, label: pipeline, shape: box, center: [8, 5], size: [12, 0.4]}
  - {id: 5, label: marker, shape: point, center: [8, 8]}
)",
                                    "occlusion");
    SemanticDetectorModel::TOptions o;
    o.fov_deg = 360;
    const SemanticDetectorModel det(w, o);
    std::set<int> ids;
    for (const auto& v : det.visibleObjects({0, 0, 0}))
    {
        ids.insert(w.objects[v.index].id);
    }
    // The pillar hides the wellhead and the marker behind it; the long pipeline (whose
    // extent reaches past the sensor's distance to it) is seen and hides marker 5.
    EXPECT_EQ(ids, (std::set<int>{1, 4}));
    // From the side, the wellhead and the marker behind it come out of the pillar's shadow.
    ids.clear();
    for (const auto& v : det.visibleObjects({10, -4, M_PI / 2}))
    {
        ids.insert(w.objects[v.index].id);
    }
    EXPECT_TRUE(ids.count(2));
}

// ------------------------------------------------------------------ error statistics

TEST(SemanticDetectorModel, MisreadRangesAreUniformAndKeepTheBearing)
{
    const World w = World::FromText(R"(
name: misread
bounds: {x_min: -30, x_max: 30, y_min: -30, y_max: 30}
objects:
  - {id: 1, label: a, shape: point, center: [10, 0]}
)",
                                    "misread");
    SemanticDetectorModel::TOptions o;
    o.max_range_m = 20;
    o.p_detect_near = o.p_detect_far = 1;
    o.false_positives_per_scan = 0;
    o.range_noise_std_m = 0.1;
    o.bearing_noise_std_deg = 1;
    o.p_range_outlier = 0.25;
    const SemanticDetectorModel det(w, o);
    mrpt::random::CRandomGenerator rng(5);
    const int n = 8000;
    int far = 0;
    double farMean = 0, maxBearing = 0;
    for (int i = 0; i < n; i++)
    {
        const auto obs = det.measure({0, 0, 0}, rng);
        ASSERT_EQ(obs->detections.size(), 1u);
        const auto& d = obs->detections[0];
        ASSERT_TRUE(obs->isValid(d));
        maxBearing = std::max(maxBearing, std::abs(d.bearing_rad));
        if (std::abs(d.range_m - 10) > 1)  // 10 sigma: a misread
        {
            far++;
            farMean += d.range_m;
        }
    }
    // A misread lands outside 10 +- 1 m with probability 18 / 20.
    const double share = static_cast<double>(far) / n, expected = 0.25 * 0.9;
    EXPECT_NEAR(share, expected, 4 * std::sqrt(expected * (1 - expected) / n));
    // Uniform over [0, 20] outside the middle: mean 10, std 5.8 / sqrt(far).
    EXPECT_NEAR(farMean / far, 10.0, 4 * 5.8 / std::sqrt(static_cast<double>(far)));
    // The bearing keeps its Gaussian noise (1 deg): nothing beyond 5 sigma.
    EXPECT_LT(maxBearing, mrpt::DEG2RAD(5.0));
}

TEST(SemanticDetectorModel, AnObjectOfUncertainClassIsSeenAsEachOfItsClasses)
{
    // Object 1 is an anchor seen as a wreck 40 % of the time; object 2 (no classes) never
    // changes; "wreck" is a label of the world only through object 1's classes.
    const World w = World::FromText(R"(
name: classes
bounds: {x_min: -30, x_max: 30, y_min: -30, y_max: 30}
objects:
  - {id: 1, label: anchor, shape: point, center: [10, 0], classes: {anchor: 0.6, wreck: 0.4}}
  - {id: 2, label: pillar, shape: point, center: [10, 3], sigma_m: 2, p_exist: 0.1}
)",
                                    "classes");
    SemanticDetectorModel::TOptions o;
    o.p_detect_near = o.p_detect_far = 1;
    o.false_positives_per_scan = 0;
    o.p_confusion = 0;
    o.report_ids = true;
    const SemanticDetectorModel det(w, o);
    EXPECT_EQ(det.labels(), (std::vector<std::string>{"anchor", "pillar", "wreck"}));
    mrpt::random::CRandomGenerator rng(3);
    const int n = 4000;
    int wreck = 0, pillar = 0;
    for (int i = 0; i < n; i++)
    {
        const auto obs = det.measure({0, 0, 0}, rng);
        // sigma_m and p_exist describe a map: the world's objects are all there, where it says.
        ASSERT_EQ(obs->detections.size(), 2u);
        for (const auto& d : obs->detections)
        {
            if (d.object_id == 1)
            {
                EXPECT_TRUE(d.label == "anchor" || d.label == "wreck") << d.label;
                wreck += d.label == "wreck" ? 1 : 0;
            }
            else
            {
                pillar += d.label == "pillar" ? 1 : 0;
            }
        }
    }
    EXPECT_NEAR(static_cast<double>(wreck) / n, 0.4, 4 * std::sqrt(0.24 / n));
    EXPECT_EQ(pillar, n);
}

TEST(SemanticDetectorModel, StatisticsMatchTheConfiguredModel)
{
    // Three point objects (no occlusion) at ranges 2, 10, 18 m, 4 labels in the world.
    const World w = World::FromText(R"(
name: stats
bounds: {x_min: -30, x_max: 30, y_min: -30, y_max: 30}
objects:
  - {id: 1, label: a, shape: point, center: [2, 0]}
  - {id: 2, label: b, shape: point, center: [8.660254037844387, 5]}
  - {id: 3, label: c, shape: point, center: [15.588457268119896, -9]}
  - {id: 4, label: d, shape: point, center: [-25, 0]}
)",
                                    "stats");
    SemanticDetectorModel::TOptions o;
    o.max_range_m = 20;
    o.fov_deg = 120;
    o.p_detect_near = 0.95;
    o.p_detect_far = 0.5;
    o.false_positives_per_scan = 0.8;
    o.p_confusion = 0.1;
    o.range_noise_std_m = 0.3;
    o.bearing_noise_std_deg = 2;
    o.report_ids = true;
    const SemanticDetectorModel det(w, o);
    ASSERT_EQ(det.labels(), (std::vector<std::string>{"a", "b", "c", "d"}));
    mrpt::random::CRandomGenerator rng(42);

    const int n = 4000;
    std::map<int, int> detected;
    std::map<std::string, int> fpLabels;
    int trueDetections = 0, confused = 0, fp = 0;
    double fpSq = 0, fpRange = 0, eR = 0, eR2 = 0, eB = 0, eB2 = 0;
    int nNoise = 0;
    for (int i = 0; i < n; i++)
    {
        const auto obs = det.measure({0, 0, 0}, rng);
        int fpHere = 0;
        for (const auto& d : obs->detections)
        {
            ASSERT_TRUE(obs->isValid(d));
            if (d.object_id < 0)
            {
                fpHere++;
                fpLabels[d.label]++;
                fpRange += d.range_m;
                continue;
            }
            detected[d.object_id]++;
            trueDetections++;
            const auto& obj = w.objects[static_cast<size_t>(w.indexOfId(d.object_id))];
            confused += d.label != obj.label ? 1 : 0;
            if (d.object_id == 2)
            {
                const double er = d.range_m - 10, eb = d.bearing_rad - M_PI / 6;
                eR += er;
                eR2 += er * er;
                eB += eb;
                eB2 += eb * eb;
                nNoise++;
            }
        }
        fp += fpHere;
        fpSq += fpHere * fpHere;
    }
    const double N = n;
    // Detection probability: linear from p_near at 0 m to p_far at max range, the same at
    // every bearing (p_detect_edge_ratio 1).
    for (const auto& [id, range] : std::map<int, double>{{1, 2.0}, {2, 10.0}, {3, 18.0}})
    {
        const double p = det.detectionProbability(range, id == 1 ? 0.0 : M_PI / 6);
        EXPECT_NEAR(p, 0.95 - 0.45 * range / 20, 1e-12);
        EXPECT_NEAR(detected[id] / N, p, kSigmas * seProportion(p, N)) << "object " << id;
    }
    EXPECT_EQ(detected.count(4), 0u);  // behind the sensor
    // False positives: Poisson(0.8): mean and variance both lambda.
    const double lambda = 0.8, mean = fp / N, var = fpSq / N - mean * mean;
    EXPECT_NEAR(mean, lambda, kSigmas * std::sqrt(lambda / N));
    EXPECT_NEAR(var, lambda, kSigmas * std::sqrt((lambda + 2 * lambda * lambda) / N));
    for (const auto& l : det.labels())
    {
        EXPECT_NEAR(fpLabels[l] / static_cast<double>(fp), 0.25, kSigmas * seProportion(0.25, fp))
            << l;
    }
    EXPECT_NEAR(fpRange / fp, 10.0, kSigmas * 20 / std::sqrt(12.0 * fp));  // uniform in [0, R]
    // Class confusion among true detections.
    EXPECT_NEAR(confused / static_cast<double>(trueDetections), 0.1,
                kSigmas * seProportion(0.1, trueDetections));
    // Range and bearing noise (object 2, far from the clamps).
    const double m = nNoise, sdR = std::sqrt(eR2 / m - (eR / m) * (eR / m));
    const double sdB = std::sqrt(eB2 / m - (eB / m) * (eB / m)), sigmaB = 2 * M_PI / 180;
    EXPECT_NEAR(eR / m, 0, kSigmas * 0.3 / std::sqrt(m));
    EXPECT_NEAR(sdR, 0.3, kSigmas * 0.3 / std::sqrt(2 * m));
    EXPECT_NEAR(eB / m, 0, kSigmas * sigmaB / std::sqrt(m));
    EXPECT_NEAR(sdB, sigmaB, kSigmas * sigmaB / std::sqrt(2 * m));
}

TEST(SemanticDetectorModel, DetectionProbabilityFallsTowardsTheEdgeOfTheView)
{
    // Point objects at 5 m, on the axis, half-way to the edge and near the edge (40 of 45
    // degrees) of a 90-degree view; P_D at the edge is a fifth of P_D on the axis.
    const World w = World::FromText(R"(
name: edge
bounds: {x_min: -30, x_max: 30, y_min: -30, y_max: 30}
objects:
  - {id: 1, label: a, shape: point, center: [5, 0]}
  - {id: 2, label: a, shape: point, center: [4.619397662556434, 1.913417161825449]}
  - {id: 3, label: a, shape: point, center: [3.830222215594891, -3.2139380484326967]}
)",
                                    "edge");
    SemanticDetectorModel::TOptions o;
    o.max_range_m = 10;
    o.fov_deg = 90;
    o.p_detect_near = 0.9;
    o.p_detect_far = 0.5;
    o.p_detect_edge_ratio = 0.2;
    o.false_positives_per_scan = 0;
    o.p_confusion = 0;
    o.range_noise_std_m = 0.1;
    o.bearing_noise_std_deg = 0.1;
    o.report_ids = true;
    const SemanticDetectorModel det(w, o);
    mrpt::random::CRandomGenerator rng(7);
    const int n = 4000;
    std::map<int, int> detected;
    for (int i = 0; i < n; i++)
    {
        const auto obs = det.measure({0, 0, 0}, rng);
        for (const auto& d : obs->detections)
        {
            detected[d.object_id]++;
        }
    }
    const double onAxis = 0.9 - 0.4 * 5 / 10;  // the range line at 5 m
    for (const auto& [id, bearing] :
         std::map<int, double>{{1, 0.0}, {2, M_PI / 8}, {3, -M_PI * 40 / 180}})
    {
        const double p = det.detectionProbability(5, bearing);
        EXPECT_NEAR(p, onAxis * (1 - 0.8 * std::abs(bearing) / (M_PI / 4)), 1e-12) << id;
        EXPECT_NEAR(detected[id] / static_cast<double>(n), p, kSigmas * seProportion(p, n))
            << "object " << id;
    }
    EXPECT_NEAR(det.detectionProbability(5, 2.0), onAxis * 0.2, 1e-12);  // beyond: the edge's
}

TEST(SonarModel, DropoutsAndRangeNoiseMatchTheConfiguredModel)
{
    const World w = World::FromText(R"(
name: wall
bounds: {x_min: -20, x_max: 20, y_min: -20, y_max: 20}
objects:
  - {id: 1, label: wall, shape: box, center: [10.5, 0], size: [1, 30]}
)",
                                    "wall");
    SonarModel::TOptions o;
    o.beam_count = 31;
    o.aperture_deg = 180;
    o.range_noise_std_m = 0.2;
    o.dropout_probability = 0.1;
    const SonarModel sonar(w, o);
    mrpt::random::CRandomGenerator rng(7);
    const int n = 2000;
    double beams = 0, dropped = 0, e = 0, e2 = 0, nHits = 0;
    for (int i = 0; i < n; i++)
    {
        const auto scan = sonar.measure({0, 0, 0}, rng);
        for (size_t b = 0; b < scan->getScanSize(); b++)
        {
            const double a = scan->getScanAngle(b);
            const double truth = sonar.rayCaster().cast(0, 0, a, 20);
            beams++;
            if (!scan->getScanRangeValidity(b))
            {
                dropped++;
                continue;
            }
            if (truth >= 20)
            {
                EXPECT_EQ(scan->getScanRange(b), 20.0f);  // no echo: exactly max range
            }
            else if (std::abs(a) < 0.5)  // hits near 10 m: no clamping
            {
                const double err = scan->getScanRange(b) - truth;
                e += err;
                e2 += err * err;
                nHits++;
            }
        }
    }
    EXPECT_NEAR(dropped / beams, 0.1, kSigmas * seProportion(0.1, beams));
    const double sd = std::sqrt(e2 / nHits - (e / nHits) * (e / nHits));
    EXPECT_NEAR(e / nHits, 0, kSigmas * 0.2 / std::sqrt(nHits) + 1e-6);  // float ranges
    EXPECT_NEAR(sd, 0.2, kSigmas * 0.2 / std::sqrt(2 * nHits));
}

TEST(SimulatedOdometry, NoiseIsDrawnFromTheStoredMotionModel)
{
    SimulatedOdometry::TOptions o;
    o.xy_std_per_m = 0.1;
    o.xy_std_m_per_rad = 0.02;
    o.phi_std_deg_per_m = 2;
    o.phi_std_per_rad = 0.1;
    const SimulatedOdometry odo(o);
    const CPose2D truth(0.5, 0.05, 0.3);
    mrpt::random::CRandomGenerator rng(3);
    const int n = 4000;
    double d2 = 0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; i++)
    {
        const auto a = odo.measure(truth, rng);
        const auto& m = a.motionModelConfiguration.gaussianModel;
        ASSERT_EQ(m.a1, 0.1);
        ASSERT_EQ(m.a2, 0.02);
        ASSERT_NEAR(m.a3, 2 * M_PI / 180, 1e-15);
        ASSERT_EQ(m.a4, 0.1);
        ASSERT_NEAR(m.minStdPHI, 0.2 * M_PI / 180, 1e-15);
        ASSERT_EQ(m.minStdXY, 0.01);
        const auto& z = a.rawOdometryIncrementReading;
        const Eigen::Vector3d e(z.x() - truth.x(), z.y() - truth.y(),
                                mrpt::math::wrapToPi(z.phi() - truth.phi()));
        // The filter's covariance (at the reading) explains the error: E[d^2] = 3 (chi2, 3 dof).
        const Eigen::Matrix3d cov = a.poseChange->getCovariance().asEigen();
        d2 += e.dot(cov.ldlt().solve(e));
        mean += e;
    }
    EXPECT_NEAR(d2 / n, 3.0, kSigmas * std::sqrt(6.0 / n));
    EXPECT_LT(mean.norm() / n, 0.005);
}

// ------------------------------------------------------------------ determinism

TEST(Simulator, SameSeedSameBytesOtherSeedOtherData)
{
    TSimulatorOptions o = paperRun(120);
    const Simulator a(o);
    const std::string p1 = kOut + "/sim_det_1.rawlog", p2 = kOut + "/sim_det_2.rawlog";
    const std::string p3 = kOut + "/sim_det_3.rawlog";
    a.writeDataset(a.run(), p1);
    a.writeDataset(a.run(), p2);
    EXPECT_EQ(fileBytes(p1), fileBytes(p2));
    EXPECT_EQ(fileBytes(GroundTruthFile::PathFor(p1)), fileBytes(GroundTruthFile::PathFor(p2)));
    EXPECT_GT(fileBytes(p1).size(), 1000u);

    o.simulation.seed = 2;
    const Simulator b(o);
    const auto rb = b.run();
    b.writeDataset(rb, p3);
    EXPECT_NE(fileBytes(p1), fileBytes(p3));
    // The trajectory does not depend on the seed; the noise does.
    EXPECT_EQ(fileBytes(GroundTruthFile::PathFor(p1)), fileBytes(GroundTruthFile::PathFor(p3)));
    const auto ra = a.run();
    EXPECT_NE(stepOf(ra, 5).odometry->rawOdometryIncrementReading,
              stepOf(rb, 5).odometry->rawOdometryIncrementReading);
    size_t differentBeams = 0;
    for (size_t beam = 0; beam < 61; beam++)
    {
        differentBeams +=
            stepOf(ra, 5).sonar->getScanRange(beam) != stepOf(rb, 5).sonar->getScanRange(beam) ? 1
                                                                                               : 0;
    }
    EXPECT_GT(differentBeams, 0u);

    // Each component has its own stream: other detector settings leave the odometry as is.
    TSimulatorOptions c = o;
    c.detector.false_positives_per_scan = 3;
    const auto rc = Simulator(c).run();
    for (size_t k = 0; k < rb.steps; k++)
    {
        ASSERT_EQ(stepOf(rb, k).odometry->rawOdometryIncrementReading,
                  stepOf(rc, k).odometry->rawOdometryIncrementReading);
    }
}

TEST(Simulator, WrittenDatasetReadsBack)
{
    TSimulatorOptions o = paperRun(40);
    o.simulation.time_step_s = 0.1;  // timestamps that are not whole seconds
    const Simulator sim(o);
    const auto res = sim.run();
    const std::string path = kOut + "/sim_readback.rawlog";
    sim.writeDataset(res, path);

    const auto gt = GroundTruthFile::Read(GroundTruthFile::PathFor(path));
    ASSERT_EQ(gt.size(), res.groundTruth.size());
    for (size_t k = 0; k < gt.size(); k++)
    {
        EXPECT_EQ(gt[k].t, res.groundTruth[k].t);  // full precision, bit-exact
        EXPECT_EQ(gt[k].x, res.groundTruth[k].x);
        EXPECT_EQ(gt[k].y, res.groundTruth[k].y);
        EXPECT_EQ(gt[k].phi, res.groundTruth[k].phi);
    }
    mrpt::obs::CRawlog rawlog;
    ASSERT_TRUE(rawlog.loadFromRawLogFile(path));
    ASSERT_EQ(rawlog.size(), 2 * res.steps);
    for (size_t k = 0; k < res.steps; k++)
    {
        const auto sf = std::dynamic_pointer_cast<CSensoryFrame>(rawlog.getAsGeneric(2 * k + 1));
        ASSERT_TRUE(sf);
        const auto obs = sf->getObservationByClass<CObservationSemantic>();
        ASSERT_TRUE(obs);
        EXPECT_EQ(obs->detections, stepOf(res, k).semantic->detections);
        EXPECT_EQ(mrpt::Clock::toDouble(obs->timestamp), gt[k].t);
    }

    // The effective configuration reproduces the dataset.
    const auto again = TSimulatorOptions::FromConfigFile(Simulator::configPath(path));
    EXPECT_EQ(again.simulation.output_rawlog, path);
    EXPECT_EQ(again.simulation.time_step_s, 0.1);
    const std::string path2 = kOut + "/sim_readback_again.rawlog";
    const Simulator sim2(again);
    sim2.writeDataset(sim2.run(), path2);
    EXPECT_EQ(fileBytes(path), fileBytes(path2));
}

TEST(Simulator, InterruptWritesNothingAndKeepsAPreviousDataset)
{
    // A request (Ctrl-C in semloc-simulate) stops run() and writeDataset(): Interrupted, and
    // no output, temporary file or half-written dataset; a previous dataset stays as it was.
    TSimulatorOptions o = paperRun(30);
    const Simulator sim(o);
    const auto res = sim.run();
    const std::string path = kOut + "/sim_interrupt_" + std::to_string(::getpid()) + ".rawlog";
    const std::string fresh = kOut + "/sim_interrupt_new_" + std::to_string(::getpid()) + ".rawlog";
    sim.writeDataset(res, path);
    const std::string before = fileBytes(path),
                      gtBefore = fileBytes(GroundTruthFile::PathFor(path));

    TSimulatorOptions o9 = o;
    o9.simulation.seed = 9;  // other data: a rename would show
    const Simulator other(o9);
    const auto res9 = other.run();

    semloc::requestInterrupt();
    EXPECT_THROW(sim.run(), semloc::Interrupted);
    EXPECT_THROW(sim.writeDataset(res, fresh), semloc::Interrupted);
    EXPECT_THROW(other.writeDataset(res9, path), semloc::Interrupted);
    semloc::clearInterrupt();

    for (const auto& f : {fresh, GroundTruthFile::PathFor(fresh), Simulator::configPath(fresh)})
    {
        EXPECT_FALSE(std::filesystem::exists(f)) << f;
        EXPECT_FALSE(std::filesystem::exists(f + ".tmp")) << f;
    }
    EXPECT_EQ(fileBytes(path), before);
    EXPECT_EQ(fileBytes(GroundTruthFile::PathFor(path)), gtBefore);
    for (const auto& f : {path, GroundTruthFile::PathFor(path), Simulator::configPath(path)})
    {
        EXPECT_FALSE(std::filesystem::exists(f + ".tmp")) << f;
    }
    EXPECT_EQ(sim.run().steps, res.steps);  // cleared: runs again
}

// ------------------------------------------------------------------ kidnapping

TEST(Simulator, KidnappingTeleportsBehindTheOdometrysBack)
{
    TSimulatorOptions o = noiseFree();
    o.kidnapping.enabled = true;
    o.kidnapping.step = 30;
    o.kidnapping.x_m = 25;
    o.kidnapping.y_m = 25;
    o.kidnapping.phi_deg = 90;
    const auto r = Simulator(o).run();
    const auto& g = r.groundTruth;
    ASSERT_GT(r.steps, 31u);
    EXPECT_EQ(g[30].x, 25);
    EXPECT_EQ(g[30].y, 25);
    EXPECT_NEAR(g[30].phi, M_PI / 2, 1e-15);
    // The odometry of the kidnap step is the motion the vehicle would have made (on the
    // first leg, 0.5 m straight ahead); integrated odometry no longer matches the truth.
    const CPose2D inc = stepOf(r, 30).odometry->rawOdometryIncrementReading;
    EXPECT_NEAR(inc.x(), 0.5, 1e-12);
    EXPECT_NEAR(inc.y(), 0, 1e-12);
    EXPECT_NEAR(inc.phi(), 0, 1e-12);
    // The vehicle then heads from its new pose for its next waypoint (47, 4).
    EXPECT_NEAR(std::hypot(g[31].x - 25, g[31].y - 25), 0.5, 1e-12);
    EXPECT_NEAR(g[31].phi, std::atan2(4 - 25, 47 - 25), 1e-12);
    CPose2D integrated(g[0].pose());
    for (size_t k = 1; k <= 31; k++)
    {
        integrated = integrated + stepOf(r, k).odometry->rawOdometryIncrementReading;
    }
    EXPECT_GT(std::hypot(integrated.x() - g[31].x, integrated.y() - g[31].y), 5.0);
    // Observations at the kidnap step are taken at the new pose.
    const semloc::RayCaster caster(paperWorld().outlineSegments());
    const auto& scan = *stepOf(r, 30).sonar;
    EXPECT_EQ(scan.getScanRange(30), static_cast<float>(caster.cast(25, 25, g[30].phi, 20)));

    // A random free pose, drawn from the kidnapping stream.
    o.kidnapping.random_pose = true;
    const auto r1 = Simulator(o).run(), r2 = Simulator(o).run();
    EXPECT_TRUE(paperWorld().isFree(r1.groundTruth[30].x, r1.groundTruth[30].y));
    EXPECT_EQ(r1.groundTruth[30].pose(), r2.groundTruth[30].pose());
    EXPECT_NE(r1.groundTruth[30].pose(), r.groundTruth[30].pose());
}

TEST(Simulator, KidnappingErrorsNameTheKeys)
{
    TSimulatorOptions o = noiseFree();
    o.kidnapping.enabled = true;
    o.kidnapping.x_m = 12.5;  // inside the manifold
    o.kidnapping.y_m = 10.5;
    try
    {
        Simulator s(o);
        FAIL() << "a kidnap pose inside an object was accepted";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("[Kidnapping] x_m, y_m"), std::string::npos)
            << e.what();
    }
    o.kidnapping.x_m = o.kidnapping.y_m = 25;
    o.kidnapping.step = 100;
    o.simulation.max_steps = 50;
    try
    {
        Simulator(o).run();
        FAIL() << "a kidnap step after the end was accepted";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("[Kidnapping] step"), std::string::npos) << e.what();
    }
}

// ------------------------------------------------------------------ options and files

namespace
{
std::string loadError(const std::string& ini)
{
    mrpt::config::CConfigFileMemory c(ini);
    try
    {
        TSimulatorOptions o;
        o.loadFromConfigFile(c);
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(TSimulatorOptions, StrictLoadingNamesSectionAndKey)
{
    EXPECT_EQ(loadError("[Simulation]\nworld_file=" + kPaper + "\n[Sonar]\nbeam_count=5\n"), "");
    EXPECT_NE(loadError("[Sonar]\nbeam_cout=61\n").find("[Sonar] beam_cout"), std::string::npos);
    EXPECT_NE(loadError("[Odometry]\nxy_std_per_m=-0.1\n").find("[Odometry] xy_std_per_m"),
              std::string::npos);
    EXPECT_NE(loadError("[SemanticDetector]\nrange_noise_std_m=-1\n")
                  .find("[SemanticDetector] range_noise_std_m"),
              std::string::npos);
    EXPECT_NE(loadError("[SemanticDetector]\np_range_outlier=-0.5\n").find("p_range_outlier"),
              std::string::npos);
    EXPECT_NE(loadError("[SemanticDetector]\np_confusion=1.5\n").find("p_confusion"),
              std::string::npos);
    EXPECT_NE(loadError("[Kidnapping]\nstep=0\n").find("[Kidnapping] step"), std::string::npos);
    const auto missing = loadError("[Simulation]\nworld_file=/no/such/world.yaml\n");
    EXPECT_NE(missing.find("[Simulation] world_file"), std::string::npos) << missing;
    EXPECT_NE(missing.find("/no/such/world.yaml"), std::string::npos) << missing;
    EXPECT_NE(loadError("[Simulation]\nseed=-3\n").find("[Simulation] seed"), std::string::npos);
}

TEST(TSimulatorOptions, SaveWritesEveryKeyAndReadsBackIdentically)
{
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.simulation.seed = 123456789;
    o.simulation.time_step_s = 0.1 + 0.2;  // not a short decimal
    o.odometry.xy_std_per_m = 1.0 / 3;
    o.sonar.beam_count = 181;
    o.detector.report_ids = true;
    o.detector.fov_deg = 1e-5;
    o.kidnapping.enabled = true;
    o.beacons.enabled = true;
    o.beacons.range_std_m = 0.1 + 0.7;  // not a short decimal
    // A path with "//": MRPT takes no inline comment after such a value, so none is written.
    o.simulation.output_rawlog = "runs//dataset.rawlog";
    mrpt::config::CConfigFileMemory c;
    o.saveToConfigFile(c);
    for (const auto& [section, opts] :
         std::vector<std::pair<std::string, const mrpt::config::CLoadableOptions*>>{
             {"Simulation", &o.simulation},
             {"Odometry", &o.odometry},
             {"Sonar", &o.sonar},
             {"SemanticDetector", &o.detector},
             {"Kidnapping", &o.kidnapping},
             {"BeaconRanging", &o.beacons}})
    {
        std::vector<std::string> keys;
        c.getAllKeys(section, keys);
        EXPECT_EQ(keys.size(), semloc::config::keysOf(*opts).size()) << section;
    }
    TSimulatorOptions back;
    back.loadFromConfigFile(mrpt::config::CConfigFileMemory(c.getContent()));  // as from a file
    mrpt::config::CConfigFileMemory c2;
    back.saveToConfigFile(c2);
    EXPECT_EQ(c.getContent(), c2.getContent());
    EXPECT_EQ(back.simulation.time_step_s, 0.1 + 0.2);
    EXPECT_EQ(back.odometry.xy_std_per_m, 1.0 / 3);
    EXPECT_EQ(back.beacons.range_std_m, 0.1 + 0.7);
    EXPECT_EQ(back.simulation.seed, 123456789u);
    EXPECT_EQ(back.simulation.output_rawlog, "runs//dataset.rawlog");
}

TEST(TSimulatorOptions, ExampleIniLoadsWithTheDocumentedDefaults)
{
    const auto o =
        TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini");
    const TSimulatorOptions d;
    mrpt::config::CConfigFileMemory a, b;
    TSimulatorOptions withWorld = d;
    withWorld.simulation.world_file = o.simulation.world_file;
    o.saveToConfigFile(a);
    withWorld.saveToConfigFile(b);
    EXPECT_EQ(a.getContent(), b.getContent())
        << "config/simulate/simulate.ini and the defaults differ";
    EXPECT_TRUE(std::filesystem::equivalent(o.simulation.world_file, kPaper));
}

TEST(Simulator, FailedWriteLeavesNoFileBehind)
{
    TSimulatorOptions o = paperRun(5);
    const Simulator sim(o);
    const auto res = sim.run();
    EXPECT_THROW(sim.writeDataset(res, kOut + "/no_such_dir/x.rawlog"), std::exception);

    // The ground-truth name is taken by a directory: the rawlog, already renamed into
    // place, is removed again, and no temporary remains.
    const std::string path = kOut + "/sim_blocked.rawlog";
    const std::string gt = GroundTruthFile::PathFor(path);
    std::filesystem::remove_all(gt);
    std::filesystem::create_directories(gt + "/occupied");
    EXPECT_THROW(sim.writeDataset(res, path), std::exception);
    for (const auto& f : {path, path + ".tmp", gt + ".tmp", Simulator::configPath(path),
                          Simulator::configPath(path) + ".tmp"})
    {
        EXPECT_FALSE(std::filesystem::exists(f)) << f;
    }
    std::filesystem::remove_all(gt);
}

TEST(Simulator, OutputNames)
{
    EXPECT_EQ(GroundTruthFile::PathFor("/d/run.rawlog"), "/d/run_gt.txt");
    EXPECT_EQ(Simulator::configPath("/d/run.rawlog"), "/d/run.ini");
    EXPECT_EQ(GroundTruthFile::PathFor("run.rawlog"), "run_gt.txt");
    EXPECT_EQ(Simulator::configPath("a.b/run"), "a.b/run.ini");
}

TEST(Simulator, NeedsATrajectory)
{
    const World w = World::FromText(
        "name: empty\nbounds: {x_min: 0, x_max: 10, y_min: 0, y_max: 10}\nobjects: []\n", "e");
    EXPECT_THROW(Simulator(w, TSimulatorOptions()), std::exception);
}

TEST(Simulator, HeadingDriftBiasesEveryOdometryReadingOnly)
{
    // Noise-free odometry with a drift of 15 deg/min: each 1 s increment's heading is the
    // true one plus 0.25 deg; the action's Gaussian (what the filter knows) stays the model's.
    auto o = noiseFree();
    o.simulation.max_steps = 120;
    o.odometry.heading_drift_deg_per_min = 15;
    const auto r = Simulator(o).run();
    auto plain = noiseFree();
    plain.simulation.max_steps = 120;
    const auto p = Simulator(plain).run();
    for (size_t k = 1; k < r.steps; k++)
    {
        const auto& drifted = stepOf(r, k).odometry->rawOdometryIncrementReading;
        const auto& exact = stepOf(p, k).odometry->rawOdometryIncrementReading;
        ASSERT_NEAR(mrpt::math::wrapToPi(drifted.phi() - exact.phi()), mrpt::DEG2RAD(0.25), 1e-12)
            << "step " << k;
        ASSERT_NEAR(drifted.x(), exact.x(), 1e-12);
        ASSERT_EQ(stepOf(r, k).odometry->poseChange->getCovariance(),
                  stepOf(p, k).odometry->poseChange->getCovariance());
    }
    // The ground truth and the other sensors do not change.
    EXPECT_EQ(r.groundTruth.back().x, p.groundTruth.back().x);
    EXPECT_EQ(stepOf(r, 60).semantic->detections.size(), stepOf(p, 60).semantic->detections.size());
}

TEST(Simulator, DetectorSilencesLastFromTheShortestToTheLongest)
{
    // Twelve false detections per scan: a scan is empty only inside a silence (e^-12).
    auto o = paperRun(0);
    o.detector.false_positives_per_scan = 12;
    o.detector.gap_every_s = 30;
    o.detector.gap_min_s = 20;
    o.detector.gap_max_s = 40;
    const auto r = Simulator(o).run();
    std::vector<size_t> silences;  // lengths of the runs of empty scans [steps of 1 s]
    size_t run = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        if (stepOf(r, k).semantic->detections.empty())
        {
            run++;
        }
        else if (run > 0)
        {
            silences.push_back(run);
            run = 0;
        }
    }
    ASSERT_GE(silences.size(), 3u);  // 431 s at one silence about every 60 s
    for (const size_t len : silences)
    {
        EXPECT_GE(len, 20u);
        EXPECT_LE(len, 41u);
    }
    // The same seed gives the same silences; none without gap_every_s; the other steps
    // keep their detections.
    const auto again = Simulator(o).run();
    auto none = o;
    none.detector.gap_every_s = 0;
    const auto loud = Simulator(none).run();
    size_t emptyLoud = 0;
    for (size_t k = 0; k < r.steps; k++)
    {
        EXPECT_EQ(stepOf(again, k).semantic->detections.size(),
                  stepOf(r, k).semantic->detections.size());
        emptyLoud += stepOf(loud, k).semantic->detections.empty() ? 1 : 0;
        if (!stepOf(r, k).semantic->detections.empty())
        {
            EXPECT_EQ(stepOf(r, k).semantic->detections.size(),
                      stepOf(loud, k).semantic->detections.size());
        }
    }
    EXPECT_EQ(emptyLoud, 0u);
}

TEST(Simulator, DistractorsAreUnmappedObjectsMovingUnderTheWorldsLabels)
{
    // Noise free with ids: a detection without an id is a distractor, placed exactly.
    auto o = noiseFree();
    o.simulation.max_steps = 300;
    o.detector.distractors = 1;
    o.detector.distractor_speed_mps = 0.5;
    const auto r = Simulator(o).run();
    auto quiet = o;
    quiet.detector.distractors = 0;
    const auto none = Simulator(quiet).run();
    const World w = World::FromFile(kPaper);
    std::set<std::string> labels;
    for (const auto& obj : w.objects)
    {
        labels.insert(obj.label);
    }
    std::vector<std::pair<size_t, mrpt::math::TPoint2D>> seen;  // step, where
    std::set<std::string> distractorLabels;
    for (size_t k = 0; k < r.steps; k++)
    {
        const auto s = stepOf(r, k);
        const auto plain = stepOf(none, k);
        size_t mapped = 0;
        for (const auto& d : s.semantic->detections)
        {
            if (d.object_id >= 0)
            {
                // The map objects' detections are those without distractors.
                ASSERT_LT(mapped, plain.semantic->detections.size()) << k;
                EXPECT_EQ(d.object_id, plain.semantic->detections[mapped].object_id) << k;
                EXPECT_EQ(d.range_m, plain.semantic->detections[mapped].range_m) << k;
                mapped++;
                continue;
            }
            distractorLabels.insert(d.label);
            const auto& gt = r.groundTruth[k];
            const mrpt::poses::CPose3D sensor =
                mrpt::poses::CPose3D(mrpt::math::TPose3D(gt.pose())) + s.semantic->sensorPose;
            const auto p = sensor + mrpt::poses::CPoint3D(d.range_m * std::cos(d.bearing_rad),
                                                          d.range_m * std::sin(d.bearing_rad), 0);
            EXPECT_TRUE(w.bounds.contains(p.x(), p.y())) << k;
            seen.emplace_back(k, mrpt::math::TPoint2D(p.x(), p.y()));
        }
        EXPECT_EQ(mapped, plain.semantic->detections.size()) << k;
    }
    ASSERT_GE(seen.size(), 5u);  // seen on the way at least a few times
    ASSERT_EQ(distractorLabels.size(), 1u);
    EXPECT_EQ(labels.count(*distractorLabels.begin()), 1u);
    // It moves at 0.5 m/s: never farther than that per second between two sightings, and
    // exactly that between consecutive steps away from the bounds.
    size_t consecutive = 0;
    for (size_t i = 1; i < seen.size(); i++)
    {
        const double dist = std::hypot(seen[i].second.x - seen[i - 1].second.x,
                                       seen[i].second.y - seen[i - 1].second.y);
        const double dt =
            static_cast<double>(seen[i].first - seen[i - 1].first) * o.simulation.time_step_s;
        EXPECT_LE(dist, 0.5 * dt + 1e-6) << i;
        if (seen[i].first == seen[i - 1].first + 1 && std::abs(dist - 0.5 * dt) < 1e-6)
        {
            consecutive++;
        }
    }
    EXPECT_GE(consecutive, 3u);
}

TEST(WorldChanges, ObjectsMovedGoneAndNewAsAsked)
{
    const World w = World::FromFile(kPaper);
    const size_t n = w.objects.size();
    ASSERT_GE(n, 10u);
    // Nothing asked: the same world.
    EXPECT_EQ(semloc::changeWorld(w, {}).objects.size(), n);
    EXPECT_FALSE(semloc::TWorldChanges{}.any());

    // Moved: each object and its outline by one offset, about sigma along each axis.
    semloc::TWorldChanges moved;
    moved.shift_sigma_m = 0.5;
    const World m = semloc::changeWorld(w, moved);
    ASSERT_EQ(m.objects.size(), n);
    double sum2 = 0;
    for (size_t i = 0; i < n; i++)
    {
        const double dx = m.objects[i].center.x - w.objects[i].center.x;
        const double dy = m.objects[i].center.y - w.objects[i].center.y;
        EXPECT_EQ(m.objects[i].id, w.objects[i].id);
        for (size_t k = 0; k < w.objects[i].points.size(); k++)
        {
            EXPECT_NEAR(m.objects[i].points[k].x - w.objects[i].points[k].x, dx, 1e-12);
            EXPECT_NEAR(m.objects[i].points[k].y - w.objects[i].points[k].y, dy, 1e-12);
        }
        sum2 += dx * dx + dy * dy;
    }
    const double rms = std::sqrt(sum2 / (2.0 * static_cast<double>(n)));
    EXPECT_GT(rms, 0.25);
    EXPECT_LT(rms, 0.9);

    // Gone: round(share n) of them, the others as they were; new ones with new ids, labels
    // and shapes of the world's, in its free space.
    semloc::TWorldChanges changed;
    changed.removed_share = 0.2;
    changed.added = 5;
    const World c = semloc::changeWorld(w, changed);
    const auto gone = static_cast<size_t>(std::lround(0.2 * static_cast<double>(n)));
    ASSERT_EQ(c.objects.size(), n - gone + 5);
    int maxId = 0;
    std::map<int, const semloc::WorldObject*> byId;
    for (const auto& o : w.objects)
    {
        maxId = std::max(maxId, o.id);
        byId[o.id] = &o;
    }
    std::set<int> ids;
    for (size_t i = 0; i < c.objects.size(); i++)
    {
        const auto& o = c.objects[i];
        EXPECT_TRUE(ids.insert(o.id).second) << o.id;
        if (i < n - gone)
        {
            ASSERT_EQ(byId.count(o.id), 1u);
            EXPECT_EQ(o.center.x, byId[o.id]->center.x);
            continue;
        }
        EXPECT_GT(o.id, maxId);
        EXPECT_TRUE(std::any_of(w.objects.begin(), w.objects.end(),
                                [&](const auto& k)
                                { return k.label == o.label && k.shape == o.shape; }));
        EXPECT_TRUE(w.bounds.contains(o.center.x, o.center.y));
    }
    // One changed world per seed.
    const World again = semloc::changeWorld(w, changed);
    changed.seed = 2;
    const World other = semloc::changeWorld(w, changed);
    EXPECT_EQ(again.objects.back().center.x, c.objects.back().center.x);
    EXPECT_NE(other.objects.back().center.x, c.objects.back().center.x);
}

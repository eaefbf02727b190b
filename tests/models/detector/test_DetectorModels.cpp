/* semloc tests — the detector models of the water column (side-scan, forward-looking sonar,
 * bearing-only camera) against a plain reference of their likelihood, their slant ranges and
 * depth readings, their ini sections, and the filter driven by them, the same for 1 and 2
 * threads. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/SensoryFrameLikelihood.h>
#include <semloc/models/SensorModelRegistry.h>
#include <semloc/models/camera/CBearingCameraMap.h>
#include <semloc/models/forwardsonar/CForwardSonarMap.h>
#include <semloc/models/sidescan/CSideScanMap.h>
#include <semloc/observation/CObservationDepth.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace
{
using mrpt::math::TPose2D;
using mrpt::poses::CPose3D;
using semloc::CObjectDetectorMap;
using semloc::CObservationDepth;
using semloc::CObservationSemantic;
using semloc::TSemanticDetection;

constexpr double kDeg = M_PI / 180;

/** A seabed at 30 m: boulders and tyres alike, a wreck. */
semloc::World seabed()
{
    semloc::World w;
    w.bounds = {0, 100, 0, 100};
    const char* labels[] = {"boulder", "tyre", "wreck"};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(5, 95);
    for (int i = 0; i < 40; i++)
    {
        semloc::WorldObject o;
        o.id = i + 1;
        o.label = labels[i % 7 == 0 ? 2 : i % 2];
        o.center = {u(rng), u(rng)};
        o.z = -30 + 0.5 * (i % 3);
        w.objects.push_back(o);
    }
    return w;
}

/** The reference: the documented likelihood, one object at a time, the sensor placed by MRPT's
 *  3D pose composition, the along-track angle by asin, products in long double. */
struct Reference
{
    enum class Kind
    {
        SideScan,
        Forward,
        Camera
    } kind = Kind::SideScan;
    CObjectDetectorMap::TDetectorParam p;
    double beam_deg = 0, nadir_m = 0;
    semloc::TFanParam fan;

    long double rangeDensity(double d) const
    {
        const long double g = std::exp(-0.5L * (d / p.sigma_range_m) * (d / p.sigma_range_m)) /
                              (std::sqrt(2 * M_PIl) * p.sigma_range_m);
        return (1 - p.p_range_outlier) * g + p.p_range_outlier / (p.max_range_m - p.min_range_m);
    }
    static long double gauss(double d, double s)
    {
        return std::exp(-0.5L * (d / s) * (d / s)) / (std::sqrt(2 * M_PIl) * s);
    }

    /** An object the sensor sees: its index in the world, range, bearing and side. */
    struct Seen
    {
        size_t index;
        double range, bearing;
        int side;
    };
    std::vector<Seen> seen(const semloc::World& world, const CObservationSemantic& obs,
                           double depth, const TPose2D& pose) const
    {
        const double fov = fan.fov_deg * kDeg;
        const CPose3D sensor = CPose3D(pose.x, pose.y, -depth, pose.phi, 0, 0) + obs.sensorPose;
        std::vector<Seen> out;
        for (size_t k = 0; k < world.objects.size(); k++)
        {
            const auto& o = world.objects[k];
            double u, w, dz;
            sensor.inverseComposePoint(o.center.x, o.center.y, o.z, u, w, dz);
            const double ground = std::hypot(u, w), slant = std::sqrt(u * u + w * w + dz * dz);
            const double r = p.slant ? slant : ground;
            bool in = r >= p.min_range_m && r <= p.max_range_m;
            const double bearing = std::atan2(w, u);
            if (kind == Kind::SideScan)
            {
                in = in && std::abs(w) >= nadir_m &&
                     std::abs(std::asin(u / slant)) <= 0.5 * beam_deg * kDeg;
            }
            else
            {
                in = in && std::abs(bearing) <= 0.5 * fov &&
                     (fan.vertical_fov_deg >= 180 ||
                      std::abs(std::atan2(-dz, ground) - fan.tilt_deg * kDeg) <=
                          0.5 * fan.vertical_fov_deg * kDeg);
            }
            if (in)
            {
                out.push_back({k, r, bearing, kind == Kind::SideScan ? (w >= 0 ? 1 : -1) : 0});
            }
        }
        return out;
    }

    double operator()(const semloc::World& world, const CObservationSemantic& obs, double depth,
                      const TPose2D& pose) const
    {
        std::vector<std::string> labels;
        for (const auto& o : world.objects)
        {
            if (std::find(labels.begin(), labels.end(), o.label) == labels.end())
            {
                labels.push_back(o.label);
            }
        }
        const double fov = fan.fov_deg * kDeg;
        const double volume = kind == Kind::SideScan  ? 2 * (p.max_range_m - p.min_range_m)
                              : kind == Kind::Forward ? (p.max_range_m - p.min_range_m) * fov
                                                      : fov;
        const long double kappa = p.clutter_per_scan / (volume * labels.size());
        std::vector<TSemanticDetection> dets;
        for (const auto& d : obs.detections)
        {
            const bool bearingOk =
                std::isfinite(d.bearing_rad) &&
                (kind == Kind::SideScan
                     ? d.bearing_rad != 0
                     : std::abs(std::remainder(d.bearing_rad, 2 * M_PI)) <= 0.5 * fov + 1e-9);
            const bool rangeOk =
                kind == Kind::Camera || (d.range_m >= p.min_range_m && d.range_m <= p.max_range_m);
            if (!d.label.empty() && bearingOk && rangeOk)
            {
                dets.push_back(d);
            }
        }
        std::vector<long double> acc(dets.size(), kappa);
        long double missed = 1;
        for (const auto& v : seen(world, obs, depth, pose))
        {
            const auto& o = world.objects[v.index];
            const double r = v.range, bearing = v.bearing;
            const double pd = p.p_detect_near +
                              (p.p_detect_far - p.p_detect_near) * std::min(r / p.max_range_m, 1.0);
            missed *= 1 - pd;
            for (size_t j = 0; j < dets.size(); j++)
            {
                if (dets[j].label != o.label)
                {
                    continue;
                }
                long double g = 0;
                const double db = std::remainder(dets[j].bearing_rad - bearing, 2 * M_PI);
                if (kind == Kind::SideScan)
                {
                    g = (dets[j].bearing_rad > 0) == (v.side > 0)
                            ? rangeDensity(dets[j].range_m - r)
                            : 0;
                }
                else if (kind == Kind::Forward)
                {
                    g = rangeDensity(dets[j].range_m - r) * gauss(db, fan.sigma_bearing_deg * kDeg);
                }
                else
                {
                    g = gauss(db, fan.sigma_bearing_deg * kDeg);
                }
                acc[j] += pd / (1 - pd) * g;
            }
        }
        long double lik = std::exp(-static_cast<long double>(p.clutter_per_scan)) * missed;
        long double logLik = std::log(lik);
        for (const auto& a : acc)
        {
            logLik += std::log(a);
        }
        return static_cast<double>(logLik);
    }
};

/** A scan of `sensorLabel` from the map's own world seen at `truth` (depth `depth`): every
 *  object the reference sees, measured with the model's noise, plus a label the map does not
 *  know, an invalid detection, and a false alarm. */
std::shared_ptr<CObservationSemantic> scanAt(const Reference& ref, const semloc::World& world,
                                             const TPose2D& truth, double depth, std::mt19937& rng,
                                             bool extras = true)
{
    auto obs = CObservationSemantic::Create();
    obs->sensorLabel = "sensor";
    obs->sensorPose = CPose3D(0.4, -0.1, -0.3, ref.kind == Reference::Kind::Camera ? 0.2 : 0, 0, 0);
    std::normal_distribution<double> n(0, 1);
    const CPose3D sensor = CPose3D(truth.x, truth.y, -depth, truth.phi, 0, 0) + obs->sensorPose;
    for (const auto& o : world.objects)
    {
        double u, w, dz;
        sensor.inverseComposePoint(o.center.x, o.center.y, o.z, u, w, dz);
        const double slant = std::sqrt(u * u + w * w + dz * dz);
        const double bearing = std::atan2(w, u);
        const bool seen = slant <= ref.p.max_range_m &&
                          (ref.kind == Reference::Kind::SideScan
                               ? std::abs(w) >= ref.nadir_m &&
                                     std::abs(std::asin(u / slant)) <= 0.5 * ref.beam_deg * kDeg
                               : std::abs(bearing) <= 0.5 * ref.fan.fov_deg * kDeg);
        if (seen)
        {
            TSemanticDetection d;
            d.label = o.label;
            d.range_m = std::max(0.0, slant + ref.p.sigma_range_m * n(rng));
            d.bearing_rad = ref.kind == Reference::Kind::SideScan
                                ? (w >= 0 ? M_PI / 2 : -M_PI / 2)
                                : bearing + ref.fan.sigma_bearing_deg * kDeg * n(rng);
            if (d.range_m <= ref.p.max_range_m)
            {
                obs->detections.push_back(d);
            }
        }
    }
    if (!extras)
    {
        return obs;
    }
    TSemanticDetection alien;
    alien.label = "anchor";
    alien.range_m = 10;
    alien.bearing_rad = 0.1;
    obs->detections.push_back(alien);
    TSemanticDetection bad = alien;
    bad.label = "boulder";
    bad.range_m = std::nan("");
    bad.bearing_rad = std::nan("");
    obs->detections.push_back(bad);
    TSemanticDetection clutter = alien;
    clutter.label = "tyre";
    clutter.range_m = 12;
    clutter.bearing_rad = -0.2;
    obs->detections.push_back(clutter);
    return obs;
}

std::shared_ptr<CObservationDepth> depthReading(double d)
{
    auto o = CObservationDepth::Create();
    o->depth_m = d;
    o->altitude_m = 30 - d;
    return o;
}

/** The kind's map with the reference's options. */
std::shared_ptr<CObjectDetectorMap> makeMap(Reference& ref, const semloc::World& world)
{
    std::shared_ptr<CObjectDetectorMap> map;
    if (ref.kind == Reference::Kind::SideScan)
    {
        auto m = std::make_shared<semloc::CSideScanMap>();
        m->likelihoodOptions.detector = ref.p;
        m->likelihoodOptions.beam_width_deg = ref.beam_deg;
        m->likelihoodOptions.nadir_gap_m = ref.nadir_m;
        map = m;
    }
    else if (ref.kind == Reference::Kind::Forward)
    {
        auto m = std::make_shared<semloc::CForwardSonarMap>();
        m->likelihoodOptions.detector = ref.p;
        m->likelihoodOptions.fan = ref.fan;
        map = m;
    }
    else
    {
        auto m = std::make_shared<semloc::CBearingCameraMap>();
        m->likelihoodOptions.detector = ref.p;
        m->likelihoodOptions.fan = ref.fan;
        map = m;
    }
    map->loadFromWorld(world);
    return map;
}

Reference sideScanReference()
{
    Reference ref;
    ref.kind = Reference::Kind::SideScan;
    ref.p.sensor_label = "sensor";
    ref.p.max_range_m = 40;
    ref.p.min_range_m = 1;
    ref.p.p_detect_near = 0.9;
    ref.p.p_detect_far = 0.4;
    ref.p.sigma_range_m = 0.4;
    ref.p.p_range_outlier = 0.05;
    ref.p.clutter_per_scan = 0.3;
    ref.beam_deg = 6;
    ref.nadir_m = 3;
    return ref;
}
Reference forwardReference()
{
    Reference ref = sideScanReference();
    ref.kind = Reference::Kind::Forward;
    ref.fan.fov_deg = 120;
    ref.fan.sigma_bearing_deg = 1.5;
    ref.fan.tilt_deg = 20;
    ref.fan.vertical_fov_deg = 60;
    return ref;
}
Reference cameraReference()
{
    Reference ref = forwardReference();
    ref.kind = Reference::Kind::Camera;
    ref.p.max_range_m = 15;
    ref.p.p_range_outlier = 0;
    ref.fan.fov_deg = 70;
    ref.fan.vertical_fov_deg = 180;
    return ref;
}

/** Every kind, slant and horizontal: the batch, MRPT's per-pose call and the reference agree
 *  at poses near and far from the truth. */
void checkAgainstReference(Reference ref)
{
    const auto world = seabed();
    for (const bool slant : {true, false})
    {
        ref.p.slant = slant;
        auto map = makeMap(ref, world);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(10, 90), a(-M_PI, M_PI), small(-3, 3);
        size_t seenAny = 0;
        for (int k = 0; k < 40; k++)
        {
            const TPose2D truth(u(rng), u(rng), a(rng));
            const double depth = 20 + 0.2 * k;
            const auto obs = scanAt(ref, world, truth, depth, rng);
            (void)map->prepareObservation(*depthReading(depth));
            ASSERT_DOUBLE_EQ(map->vehicleDepth(), depth);
            const auto prepared = map->prepareObservation(*obs);
            ASSERT_TRUE(prepared);
            std::vector<TPose2D> poses = {truth};
            for (int i = 0; i < 8; i++)
            {
                poses.emplace_back(truth.x + small(rng), truth.y + small(rng),
                                   truth.phi + 0.1 * small(rng));
            }
            std::vector<double> out(poses.size());
            prepared->logLikelihoods(poses.data(), poses.size(), out.data());
            for (size_t i = 0; i < poses.size(); i++)
            {
                const double want = ref(world, *obs, depth, poses[i]);
                ASSERT_TRUE(std::isfinite(out[i]));
                EXPECT_NEAR(out[i], want, 1e-9 * std::max(1.0, std::abs(want)))
                    << "kind " << static_cast<int>(ref.kind) << " slant " << slant << " scan " << k
                    << " pose " << i;
                const double mrpt = map->computeObservationLikelihood(
                    *obs, CPose3D(poses[i].x, poses[i].y, 0, poses[i].phi, 0, 0));
                // MRPT's pose holds the heading as a rotation matrix: its yaw within an ulp.
                EXPECT_NEAR(mrpt, out[i], 1e-9 * std::max(1.0, std::abs(want)));
                // What calibration matches against: the objects the reference sees.
                const auto view = map->inView(map->scan(*obs), poses[i]);
                const auto refView = ref.seen(world, *obs, depth, poses[i]);
                ASSERT_EQ(view.size(), refView.size()) << "scan " << k << " pose " << i;
                for (size_t v = 0; v < view.size(); v++)
                {
                    EXPECT_EQ(view[v].object, refView[v].index);
                    EXPECT_NEAR(view[v].range_m, refView[v].range, 1e-9);
                    EXPECT_EQ(view[v].side, refView[v].side);
                    if (map->measuresBearing())
                    {
                        EXPECT_NEAR(view[v].bearing_rad, refView[v].bearing, 1e-9);
                    }
                }
            }
            seenAny += obs->detections.size() > 3 ? 1 : 0;
        }
        EXPECT_GT(seenAny, 10u) << "the scans must see objects for the check to mean anything";
    }
}

TEST(DetectorModels, SideScanMatchesTheReference)
{
    checkAgainstReference(sideScanReference());
}
TEST(DetectorModels, ForwardSonarMatchesTheReference)
{
    checkAgainstReference(forwardReference());
}
TEST(DetectorModels, CameraMatchesTheReference)
{
    checkAgainstReference(cameraReference());
}

/** A plan counts what it refused and what the map does not know, and gives the value with
 *  nothing in view. */
TEST(DetectorModels, PlanCountsAndValueWithoutObjects)
{
    auto ref = sideScanReference();
    const auto world = seabed();
    auto map = makeMap(ref, world);
    std::mt19937 rng(1);
    const auto obs = scanAt(ref, world, TPose2D(50, 50, 0), 25, rng);
    const auto plan = map->plan(*obs);
    EXPECT_TRUE(plan.checked);
    EXPECT_EQ(plan.invalid, 1u);
    EXPECT_EQ(plan.unknown, 1u);
    EXPECT_EQ(plan.readingsWithoutMap, obs->detections.size() - 1);
    // Far outside the seabed nothing is in view: the value is the plan's, at any pose.
    const TPose2D away(1000, 1000, 0.3);
    double out = 0;
    map->logLikelihoods(*obs, &away, 1, &out);
    EXPECT_NEAR(out, plan.logLikWithoutMap, 1e-12);
    EXPECT_TRUE(map->uses(*depthReading(3)));
    auto other = CObservationSemantic::Create();
    other->sensorLabel = "camera";
    EXPECT_FALSE(map->uses(*other));
}

/** At 25 m depth over a seabed at 30 m, a side-scan's slant ranges read as horizontal put the
 *  vehicle metres off across track: the slant model prefers the truth, the ablation a pose
 *  displaced towards the objects. */
TEST(DetectorModels, SlantRangesNeedTheDepth)
{
    auto ref = sideScanReference();
    ref.p.p_range_outlier = 0;
    semloc::World world;
    world.bounds = {0, 100, 0, 100};
    semloc::WorldObject o;
    o.id = 1;
    o.label = "boulder";
    o.center = {50, 58};
    o.z = -30;
    world.objects.push_back(o);
    auto slant = makeMap(ref, world);
    ref.p.slant = false;
    auto horizontal = makeMap(ref, world);
    auto obs = CObservationSemantic::Create();
    obs->sensorLabel = "sensor";
    TSemanticDetection d;
    d.label = "boulder";
    d.range_m = std::hypot(8.0, 5.0);  // 8 m across track, 5 m below
    d.bearing_rad = M_PI / 2;
    obs->detections.push_back(d);
    const auto depth = depthReading(25);
    (void)slant->prepareObservation(*depth);
    (void)horizontal->prepareObservation(*depth);
    std::vector<TPose2D> poses;
    for (double y = 45; y <= 55; y += 0.05)
    {
        poses.emplace_back(50, y, 0);
    }
    std::vector<double> ls(poses.size()), lh(poses.size());
    slant->logLikelihoods(*obs, poses.data(), poses.size(), ls.data());
    horizontal->logLikelihoods(*obs, poses.data(), poses.size(), lh.data());
    const auto best = [&](const std::vector<double>& l)
    { return poses[std::max_element(l.begin(), l.end()) - l.begin()].y; };
    EXPECT_NEAR(best(ls), 50, 0.06);
    EXPECT_NEAR(best(lh), 58 - d.range_m, 0.06);
    // Without a depth reading the vehicle is at z = 0: the same range is 30 m of slant.
    auto fresh = makeMap(ref, world);
    EXPECT_EQ(fresh->vehicleDepth(), 0);
}

/** A frame's depth reading applies to the detections after it, in the filter's evaluation and
 *  in MRPT's per-pose sum over the frame alike. */
TEST(DetectorModels, FrameOrderOfTheDepthReading)
{
    auto ref = forwardReference();
    const auto world = seabed();
    auto map = makeMap(ref, world);
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(map);
    std::mt19937 rng(5);
    const TPose2D truth(40, 40, 0.5);
    mrpt::obs::CSensoryFrame sf;
    sf.insert(depthReading(22));
    sf.insert(scanAt(ref, world, truth, 22, rng));
    semloc::SensoryFrameLikelihood lik(*multi);
    semloc::ParallelExecutor executor(1);
    std::vector<TPose2D> poses = {truth, TPose2D(41, 39, 0.4), TPose2D(38, 42, 0.6)};
    std::vector<double> out(poses.size());
    (void)map->prepareObservation(*depthReading(0));  // a stale reading before the frame
    lik.evaluate(sf, poses.data(), poses.size(), out.data(), executor);
    for (size_t i = 0; i < poses.size(); i++)
    {
        (void)map->prepareObservation(*depthReading(0));
        const double mrpt = multi->computeObservationsLikelihood(
            sf, CPose3D(poses[i].x, poses[i].y, 0, poses[i].phi, 0, 0));
        // MRPT's CMonteCarloLocalization2D adds the frame's sum to 1 (SensoryFrameLikelihood
        // does the same): compare the sums.
        EXPECT_NEAR(out[i], 1 + mrpt, 1e-9 * std::abs(mrpt)) << i;
        EXPECT_NEAR(out[i] - 1,
                    ref(world, *sf.getObservationByClass<CObservationSemantic>(), 22, poses[i]),
                    1e-9 * std::abs(mrpt));
    }
}

mrpt::config::CConfigFileMemory iniOf(const std::string& text)
{
    mrpt::config::CConfigFileMemory ini;
    ini.setContent(text);
    return ini;
}

std::string loadError(const std::string& text)
{
    mrpt::maps::TSetOfMetricMapInitializers inits;
    try
    {
        inits.loadFromConfigFile(iniOf(text), "MetricMap");
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}

/** Each kind is created by name, its section read strictly, its options written back. */
TEST(DetectorModels, CreatedByNameFromAnIni)
{
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(iniOf("[MetricMap]\nsideScanMap_count=1\nforwardSonarMap_count=1\n"
                                   "bearingCameraMap_count=1\n"
                                   "[MetricMap_sideScanMap_00_likelihoodOpts]\n"
                                   "sensor_label=sss\nbeam_width_deg=3\nrange_kind=horizontal\n"
                                   "[MetricMap_bearingCameraMap_00_likelihoodOpts]\nfov_deg=50\n"),
                             "MetricMap");
    mrpt::maps::CMultiMetricMap multi(inits);
    ASSERT_EQ(multi.maps.size(), 3u);
    const auto find = [&](auto* tag)
    {
        using T = std::remove_pointer_t<decltype(tag)>;
        for (const auto& m : multi.maps)
        {
            if (const auto* t = dynamic_cast<const T*>(m.get()))
            {
                EXPECT_NE(semloc::SensorModelRegistry::of(*m), nullptr);
                return t;
            }
        }
        return static_cast<const T*>(nullptr);
    };
    const auto* sss = find(static_cast<semloc::CSideScanMap*>(nullptr));
    ASSERT_NE(sss, nullptr);
    EXPECT_EQ(sss->likelihoodOptions.detector.sensor_label, "sss");
    EXPECT_EQ(sss->likelihoodOptions.beam_width_deg, 3);
    EXPECT_FALSE(sss->likelihoodOptions.detector.slant);
    EXPECT_NE(find(static_cast<semloc::CForwardSonarMap*>(nullptr)), nullptr);
    const auto* cam = find(static_cast<semloc::CBearingCameraMap*>(nullptr));
    ASSERT_NE(cam, nullptr);
    EXPECT_EQ(cam->likelihoodOptions.fan.fov_deg, 50);

    const std::string head =
        "[MetricMap]\nsideScanMap_count=1\n[MetricMap_sideScanMap_00_likelihoodOpts]\n";
    EXPECT_NE(loadError(head + "fov_deg=30\n").find("fov_deg"), std::string::npos)
        << "a camera's key is not a side-scan's";
    EXPECT_NE(loadError(head + "range_kind=diagonal\n").find("range_kind"), std::string::npos);
    EXPECT_NE(loadError(head + "min_range_m=60\n").find("min_range_m"), std::string::npos);
    EXPECT_NE(loadError(head + "p_detect_near=1\n").find("p_detect_near"), std::string::npos);
    EXPECT_NE(loadError(head + "clutter_per_scan=nan\n").find("clutter_per_scan"),
              std::string::npos);
    EXPECT_NE(loadError("[MetricMap]\nbearingCameraMap_count=1\n"
                        "[MetricMap_bearingCameraMap_00_likelihoodOpts]\nsigma_range_m=1\n")
                  .find("sigma_range_m"),
              std::string::npos)
        << "a camera measures no range";
    EXPECT_NE(loadError("[MetricMap]\nforwardSonarMap_count=1\n"
                        "[MetricMap_forwardSonarMap_00_creationOpts]\nworld=x.yaml\n")
                  .find("world"),
              std::string::npos);

    mrpt::config::CConfigFileMemory written;
    sss->likelihoodOptions.saveToConfigFile(written, "s");
    std::string text;
    written.getContent(text);
    semloc::CSideScanMap::TLikelihoodOptions back;
    back.loadFromConfigFile(iniOf(text), "s");
    EXPECT_EQ(back.beam_width_deg, 3);
    EXPECT_EQ(back.detector.sensor_label, "sss");
    EXPECT_FALSE(back.detector.slant);
}

/** A map and a depth reading survive MRPT's serialization; a depth that is not one is named. */
TEST(DetectorModels, SerializationAndDepthChecks)
{
    auto ref = cameraReference();
    auto map = makeMap(ref, seabed());
    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << *map << *depthReading(12.5);
    buf.Seek(0);
    semloc::CBearingCameraMap back;
    CObservationDepth depth;
    arch >> back >> depth;
    ASSERT_EQ(back.objects().size(), map->objects().size());
    EXPECT_EQ(back.objects()[7].x, map->objects()[7].x);
    EXPECT_EQ(back.labels(), map->labels());
    EXPECT_EQ(depth.depth_m, 12.5);
    EXPECT_EQ(depth.altitude_m, 17.5);
    EXPECT_TRUE(depth.problem().empty());
    depth.depth_m = std::nan("");
    EXPECT_NE(depth.problem().find("depth_m"), std::string::npos);
    depth.depth_m = 5;
    depth.altitude_m = -1;
    EXPECT_NE(depth.problem().find("altitude_m"), std::string::npos);
    // A bad reading leaves the map's depth as it was.
    (void)map->prepareObservation(*depthReading(8));
    (void)map->prepareObservation(depth);
    EXPECT_EQ(map->vehicleDepth(), 8);
}

/** A survey leg past the objects at 25 m depth, side-scan detections at every ping: the
 *  filter, started 6 m off, localizes, bit for bit the same on 1 and 2 threads. */
struct SurveyRun
{
    std::vector<TPose2D> particles;
    double error = 0;
};

SurveyRun survey(size_t threads)
{
    auto ref = sideScanReference();
    const auto world = seabed();
    auto map = makeMap(ref, world);
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(map);
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    pdf.setExecutor(std::make_shared<semloc::ParallelExecutor>(threads));
    mrpt::random::getRandomGenerator().randomize(3);
    pdf.resetUniform(14, 26, 14, 26, -0.1, 0.1, 4000);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    std::mt19937 rng(9);
    TPose2D truth(20, 20, 0);
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
    opts.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    opts.gaussianModel.a1 = 0.02;
    opts.gaussianModel.a3 = 0.2;
    for (int k = 0; k < 60; k++)
    {
        truth.x += 1.0;
        mrpt::obs::CActionRobotMovement2D move;
        move.computeFromOdometry(mrpt::poses::CPose2D(1.0, 0, 0), opts);
        mrpt::obs::CActionCollection acts;
        acts.insert(move);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(depthReading(25));
        sf.insert(scanAt(ref, world, truth, 25, rng, false));
        pf.executeOn(pdf, &acts, &sf);
    }
    SurveyRun r;
    const auto mean = pdf.getMeanVal();
    r.error = std::hypot(mean.x() - truth.x, mean.y() - truth.y);
    for (size_t i = 0; i < pdf.size(); i++)
    {
        r.particles.push_back(pdf.m_particles[i].d);
    }
    return r;
}

TEST(DetectorModels, SideScanSurveyLocalizesTheSameOnAnyThreads)
{
    const auto one = survey(1), two = survey(2);
    EXPECT_LT(one.error, 1.0);
    ASSERT_EQ(one.particles.size(), two.particles.size());
    for (size_t i = 0; i < one.particles.size(); i++)
    {
        ASSERT_EQ(one.particles[i].x, two.particles[i].x) << i;
        ASSERT_EQ(one.particles[i].y, two.particles[i].y) << i;
        ASSERT_EQ(one.particles[i].phi, two.particles[i].phi) << i;
    }
}

}  // namespace

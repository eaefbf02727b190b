/* semloc tests — SensorCalibration: the simulator's known noise recovered from its datasets
 * (misses, clutter and confusion injected), the fits' building blocks, the output ini. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/simulator/Simulator.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "calibration/CalibrationFits.h"

using semloc::GroundTruthFile;
using semloc::SensorCalibration;
using semloc::Simulator;
using semloc::TCalibrationResult;
using semloc::TSimulatorOptions;
using semloc::World;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kSemanticIni = SEMLOC_SOURCE_DIR "/config/localize/semantic.ini";

std::string readFile(const std::string& path)
{
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

/** The paper world's whole trajectory with a short time step (many scans). */
TSimulatorOptions paperRun(uint32_t seed)
{
    TSimulatorOptions o;
    o.simulation.world_file = kPaper;
    o.simulation.seed = seed;
    o.simulation.time_step_s = 0.5;
    return o;
}

TCalibrationResult calibrate(const TSimulatorOptions& o)
{
    const Simulator sim(o);
    const auto res = sim.run();
    return SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(), res.groundTruth,
                                       SensorCalibration::TOptions());
}

/** The stated tolerances: sigmas 10 %, detection probabilities 0.05 (their edge ratio 0.1),
 *  clutter 20 %. */
void expectRecovered(const TSimulatorOptions& o, const TCalibrationResult& r)
{
    const auto& d = o.detector;
    std::cout << "fitted: sigma_range_m " << r.sigma_range_m.value << ", sigma_bearing_deg "
              << r.sigma_bearing_deg.value << ", p_detect " << r.p_detect_near.value << " .. "
              << r.p_detect_far.value << " (edge ratio " << r.p_detect_edge_ratio.value
              << "), clutter_per_scan " << r.clutter_per_scan.value << ", p_confusion "
              << r.p_confusion.value << ", p_range_outlier " << r.p_range_outlier.value
              << ", minStdXY " << r.minStdXY.value << ", a1 " << r.a1.value << ", a2 " << r.a2.value
              << ", minStdPHI " << r.minStdPHI.value << ", a3 " << r.a3.value << ", a4 "
              << r.a4.value << ", lookalike_persistence " << r.lookalike_persistence.value << " ("
              << r.lookalike_persistence.method << "; " << r.scans << " scans, " << r.matched
              << " matched, " << r.confused << " confused, " << r.misread << " misread, "
              << r.clutter << " clutter, " << r.increments << " increments)\n";
    EXPECT_NEAR(r.sigma_range_m.value, d.range_noise_std_m, 0.1 * d.range_noise_std_m);
    EXPECT_NEAR(r.sigma_bearing_deg.value, d.bearing_noise_std_deg, 0.1 * d.bearing_noise_std_deg);
    EXPECT_NEAR(r.p_detect_near.value, d.p_detect_near, 0.05);
    EXPECT_NEAR(r.p_detect_far.value, d.p_detect_far, 0.05);
    EXPECT_NEAR(r.p_detect_edge_ratio.value, d.p_detect_edge_ratio, 0.1);
    EXPECT_NEAR(r.clutter_per_scan.value, d.false_positives_per_scan,
                0.2 * d.false_positives_per_scan);
    EXPECT_NEAR(r.p_confusion.value, d.p_confusion, 0.03);
    // Clutter drawn anew at every scan is not taken for look-alikes seen again.
    if (d.distractors == 0)
    {
        EXPECT_EQ(r.lookalike_persistence.value, 0);
    }
    // The odometry: the fitted standard deviation of a typical straight step within 15 %.
    const auto& m = o.odometry;
    const double step = 0.5 * o.simulation.time_step_s;  // the paper trajectory's 0.5 m/s
    const double trueXY = m.min_xy_std_m + m.xy_std_per_m * step;
    const double truePhi = m.min_phi_std_deg + m.phi_std_deg_per_m * step;
    EXPECT_NEAR(r.minStdXY.value + r.a1.value * step, trueXY, 0.15 * trueXY);
    EXPECT_NEAR(r.minStdPHI.value + r.a3.value * step, truePhi, 0.15 * truePhi);
}
}  // namespace

TEST(SensorCalibration, RecoversTheDefaultDetectorAndOdometry)
{
    const auto o = paperRun(3);
    const auto r = calibrate(o);
    EXPECT_GT(r.scans, 500U);
    EXPECT_GT(r.matched, 1000U);
    expectRecovered(o, r);
    // Neither a range bias nor an odometry delay where the simulator has none.
    EXPECT_TRUE(r.rangeBias_m.empty());
    EXPECT_EQ(r.odometry_delay_s.value, 0);
    EXPECT_GT(r.odometry_delay_s.n, 500U);
}

TEST(SensorCalibration, RecoversARangeBiasByBearing)
{
    // Ranges read 0.3 m long on the axis and short towards the edges of the 120-degree view
    // (a camera ranging by apparent size): each coefficient within twice its 95 % interval,
    // and the sigma that of the noise alone once the bias is taken off.
    auto o = paperRun(6);
    o.detector.range_noise_std_m = 0.2;
    const std::vector<double> truth = {0.3, 0.2, -0.9, -0.2};
    o.detector.range_bias_m = truth;
    const auto r = calibrate(o);
    ASSERT_EQ(r.rangeBias_m.size(), truth.size());
    for (size_t k = 0; k < truth.size(); k++)
    {
        std::cout << "range bias c" << k << ": fitted " << r.rangeBias_m[k] << " +/- "
                  << r.rangeBiasCi95_m[k] << " (truth " << truth[k] << ")\n";
        EXPECT_GT(r.rangeBiasCi95_m[k], 0);
        EXPECT_NEAR(r.rangeBias_m[k], truth[k], 2 * r.rangeBiasCi95_m[k]) << k;
    }
    EXPECT_NEAR(r.sigma_range_m.value, 0.2, 0.02);
    EXPECT_GT(r.sigmaRangeUncorrected_m, 0.25);  // with the bias left on
    const std::string ini =
        SensorCalibration::ApplyToIni(readFile(kSemanticIni), "semantic.ini", r);
    mrpt::config::CConfigFileMemory c(ini);
    semloc::CSemanticMap::TLikelihoodOptions lo;
    lo.loadFromConfigFile(c, "MetricMap_semanticMap_00_likelihoodOpts");
    ASSERT_EQ(lo.detector.range_bias_m.size(), 4U);
    EXPECT_NEAR(lo.detector.range_bias_m[0], r.rangeBias_m[0], 1e-3);
    EXPECT_NE(ini.find("m on the axis"), std::string::npos);
    EXPECT_NE(SensorCalibration::BiasText(r).find("range bias by bearing"), std::string::npos);
}

TEST(SensorCalibration, FindsTheDelayOfAnOdometryTheVehicleFollowsLate)
{
    // The simulated run's odometry replaced by the truth 0.3 s ahead (what the vehicle does
    // 0.3 s after its odometry says so), with a little noise: the delay found, the increments'
    // heading errors smaller re-cut, and the ini says so.
    const double delay = 0.3;
    auto o = paperRun(8);
    o.simulation.time_step_s = 0.2;
    // A slalom through the paper's harbour: a turn rate that keeps changing (a delay is
    // invisible on a straight line or a steady arc), waypoints as close as the steps.
    World world = World::FromFile(kPaper);
    world.trajectory->waypoints.clear();
    for (double x = 5; x <= 45; x += 0.1)
    {
        world.trajectory->waypoints.push_back({x, 25 + 8 * std::sin(2 * M_PI * x / 20)});
    }
    const Simulator sim(world, o);
    auto res = sim.run();
    const auto& gt = res.groundTruth;
    // The truth at time t, linear between the rows (the heading unwrapped).
    std::vector<double> phi(gt.size());
    for (size_t i = 0; i < gt.size(); i++)
    {
        phi[i] = i == 0 ? gt[0].phi : phi[i - 1] + mrpt::math::wrapToPi(gt[i].phi - gt[i - 1].phi);
    }
    const auto at = [&](double t)
    {
        size_t i = 1;
        while (i + 1 < gt.size() && gt[i].t < t)
        {
            i++;
        }
        const double f = std::clamp((t - gt[i - 1].t) / (gt[i].t - gt[i - 1].t), 0.0, 1.0);
        return mrpt::poses::CPose2D(gt[i - 1].x + f * (gt[i].x - gt[i - 1].x),
                                    gt[i - 1].y + f * (gt[i].y - gt[i - 1].y),
                                    phi[i - 1] + f * (phi[i] - phi[i - 1]));
    };
    std::mt19937 gen(5);
    std::normal_distribution<double> noise(0, 1);
    double prev = -1;
    size_t replaced = 0;
    for (size_t i = 0; i < res.rawlog.size(); i++)
    {
        if (res.rawlog.getType(i) != mrpt::obs::CRawlog::etActionCollection)
        {
            continue;
        }
        const auto mv = res.rawlog.getAsAction(i)->getBestMovementEstimation();
        const double t = mrpt::Clock::toDouble(mv->timestamp);
        if (prev >= 0)
        {
            const mrpt::poses::CPose2D truth = at(t + delay) - at(prev + delay);
            const mrpt::poses::CPose2D u(truth.x() + 0.003 * noise(gen),
                                         truth.y() + 0.003 * noise(gen),
                                         truth.phi() + mrpt::DEG2RAD(0.1) * noise(gen));
            mv->computeFromOdometry(u, mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
            replaced++;
        }
        prev = t;
    }
    ASSERT_GT(replaced, 500U);
    const auto r = SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(), gt,
                                               SensorCalibration::TOptions());
    std::cout << "odometry delay: fitted " << r.odometry_delay_s.value << " +/- "
              << r.odometry_delay_s.ci95 << " s; heading RMS " << r.odomHeadingRms_deg << " -> "
              << r.odomHeadingRmsDelayed_deg << " deg\n";
    // Within 0.03 s: the truth between the rows is a straight line, the re-cut a constant
    // twist (a few hundredths of a degree apart per step, which bias the fit that much).
    EXPECT_NEAR(r.odometry_delay_s.value, delay, 0.03);
    EXPECT_GT(r.odometry_delay_s.ci95, 0);
    EXPECT_LT(r.odomHeadingRmsDelayed_deg, 0.6 * r.odomHeadingRms_deg);
    const std::string ini =
        SensorCalibration::ApplyToIni(readFile(kSemanticIni), "semantic.ini", r);
    mrpt::config::CConfigFileMemory c(ini);
    semloc::MotionModelConfig::TOptions mm;
    mm.loadFromConfigFile(c, "MotionModel");
    EXPECT_NEAR(mm.odometry_delay_s, r.odometry_delay_s.value, 1e-9);
}

TEST(SensorCalibration, RecoversHeavyMissesClutterAndConfusion)
{
    auto o = paperRun(5);
    o.detector.range_noise_std_m = 0.3;
    o.detector.bearing_noise_std_deg = 5.0;
    o.detector.p_detect_near = 0.8;
    o.detector.p_detect_far = 0.4;
    o.detector.false_positives_per_scan = 1.0;
    o.detector.p_confusion = 0.15;
    o.odometry.xy_std_per_m = 0.1;
    o.odometry.phi_std_deg_per_m = 1.0;
    expectRecovered(o, calibrate(o));
}

TEST(SensorCalibration, RecoversADetectorThatMissesAtTheEdgeOfItsView)
{
    // P_D at the edge of the 120-degree view a quarter of that on its axis: the ratio is
    // fitted with the range line, which stays that of the axis. The line's near end and the
    // ratio trade against each other (fewer detections at the edge than a flat detector
    // gives): each within its own 95 % interval, the ratio also within 0.1.
    auto o = paperRun(37);
    o.detector.p_detect_near = 0.8;
    o.detector.p_detect_far = 0.4;
    o.detector.p_detect_edge_ratio = 0.25;
    const auto r = calibrate(o);
    for (const auto& [fit, truth] :
         {std::pair{&r.p_detect_near, 0.8}, std::pair{&r.p_detect_far, 0.4},
          std::pair{&r.p_detect_edge_ratio, 0.25}})
    {
        EXPECT_GT(fit->ci95, 0);
        EXPECT_NEAR(fit->value, truth, fit->ci95) << fit->method;
    }
    EXPECT_NEAR(r.p_detect_edge_ratio.value, 0.25, 0.1);
    EXPECT_LT(r.p_detect_edge_ratio.ci95, 0.2);
    EXPECT_NEAR(r.sigma_range_m.value, 0.5, 0.05);
    EXPECT_NEAR(r.sigma_bearing_deg.value, 3.0, 0.3);
}

TEST(SensorCalibration, RecoversMisreadRanges)
{
    // A fifth of the ranges misread (uniform over [0, max range]): the share is estimated
    // (within 0.03), the detection line is not lowered by the misreads the gates refuse, and
    // the other fits hold.
    for (const double eps : {0.2, 0.05})
    {
        auto o = paperRun(eps > 0.1 ? 13 : 17);
        o.detector.p_range_outlier = eps;
        const auto r = calibrate(o);
        expectRecovered(o, r);
        EXPECT_NEAR(r.p_range_outlier.value, eps, 0.03);
        EXPECT_GT(r.misread, 0U);
    }
    // None misread: none estimated, though dense clutter falls at objects' bearings (the
    // clutter it takes for misreads is moved back to the clutter rate).
    auto o = paperRun(19);
    o.detector.false_positives_per_scan = 2.0;
    const auto r = calibrate(o);
    EXPECT_GT(r.misread, 0U);
    EXPECT_LT(r.p_range_outlier.value, 0.01);
    EXPECT_NEAR(r.clutter_per_scan.value, 2.0, 0.2);
}

TEST(SensorCalibration, RecoversACleanDetector)
{
    auto o = paperRun(7);
    o.detector.range_noise_std_m = 1.0;
    o.detector.bearing_noise_std_deg = 1.0;
    o.detector.p_detect_near = 1.0;
    o.detector.p_detect_far = 0.9;
    o.detector.false_positives_per_scan = 0.5;
    o.detector.p_confusion = 0.0;
    expectRecovered(o, calibrate(o));
}

TEST(SensorCalibration, DenseClutterIsNotTakenForConfusion)
{
    // Three false detections per scan and no confusion at all: the clutter that falls into
    // the gate of an undetected object of another label must be counted as clutter (the
    // expected share is moved back), not as confusion.
    auto o = paperRun(9);
    o.detector.false_positives_per_scan = 3.0;
    o.detector.p_confusion = 0.0;
    const auto r = calibrate(o);
    expectRecovered(o, r);
    EXPECT_LT(r.p_confusion.value, 0.02);
}

TEST(SensorCalibration, MadSigmaIgnoresOutliers)
{
    mrpt::random::CRandomGenerator rng(11);
    std::vector<double> x;
    for (int i = 0; i < 20000; i++)
    {
        x.push_back(2.0 * rng.drawGaussian1D_normalized());
    }
    for (int i = 0; i < 1000; i++)
    {
        x.push_back(1000.0 + i);  // 5 % gross outliers
    }
    EXPECT_NEAR(semloc::detail::madSigma(x), 2.0, 0.15);
    EXPECT_EQ(semloc::detail::madSigma({}), 0.0);
}

TEST(SensorCalibration, NonNegativeLeastSquares)
{
    // y = 2 + 3 x exactly; a third column that would get a negative coefficient is dropped.
    std::vector<double> ones, x, z, y;
    for (int i = 0; i < 10; i++)
    {
        ones.push_back(1);
        x.push_back(i);
        z.push_back(i % 2);
        y.push_back(2 + 3 * i - 0.5 * (i % 2));
    }
    std::vector<double> ci;
    const auto c = semloc::detail::nonNegativeLeastSquares({ones, x}, y, ci);
    ASSERT_EQ(c.size(), 2U);
    EXPECT_GT(c[0], 1.5);
    EXPECT_NEAR(c[1], 3.0, 0.1);
    const auto c3 = semloc::detail::nonNegativeLeastSquares({ones, x, z}, y, ci);
    EXPECT_EQ(c3[2], 0.0);
}

/** Detector samples of `n` in-view objects at ranges uniform in [0, 10 m], detected with
 *  probability pd(range), and a few residuals (fitDetector needs them). */
TCalibrationResult detectionSamples(size_t n, const std::function<double(double)>& pd)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    TCalibrationResult r;
    r.maxRange_m = 10;
    r.scans = 500;
    for (size_t i = 0; i < n; i++)
    {
        const double range = 10 * u(rng);
        const int detected = u(rng) < pd(range) ? 1 : 0;
        r.samples.visibleRanges_m.push_back(range);
        r.samples.visibleDetected.push_back(detected);
        r.samples.visibleSpurious.push_back(0);
        r.samples.visibleMisreadSpurious.push_back(0);
        r.matched += static_cast<size_t>(detected);
    }
    for (int i = 0; i < 50; i++)
    {
        r.samples.rangeResiduals_m.push_back(0.1 * (u(rng) - 0.5));
        r.samples.bearingResiduals_deg.push_back(u(rng) - 0.5);
    }
    return r;
}

TEST(SensorCalibration, DetectionLineByMaximumLikelihood)
{
    // A linear P_D, 0.8 at 0 m to 0.2 at 10 m: both ends within 0.05.
    auto r = detectionSamples(4000, [](double x) { return 0.8 - 0.06 * x; });
    semloc::detail::fitDetector(r);
    EXPECT_NEAR(r.p_detect_near.value, 0.8, 0.05);
    EXPECT_NEAR(r.p_detect_far.value, 0.2, 0.05);
    EXPECT_GT(r.p_detect_near.ci95, 0);
    // A detector that sees most objects within 5 m and few beyond (none past 9.5 m): the line
    // fitted explains the detections better than the least-squares line (clamped into [0, 1]
    // at its ends, as a probability must be), which overshoots near and falls to 0 far out.
    auto s = detectionSamples(4000, [](double x) { return x < 5 ? 0.8 : (x < 9.5 ? 0.05 : 0); });
    semloc::detail::fitDetector(s);
    const auto& xs = s.samples.visibleRanges_m;
    const auto& ys = s.samples.visibleDetected;
    double mx = 0, my = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < xs.size(); i++)
    {
        mx += xs[i] / 10 / static_cast<double>(xs.size());
        my += ys[i] / static_cast<double>(xs.size());
    }
    for (size_t i = 0; i < xs.size(); i++)
    {
        sxx += (xs[i] / 10 - mx) * (xs[i] / 10 - mx);
        sxy += (xs[i] / 10 - mx) * (ys[i] - my);
    }
    const double lsNear = std::clamp(my - sxy / sxx * mx, 0.0, 1.0);
    const double lsFar = std::clamp(my + sxy / sxx * (1 - mx), 0.0, 1.0);
    const auto logLik = [&](double pn, double pf)
    {
        double l = 0;
        for (size_t i = 0; i < xs.size(); i++)
        {
            const double q = std::clamp(pn + (pf - pn) * xs[i] / 10, 1e-12, 1 - 1e-12);
            l += ys[i] != 0 ? std::log(q) : std::log1p(-q);
        }
        return l;
    };
    const double ml = logLik(s.p_detect_near.value, s.p_detect_far.value);
    std::cout << "fitted " << s.p_detect_near.value << " .. " << s.p_detect_far.value
              << " (log-likelihood " << ml << "), least squares " << lsNear << " .. " << lsFar
              << " (" << logLik(lsNear, lsFar) << ")\n";
    EXPECT_GT(ml, logLik(lsNear, lsFar) + 1)
        << "fitted " << s.p_detect_near.value << " .. " << s.p_detect_far.value
        << ", least squares " << lsNear << " .. " << lsFar;
    EXPECT_GE(s.p_detect_far.value, 0.0);
    EXPECT_LE(s.p_detect_near.value, 1.0);
}

namespace
{
/** Odometry samples: `spans` spans of 10 steps of 0.1 m; each step's position error is
 *  Gaussian (sigma 0.01 m per axis), in a direction drawn per step (`correlated` false) or the
 *  same for the whole span (true: a wheel that slips for seconds). */
TCalibrationResult odometrySpans(size_t spans, bool correlated)
{
    std::mt19937 rng(5);
    std::normal_distribution<double> n(0, 0.01);
    TCalibrationResult r;
    auto& sm = r.samples;
    for (size_t j = 0; j < spans; j++)
    {
        sm.spanBegin.push_back(sm.odomDist_m.size());
        double ex = 0, ey = 0, dx = n(rng), dy = n(rng);
        for (int k = 0; k < 10; k++)
        {
            if (!correlated)
            {
                dx = n(rng), dy = n(rng);
            }
            ex += dx, ey += dy;
            const double phi = 0.2 * n(rng);
            sm.odomDist_m.push_back(0.1);
            sm.odomTurn_rad.push_back(0);
            sm.odomErrXY_m.push_back(std::hypot(dx, dy));
            sm.odomErrPhi_rad.push_back(std::abs(phi));
            sm.odomErrPhiSigned_rad.push_back(phi);
            sm.odomDt_s.push_back(0.2);
        }
        sm.spanEnd.push_back(sm.odomDist_m.size());
        sm.spanErrXY_m.push_back(std::hypot(ex, ey));
        sm.spanErrPhi_rad.push_back(0);
        sm.spanDt_s.push_back(2);
    }
    r.increments = sm.odomDist_m.size();
    return r;
}
}  // namespace

TEST(SensorCalibration, OdometryNoiseWidenedForErrorsThatDoNotCancelOverTheSpans)
{
    // Independent steps add up as the per-step model says: no factor worth the name.
    auto independent = odometrySpans(300, false);
    semloc::detail::fitOdometry(independent);
    EXPECT_LT(independent.spanFactorXY, 1.35);
    // The same error for ten steps grows ten-fold, not sqrt(10)-fold: the position noise is
    // widened by about sqrt(10) (the 95 % quantile against the chi-square bound).
    auto correlated = odometrySpans(300, true);
    semloc::detail::fitOdometry(correlated);
    EXPECT_GT(correlated.spanFactorXY, 2.5);
    EXPECT_LT(correlated.spanFactorXY, 5.0);
    EXPECT_NEAR(correlated.minStdXY.value,
                independent.minStdXY.value * correlated.spanFactorXY / independent.spanFactorXY,
                0.3 * correlated.minStdXY.value);
    EXPECT_NE(correlated.minStdXY.method.find("spans between detections"), std::string::npos);
}

TEST(SensorCalibration, OutputIniIsTheBaseWithTheFits)
{
    const auto o = paperRun(3);
    const auto r = calibrate(o);
    const std::string base = readFile(kSemanticIni);
    const std::string out = SensorCalibration::ApplyToIni(base, "semantic.ini", r);
    mrpt::config::CConfigFileMemory c(out);
    const std::string lik = "MetricMap_semanticMap_00_likelihoodOpts";
    EXPECT_EQ(c.read_string(lik, "model", ""), "probabilistic");
    EXPECT_NEAR(c.read_double(lik, "sigma_range_m", 0), r.sigma_range_m.value, 1e-3);
    EXPECT_NEAR(c.read_double(lik, "p_detect_far", 0), r.p_detect_far.value, 1e-3);
    EXPECT_NEAR(c.read_double(lik, "clutter_per_scan", 0), r.clutter_per_scan.value, 1e-3);
    EXPECT_EQ(c.read_string("MotionModel", "source", ""), "gaussian");
    EXPECT_NEAR(c.read_double("MotionModel", "a1", -1), r.a1.value, 1e-3);
    // The rest of the base is kept.
    EXPECT_EQ(c.read_int("MetricMap", "semanticMap_count", 0), 1);
    EXPECT_EQ(c.read_string("LocalizationExperiment", "variant", ""), "semantic");
    EXPECT_NE(out.find("// calibrated: n = "), std::string::npos);
    // No heading drift in this run: the drift state stays off, and says why.
    EXPECT_FALSE(r.headingDrifts);
    EXPECT_EQ(c.read_double("MotionModel", "heading_drift_walk_deg_per_min", -1), 0.0);
    EXPECT_NE(out.find("// calibrated: no heading drift ("), std::string::npos);
}

TEST(SensorCalibration, FindsTheOdometrysHeadingDriftAndTurnsTheDriftStateOn)
{
    // Odometry whose heading gains 15 deg a minute (the same on every reading, beyond its
    // noise): the drift within 1 deg/min, its interval covering it, the heading noise fitted
    // without it (within the default's 15 %), and the calibrated ini with the drift state on.
    for (const double drift : {15.0, -6.0})
    {
        auto o = paperRun(4);
        o.odometry.heading_drift_deg_per_min = drift;
        const auto r = calibrate(o);
        std::cout << "heading drift " << drift << ": fitted " << r.heading_drift_deg_per_min.value
                  << " +/- " << r.heading_drift_deg_per_min.ci95 << " deg/min\n";
        EXPECT_NEAR(r.heading_drift_deg_per_min.value, drift, 1.0);
        EXPECT_LT(std::abs(r.heading_drift_deg_per_min.value - drift),
                  r.heading_drift_deg_per_min.ci95 * 1.5);
        EXPECT_GT(r.heading_drift_deg_per_min.ci95, 0);
        EXPECT_TRUE(r.headingDrifts);
        expectRecovered(o, r);
        const std::string out =
            SensorCalibration::ApplyToIni(readFile(kSemanticIni), "semantic.ini", r);
        mrpt::config::CConfigFileMemory c(out);
        EXPECT_EQ(c.read_double("MotionModel", "heading_drift_walk_deg_per_min", 0),
                  semloc::MotionModelConfig::TOptions::kCalibratedDriftWalkDegPerMin);
        EXPECT_EQ(c.read_double("MotionModel", "heading_drift_std_deg_per_min", -1), 0.0);
        EXPECT_NE(out.find("// calibrated: the heading drifts "), std::string::npos);
    }
}

TEST(SensorCalibration, OutputIniErrorsNameFileLineAndKey)
{
    TCalibrationResult r;
    try
    {
        (void)SensorCalibration::ApplyToIni("[MetricMap]\nstructureMap_count = 1\n", "g.ini", r);
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("ini 'g.ini': [MetricMap] semanticMap_count"),
                  std::string::npos)
            << e.what();
    }
    try
    {
        (void)SensorCalibration::ApplyToIni(
            "[MetricMap]\nsemanticMap_count = 1\n[MetricMap_semanticMap_00_likelihoodOpts]\n"
            "sigma_range_m = 1\nsigma_range_m = 2\n",
            "d.ini", r);
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("ini 'd.ini': line 5: "
                                             "[MetricMap_semanticMap_00_likelihoodOpts] "
                                             "sigma_range_m: set twice (first on line 4)"),
                  std::string::npos)
            << e.what();
    }
}

TEST(SensorCalibration, ScanWithoutGroundTruthIsAnErrorNamingTheEntry)
{
    auto o = paperRun(3);
    o.simulation.max_steps = 20;
    const Simulator sim(o);
    const auto res = sim.run();
    auto gt = res.groundTruth;
    gt.resize(10);
    try
    {
        (void)SensorCalibration::Estimate(res.rawlog, "x.rawlog", sim.world(), gt,
                                          SensorCalibration::TOptions());
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("rawlog 'x.rawlog': entry 20: no ground-truth row"),
                  std::string::npos)
            << e.what();
    }
}

#ifdef SEMLOC_BIN_DIR
TEST(SensorCalibration, ToolWritesTheIniAndTheReport)
{
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "calibrate_tool";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto o = paperRun(9);
    o.detector.range_noise_std_m = 0.8;
    const Simulator sim(o);
    const std::string rawlog = (dir / "data.rawlog").string();
    sim.writeDataset(sim.run(), rawlog);
    const std::string cmd = std::string(SEMLOC_BIN_DIR) + "/semloc-calibrate " + rawlog +
                            " --world " + kPaper + " --ground-truth " +
                            GroundTruthFile::PathFor(rawlog) + " --base " + kSemanticIni + " -o " +
                            (dir / "out.ini").string() + " --report " + (dir / "report").string() +
                            " --consistency-seeds 0 > " + (dir / "stdout").string();
    for (int run = 0; run < 2; run++)  // the second run replaces the first's outputs
    {
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    mrpt::config::CConfigFileMemory c(readFile((dir / "out.ini").string()));
    EXPECT_NEAR(c.read_double("MetricMap_semanticMap_00_likelihoodOpts", "sigma_range_m", 0), 0.8,
                0.08);
    EXPECT_EQ(c.read_string("LocalizationExperiment", "map_file", ""),
              fs::path(kPaper).lexically_normal().string());
    for (const char* f : {"report.md", "fig_residuals.png", "fig_detection.png", "fig_odometry.png",
                          ".semloc-output"})
    {
        EXPECT_TRUE(fs::exists(dir / "report" / f)) << f;
    }
    const std::string md = readFile((dir / "report" / "report.md").string());
    EXPECT_NE(md.find("| `sigma_range_m` |"), std::string::npos);
    EXPECT_NE(md.find("| `p_range_outlier` |"), std::string::npos);
    EXPECT_NE(md.find("| `odometry_delay_s` |"), std::string::npos);
    EXPECT_TRUE(c.keyExists("MetricMap_semanticMap_00_likelihoodOpts", "p_range_outlier"));
    // Every row of the table has its five cells: a '|' inside a cell is escaped.
    std::istringstream rows(md);
    std::string line;
    size_t tableRows = 0;
    while (std::getline(rows, line))
    {
        if (line.rfind("| `", 0) != 0)
        {
            continue;
        }
        size_t bars = 0;
        for (size_t i = 0; i < line.size(); i++)
        {
            bars += (line[i] == '|' && (i == 0 || line[i - 1] != '\\')) ? 1 : 0;
        }
        EXPECT_EQ(bars, 6U) << line;
        tableRows++;
    }
    EXPECT_EQ(tableRows, 17U);  // 16 keys and the heading drift
}

// One scan: no odometry increment, a single residual (a zero standard deviation) or a few.
// The ini (the base's values kept) and the whole report are written, every figure drawn (a
// panel without data says so).
TEST(SensorCalibration, ToolCalibratesOneScanAndDrawsEveryFigure)
{
    namespace fs = std::filesystem;
    for (const uint32_t seed : {2U, 3U})
    {
        const fs::path dir =
            fs::path(SEMLOC_TEST_OUT) / ("calibrate_one_scan_" + std::to_string(seed));
        fs::remove_all(dir);
        fs::create_directories(dir);
        auto o =
            TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini");
        o.simulation.max_steps = 1;
        o.simulation.seed = seed;
        const Simulator sim(o);
        const std::string rawlog = (dir / "one.rawlog").string();
        sim.writeDataset(sim.run(), rawlog);
        const std::string cmd =
            std::string(SEMLOC_BIN_DIR) + "/semloc-calibrate " + rawlog + " --world " + kPaper +
            " --ground-truth " + GroundTruthFile::PathFor(rawlog) + " --base " + kSemanticIni +
            " -o " + (dir / "out.ini").string() + " --report " + (dir / "report").string() + " > " +
            (dir / "stdout").string() + " 2> " + (dir / "stderr").string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n"
                                               << readFile((dir / "stderr").string());
        EXPECT_NE(readFile((dir / "stdout").string()).find("1 scans, 0 odometry increments"),
                  std::string::npos);
        // Every fit is left out (too little data, said on stderr), nothing else is warned of.
        std::istringstream err(readFile((dir / "stderr").string()));
        for (std::string line; std::getline(err, line);)
        {
            EXPECT_NE(line.find(": not fitted, too little data ("), std::string::npos) << line;
        }
        EXPECT_GT(fs::file_size(dir / "out.ini"), 0U);
        for (const char* f :
             {"report.md", "fig_residuals.png", "fig_detection.png", "fig_odometry.png"})
        {
            EXPECT_TRUE(fs::exists(dir / "report" / f) && fs::file_size(dir / "report" / f) > 0)
                << seed << ": " << f;
        }
        EXPECT_EQ(readFile((dir / "report" / "report.md").string()).find("not drawn"),
                  std::string::npos);
    }
}
#endif

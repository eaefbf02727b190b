/* Tests of the detector's posterior Cramér–Rao bound: the Gaussian mean error, the
 * recursion against hand-computed information, and the bound of simulated runs. */
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/simulator/DetectorBound.h>
#include <semloc/simulator/Simulator.h>

#include <Eigen/Dense>
#include <cmath>

#include "TestHelpers.h"

using semloc::detectorCramerRaoBound;
using semloc::gaussianMeanError;
using semloc::TDetectorBoundInput;
using semloc::TDetectorBoundSensor;

namespace
{
/** A static vehicle at the origin, heading 0, for `steps` steps with exact odometry, seeing
 *  the objects at (10, 0) and (0, 10) at every step. */
std::vector<TDetectorBoundInput> staticScene(size_t steps)
{
    std::vector<TDetectorBoundInput> in(steps);
    for (auto& s : in)
    {
        s.pose = {0, 0, 0};
        s.incrementCov.setZero();
        s.visible = {{10, 0}, {0, 10}};
    }
    return in;
}

/** Straight ahead 1 m and 1 s per step for `steps` steps, seeing two objects that keep
 *  their place relative to the vehicle, with a little odometry noise; silent from step 3. */
std::vector<TDetectorBoundInput> movingScene(size_t steps)
{
    auto in = staticScene(steps);
    for (size_t k = 0; k < in.size(); k++)
    {
        in[k].pose = {static_cast<double>(k), 0, 0};
        in[k].visible = {{10.0 + static_cast<double>(k), 0}, {static_cast<double>(k), 10}};
        in[k].incrementCov = mrpt::math::CMatrixDouble33(
            Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal().toDenseMatrix());
        in[k].silent = k >= 3;
        in[k].dt_s = 1;
    }
    return in;
}

TDetectorBoundSensor sensor(double pd)
{
    TDetectorBoundSensor s;
    s.sigma_range_m = 0.5;       // 1 / sigma^2 = 4
    s.sigma_bearing_rad = 0.05;  // 1 / sigma^2 = 400
    s.detectionProbability = [pd](double, double) { return pd; };
    return s;
}

/** The information of one scan of staticScene(), by hand: for the object at (10, 0) the
 *  range row of H is (-1, 0, 0) and the bearing row (0, -0.1, -1); for (0, 10) they are
 *  (0, -1, 0) and (0.1, 0, -1). Sum of 4 h_r h_rᵀ + 400 h_b h_bᵀ. */
Eigen::Matrix3d handInformation()
{
    Eigen::Matrix3d J;
    J << 8, 0, -40, 0, 8, 40, -40, 40, 800;
    return J;
}

double rmsOf(const Eigen::Matrix3d& P)
{
    return std::sqrt(P(0, 0) + P(1, 1));
}
}  // namespace

TEST(DetectorBound, GaussianMeanErrorKnownCases)
{
    // Isotropic: sigma sqrt(pi / 2) (a Rayleigh mean); degenerate: a half-normal mean.
    EXPECT_NEAR(gaussianMeanError(0.09, 0, 0.09), 0.3 * std::sqrt(M_PI / 2), 1e-12);
    EXPECT_NEAR(gaussianMeanError(0.04, 0, 0), std::sqrt(2 * 0.04 / M_PI), 1e-12);
    EXPECT_EQ(gaussianMeanError(0, 0, 0), 0.0);
    // Rotation does not change it.
    const double a = 0.7, c = std::cos(a), s = std::sin(a);
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    const Eigen::Matrix2d C = R * Eigen::Vector2d(0.09, 0.01).asDiagonal() * R.transpose();
    EXPECT_NEAR(gaussianMeanError(C(0, 0), C(0, 1), C(1, 1)), gaussianMeanError(0.09, 0, 0.01),
                1e-12);
}

TEST(DetectorBound, GaussianMeanErrorMatchesSampling)
{
    mrpt::random::CRandomGenerator rng(7);
    const double sx = 0.3, sy = 0.1;
    double sum = 0;
    const int n = 400000;
    for (int i = 0; i < n; i++)
    {
        sum +=
            std::hypot(sx * rng.drawGaussian1D_normalized(), sy * rng.drawGaussian1D_normalized());
    }
    EXPECT_NEAR(gaussianMeanError(sx * sx, 0, sy * sy), sum / n, 1e-3);
}

TEST(DetectorBound, StaticVehicleAccumulatesTheHandInformation)
{
    const auto out = detectorCramerRaoBound(staticScene(5), sensor(1.0));
    ASSERT_EQ(out.size(), 5u);
    for (size_t k = 0; k < out.size(); k++)
    {
        // k + 1 scans, the vague prior (variance 1e6) adds 1e-6 to each diagonal entry.
        const Eigen::Matrix3d J =
            static_cast<double>(k + 1) * handInformation() + 1e-6 * Eigen::Matrix3d::Identity();
        const Eigen::Matrix3d P = J.inverse();
        EXPECT_NEAR(out[k].rms_xy_m, rmsOf(P), 1e-9) << "step " << k;
        EXPECT_NEAR(out[k].mean_err_xy_m, gaussianMeanError(P(0, 0), P(0, 1), P(1, 1)), 1e-9);
    }
    // Information adds up: the variance falls as 1 / scans.
    EXPECT_NEAR(out[3].rms_xy_m, out[0].rms_xy_m / 2, 1e-6);
}

TEST(DetectorBound, DetectionProbabilityScalesTheInformation)
{
    const auto sure = detectorCramerRaoBound(staticScene(3), sensor(1.0));
    const auto half = detectorCramerRaoBound(staticScene(3), sensor(0.5));
    // P_D = 0.5 halves the information: the variance doubles.
    EXPECT_NEAR(half.back().rms_xy_m, std::sqrt(2.0) * sure.back().rms_xy_m, 1e-6);
}

TEST(DetectorBound, MotionAndSilencesOnlyPredict)
{
    // Straight ahead 1 m per step, heading known well after three scans, then silent.
    auto in = movingScene(6);
    const auto out = detectorCramerRaoBound(in, sensor(1.0));
    // A silent step gains nothing: the bound grows with the motion noise.
    for (size_t k = 3; k < out.size(); k++)
    {
        EXPECT_GT(out[k].rms_xy_m, out[k - 1].rms_xy_m + 0.005);
    }
    // Silent steps are those with nothing visible.
    auto blind = in;
    for (size_t k = 3; k < blind.size(); k++)
    {
        blind[k].silent = false;
        blind[k].visible.clear();
    }
    const auto same = detectorCramerRaoBound(blind, sensor(1.0));
    for (size_t k = 0; k < out.size(); k++)
    {
        EXPECT_EQ(out[k].rms_xy_m, same[k].rms_xy_m);
    }
    // A restart forgets everything: back to the vague prior.
    in[4].restart = true;
    EXPECT_GT(detectorCramerRaoBound(in, sensor(1.0))[4].rms_xy_m, 1000.0);
}

TEST(DetectorBound, AnUnknownHeadingDriftOnlyRaisesTheBound)
{
    // movingScene(): with a heading drift no estimator is told, the bound is at least the
    // known odometry's at every step (equal at the first, where nothing has moved), and
    // through the silence it grows faster: the drift learned from three scans is uncertain
    // and turns the heading.
    auto in = movingScene(8);
    const auto known = detectorCramerRaoBound(in, sensor(1.0));
    const auto unknown = detectorCramerRaoBound(in, sensor(1.0), true);
    ASSERT_EQ(unknown.size(), known.size());
    EXPECT_NEAR(unknown[0].rms_xy_m, known[0].rms_xy_m, 1e-9 * known[0].rms_xy_m);
    for (size_t k = 1; k < in.size(); k++)
    {
        EXPECT_GE(unknown[k].rms_xy_m, known[k].rms_xy_m * (1 - 1e-9)) << k;
    }
    const double growthKnown = known.back().rms_xy_m - known[2].rms_xy_m;
    const double growthUnknown = unknown.back().rms_xy_m - unknown[2].rms_xy_m;
    EXPECT_GT(growthUnknown, 1.5 * growthKnown);
    // A restart forgets the pose, not what was learned of the drift: after three scans, a
    // restart with one scan and a silence ends far closer than the same with no scan before
    // the restart (a drift never seen).
    auto learned = in;
    learned[3].restart = true;
    learned[3].silent = false;
    auto unseen = learned;
    for (size_t k = 0; k < 3; k++)
    {
        unseen[k].silent = true;
    }
    const auto a = detectorCramerRaoBound(learned, sensor(1.0), true);
    const auto b = detectorCramerRaoBound(unseen, sensor(1.0), true);
    ASSERT_TRUE(std::isfinite(a.back().rms_xy_m) && std::isfinite(b.back().rms_xy_m));
    EXPECT_LT(a.back().rms_xy_m, 0.5 * b.back().rms_xy_m);
}

TEST(DetectorBound, SimulatedRunFollowsTheDetector)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR
                                                       "/config/simulate/simulate.ini");
    o.simulation.max_steps = 120;
    const semloc::Simulator sim(o);
    const auto run = sim.run();
    const auto bound = detectorCramerRaoBound(sim, run);
    ASSERT_EQ(bound.size(), run.groundTruth.size());
    const auto meanFrom = [](const std::vector<semloc::TDetectorBoundStep>& b, size_t from)
    {
        double s = 0;
        for (size_t k = from; k < b.size(); k++)
        {
            EXPECT_TRUE(std::isfinite(b[k].mean_err_xy_m) && b[k].mean_err_xy_m > 0);
            EXPECT_LT(b[k].mean_err_xy_m, b[k].rms_xy_m);
            s += b[k].mean_err_xy_m;
        }
        return s / static_cast<double>(b.size() - from);
    };
    const double nominal = meanFrom(bound, 20);
    EXPECT_LT(nominal, 1.0);

    // Noisier detections or fewer of them: a larger bound. The noise is not drawn.
    auto noisy = o;
    noisy.detector.range_noise_std_m *= 2;
    noisy.detector.bearing_noise_std_deg *= 2;
    const semloc::Simulator simNoisy(noisy);
    EXPECT_GT(meanFrom(detectorCramerRaoBound(simNoisy, simNoisy.run()), 20), 1.3 * nominal);
    auto rare = o;
    rare.detector.p_detect_near /= 2;
    rare.detector.p_detect_far /= 2;
    const semloc::Simulator simRare(rare);
    EXPECT_GT(meanFrom(detectorCramerRaoBound(simRare, simRare.run()), 20), 1.1 * nominal);

    // The detector's silences are the steps the simulator left without detections.
    auto gaps = o;
    gaps.detector.gap_every_s = 30;
    gaps.detector.gap_min_s = 10;
    gaps.detector.gap_max_s = 20;
    const semloc::Simulator simGaps(gaps);
    const auto gapRun = simGaps.run();
    ASSERT_EQ(gapRun.detectorSilent.size(), gapRun.steps);
    size_t silent = 0;
    for (size_t k = 0; k < gapRun.steps; k++)
    {
        if (gapRun.detectorSilent[k])
        {
            silent++;
            const auto sf = gapRun.rawlog.getAsObservations(2 * k + 1);
            EXPECT_EQ(sf->getObservationByClass<semloc::CObservationSemantic>()->detections.size(),
                      0u);
        }
    }
    EXPECT_GT(silent, 10u);
    const double withGaps = meanFrom(detectorCramerRaoBound(simGaps, gapRun), 20);
    EXPECT_GT(withGaps, nominal);

    // Odometry whose heading drifts (unknown to the estimator): the same path, visibility
    // and silences, a larger bound.
    auto drifting = gaps;
    drifting.odometry.heading_drift_deg_per_min = 15;
    const semloc::Simulator simDrift(drifting);
    EXPECT_GT(meanFrom(detectorCramerRaoBound(simDrift, simDrift.run()), 20), 1.02 * withGaps);
}

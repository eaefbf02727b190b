/* semloc tests — semloc-calibrate's look-alike persistence: the rates of a known two-part
 * clutter recovered by the fit, and a simulated run's slow look-alikes found (none where the
 * clutter is drawn anew at every scan). */
#include <gtest/gtest.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "calibration/CalibrationLookAlikes.h"

using semloc::SensorCalibration;
using semloc::Simulator;
using semloc::TCalibrationFit;
using semloc::TCalibrationResult;
using semloc::TSimulatorOptions;

namespace
{
/** Clutter in a 10 m x 10 m field, scan after scan: `remembered` earlier detections in view,
 *  each seen again with chance `rho` (Gaussian, sigma 0.3 m, around where it was), and a
 *  uniform part of `lambda` per scan; the samples the fit reads (densities over the field). */
TCalibrationResult twoPartClutter(double rho, double lambda, int remembered, uint32_t seed)
{
    constexpr double kSide = 10, kSigma = 0.3;
    constexpr int kScans = 3000;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> where(0, kSide);
    std::bernoulli_distribution again(rho);
    std::poisson_distribution<int> uniform(lambda);
    std::normal_distribution<double> noise(0, kSigma);
    TCalibrationResult r;
    r.scans = kScans;
    r.clutter_per_scan.value = lambda + rho * remembered;
    for (int s = 0; s < kScans; s++)
    {
        std::vector<double> px, py, cx, cy;
        for (int j = 0; j < remembered; j++)
        {
            px.push_back(where(rng));
            py.push_back(where(rng));
            if (again(rng))
            {
                cx.push_back(px.back() + noise(rng));
                cy.push_back(py.back() + noise(rng));
            }
        }
        for (int k = uniform(rng); k > 0; k--)
        {
            cx.push_back(where(rng));
            cy.push_back(where(rng));
        }
        for (size_t k = 0; k < cx.size(); k++)
        {
            double best = 0;
            for (size_t j = 0; j < px.size(); j++)
            {
                const double d2 =
                    (cx[k] - px[j]) * (cx[k] - px[j]) + (cy[k] - py[j]) * (cy[k] - py[j]);
                best = std::max(
                    best, std::exp(-0.5 * d2 / (kSigma * kSigma)) / (2 * M_PI * kSigma * kSigma));
            }
            r.samples.lookAlikeDensity.push_back(best);
            r.samples.lookAlikeUniform.push_back(1 / (kSide * kSide));
        }
        r.samples.lookAlikeInView.push_back(remembered);
    }
    return r;
}

/** The paper world's route with the real run's detector: 9 m, 70 degrees, P_D 0.5 .. 0.3. */
TSimulatorOptions narrowDetectorRun(int lookAlikes, uint32_t seed)
{
    TSimulatorOptions o;
    o.simulation.world_file = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
    o.simulation.seed = seed;
    o.simulation.time_step_s = 0.5;
    o.detector.max_range_m = 9;
    o.detector.fov_deg = 70;
    o.detector.p_detect_near = 0.5;
    o.detector.p_detect_far = 0.3;
    o.detector.distractors = lookAlikes;
    o.detector.distractor_speed_mps = 0.2;
    return o;
}

TCalibrationResult calibrate(const TSimulatorOptions& o)
{
    const Simulator sim(o);
    const auto res = sim.run();
    auto r = SensorCalibration::Estimate(res.rawlog, "sim.rawlog", sim.world(), res.groundTruth,
                                         SensorCalibration::TOptions());
    std::cout << "lookalike_persistence " << r.lookalike_persistence.value << " +/- "
              << r.lookalike_persistence.ci95 << " (" << r.lookalike_persistence.method
              << "), clutter_per_scan " << r.clutter_per_scan.value << "\n";
    return r;
}
}  // namespace

TEST(CalibrationLookAlikes, RecoversBothRatesOfATwoPartClutter)
{
    for (const double rho : {0.1, 0.3})
    {
        auto r = twoPartClutter(rho, 0.2, 3, 7);
        semloc::detail::fitLookAlikes(r);
        const auto& f = r.lookalike_persistence;
        std::cout << "rho " << rho << ": fitted " << f.value << " +/- " << f.ci95 << "\n";
        EXPECT_GT(f.ci95, 0);
        EXPECT_NEAR(f.value, rho, std::max(f.ci95, 0.1 * rho));
        // The clutter rate written is the uniform part: the total less the re-sightings.
        EXPECT_NEAR(r.clutter_per_scan.value, 0.2, 0.03);
        EXPECT_NEAR(r.lookAlikeResightings, rho * 3 * 3000, 0.15 * rho * 3 * 3000);
    }
}

TEST(CalibrationLookAlikes, UniformClutterAloneIsNotTakenForLookAlikes)
{
    auto r = twoPartClutter(0.0, 0.5, 3, 11);
    semloc::detail::fitLookAlikes(r);
    EXPECT_EQ(r.lookalike_persistence.value, 0);
    EXPECT_NE(r.lookalike_persistence.method.find("not significant"), std::string::npos);
    EXPECT_NEAR(r.clutter_per_scan.value, 0.5, 1e-12);  // left as it was
    EXPECT_EQ(r.lookAlikeResightings, 0);
}

TEST(CalibrationLookAlikes, NothingToFitWithoutClutterOrMemory)
{
    TCalibrationResult r;
    r.scans = 10;
    r.samples.lookAlikeInView.assign(10, 0);
    semloc::detail::fitLookAlikes(r);
    EXPECT_EQ(r.lookalike_persistence.value, 0);
    EXPECT_EQ(r.lookalike_persistence.status, TCalibrationFit::Status::Fitted);
    EXPECT_FALSE(r.lookalike_persistence.method.empty());
}

TEST(CalibrationLookAlikes, FindsTheSlowLookAlikesOfASimulatedRun)
{
    const auto with = calibrate(narrowDetectorRun(12, 3));
    EXPECT_GT(with.lookalike_persistence.value, 0);
    EXPECT_GT(with.lookAlikeResightings, 10);
    const auto without = calibrate(narrowDetectorRun(0, 3));
    EXPECT_EQ(without.lookalike_persistence.value, 0);
    // The clutter rate of the run with look-alikes is the uniform part: near the simulator's.
    EXPECT_NEAR(with.clutter_per_scan.value, without.clutter_per_scan.value,
                0.5 * without.clutter_per_scan.value);
}

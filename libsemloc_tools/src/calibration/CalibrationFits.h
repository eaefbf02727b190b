/* semloc — the fits of semloc-calibrate: robust sigmas, the detection line, rates, the
 * odometry's Gaussian model (private). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace semloc::detail
{
/** Marks `f` TooLittleData when `have` < `need` (`tooLittle`: why) or its value is not finite,
 *  else clamps it into `range` (Clamped, `outside`: why it fell outside). */
void limit(TCalibrationFit& f, const config::TValueRange& range, size_t have, size_t need,
           const std::string& tooLittle, const std::string& outside);

/** 1.4826 x the median absolute deviation from the median (a Gaussian's sigma); 0 if empty. */
double madSigma(std::vector<double> x);

/** Least squares of y against the columns of `cols` (one vector per regressor, each as long
 *  as y) with every coefficient >= 0: the best of the column subsets whose unconstrained fit
 *  is non-negative (exact for 3 columns). `ci95` gets each coefficient's 95 % half-width. */
std::vector<double> nonNegativeLeastSquares(const std::vector<std::vector<double>>& cols,
                                            const std::vector<double>& y,
                                            std::vector<double>& ci95);

/** Called as the detection model's search goes on: `step` of about `steps` of round `round`
 *  (from 1; at most 50 rounds, most searches end after a few). */
using FitProgress = std::function<void(int round, size_t step, size_t steps)>;

/** sigma_range_m, sigma_bearing_deg, p_detect_near/far, clutter_per_scan, p_confusion from
 *  the samples and counts of `r`. Throws when no detection matched an object. */
void fitDetector(TCalibrationResult& r, const FitProgress& progress = {});

/** The range bias by bearing the residuals of `s` show (TCalibrationResult::rangeBias_m):
 *  kRangeBiasTerms coefficients and their 95 % half-widths in `ci95`, or none (empty) when
 *  it is not significant, there are fewer than kMinRangeBiasResiduals residuals or their
 *  bearings do not vary enough to fit a cubic. */
std::vector<double> fitRangeBias(const TCalibrationSamples& s, std::vector<double>& ci95);
constexpr size_t kMinRangeBiasResiduals = 40;
/** `bias` (kRangeBiasTerms coefficients, or empty: none) plus what fitRangeBias() finds in
 *  `s`, its interval in `ci95`; both left as they are when it finds none. */
void addRangeBias(const TCalibrationSamples& s, std::vector<double>& bias,
                  std::vector<double>& ci95);
/** `obs` with each detection's range less the bias (rangeLessBias(): within [0, its max
 *  range]), in `copy`: the ranges the filter reads; `obs` itself without a bias. */
const CObservationSemantic& lessRangeBias(const CObservationSemantic& obs,
                                          const std::vector<double>& bias,
                                          CObservationSemantic& copy);

/** One odometry action of the rawlog: its time, its increment and the ground-truth row at
 *  that time. */
struct TimedIncrement
{
    double t;
    mrpt::math::TPose2D u;
    const GroundTruthRow* row;
};

/** TCalibrationResult::odometry_delay_s from the actions `steps` in their order, and the
 *  heading RMS of the increments before and after it (odomHeadingRms_deg,
 *  odomHeadingRmsDelayed_deg). */
void fitOdometryDelay(const std::vector<TimedIncrement>& steps, TCalibrationResult& r);

/** a1..a4, minStdXY, minStdPHI from the odometry samples of `r` (all 0 with fewer than 4
 *  increments: n says so). */
void fitOdometry(TCalibrationResult& r);

/** A rigid 2D transform p -> R(theta) p + (tx, ty): the ground truth's frame to the map's. */
struct RigidTransform2D
{
    double theta = 0, tx = 0, ty = 0;
    /** The pose `p` moved by the transform (its heading turned by theta). */
    mrpt::math::TPose2D apply(const mrpt::math::TPose2D& p) const;
    /** This transform after `first`. */
    RigidTransform2D after(const RigidTransform2D& first) const;
};

/** The rigid transform that best aligns the matched detections' positions with their objects
 *  (samples detectedX/Y, objectX/Y of `r`): least squares, then again without the pairs over
 *  3.5 times the median distance. Identity when fewer than kMinResiduals pairs or fewer than
 *  2 distinct objects. `r.mapOffset` gets `sofar` then it, as the report gives it. */
RigidTransform2D fitMapOffset(TCalibrationResult& r, const RigidTransform2D& sofar);

/** r.bias from the residuals, and the sigmas made those of the zero-mean model the filter
 *  has: sqrt(sigma around the bias^2 + bias^2). */
void fitBias(TCalibrationResult& r);

/** Every fit of `r` moved into the range semloc-localize accepts for its key (Clamped, with
 *  why), or marked TooLittleData when its data are under the kMin* of TCalibrationResult. */
void applyLimits(TCalibrationResult& r);
}  // namespace semloc::detail

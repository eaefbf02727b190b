/* semloc — the fits of semloc-calibrate: robust sigmas, the detection line, rates, the
 * odometry's Gaussian model (private). */
#pragma once

#include <semloc/calibration/SensorCalibration.h>

#include <vector>

namespace semloc::detail
{
/** 1.4826 x the median absolute deviation from the median (a Gaussian's sigma); 0 if empty. */
double madSigma(std::vector<double> x);

/** Least squares of y against the columns of `cols` (one vector per regressor, each as long
 *  as y) with every coefficient >= 0: the best of the column subsets whose unconstrained fit
 *  is non-negative (exact for 3 columns). `ci95` gets each coefficient's 95 % half-width. */
std::vector<double> nonNegativeLeastSquares(const std::vector<std::vector<double>>& cols,
                                            const std::vector<double>& y,
                                            std::vector<double>& ci95);

/** sigma_range_m, sigma_bearing_deg, p_detect_near/far, clutter_per_scan, p_confusion from
 *  the samples and counts of `r`. Throws when no detection matched an object. */
void fitDetector(TCalibrationResult& r);

/** a1..a4, minStdXY, minStdPHI from the odometry samples of `r` (all 0 with fewer than 4
 *  increments: n says so). */
void fitOdometry(TCalibrationResult& r);
}  // namespace semloc::detail

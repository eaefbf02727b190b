/* semloc — semloc-calibrate's fit of how late the vehicle follows its odometry: the delay
 * whose re-cut increments err least in heading against the ground truth. */
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/filter/OdometryDelay.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "calibration/CalibrationFits.h"

namespace semloc::detail
{
namespace
{
/** The sum of the squared heading errors [rad^2] of the increments re-cut by `delay_s`
 *  against the ground truth, and how many there are. */
double headingSse(const std::vector<TimedIncrement>& steps, double delay_s, size_t& n)
{
    OdometryDelay delay(delay_s);
    double sse = 0;
    n = 0;
    for (size_t k = 0; k < steps.size(); k++)
    {
        const double phi = delay.step(steps[k].t, steps[k].u).phi;
        if (k == 0)
        {
            continue;
        }
        const double truth = mrpt::math::wrapToPi(steps[k].row->phi - steps[k - 1].row->phi);
        const double e = mrpt::math::wrapToPi(phi - truth);
        sse += e * e;
        n++;
    }
    return sse;
}
}  // namespace

void fitOdometryDelay(const std::vector<TimedIncrement>& steps, TCalibrationResult& r)
{
    size_t n = 0;
    const double sse0 = headingSse(steps, 0, n);
    const auto grid = static_cast<int>(
        std::lround(TCalibrationResult::kMaxFittedDelay_s / TCalibrationResult::kDelayStep_s));
    std::vector<double> sse(static_cast<size_t>(grid) + 1, sse0);
    size_t best = 0;
    for (int k = 1; k <= grid; k++)
    {
        size_t nk = 0;
        sse[static_cast<size_t>(k)] = headingSse(steps, k * TCalibrationResult::kDelayStep_s, nk);
        if (sse[static_cast<size_t>(k)] < sse[best])
        {
            best = static_cast<size_t>(k);
        }
    }
    auto& f = r.odometry_delay_s;
    f.n = n;
    f.method = "the delay whose re-cut increments err least in heading (grid of " +
               std::to_string(static_cast<int>(TCalibrationResult::kDelayStep_s * 1000)) +
               " ms), kept when n ln(SSE(0) / SSE(delay)) > " +
               std::to_string(TCalibrationResult::kDelayChi2).substr(0, 5);
    r.odomHeadingRms_deg = n > 0 ? mrpt::RAD2DEG(std::sqrt(sse0 / static_cast<double>(n))) : 0;
    r.odomHeadingRmsDelayed_deg = r.odomHeadingRms_deg;
    if (n < TCalibrationResult::kMinMovingIncrements || !(sse[best] > 0) ||
        static_cast<double>(n) * std::log(sse0 / sse[best]) <= TCalibrationResult::kDelayChi2)
    {
        f.value = 0;
        return;
    }
    f.value = static_cast<double>(best) * TCalibrationResult::kDelayStep_s;
    // The profile interval: the delays within chi2(1, 95 %) = 3.84 of the best.
    double half = 0;
    for (size_t k = 0; k < sse.size(); k++)
    {
        if (static_cast<double>(n) * std::log(sse[k] / sse[best]) <= 3.84)
        {
            half = std::max(half, std::abs(static_cast<double>(k) - static_cast<double>(best)) *
                                      TCalibrationResult::kDelayStep_s);
        }
    }
    f.ci95 = std::max(half, TCalibrationResult::kDelayStep_s);
    r.odomHeadingRmsDelayed_deg = mrpt::RAD2DEG(std::sqrt(sse[best] / static_cast<double>(n)));
}

}  // namespace semloc::detail

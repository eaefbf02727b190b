/* semloc — the fits of the compass, the position fixes and the DVL's motion model
 * (SensorModelCalibration; the detector kinds' are in SensorModelFits.cpp). */
#include <mrpt/poses/CPose2D.h>
#include <semloc/filter/MotionModelConfig.h>

#include <algorithm>
#include <cmath>

#include "calibration/CalibrationFits.h"
#include "calibration/SensorModelFits.h"
#include "experiment/Statistics.h"

namespace semloc::detail
{
namespace
{
constexpr double kDeg = M_PI / 180;
}  // namespace

void CompassFit::add(const mrpt::obs::CObservationIMU& imu, const GroundTruthRow& truth)
{
    const double mountYaw = imu.sensorPose.yaw();
    e.push_back(std::remainder(imu.get(mrpt::obs::IMU_YAW) - mountYaw - truth.phi, 2 * M_PI));
}

void CompassFit::fit()
{
    const double s = madSigma(e), mid = median(e);
    std::vector<double> in;
    for (const double v : e)
    {
        if (std::abs(v - mid) <= 5 * s)
        {
            in.push_back(v);
        }
    }
    double ms = 0;
    for (const double v : in)
    {
        ms += v * v;
    }
    const size_t n = e.size(), m = in.size();
    const double rms = std::sqrt(ms / static_cast<double>(std::max<size_t>(m, 1)));
    const double tau = autocorrelationTime(in, std::min<size_t>(m / 4, 5000));
    const double sigma = rms * std::sqrt(tau) / kDeg;
    out.keys.emplace_back(
        "sigma_deg",
        fitValue(sigma, m,
                 1.96 * sigma / std::sqrt(2.0 * std::max(static_cast<double>(m) / tau, 1.0)),
                 "RMS of the residuals within 5 robust sigmas (" + number(rms / kDeg) +
                     " deg) x sqrt of their autocorrelation time (" + number(tau) + " readings)",
                 TCalibrationResult::kMinResiduals, 1e-6, 180));
    const double out_ = static_cast<double>(n - m);
    out.keys.emplace_back("p_outlier",
                          fitValue((out_ + 0.5) / (static_cast<double>(n) + 1), n,
                                   1.96 * std::sqrt(out_ + 0.5) / (static_cast<double>(n) + 1),
                                   "share of the readings beyond 5 robust sigmas (Jeffreys)",
                                   TCalibrationResult::kMinChances, 0, 0.999999));
    out.samples = n;
    out.unit = "readings";
}

void FixFit::add(const mrpt::obs::CObservationRobotPose& fix, const GroundTruthRow& truth)
{
    ex.push_back(fix.pose.mean.x() - truth.x);
    ey.push_back(fix.pose.mean.y() - truth.y);
}

void FixFit::fit()
{
    std::vector<double> pooled = ex;
    pooled.insert(pooled.end(), ey.begin(), ey.end());
    const double s = madSigma(pooled);
    double in2 = 0, out2 = 0;
    size_t nIn = 0, nOut = 0;
    for (size_t i = 0; i < ex.size(); i++)
    {
        const double r2 = ex[i] * ex[i] + ey[i] * ey[i];
        const bool outlier = r2 > 18.42 * s * s;  // chi-square, 2 dof, 99.99 %
        (outlier ? out2 : in2) += r2;
        (outlier ? nOut : nIn)++;
    }
    const size_t n = ex.size();
    const double sigma = std::sqrt(in2 / (2.0 * static_cast<double>(std::max<size_t>(nIn, 1))));
    out.keys.emplace_back(
        "sigma_m",
        fitValue(sigma, nIn,
                 1.96 * sigma / std::sqrt(4.0 * static_cast<double>(std::max<size_t>(nIn, 1))),
                 "RMS of the x and y residuals within the 99.99 % radius "
                 "of their robust sigma",
                 TCalibrationResult::kMinResiduals, 1e-3, 1e6));
    const double k = static_cast<double>(nOut);
    out.keys.emplace_back("p_outlier",
                          fitValue((k + 0.5) / (static_cast<double>(n) + 1), n,
                                   1.96 * std::sqrt(k + 0.5) / (static_cast<double>(n) + 1),
                                   "share of the fixes beyond that radius (Jeffreys)",
                                   TCalibrationResult::kMinResiduals, 0, 0.999999));
    const double outSigma = std::sqrt(out2 / (2.0 * std::max(k, 1.0)));
    out.keys.emplace_back("outlier_sigma_m",
                          fitValue(std::max(outSigma, 3 * sigma), nOut, 0,
                                   "RMS of the outliers' x and y residuals (at least 3 "
                                   "sigma_m)",
                                   3, 1e-3, 1e7));
    out.samples = n;
    out.unit = "fixes";
}

void DvlFit::add(const mrpt::obs::CActionRobotMovement2D& move, const GroundTruthRow* truth)
{
    if (truth == nullptr)
    {
        havePrevious = false;
        return;
    }
    if (havePrevious)
    {
        const mrpt::poses::CPose2D a(previous.x, previous.y, previous.phi);
        const mrpt::poses::CPose2D b(truth->x, truth->y, truth->phi);
        const mrpt::poses::CPose2D inc = b - a, odo = move.poseChange->getMeanVal();
        const double d = std::hypot(inc.x(), inc.y());
        if (d >= TCalibrationResult::kMinMove_m)
        {
            const double ex = odo.x() - inc.x(), ey = odo.y() - inc.y();
            const double ephi = std::remainder(odo.phi() - inc.phi(), 2 * M_PI);
            sumXY += (ex * ex + ey * ey) / (d * d);
            sumPhi += ephi * ephi / (d * d);
            n++;
        }
    }
    previous = *truth;
    havePrevious = true;
}

void DvlFit::fit()
{
    const double nn = static_cast<double>(std::max<size_t>(n, 1));
    const double a1 = std::sqrt(sumXY / (2 * nn)), a3 = std::sqrt(sumPhi / nn) / kDeg;
    const auto range = [](const char* key) { return MotionModelConfig::TOptions::range(key); };
    const std::string how = "maximum likelihood of sigma = a d over the increments that moved";
    out.keys.emplace_back(
        "a1", fitValue(a1, n, 1.96 * a1 / std::sqrt(4 * nn), how + " (each body axis)",
                       TCalibrationResult::kMinMovingIncrements, range("a1").lo, range("a1").hi));
    out.keys.emplace_back(
        "a3", fitValue(a3, n, 1.96 * a3 / std::sqrt(2 * nn), how + " (the heading, deg/m)",
                       TCalibrationResult::kMinMovingIncrements, range("a3").lo, range("a3").hi));
    out.samples = n;
    out.unit = "increments";
}

}  // namespace semloc::detail

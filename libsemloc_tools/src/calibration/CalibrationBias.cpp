/* semloc — the detector's bias and the map's offset against the ground truth
 * (semloc-calibrate; docs/tools.md, "semloc-calibrate"). */
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/calibration/SensorCalibration.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <utility>

#include "calibration/CalibrationFits.h"

namespace semloc::detail
{
namespace
{
/** A number in 3 significant digits. */
std::string num(double v)
{
    std::ostringstream s;
    s << std::setprecision(3) << v;
    return s.str();
}

double median(std::vector<double> x)
{
    if (x.empty())
    {
        return 0;
    }
    const auto h = static_cast<std::ptrdiff_t>(x.size() / 2);
    std::nth_element(x.begin(), x.begin() + h, x.end());
    return x[static_cast<size_t>(h)];
}

/** The mean of the values within 3 robust sigmas of the median (all when the sigma is 0). */
double trimmedMean(const std::vector<double>& x)
{
    const double m = median(x), lim = 3 * madSigma(x);
    double sum = 0;
    size_t n = 0;
    for (const double v : x)
    {
        if (std::abs(v - m) <= lim)
        {
            sum += v;
            n++;
        }
    }
    return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

/** Least-squares rigid transform taking the points `p` (of `use`) onto `m` (2D Procrustes). */
RigidTransform2D procrustes(const TCalibrationSamples& s, const std::vector<size_t>& use)
{
    double px = 0, py = 0, mx = 0, my = 0;
    for (const size_t i : use)
    {
        px += s.detectedX_m[i];
        py += s.detectedY_m[i];
        mx += s.objectX_m[i];
        my += s.objectY_m[i];
    }
    const auto n = static_cast<double>(use.size());
    px /= n;
    py /= n;
    mx /= n;
    my /= n;
    double dot = 0, cross = 0;
    for (const size_t i : use)
    {
        const double ax = s.detectedX_m[i] - px, ay = s.detectedY_m[i] - py;
        const double bx = s.objectX_m[i] - mx, by = s.objectY_m[i] - my;
        dot += ax * bx + ay * by;
        cross += ax * by - ay * bx;
    }
    RigidTransform2D t;
    t.theta = (dot == 0 && cross == 0) ? 0.0 : std::atan2(cross, dot);
    const double c = std::cos(t.theta), sn = std::sin(t.theta);
    t.tx = mx - (c * px - sn * py);
    t.ty = my - (sn * px + c * py);
    return t;
}

/** Distance of pair `i` after the transform `t`. */
double pairDistance(const TCalibrationSamples& s, size_t i, const RigidTransform2D& t)
{
    const auto q = t.apply({s.detectedX_m[i], s.detectedY_m[i], 0});
    return std::hypot(q.x - s.objectX_m[i], q.y - s.objectY_m[i]);
}

/** The report of the transform `t`: its translation about the centroid of the objects of
 *  `use`, its rotation, and how far it moves them. */
void describe(const TCalibrationSamples& s, const std::vector<size_t>& use,
              const RigidTransform2D& t, TMapOffset& out)
{
    double cx = 0, cy = 0, ss = 0;
    std::set<std::pair<double, double>> objects;
    for (const size_t i : use)
    {
        cx += s.objectX_m[i];
        cy += s.objectY_m[i];
        objects.insert({s.objectX_m[i], s.objectY_m[i]});
    }
    const auto n = static_cast<double>(use.size());
    cx /= n;
    cy /= n;
    for (const size_t i : use)
    {
        const auto q = t.apply({s.objectX_m[i], s.objectY_m[i], 0});
        ss += (q.x - s.objectX_m[i]) * (q.x - s.objectX_m[i]) +
              (q.y - s.objectY_m[i]) * (q.y - s.objectY_m[i]);
    }
    const auto c = t.apply({cx, cy, 0});
    out.cx_m = cx;
    out.cy_m = cy;
    out.dx_m = c.x - cx;
    out.dy_m = c.y - cy;
    out.dtheta_deg = mrpt::RAD2DEG(mrpt::math::wrapToPi(t.theta));
    out.rms_m = std::sqrt(ss / n);
    out.n = use.size();
    out.objects = objects.size();
}
}  // namespace

mrpt::math::TPose2D RigidTransform2D::apply(const mrpt::math::TPose2D& p) const
{
    const double c = std::cos(theta), s = std::sin(theta);
    return {c * p.x - s * p.y + tx, s * p.x + c * p.y + ty, mrpt::math::wrapToPi(p.phi + theta)};
}

RigidTransform2D RigidTransform2D::after(const RigidTransform2D& first) const
{
    const auto t = apply({first.tx, first.ty, 0});
    RigidTransform2D out;
    out.theta = mrpt::math::wrapToPi(theta + first.theta);
    out.tx = t.x;
    out.ty = t.y;
    return out;
}

RigidTransform2D fitMapOffset(TCalibrationResult& r, const RigidTransform2D& sofar)
{
    const auto& s = r.samples;
    std::vector<size_t> use(s.detectedX_m.size());
    std::set<std::pair<double, double>> objects;
    for (size_t i = 0; i < use.size(); i++)
    {
        use[i] = i;
        objects.insert({s.objectX_m[i], s.objectY_m[i]});
    }
    const bool removed = r.mapOffset.removed;
    r.mapOffset = TMapOffset();
    r.mapOffset.removed = removed;
    r.mapOffset.n = use.size();
    r.mapOffset.objects = objects.size();
    if (use.size() < TCalibrationResult::kMinResiduals || objects.size() < 2)
    {
        return {};
    }
    RigidTransform2D t = procrustes(s, use);
    // Once again without the pairs far off (clutter the gate let in, a wrong match).
    std::vector<double> d;
    d.reserve(use.size());
    for (const size_t i : use)
    {
        d.push_back(pairDistance(s, i, t));
    }
    const double lim = 3.5 * median(d);
    std::vector<size_t> kept;
    for (const size_t i : use)
    {
        if (pairDistance(s, i, t) <= lim)
        {
            kept.push_back(i);
        }
    }
    if (kept.size() >= TCalibrationResult::kMinResiduals && kept.size() < use.size())
    {
        t = procrustes(s, kept);
        use = kept;
    }
    describe(s, use, t.after(sofar), r.mapOffset);
    r.mapOffset.fitted = true;
    return t;
}

void fitBias(TCalibrationResult& r)
{
    const auto& s = r.samples;
    auto& b = r.bias;
    b.range_m = trimmedMean(s.rangeResiduals_m);
    b.bearing_deg = trimmedMean(s.bearingResiduals_deg);
    b.sigmaRangeAround_m = r.sigma_range_m.value;
    b.sigmaBearingAround_deg = r.sigma_bearing_deg.value;
    b.sigmaRangeAtTruth_m = madSigma(s.rangeResidualsAtTruth_m);
    b.sigmaBearingAtTruth_deg = madSigma(s.bearingResidualsAtTruth_deg);
    // The filter's model has no bias: the sigma of a zero-mean Gaussian that best explains
    // residuals of mean b and sigma s (maximum likelihood) is sqrt(s^2 + b^2).
    const auto withBias = [](TCalibrationFit& f, double bias)
    {
        f.value = std::hypot(f.value, bias);
        f.method += ", with the mean residual (" + num(bias) + ") as sqrt(sigma^2 + mean^2)";
    };
    withBias(r.sigma_range_m, b.range_m);
    withBias(r.sigma_bearing_deg, b.bearing_deg);
}

}  // namespace semloc::detail

namespace semloc
{
namespace
{
/** "S about 0 (fitted)": the sigma about 0 as fitted, and what the ini has instead when it is
 *  not that (the base's value, a clamp). */
std::string aboutZero(const TCalibrationFit& f)
{
    using detail::num;
    using Status = TCalibrationFit::Status;
    const double fitted = f.status == Status::Clamped ? f.fitted : f.value / f.widenedBy;
    std::string t = num(fitted) + " about 0 (fitted";
    if (f.status == Status::TooLittleData)
    {
        t += "; not written: too little data";
    }
    else if (f.status == Status::Clamped)
    {
        t += "; written clamped to " + num(f.value / f.widenedBy);
    }
    return t + ")";
}
}  // namespace

std::string SensorCalibration::BiasText(const TCalibrationResult& r)
{
    using detail::num;
    const auto& b = r.bias;
    std::ostringstream t;
    t << "bias: mean range residual " << num(b.range_m) << " m, mean bearing residual "
      << num(b.bearing_deg) << " deg; sigma_range_m " << num(b.sigmaRangeAround_m)
      << " around the mean, " << aboutZero(r.sigma_range_m) << ", " << num(b.sigmaRangeAtTruth_m)
      << " at the ground truth as given; sigma_bearing_deg " << num(b.sigmaBearingAround_deg)
      << " around the mean, " << aboutZero(r.sigma_bearing_deg) << ", "
      << num(b.sigmaBearingAtTruth_deg) << " at the ground truth as given\n";
    if (!r.rangeBias_m.empty())
    {
        const auto& c = r.rangeBias_m;
        t << "range bias by bearing: " << num(c[0]) << " m on the axis, "
          << num(c[0] - c[1] + c[2] - c[3]) << " m at bearing -fov/2, "
          << num(c[0] + c[1] + c[2] + c[3])
          << " m at +fov/2; taken off each detection (range_bias_m), the "
             "range residuals' robust sigma "
          << num(r.sigmaRangeUncorrected_m) << " m with it left on\n";
    }
    const auto& o = r.mapOffset;
    if (o.fitted)
    {
        t << "map offset: dx " << num(o.dx_m) << " m, dy " << num(o.dy_m) << " m, dtheta "
          << num(o.dtheta_deg) << " deg about (" << num(o.cx_m) << ", " << num(o.cy_m)
          << "), moving the matched objects by " << num(o.rms_m) << " m RMS (" << o.n
          << " detections of " << o.objects << " objects; "
          << (o.removed ? "removed from the poses of the fits"
                        : "not removed: under half sigma_range_m")
          << ")\n";
    }
    else
    {
        t << "map offset: not fitted: too little data (" << o.n << " matched detections of "
          << o.objects << " objects; at least " << TCalibrationResult::kMinResiduals
          << " of 2 needed)\n";
    }
    return t.str();
}
}  // namespace semloc

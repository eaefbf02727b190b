/* semloc — semloc-calibrate's fits kept to what semloc-localize accepts: a fit outside the
 * range of its key is clamped into it, a fit from too little data is not written (the base's
 * value stays); the warnings that say so, and those of a bias and a map offset. */
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "calibration/CalibrationFits.h"
#include "io/Text.h"

namespace semloc
{
namespace detail
{
/** Marks `f` TooLittleData when `have` < `need`, else clamps it into `range` (`outside`: why
 *  it fell outside, as the data show it). */
void limit(TCalibrationFit& f, const config::TValueRange& range, size_t have, size_t need,
           const std::string& tooLittle, const std::string& outside)
{
    if (have < need || !std::isfinite(f.value))
    {
        f.status = TCalibrationFit::Status::TooLittleData;
        f.why = have < need ? tooLittle : "the fit is not a finite number";
        return;
    }
    const double v = range.clamp(f.value);
    if (v != f.value)
    {
        f.status = TCalibrationFit::Status::Clamped;
        f.fitted = f.value;
        f.why = outside;
        f.value = v;
    }
}

}  // namespace detail

namespace
{
using detail::limit;
using Status = TCalibrationFit::Status;

std::string num(double v)
{
    std::ostringstream s;
    s << std::setprecision(4) << v;
    return s.str();
}

std::string count(size_t n)
{
    return std::to_string(n);
}

/** "k detections of n in-view objects <where>" over the in-view objects whose range `in`. */
template <typename IN>
std::string detectedShare(const TCalibrationSamples& s, IN in, const std::string& where)
{
    size_t n = 0, k = 0;
    for (size_t i = 0; i < s.visibleRanges_m.size(); i++)
    {
        if (in(s.visibleRanges_m[i]))
        {
            n++;
            k += s.visibleDetected[i] != 0 ? 1 : 0;
        }
    }
    return count(k) + " detections of " + count(n) + " in-view objects " + where;
}

void limitDetector(TCalibrationResult& r)
{
    using L = CSemanticMap::TLikelihoodOptions;
    const auto& s = r.samples;
    const size_t kRes = TCalibrationResult::kMinResiduals, kCh = TCalibrationResult::kMinChances;
    const auto few = [](size_t n, const std::string& what, size_t need, const std::string& fit)
    { return count(n) + " " + what + ", fewer than the " + count(need) + " " + fit + " needs"; };
    limit(r.sigma_range_m, L::range("sigma_range_m"), s.rangeResiduals_m.size(), kRes,
          few(s.rangeResiduals_m.size(), "matched range residuals", kRes, "a sigma"),
          "the " + count(s.rangeResiduals_m.size()) + " matched range residuals do not vary");
    limit(r.sigma_bearing_deg, L::range("sigma_bearing_deg"), s.bearingResiduals_deg.size(), kRes,
          few(s.bearingResiduals_deg.size(), "matched bearing residuals", kRes, "a sigma"),
          "the " + count(s.bearingResiduals_deg.size()) + " matched bearing residuals do not vary");
    const double R = r.maxRange_m;
    const size_t chances = s.visibleRanges_m.size();
    const std::string line = few(chances, "in-view objects", kCh, "the detection line");
    limit(r.p_detect_near, L::range("p_detect_near"), chances, kCh, line,
          detectedShare(
              s, [&](double x) { return x <= R / 3; }, "within " + num(R / 3) + " m"));
    limit(r.p_detect_far, L::range("p_detect_far"), chances, kCh, line,
          detectedShare(
              s, [&](double x) { return x >= 2 * R / 3; }, "beyond " + num(2 * R / 3) + " m"));
    limit(r.p_detect_edge_ratio, L::range("p_detect_edge_ratio"), chances, kCh, line,
          "the fitted ratio lies outside [0, 1]");
    limit(r.clutter_per_scan, L::range("clutter_per_scan"), r.scans, TCalibrationResult::kMinScans,
          few(r.scans, "scans", TCalibrationResult::kMinScans, "a clutter rate"),
          count(r.clutter) + " detections matching no in-view object in " + count(r.scans) +
              " scans");
    const size_t matches = r.matched + r.confused;
    limit(r.p_confusion, L::range("p_confusion"), matches, kCh,
          few(matches, "matched detections", kCh, "a confusion rate"),
          count(r.confused) + " of " + count(matches) + " matched detections of another label");
    limit(
        r.p_range_outlier, L::range("p_range_outlier"), r.matched + r.misread, kCh,
        few(r.matched + r.misread, "detections of an object of their label", kCh, "a misread rate"),
        count(r.misread) + " misread of " + count(r.matched + r.misread) +
            " detections of an object of their label");
    limit(r.lookalike_persistence, L::range("lookalike_persistence"), r.scans,
          TCalibrationResult::kMinScans,
          few(r.scans, "scans", TCalibrationResult::kMinScans, "a look-alike persistence"),
          "the fitted chance lies outside [0, 1]");
}

void limitOdometry(TCalibrationResult& r)
{
    const auto& s = r.samples;
    r.movingIncrements = 0;
    for (size_t i = 0; i < s.odomDist_m.size(); i++)
    {
        const bool moved = s.odomDist_m[i] >= TCalibrationResult::kMinMove_m ||
                           s.odomTurn_rad[i] >= TCalibrationResult::kMinTurn_deg * M_PI / 180;
        r.movingIncrements += moved ? 1 : 0;
    }
    const size_t need = TCalibrationResult::kMinMovingIncrements;
    const std::string still = "the vehicle moved in " + count(r.movingIncrements) + " of " +
                              count(r.increments) + " odometry increments, fewer than the " +
                              count(need) + " the odometry's model needs";
    for (const auto& [key, fit] : {std::pair<const char*, TCalibrationFit*>{"a1", &r.a1},
                                   {"a2", &r.a2},
                                   {"a3", &r.a3},
                                   {"a4", &r.a4},
                                   {"minStdXY", &r.minStdXY},
                                   {"minStdPHI", &r.minStdPHI}})
    {
        limit(*fit, MotionModelConfig::TOptions::range(key), r.movingIncrements, need, still,
              "beyond what the filter takes");
    }
    if (r.movingIncrements < need)
    {
        r.headingDrifts = false;
    }
}

/** The warning of one fit, "" when it is as fitted. */
std::string fitWarning(const char* key, const TCalibrationFit& f)
{
    if (f.status == Status::Clamped)
    {
        return std::string(key) + ": fitted " + num(f.fitted) + " (" + f.why +
               "), clamped into the range semloc-localize accepts: " +
               detail::shortestText(f.value) + " written";
    }
    if (f.status == Status::TooLittleData)
    {
        return std::string(key) + ": not fitted, too little data (" + f.why +
               "): the base ini's value kept";
    }
    return "";
}

/** The warnings of a bias over half its sigma and of a map offset over sigma_range_m. */
void biasWarnings(const TCalibrationResult& r, std::vector<std::string>& out)
{
    using L = CSemanticMap::TLikelihoodOptions;
    const auto& b = r.bias;
    const double kBias = TCalibrationResult::kBiasSigmas;
    const double minRange = L::range("sigma_range_m").lo;
    const double minBearing = L::range("sigma_bearing_deg").lo;
    if (r.sigma_range_m.status != Status::TooLittleData &&
        std::abs(b.range_m) > std::max(kBias * b.sigmaRangeAround_m, minRange))
    {
        out.push_back("the range residuals' mean is " + num(b.range_m) +
                      " m, more than half their sigma (" + num(b.sigmaRangeAround_m) +
                      " m): a bias of the detector's ranges; sigma_range_m is written as "
                      "sqrt(sigma^2 + mean^2) = " +
                      num(r.sigma_range_m.value) + " m (the filter's model has no bias)");
    }
    if (!r.rangeBias_m.empty())
    {
        // The bias on the axis and at the two edges of the view (u = 0, -1, 1).
        const auto& c = r.rangeBias_m;
        const double axis = c[0], lo = c[0] - c[1] + c[2] - c[3], hi = c[0] + c[1] + c[2] + c[3];
        const double largest = std::max({std::abs(axis), std::abs(lo), std::abs(hi)});
        if (largest > std::max(kBias * b.sigmaRangeAround_m, minRange))
        {
            out.push_back("the detector's ranges read " + num(axis) + " m off on its axis, " +
                          num(lo) + " and " + num(hi) +
                          " m at the edges of its view, more than half their sigma (" +
                          num(b.sigmaRangeAround_m) +
                          " m): a range bias by bearing, taken off each detection "
                          "(range_bias_m); check the detector's range calibration");
        }
    }
    if (r.sigma_bearing_deg.status != Status::TooLittleData &&
        std::abs(b.bearing_deg) > std::max(kBias * b.sigmaBearingAround_deg, minBearing))
    {
        out.push_back("the bearing residuals' mean is " + num(b.bearing_deg) +
                      " deg, more than half their sigma (" + num(b.sigmaBearingAround_deg) +
                      " deg): a bias of the detector's bearings (its yaw on the vehicle?); "
                      "sigma_bearing_deg is written as sqrt(sigma^2 + mean^2) = " +
                      num(r.sigma_bearing_deg.value) + " deg");
    }
    const auto& o = r.mapOffset;
    if (o.fitted && o.rms_m > std::max(kBias * b.sigmaRangeAround_m, minRange))
    {
        out.push_back("the map is offset from the ground truth by dx " + num(o.dx_m) + " m, dy " +
                      num(o.dy_m) + " m, dtheta " + num(o.dtheta_deg) +
                      " deg (moving the matched objects by " + num(o.rms_m) +
                      " m RMS, more than half sigma_range_m " + num(b.sigmaRangeAround_m) +
                      (o.removed ? " m): the fits are made at the ground-truth poses moved by "
                                   "it (at the poses as given sigma_range_m would be " +
                                       num(b.sigmaRangeAtTruth_m) + " m)"
                                 : " m)") +
                      "; semloc-localize localizes in the map's frame, as far off the "
                      "ground truth: check the map's and the ground truth's frames");
    }
}
}  // namespace

namespace detail
{
void applyLimits(TCalibrationResult& r)
{
    limitDetector(r);
    limitOdometry(r);
}
}  // namespace detail

std::vector<std::string> SensorCalibration::Warnings(const TCalibrationResult& r)
{
    std::vector<std::string> out;
    for (const auto& [key, fit] :
         {std::pair<const char*, const TCalibrationFit*>{"sigma_range_m", &r.sigma_range_m},
          {"sigma_bearing_deg", &r.sigma_bearing_deg},
          {"p_detect_near", &r.p_detect_near},
          {"p_detect_far", &r.p_detect_far},
          {"p_detect_edge_ratio", &r.p_detect_edge_ratio},
          {"clutter_per_scan", &r.clutter_per_scan},
          {"p_confusion", &r.p_confusion},
          {"p_range_outlier", &r.p_range_outlier},
          {"lookalike_persistence", &r.lookalike_persistence},
          {"[MotionModel] a1", &r.a1},
          {"[MotionModel] a2", &r.a2},
          {"[MotionModel] a3", &r.a3},
          {"[MotionModel] a4", &r.a4},
          {"[MotionModel] minStdXY", &r.minStdXY},
          {"[MotionModel] minStdPHI", &r.minStdPHI}})
    {
        if (fit == &r.a1 && r.a1.status == Status::TooLittleData)
        {
            out.push_back("[MotionModel]: not fitted, too little data (" + r.a1.why +
                          "): the base ini's section kept");
            break;  // the odometry's keys are fitted together
        }
        if (std::string w = fitWarning(key, *fit); !w.empty())
        {
            out.push_back(std::move(w));
        }
    }
    biasWarnings(r, out);
    return out;
}

}  // namespace semloc

/* semloc — SensorModelCalibration::Estimate: the water column's sensor models fitted against
 * the ground truth (the ini and the summary are in SensorModelIni.cpp). */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <semloc/calibration/SensorModelCalibration.h>
#include <semloc/experiment/GroundTruth.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/compass/CCompassMap.h>
#include <semloc/models/detector/CObjectDetectorMap.h>
#include <semloc/models/fix/CPoseFixMap.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "calibration/CalibrationFits.h"
#include "calibration/CalibrationPasses.h"
#include "calibration/SensorModelFits.h"

namespace semloc
{
namespace detail
{
TCalibrationFit fitValue(double value, size_t n, double ci95, const std::string& method,
                         size_t minSamples, double lo, double hi)
{
    TCalibrationFit f;
    f.value = value;
    f.n = n;
    f.ci95 = ci95;
    f.method = method;
    limit(f, {lo, hi}, n, minSamples,
          std::to_string(n) + " samples, fewer than " + std::to_string(minSamples),
          value < lo ? "below " + number(lo) : "above " + number(hi));
    return f;
}

double autocorrelationTime(const std::vector<double>& x, size_t maxLag)
{
    const size_t n = x.size();
    if (n < 3)
    {
        return 1;
    }
    double mean = 0;
    for (const double v : x)
    {
        mean += v;
    }
    mean /= static_cast<double>(n);
    double c0 = 0;
    for (const double v : x)
    {
        c0 += (v - mean) * (v - mean);
    }
    if (!(c0 > 0))
    {
        return 1;
    }
    double tau = 1;
    for (size_t k = 1; k <= std::min(maxLag, n - 1); k++)
    {
        double ck = 0;
        for (size_t i = 0; i + k < n; i++)
        {
            ck += (x[i] - mean) * (x[i + k] - mean);
        }
        const double rho = ck / c0;
        if (!(rho > 0))
        {
            break;
        }
        tau += 2 * rho;
    }
    return tau;
}

}  // namespace detail

namespace
{
using detail::CompassFit;
using detail::DvlFit;
using detail::fitValue;
using detail::FixFit;
using detail::number;
constexpr double kDeg = M_PI / 180;

/** The vehicle's true pose at `t` (the nearest ground-truth row within the tolerance). */
const GroundTruthRow* truthAt(const GroundTruth& gt, mrpt::Clock::time_point t, double tol)
{
    return gt.nearest(mrpt::Clock::toDouble(t), tol);
}

/** The section of the `index`-th map of kind `kind`. */
std::string likelihoodSection(const std::string& kind, size_t index)
{
    return mrpt::format("MetricMap_%s_%02zu_likelihoodOpts", kind.c_str(), index);
}

/** A detector kind's matching and its samples, pass by pass. */
struct DetectorFit
{
    const CObjectDetectorMap* map = nullptr;
    TModelFits out;
    /** The gates: a disc of gate_m across (first pass) or 4 sigmas of the previous fits. */
    double gate_m = 3, sigmaRange = 0, sigmaBearing = 0;
    std::vector<double> dr, db, visibleX;
    std::vector<int> detected;
    size_t scans = 0, unmatched = 0;

    void clearSamples()
    {
        dr.clear();
        db.clear();
        visibleX.clear();
        detected.clear();
        scans = unmatched = 0;
    }

    /** The squared gate distance of detection `d` from the object in view `v` (> 1: out). */
    double gateDistance2(const CObjectDetectorMap::TScan::TDetection& d,
                         const CObjectDetectorMap::TInView& v, double& er, double& eb) const
    {
        er = map->measuresRange() ? d.range_m - v.range_m : 0;
        eb = map->measuresBearing() ? std::remainder(d.bearing_rad - v.bearing_rad, 2 * M_PI) : 0;
        if (!map->measuresBearing() && (d.bearing_rad > 0) != (v.side > 0))
        {
            return 1e300;  // the other side
        }
        if (sigmaRange > 0 || sigmaBearing > 0)
        {
            const double a = sigmaRange > 0 ? er / (4 * sigmaRange) : 0;
            const double b = sigmaBearing > 0 ? eb / (4 * sigmaBearing) : 0;
            return a * a + b * b;
        }
        const double across = v.range_m * eb;
        return (er * er + across * across) / (gate_m * gate_m);
    }

    void addScan(const CObservationSemantic& obs, const mrpt::math::TPose2D& pose)
    {
        const auto scan = map->scan(obs);
        const auto view = map->inView(scan, pose);
        struct Pair
        {
            double d2, er, eb;
            size_t det, vis;
        };
        std::vector<Pair> pairs;
        for (size_t j = 0; j < scan.detections.size(); j++)
        {
            for (size_t v = 0; v < view.size(); v++)
            {
                double er = 0, eb = 0;
                if (map->objects()[view[v].object].label != scan.detections[j].label)
                {
                    continue;
                }
                if (const double d2 = gateDistance2(scan.detections[j], view[v], er, eb); d2 <= 1)
                {
                    pairs.push_back({d2, er, eb, j, v});
                }
            }
        }
        std::sort(pairs.begin(), pairs.end(),
                  [](const Pair& a, const Pair& b)
                  { return a.d2 < b.d2 || (a.d2 == b.d2 && a.det < b.det); });
        std::vector<int> detTaken(scan.detections.size(), 0), visTaken(view.size(), 0);
        size_t matched = 0;
        for (const auto& p : pairs)
        {
            if (detTaken[p.det] == 0 && visTaken[p.vis] == 0)
            {
                detTaken[p.det] = visTaken[p.vis] = 1;
                dr.push_back(p.er);
                db.push_back(p.eb);
                matched++;
            }
        }
        const double maxRange = map->detectorParam().max_range_m;
        for (size_t v = 0; v < view.size(); v++)
        {
            visibleX.push_back(view[v].range_m / maxRange);
            detected.push_back(visTaken[v]);
        }
        unmatched += scan.detections.size() - matched;
        scans++;
    }

    /** The sigmas of this pass: the next pass's gates. */
    void narrowGates()
    {
        if (dr.size() >= TCalibrationResult::kMinResiduals)
        {
            sigmaRange = map->measuresRange() ? detail::madSigma(dr) : 0;
            sigmaBearing = map->measuresBearing() ? detail::madSigma(db) : 0;
        }
    }

    void fit()
    {
        const size_t n = dr.size();
        const auto sigmaFit = [n](double sigma, double scale, const char* what)
        {
            return fitValue(
                sigma * scale, n,
                1.96 * sigma * scale / std::sqrt(2.0 * static_cast<double>(std::max<size_t>(n, 1))),
                std::string("1.4826 MAD of the matched ") + what + " residuals",
                TCalibrationResult::kMinResiduals, 1e-6, 1e6);
        };
        if (map->measuresRange())
        {
            out.keys.emplace_back("sigma_range_m", sigmaFit(detail::madSigma(dr), 1, "range"));
        }
        if (map->measuresBearing())
        {
            out.keys.emplace_back("sigma_bearing_deg",
                                  sigmaFit(detail::madSigma(db), 1 / kDeg, "bearing"));
        }
        fitDetection();
        const double k = static_cast<double>(unmatched);
        const double s = static_cast<double>(std::max<size_t>(scans, 1));
        out.keys.emplace_back(
            "clutter_per_scan",
            fitValue((k + 0.5) / s, scans, 1.96 * std::sqrt(k + 0.5) / s,
                     "unmatched detections per scan (" + std::to_string(unmatched) + " in " +
                         std::to_string(scans) + " scans, Jeffreys' Poisson estimate)",
                     TCalibrationResult::kMinScans, 1e-9, 1e6));
        out.samples = scans;
        out.unit = "scans";
    }

    /** p_detect_near/far: the least-squares line of detected against range / max range. */
    void fitDetection()
    {
        const size_t n = visibleX.size();
        double mx = 0, my = 0;
        for (size_t i = 0; i < n; i++)
        {
            mx += visibleX[i];
            my += detected[i];
        }
        mx /= static_cast<double>(std::max<size_t>(n, 1));
        my /= static_cast<double>(std::max<size_t>(n, 1));
        double sxx = 0, sxy = 0;
        for (size_t i = 0; i < n; i++)
        {
            sxx += (visibleX[i] - mx) * (visibleX[i] - mx);
            sxy += (visibleX[i] - mx) * (detected[i] - my);
        }
        const double slope = sxx > 1e-12 * static_cast<double>(n) ? sxy / sxx : 0;
        // The line's 95 % half-width at x0: s sqrt(1/n + (x0 - mean)^2 / Sxx).
        double sse = 0;
        for (size_t i = 0; i < n; i++)
        {
            const double r = detected[i] - my - slope * (visibleX[i] - mx);
            sse += r * r;
        }
        const double nn = static_cast<double>(std::max<size_t>(n, 3));
        const double s2 = sse / (nn - 2);
        const auto ci = [&](double x0)
        { return 1.96 * std::sqrt(s2 * (1 / nn + (x0 - mx) * (x0 - mx) / std::max(sxx, 1e-12))); };
        const std::string how =
            "least-squares line of detected (0/1) against range / max_range_m "
            "over the objects in view";
        out.keys.emplace_back("p_detect_near", fitValue(my - slope * mx, n, ci(0), how + ", at 0",
                                                        TCalibrationResult::kMinChances, 0, 0.999));
        out.keys.emplace_back("p_detect_far",
                              fitValue(my + slope * (1 - mx), n, ci(1), how + ", at 1",
                                       TCalibrationResult::kMinChances, 0, 0.999));
    }
};

/** Every model's fit, walking the rawlog. */
struct Fits
{
    std::vector<DetectorFit> detectors;
    std::vector<CompassFit> compasses;
    std::vector<FixFit> fixes;
    std::unique_ptr<DvlFit> dvl;

    void observe(const mrpt::obs::CObservation& obs, const GroundTruth& gt, double tol,
                 bool detectorsOnly)
    {
        const GroundTruthRow* truth = truthAt(gt, obs.timestamp, tol);
        const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs);
        for (auto& d : detectors)
        {
            if (sem == nullptr)
            {
                // The other observations in frame order: a depth reading sets the sensor's
                // height for the scans after it.
                d.map->prepareObservation(obs);
            }
            else if (truth != nullptr && d.map->uses(obs))
            {
                d.addScan(*sem, {truth->x, truth->y, truth->phi});
            }
        }
        if (detectorsOnly || truth == nullptr)
        {
            return;
        }
        if (const auto* imu = dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs))
        {
            for (auto& c : compasses)
            {
                if (c.map->uses(obs))
                {
                    c.add(*imu, *truth);
                }
            }
        }
        if (const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs))
        {
            for (auto& f : fixes)
            {
                if (f.map->uses(obs))
                {
                    f.add(*fix, *truth);
                }
            }
        }
    }

    void walk(const detail::RawlogWalk& walk, const GroundTruth& gt, double tol, bool detectorsOnly)
    {
        walk(
            [&](size_t, const mrpt::serialization::CSerializable::Ptr& e)
            {
                if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(e))
                {
                    for (const auto& o : *sf)
                    {
                        observe(*o, gt, tol, detectorsOnly);
                    }
                }
                else if (const auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(e))
                {
                    observe(*o, gt, tol, detectorsOnly);
                }
                else if (const auto acts =
                             std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(e);
                         acts && dvl && !detectorsOnly)
                {
                    if (const auto move = acts->getBestMovementEstimation())
                    {
                        dvl->add(*move, truthAt(gt, move->timestamp, tol));
                    }
                }
            });
    }
};

/** The models of the maps of `lm` this file fits, named by their sections. */
Fits modelsOf(const LocalizationMap& lm, double gate_m)
{
    Fits f;
    std::map<std::string, size_t> count;
    for (const auto& m : lm.map->maps)
    {
        const std::string kind = LocalizationMap::kindOf(*m);
        const std::string section = likelihoodSection(kind, count[kind]++);
        if (const auto* d = dynamic_cast<const CObjectDetectorMap*>(m.get()))
        {
            DetectorFit fit;
            fit.map = d;
            fit.gate_m = gate_m;
            fit.out.section = section;
            fit.out.name = kind + " '" + d->detectorParam().sensor_label + "'";
            f.detectors.push_back(std::move(fit));
        }
        else if (const auto* c = dynamic_cast<const CCompassMap*>(m.get()))
        {
            f.compasses.push_back({c, {section, kind, 0, "", {}}, {}});
        }
        else if (const auto* x = dynamic_cast<const CPoseFixMap*>(m.get()))
        {
            f.fixes.push_back({x, {section, kind, 0, "", {}}, {}, {}});
        }
    }
    return f;
}
}  // namespace

bool SensorModelCalibration::HasModels(const std::string& baseIni)
{
    const mrpt::config::CConfigFileMemory ini(baseIni);
    for (const char* kind :
         {"sideScanMap", "forwardSonarMap", "bearingCameraMap", "compassMap", "poseFixMap"})
    {
        if (ini.read_int("MetricMap", std::string(kind) + "_count", 0) > 0)
        {
            return true;
        }
    }
    return ini.read_string(MotionModelConfig::kSection, "kind", "") == "dvl";
}

std::vector<TModelFits> SensorModelCalibration::Estimate(const std::string& rawlogPath,
                                                         const std::string& baseIni,
                                                         const std::string& basePath,
                                                         const std::string& worldPath,
                                                         const std::vector<GroundTruthRow>& gt,
                                                         double gtTolerance_s, double gate_m)
{
    (void)basePath;
    const World world = World::FromFile(worldPath);
    const mrpt::config::CConfigFileMemory ini(baseIni);
    const auto lm = LocalizationMap::FromConfig(ini, world, worldPath);
    Fits fits = modelsOf(lm, gate_m);
    if (ini.read_string(MotionModelConfig::kSection, "kind", "") == "dvl")
    {
        fits.dvl = std::make_unique<DvlFit>();
        fits.dvl->out.section = MotionModelConfig::kSection;
        fits.dvl->out.name = "[MotionModel] dvl";
    }
    const GroundTruth truth(gt);
    const auto walk = detail::walkFile(rawlogPath);
    fits.walk(walk, truth, gtTolerance_s, false);
    if (!fits.detectors.empty())
    {
        // The second pass gates by the first pass's sigmas.
        for (auto& d : fits.detectors)
        {
            d.narrowGates();
            d.clearSamples();
        }
        fits.walk(walk, truth, gtTolerance_s, true);
    }
    std::vector<TModelFits> out;
    for (auto& d : fits.detectors)
    {
        d.fit();
        out.push_back(d.out);
    }
    for (auto& c : fits.compasses)
    {
        c.fit();
        out.push_back(c.out);
    }
    for (auto& f : fits.fixes)
    {
        f.fit();
        out.push_back(f.out);
    }
    if (fits.dvl)
    {
        fits.dvl->fit();
        out.push_back(fits.dvl->out);
    }
    return out;
}

}  // namespace semloc

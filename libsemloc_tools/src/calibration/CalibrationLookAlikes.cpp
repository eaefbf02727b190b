/* semloc — semloc-calibrate's fit of the look-alike persistence (CalibrationLookAlikes.h). */
#include "calibration/CalibrationLookAlikes.h"

#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace semloc::detail
{
void addLookAlikeScan(const CObservationSemantic& obs, const mrpt::poses::CPose2D& sensor,
                      const std::vector<int>& detTo, const std::vector<std::string>& labels,
                      double sigmaRange_m, double sigmaBearing_rad,
                      const SensorCalibration::TOptions& o, LookAlikeMemory& memory,
                      TCalibrationSamples& s)
{
    const double R = obs.maxRange_m, fov = std::min(obs.fov_rad, 2 * M_PI);
    if (!(sigmaRange_m > 0) || !(sigmaBearing_rad > 0) || obs.timestamp == INVALID_TIMESTAMP ||
        !(R > 0) || !(fov > 0) || labels.empty())
    {
        return;
    }
    const double t = mrpt::Clock::toDouble(obs.timestamp);
    memory.forget(t, o.lookAlikeWindow_s);
    double inView = 0;
    for (const auto& q : memory.points())
    {
        const auto local = sensor.inverseComposePoint(mrpt::math::TPoint2D(q.x, q.y));
        const bool within = local.norm() <= R &&
                            (fov >= 2 * M_PI || std::abs(std::atan2(local.y, local.x)) <= fov / 2);
        inView += q.t < t && within ? 1 : 0;
    }
    s.lookAlikeInView.push_back(inView);
    const double uniform = 1.0 / (R * fov * static_cast<double>(labels.size()));
    for (size_t k = 0; k < obs.detections.size(); k++)
    {
        const auto& d = obs.detections[k];
        if (std::find(labels.begin(), labels.end(), d.label) == labels.end())
        {
            continue;
        }
        const auto at = sensor.composePoint(mrpt::math::TPoint2D(
            d.range_m * std::cos(d.bearing_rad), d.range_m * std::sin(d.bearing_rad)));
        LookAlikeMemory::Point p;
        p.x = at.x;
        p.y = at.y;
        p.var = sigmaRange_m * sigmaRange_m +
                d.range_m * d.range_m * sigmaBearing_rad * sigmaBearing_rad;
        p.t = t;
        p.label = d.label;
        if (detTo[k] < 0)
        {
            s.lookAlikeDensity.push_back(d.range_m *
                                         memory.nearestDensity(p, o.lookAlikeSpeed_mps));
            s.lookAlikeUniform.push_back(uniform);
        }
        memory.remember(std::move(p));
    }
}

namespace
{
std::string text(double v)
{
    std::ostringstream o;
    o.precision(3);
    o << v;
    return o.str();
}

/** The clutter's Poisson log-likelihood at uniform rate `lambda` and persistence `rho`. */
double logLikelihood(const TCalibrationSamples& s, double scans, double inView, double lambda,
                     double rho)
{
    double ll = -lambda * scans - rho * inView;
    for (size_t k = 0; k < s.lookAlikeDensity.size(); k++)
    {
        ll += std::log(lambda * s.lookAlikeUniform[k] + rho * s.lookAlikeDensity[k]);
    }
    return ll;
}
}  // namespace

void fitLookAlikes(TCalibrationResult& r)
{
    const auto& s = r.samples;
    auto& f = r.lookalike_persistence;
    const double scans = static_cast<double>(s.lookAlikeInView.size());
    const double inView = std::accumulate(s.lookAlikeInView.begin(), s.lookAlikeInView.end(), 0.0);
    const double clutter = static_cast<double>(s.lookAlikeDensity.size());
    f = TCalibrationFit();
    f.n = s.lookAlikeDensity.size();
    r.lookAlikeResightings = 0;
    if (clutter == 0 || inView == 0)
    {
        f.method = "no clutter detection of a map label, or none remembered in view";
        return;
    }
    // Expectation-maximization of the two-component Poisson intensity: each clutter
    // detection's share from the re-sighting component, then both rates from the shares.
    double lambda = 0.5 * clutter / scans, rho = std::min(1.0, 0.5 * clutter / inView);
    double share = 0;
    for (int it = 0; it < 2000; it++)
    {
        share = 0;
        for (size_t k = 0; k < s.lookAlikeDensity.size(); k++)
        {
            const double g = rho * s.lookAlikeDensity[k];
            share += g / (lambda * s.lookAlikeUniform[k] + g);
        }
        const double nextRho = std::min(1.0, share / inView);
        const double nextLambda = std::max(clutter - share, 1e-9) / scans;
        const bool done = std::abs(nextRho - rho) < 1e-10 && std::abs(nextLambda - lambda) < 1e-10;
        rho = nextRho;
        lambda = nextLambda;
        if (done)
        {
            break;
        }
    }
    const double lr = 2 * (logLikelihood(s, scans, inView, lambda, rho) -
                           logLikelihood(s, scans, inView, clutter / scans, 0));
    // The interval from the observed information of (lambda, rho).
    double a = 0, b = 0, c = 0;
    for (size_t k = 0; k < s.lookAlikeDensity.size(); k++)
    {
        const double u = s.lookAlikeUniform[k], g = s.lookAlikeDensity[k];
        const double den = lambda * u + rho * g;
        a += u * u / (den * den);
        b += u * g / (den * den);
        c += g * g / (den * den);
    }
    const double det = a * c - b * b;
    f.ci95 = det > 0 ? 1.96 * std::sqrt(a / det) : 0.0;
    const std::string how = std::to_string(s.lookAlikeDensity.size()) +
                            " clutter detections of map labels, " + text(share) +
                            " of them re-sightings, of " + text(inView) +
                            " remembered detections in view; likelihood ratio " + text(lr);
    if (!(lr > TCalibrationResult::kLookAlikeChi2))
    {
        f.method = how + ": not significant, 0";
        return;
    }
    f.value = rho;
    f.fitted = rho;
    f.method = how;
    r.lookAlikeResightings = share;
    // The filter adds the re-sightings to a uniform part: the clutter rate less them.
    auto& cl = r.clutter_per_scan;
    cl.value = std::max(0.0, cl.value - share / static_cast<double>(r.scans));
    cl.method += ", less " + text(share) + " look-alike re-sightings";
}
}  // namespace semloc::detail

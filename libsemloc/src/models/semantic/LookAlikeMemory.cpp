/* semloc — the look-alike persistence's memory of detections (see LookAlikeMemory.h). */
#include <semloc/models/semantic/LookAlikeMemory.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/system/datetime.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <algorithm>
#include <cmath>

namespace semloc
{
void LookAlikeMemory::note(const CObservationSemantic& obs, const CSemanticMap& map,
                           const mrpt::math::TPose2D& odometry, std::vector<double>& factors)
{
    const auto& lo = map.likelihoodOptions;
    factors.assign(obs.detections.size(), 0.0);
    if (obs.timestamp == INVALID_TIMESTAMP)
    {
        THROW_EXCEPTION(
            "a semantic observation without a timestamp: lookalike_persistence > 0 needs the "
            "time between scans (set the timestamps, or lookalike_persistence = 0)");
    }
    const double t = mrpt::Clock::toDouble(obs.timestamp);
    forget(t, lo.lookalike.lookalike_window_s);
    const double kappa = map.clutterDensity(obs);
    const double R = lo.maxRange(obs), fov = lo.fieldOfView(obs);
    const double sb = lo.detector.sigma_bearing_deg * M_PI / 180.0;
    const double sr2 = lo.detector.sigma_range_m * lo.detector.sigma_range_m;
    const double u = lo.lookalike.lookalike_speed_mps;
    // The detector's pose in the odometry frame.
    const auto& sp = obs.sensorPose;
    const double c = std::cos(odometry.phi), s = std::sin(odometry.phi);
    const double sx = odometry.x + c * sp.x() - s * sp.y();
    const double sy = odometry.y + s * sp.x() + c * sp.y();
    const double syaw = odometry.phi + sp.yaw();
    for (size_t k = 0; k < obs.detections.size(); k++)
    {
        const auto& d = obs.detections[k];
        if (!map.isUsable(obs, d) || map.candidatesOf(obs, d).empty())
        {
            continue;
        }
        const double r = lo.correctedRange(d.range_m, d.bearing_rad, R, fov);
        Point p;
        p.x = sx + r * std::cos(syaw + d.bearing_rad);
        p.y = sy + r * std::sin(syaw + d.bearing_rad);
        p.var = sr2 + r * r * sb * sb;
        p.t = t;
        p.label = d.label;
        const double best = nearestDensity(p, u);
        if (kappa > 0)
        {
            factors[k] = std::log1p(lo.lookalike.lookalike_persistence * r * best / kappa);
        }
        remember(std::move(p));
    }
}

void LookAlikeMemory::forget(double t, double window_s)
{
    if (!m_points.empty() && t < m_points.back().t)
    {
        m_points.clear();  // the log went back in time: nothing earlier is known
    }
    while (!m_points.empty() && t - m_points.front().t > window_s)
    {
        m_points.pop_front();
    }
}

double LookAlikeMemory::nearestDensity(const Point& p, double speed_mps) const
{
    double best = 0;
    for (const Point& q : m_points)
    {
        if (q.t >= p.t || q.label != p.label)
        {
            continue;  // the same scan, or another label
        }
        const double dt = p.t - q.t;
        const double var = p.var + q.var + speed_mps * speed_mps * dt * dt;
        const double d2 = (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
        best = std::max(best, std::exp(-0.5 * d2 / var) / (2 * M_PI * var));
    }
    return best;
}
}  // namespace semloc

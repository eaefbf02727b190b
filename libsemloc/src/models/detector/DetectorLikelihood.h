/* semloc — the detector models' likelihood over a block of poses, one kind's geometry inlined
 * (private; docs/design.md, "The detector models"). */
#pragma once

#include <semloc/models/detector/CObjectDetectorMap.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace semloc::detail
{
/** What a kind's geometry says of one object seen from the sensor. */
struct TSeen
{
    /** The range the kind measures (slant or horizontal) [m]. */
    double range = 0;
    /** The bearing in the sensor's frame [rad] (kinds that measure one). */
    double bearing = 0;
    /** +1 port (left), -1 starboard (the side-scan's side). */
    int side = 0;
};

/** P_D at range r (linear from near at 0 to far at R, held at far beyond). */
inline double detectionProbability(const CObjectDetectorMap::TDetectorParam& p, double r)
{
    const double t = std::min(r / p.max_range_m, 1.0);
    return p.p_detect_near + (p.p_detect_far - p.p_detect_near) * t;
}

/** The Gaussian density N(d; 0, sigma). */
inline double gaussianDensity(double d, double sigma)
{
    constexpr double kInvSqrt2Pi = 0.39894228040143267794;
    const double u = d / sigma;
    return kInvSqrt2Pi / sigma * std::exp(-0.5 * u * u);
}

/** A range residual's density: the Gaussian, mixed with the uniform over the window when
 *  ranges may be misread. */
inline double rangeDensity(const CObjectDetectorMap::TDetectorParam& p, double d)
{
    const double g = gaussianDensity(d, p.sigma_range_m);
    if (p.p_range_outlier <= 0)
    {
        return g;
    }
    return (1 - p.p_range_outlier) * g +
           p.p_range_outlier / std::max(p.max_range_m - p.min_range_m, 1e-9);
}

/** The sensor in the world for the vehicle at `pose`: its position and heading's cosine and
 *  sine (phi + mount yaw by the sum's formulas: the same bits as its own cosine and sine for a
 *  mount along the vehicle's axis, yaw 0). */
struct SensorInWorld
{
    double x, y, c, s;

    SensorInWorld(const CObjectDetectorMap::TScan& scan, const mrpt::math::TPose2D& pose, double cm,
                  double sm)
    {
        const double cp = std::cos(pose.phi), sp = std::sin(pose.phi);
        x = pose.x + cp * scan.mountX - sp * scan.mountY;
        y = pose.y + sp * scan.mountX + cp * scan.mountY;
        c = cp * cm - sp * sm;
        s = sp * cm + cp * sm;
    }
    /** Object `o` in the sensor's horizontal frame: (u, w), x ahead, y to port. */
    void toSensor(const CObjectDetectorMap::TObject& o, double& u, double& w) const
    {
        const double dx = o.x - x, dy = o.y - y;
        u = c * dx + s * dy;
        w = -s * dx + c * dy;
    }
};

/** CObjectDetectorMap::inView() for Geometry `g` (detectorLogLikelihoods()'s). */
template <typename Geometry>
std::vector<CObjectDetectorMap::TInView> detectorInView(const CObjectDetectorMap& map,
                                                        const Geometry& g,
                                                        const CObjectDetectorMap::TScan& scan,
                                                        const mrpt::math::TPose2D& pose)
{
    const SensorInWorld sensor(scan, pose, std::cos(scan.mountYaw), std::sin(scan.mountYaw));
    std::vector<CObjectDetectorMap::TInView> out;
    map.forEachCellNear(sensor.x, sensor.y, map.detectorParam().max_range_m,
                        [&](uint32_t b, uint32_t e)
                        {
                            for (uint32_t k = b; k < e; k++)
                            {
                                const uint32_t idx = map.cellObjects()[k];
                                const auto& o = map.objects()[idx];
                                double u = 0, w = 0;
                                sensor.toSensor(o, u, w);
                                TSeen seen;
                                if (g.see(u, w, o.z - scan.sensorZ, seen))
                                {
                                    out.push_back({idx, seen.range, seen.bearing, seen.side});
                                }
                            }
                        });
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.object < b.object; });
    return out;
}

/** out[i] = log p(scan | poses[i]) for Geometry `g`: `g.see(u, w, dz, seen)` (the object at
 *  (u, w) in the sensor's horizontal frame, x ahead, y to port, dz above the sensor: false
 *  when out of view, else its measured quantities) and `g.density(detection, seen)` (the
 *  detection's density given the object). Safe from several threads at once. */
template <typename Geometry>
void detectorLogLikelihoods(const CObjectDetectorMap& map, const Geometry& g,
                            const CObjectDetectorMap::TScan& scan, const mrpt::math::TPose2D* poses,
                            size_t n, double* out)
{
    const auto& p = map.detectorParam();
    const auto& objects = map.objects();
    const auto& cells = map.cellObjects();
    const size_t l = scan.detections.size();
    const double kappa = std::exp(scan.logKappa);
    const size_t nLabels = map.labels().size();
    const double cm = std::cos(scan.mountYaw), sm = std::sin(scan.mountYaw);
    thread_local std::vector<double> acc;
    acc.resize(l);
    for (size_t i = 0; i < n; i++)
    {
        const SensorInWorld sensor(scan, poses[i], cm, sm);
        std::fill(acc.begin(), acc.end(), kappa);
        double missed = 0;
        map.forEachCellNear(sensor.x, sensor.y, p.max_range_m,
                            [&](uint32_t b, uint32_t e)
                            {
                                for (uint32_t k = b; k < e; k++)
                                {
                                    const auto& o = objects[cells[k]];
                                    double u = 0, w = 0;
                                    sensor.toSensor(o, u, w);
                                    TSeen seen;
                                    if (!g.see(u, w, o.z - scan.sensorZ, seen))
                                    {
                                        continue;
                                    }
                                    const double pd = detectionProbability(p, seen.range);
                                    missed += std::log1p(-pd);
                                    if (o.label >= nLabels || pd <= 0)
                                    {
                                        continue;
                                    }
                                    const double ratio = pd / (1 - pd);
                                    for (uint32_t j = scan.labelBegin[o.label];
                                         j < scan.labelBegin[o.label + 1]; j++)
                                    {
                                        acc[j] += ratio * g.density(scan.detections[j], seen);
                                    }
                                }
                            });
        double sum = scan.minusLambda + missed;
        for (size_t j = 0; j < l; j++)
        {
            sum += std::log(acc[j]);
        }
        out[i] = sum;
    }
}

/** An angle's difference wrapped to [-pi, pi]. */
inline double angleDifference(double a, double b)
{
    return std::remainder(a - b, 2 * M_PI);
}

/** A fan ahead of the sensor (the forward-looking sonar's, the camera's): the bearing within
 *  half the horizontal field of view, the depression angle (down from the horizontal)
 *  within half the vertical one about the tilt (no limit at 180 deg), the range in the
 *  window. */
struct FanView
{
    const CObjectDetectorMap::TDetectorParam& p;
    double halfFov, tilt, halfVerticalFov;

    bool see(double u, double w, double dz, TSeen& seen) const
    {
        const double ground2 = u * u + w * w;
        seen.range = std::sqrt(p.slant ? ground2 + dz * dz : ground2);
        if (seen.range < p.min_range_m || seen.range > p.max_range_m)
        {
            return false;
        }
        seen.bearing = std::atan2(w, u);
        if (std::abs(seen.bearing) > halfFov)
        {
            return false;
        }
        return halfVerticalFov >= 0.5 * M_PI ||
               std::abs(std::atan2(-dz, std::sqrt(ground2)) - tilt) <= halfVerticalFov;
    }
};

}  // namespace semloc::detail

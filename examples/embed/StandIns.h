/* The robot's sensors as the examples stand them in: a noisy odometry and an object detector
 * that reports the world's objects in its view. On a vehicle, odometry comes from the DVL and
 * compass, detections from the object recognizer. */
#pragma once

#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>

namespace standin
{
/** The odometry: the true increment `u` with Gaussian noise (2 cm, 0.3 degrees a step), and
 *  MRPT's default Gaussian odometry model around the reading. */
inline mrpt::obs::CActionRobotMovement2D odometryReading(const mrpt::poses::CPose2D& u,
                                                         mrpt::random::CRandomGenerator& rng)
{
    const mrpt::poses::CPose2D reading(u.x() + 0.02 * rng.drawGaussian1D_normalized(),
                                       u.y() + 0.02 * rng.drawGaussian1D_normalized(),
                                       u.phi() + 0.005 * rng.drawGaussian1D_normalized());
    mrpt::obs::CActionRobotMovement2D action;
    action.computeFromOdometry(reading, {});
    return action;
}

/** What the detector sees. */
struct Detector
{
    double maxRange_m = 20.0;
    double fov_deg = 120.0;
    /** P(an object in view is detected); 1: every one (no random draw). */
    double p_detect = 1.0;
};

/** A scan of `detector` from the true pose `vehicle`: each object of `world` in view, detected
 *  with p_detect, its range (10 cm) and bearing (0.6 degrees) with noise, within the view; its
 *  label only (no id: the map tells objects apart). */
inline semloc::CObservationSemantic::Ptr detectorScan(const Detector& detector,
                                                      const semloc::World& world,
                                                      const mrpt::poses::CPose2D& vehicle,
                                                      mrpt::random::CRandomGenerator& rng)
{
    auto scan = semloc::CObservationSemantic::Create();
    scan->maxRange_m = detector.maxRange_m;
    scan->fov_rad = detector.fov_deg * M_PI / 180.0;
    const double half = scan->fov_rad / 2;
    for (const auto& object : world.objects)
    {
        const double dx = object.center.x - vehicle.x(), dy = object.center.y - vehicle.y();
        const double range = std::hypot(dx, dy);
        const double bearing = mrpt::math::wrapToPi(std::atan2(dy, dx) - vehicle.phi());
        if (range > scan->maxRange_m || std::abs(bearing) > half ||
            (detector.p_detect < 1 && rng.drawUniform(0.0, 1.0) > detector.p_detect))
        {
            continue;
        }
        semloc::TSemanticDetection d;
        d.label = object.label;
        d.range_m =
            std::clamp(range + 0.1 * rng.drawGaussian1D_normalized(), 0.0, scan->maxRange_m);
        d.bearing_rad = std::clamp(bearing + 0.01 * rng.drawGaussian1D_normalized(), -half, half);
        scan->detections.push_back(d);
    }
    return scan;
}
}  // namespace standin

/* A robot's localization loop with semloc: every step, feed the odometry increment and the
 * object detector's output to the localizer and read the pose estimate.
 *   robot_loop <world.yaml>
 * It links semloc::semloc alone, the core a robot needs. The "robot" here is two stand-ins
 * written below (a noisy odometry and a detector that reports the world's objects in view);
 * on a vehicle, odometry and detections come from the DVL/compass and the object recognizer. */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/Localizer.h>
#include <semloc/maps/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cmath>
#include <cstdio>

namespace
{
/** The odometry's stand-in: the true increment with Gaussian noise, and MRPT's Gaussian
 *  odometry model around the reading. */
mrpt::obs::CActionRobotMovement2D odometryReading(const mrpt::poses::CPose2D& u,
                                                  mrpt::random::CRandomGenerator& rng)
{
    const mrpt::poses::CPose2D reading(u.x() + 0.02 * rng.drawGaussian1D_normalized(),
                                       u.y() + 0.02 * rng.drawGaussian1D_normalized(),
                                       u.phi() + 0.005 * rng.drawGaussian1D_normalized());
    mrpt::obs::CActionRobotMovement2D action;
    action.computeFromOdometry(reading, {});  // MRPT's default Gaussian model
    return action;
}

/** The detector's stand-in: every object of the world within 20 m and a 120 degree view,
 *  its range and bearing with noise, its label (no id: the map tells objects apart). */
semloc::CObservationSemantic::Ptr detectorScan(const semloc::World& world,
                                               const mrpt::poses::CPose2D& vehicle,
                                               mrpt::random::CRandomGenerator& rng)
{
    auto scan = semloc::CObservationSemantic::Create();
    scan->maxRange_m = 20.0;
    scan->fov_rad = 120.0 * M_PI / 180.0;
    for (const auto& object : world.objects)
    {
        const double dx = object.center.x - vehicle.x(), dy = object.center.y - vehicle.y();
        const double range = std::hypot(dx, dy);
        const double bearing = mrpt::math::wrapToPi(std::atan2(dy, dx) - vehicle.phi());
        if (range > scan->maxRange_m || std::abs(bearing) > scan->fov_rad / 2)
            continue;
        semloc::TSemanticDetection d;
        d.label = object.label;
        d.range_m = std::max(0.0, range + 0.1 * rng.drawGaussian1D_normalized());
        d.bearing_rad = mrpt::math::wrapToPi(bearing + 0.01 * rng.drawGaussian1D_normalized());
        scan->detections.push_back(d);
    }
    return scan;
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: robot_loop <world.yaml>\n");
        return 1;
    }
    const auto world = semloc::World::FromFile(argv[1]);

    // The map the robot knows: its semantic objects.
    auto map = mrpt::maps::CMultiMetricMap::Create();
    auto semantic = semloc::CSemanticMap::Create();
    semantic->likelihoodOptions.model = semloc::CSemanticMap::Model::Probabilistic;
    semantic->loadFromWorld(world);
    map->maps.push_back(semantic);

    // Global localization: particles uniform over the world's free space.
    semloc::Localizer::TOptions opts;
    opts.particles_count = 20000;
    opts.seed = 7;
    opts.free_space_prior = true;  // particles inside structures or off the map weigh 0
    semloc::Localizer localizer(opts, map, &world);

    // The random numbers of the sensors' stand-ins.
    mrpt::random::CRandomGenerator rng(42);

    mrpt::poses::CPose2D truth(world.trajectory->waypoints[0].x, world.trajectory->waypoints[0].y,
                               0);
    const mrpt::poses::CPose2D u(0.5, 0, 0);  // the robot drives straight on at 0.5 m/step
    double err = 0;
    for (int k = 0; k < 60; k++)
    {
        truth = truth + u;
        mrpt::obs::CActionCollection action;
        action.insert(odometryReading(u, rng));
        mrpt::obs::CSensoryFrame frame;
        frame.insert(detectorScan(world, truth, rng));

        localizer.step(action, frame);  // prediction + likelihood + resampling

        const auto est = localizer.mean();
        err = std::hypot(est.x() - truth.x(), est.y() - truth.y());
        std::printf("step %2d  estimate (%6.2f, %6.2f, %7.2f deg)  error %.2f m  var %.3f m^2\n", k,
                    est.x(), est.y(), est.phi() * 180 / M_PI, err, localizer.varianceXY());
    }
    std::printf("final error %.3f m\n", err);
    return err < 1.0 ? 0 : 2;
}

/* A robot's localization loop with semloc: every step, feed the odometry increment and the
 * object detector's output to the localizer and read the pose estimate.
 *   robot_loop <world.yaml>
 * It links semloc::semloc alone, the core a robot needs. The "robot" here is two stand-ins
 * (StandIns.h: a noisy odometry and a detector of 20 m and 120 degrees that reports the
 * world's objects in view); on a vehicle, odometry and detections come from the DVL/compass
 * and the object recognizer. */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/filter/Localizer.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <cstdio>

#include "StandIns.h"

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
        action.insert(standin::odometryReading(u, rng));
        mrpt::obs::CSensoryFrame frame;
        frame.insert(standin::detectorScan(standin::Detector{}, world, truth, rng));

        localizer.step(action, frame);  // prediction + likelihood + resampling

        const auto est = localizer.mean();
        err = std::hypot(est.x() - truth.x(), est.y() - truth.y());
        std::printf("step %2d  estimate (%6.2f, %6.2f, %7.2f deg)  error %.2f m  var %.3f m^2\n", k,
                    est.x(), est.y(), est.phi() * 180 / M_PI, err, localizer.varianceXY());
    }
    std::printf("final error %.3f m\n", err);
    return err < 1.0 ? 0 : 2;
}

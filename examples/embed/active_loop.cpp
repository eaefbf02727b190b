/* A robot that chooses where to look: while its particles are spread, it asks semloc's active
 * policy for the next motion (the one expected to tell its hypotheses apart best); once they
 * have converged, it goes back to its mission (here: straight on).
 *   active_loop <world.yaml>
 * It links semloc::semloc alone. The "robot" is stand-ins: noisy odometry and a detector of 12 m
 * and 120 degrees (StandIns.h), and the world itself as its obstacle sonar (a motion whose
 * path would hit something is not made); on a vehicle these come from its own sensors. */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/filter/Localizer.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "StandIns.h"

namespace
{
/** The detector: 12 m and 120 degrees, 90 % of the objects in view detected. */
const standin::Detector kDetector{12.0, 120.0, 0.9};

/** The obstacle sonar's stand-in: true when `m` from the true pose stays in free space. */
bool clear(const semloc::World& world, const mrpt::poses::CPose2D& truth,
           const semloc::TActiveMotion& m)
{
    return semloc::pathIsFree(world, truth.asTPose(), m);
}

/** The robot: its true pose (known to the stand-ins only), its localizer and its policy. */
struct Robot
{
    const semloc::World& world;
    semloc::Localizer& localizer;
    semloc::ActivePolicy& policy;
    mrpt::random::CRandomGenerator rng{42};
    mrpt::poses::CPose2D truth;
    semloc::CObservationSemantic::Ptr scan;

    /** The policy's best candidate the obstacle sonar allows (else a turn on the spot); none
     *  (and `converged`) once the particles have converged. */
    std::optional<semloc::TActiveMotion> decide(int k, bool& converged)
    {
        const auto d = policy.decide(localizer.pdf(), *scan);
        converged = d.converged;
        if (converged)
        {
            std::printf("step %3d  converged: back to the mission\n", k);
            return std::nullopt;
        }
        const semloc::ActivePolicy::TCandidate* best = nullptr;
        for (const auto& c : d.candidates)
        {
            if (c.admissible && clear(world, truth, c.motion) && (!best || c.score < best->score))
            {
                best = &c;
            }
        }
        const semloc::TActiveMotion m = best ? best->motion : semloc::TActiveMotion{M_PI / 2, 0};
        std::printf("step %3d  %zu hypotheses, entropy %.2f: turn %4.0f deg, go %4.1f m\n", k,
                    d.representatives, d.entropy, m.turn_rad * 180 / M_PI, m.distance_m);
        return m;
    }

    /** Makes `u`, then feeds its odometry and the new scan to the localizer. */
    void move(const mrpt::poses::CPose2D& u)
    {
        truth = truth + u;
        mrpt::obs::CActionCollection action;
        action.insert(standin::odometryReading(u, rng));
        scan = standin::detectorScan(kDetector, world, truth, rng);
        mrpt::obs::CSensoryFrame frame;
        frame.insert(scan);
        localizer.step(action, frame);
    }
};
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: active_loop <world.yaml>\n");
        return 1;
    }
    const auto world = semloc::World::FromFile(argv[1]);
    auto map = mrpt::maps::CMultiMetricMap::Create();
    auto semantic = semloc::CSemanticMap::Create();
    auto& lo = semantic->likelihoodOptions;  // the detector below, as the map models it
    lo.model = semloc::CSemanticMap::Model::Probabilistic;
    lo.detector.sigma_range_m = 0.2;
    lo.detector.sigma_bearing_deg = 2;
    lo.probabilistic.p_detect_near = lo.probabilistic.p_detect_far = 0.9;
    lo.probabilistic.clutter_per_scan = 0.05;
    semantic->loadFromWorld(world);
    map->maps.push_back(semantic);

    semloc::Localizer::TOptions opts;  // global localization over the free space
    opts.particles_count = 20000;
    opts.seed = 7;
    opts.free_space_prior = true;
    // Look-alike places can fool the filter: recovery injects particles drawn from the
    // detections while they are explained worse than by no object at all ([Recovery]).
    opts.recovery.trigger = semloc::RecoveryTrigger::Evidence;
    semloc::Localizer localizer(opts, map, &world);
    semloc::ActivePolicy policy(semloc::ActivePolicy::TOptions(), *semantic, &world);

    const auto& start = world.trajectory->waypoints[0];
    Robot robot{world, localizer, policy};
    robot.truth = mrpt::poses::CPose2D(start.x, start.y, 0);
    robot.scan = standin::detectorScan(kDetector, world, robot.truth, robot.rng);
    const double step = 0.5;     // metres per step
    semloc::TActiveMotion plan;  // the motion under way: a turn to make, metres to go
    bool converged = false;
    double err = 0;
    for (int k = 0; k < 300; k++)
    {
        if (!converged && plan.turn_rad == 0 && plan.distance_m <= 0)
        {
            plan = robot.decide(k, converged).value_or(semloc::TActiveMotion{});
        }
        // Once converged, the mission: straight on, turning at the map's edge.
        semloc::TActiveMotion now{plan.turn_rad, std::min(step, plan.distance_m)};
        if (converged)
        {
            now = clear(world, robot.truth, {0, step}) ? semloc::TActiveMotion{0, step}
                                                       : semloc::TActiveMotion{M_PI / 2, 0};
        }
        if (!clear(world, robot.truth, now))
        {
            now.distance_m = plan.distance_m = 0;  // the sonar stops the vehicle
        }
        plan.turn_rad = 0;
        plan.distance_m -= now.distance_m;
        robot.move(now.increment());
        const auto est = localizer.mean();
        err = std::hypot(est.x() - robot.truth.x(), est.y() - robot.truth.y());
        if (converged && k % 20 == 0)
        {
            std::printf("step %3d  error %.2f m  var %.3f m^2\n", k, err, localizer.varianceXY());
        }
    }
    std::printf("final error %.3f m\n", err);
    return converged && err < 1.0 ? 0 : 2;
}

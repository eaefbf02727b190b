/* semloc — the simulated vehicle's motion: waypoints followed at constant speed. */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <vector>

namespace semloc
{
/** Planar AUV kinematics (x, y, heading) reduced to what a survey needs: the vehicle heads
 *  straight for its next waypoint and covers `stepLength_m` per step, at constant speed.
 *
 *  - A step that reaches a waypoint carries the rest of its length on to the next one, so
 *    the vehicle stays on the polyline and corners are cut by no more than the polyline
 *    itself; the step length is exact (every step but the last, which stops at the final
 *    waypoint).
 *  - The heading is the direction towards the current target waypoint (at the end: the
 *    direction of the last leg). It is not rate-limited: at a corner it changes by the
 *    whole corner angle within the one step that passes the corner, so the step's pose
 *    increment is the chord plus the full turn (documented simplification; the odometry
 *    reports exactly that increment).
 *  - teleport() moves the vehicle elsewhere (kidnapping); it keeps its target waypoint and
 *    heads for it from the new position at the next step. */
class TrajectoryFollower
{
public:
    /** Starts at waypoints[0], heading for waypoints[1]. Throws if there are fewer than two
     *  waypoints, the path has zero length, or `stepLength_m` is not a positive number. */
    TrajectoryFollower(std::vector<mrpt::math::TPoint2D> waypoints, double stepLength_m);

    /** Current pose [m, rad]. */
    const mrpt::math::TPose2D& pose() const { return m_pose; }
    /** True once the final waypoint is reached. */
    bool finished() const { return m_target >= m_waypoints.size(); }
    /** Moves one step (no-op when finished). */
    void step();
    /** Places the vehicle at `p` (heading included) without changing its target. */
    void teleport(const mrpt::math::TPose2D& p) { m_pose = p; }
    /** Number of steps from the start to the final waypoint, the start pose included. */
    size_t stepsToEnd() const;

private:
    std::vector<mrpt::math::TPoint2D> m_waypoints;
    double m_step;
    mrpt::math::TPose2D m_pose;
    size_t m_target = 1;  // index of the waypoint the vehicle heads for
};

}  // namespace semloc

/* semloc — TrajectoryFollower: constant-speed waypoint following. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/simulator/TrajectoryFollower.h>

#include <cmath>

namespace semloc
{
namespace
{
/** A remaining distance this close [m] to the step length counts as reaching the waypoint:
 *  legs that are whole multiples of the step end on the waypoint, not 1e-15 m short. */
constexpr double kReachTolerance_m = 1e-9;
}  // namespace

TrajectoryFollower::TrajectoryFollower(std::vector<mrpt::math::TPoint2D> waypoints,
                                       double stepLength_m)
    : m_waypoints(std::move(waypoints)), m_step(stepLength_m)
{
    ASSERTMSG_(m_waypoints.size() >= 2, "TrajectoryFollower: needs at least two waypoints");
    ASSERTMSG_(std::isfinite(m_step) && m_step > 0,
               "TrajectoryFollower: the step length must be a positive number");
    double length = 0;
    for (size_t i = 1; i < m_waypoints.size(); i++)
    {
        length += (m_waypoints[i] - m_waypoints[i - 1]).norm();
    }
    if (!(length > 0))
    {
        // World files refuse this when loaded, naming the file and key (World::FromText).
        THROW_EXCEPTION(mrpt::format(
            "TrajectoryFollower: the trajectory has zero length (its %zu waypoints are all "
            "[%.17g, %.17g])",
            m_waypoints.size(), m_waypoints[0].x, m_waypoints[0].y));
    }
    m_pose = {m_waypoints[0].x, m_waypoints[0].y, 0};
    // Skip waypoints that coincide with the start, then face the first real leg.
    while (m_target < m_waypoints.size() &&
           (m_waypoints[m_target] - m_waypoints[0]).norm() <= kReachTolerance_m)
    {
        m_target++;
    }
    const auto d = m_waypoints[m_target] - m_waypoints[0];
    m_pose.phi = std::atan2(d.y, d.x);
}

void TrajectoryFollower::step()
{
    double left = m_step;
    while (!finished() && left > 0)
    {
        const auto& w = m_waypoints[m_target];
        const double dx = w.x - m_pose.x, dy = w.y - m_pose.y;
        const double d = std::hypot(dx, dy);
        if (d > 0)
        {
            m_pose.phi = std::atan2(dy, dx);  // turn towards the target within the step
        }
        if (d <= left + kReachTolerance_m)
        {
            m_pose.x = w.x;
            m_pose.y = w.y;
            left -= d;
            m_target++;
        }
        else
        {
            m_pose.x += left * dx / d;
            m_pose.y += left * dy / d;
            left = 0;
        }
    }
    if (!finished())
    {
        const auto& w = m_waypoints[m_target];
        if (w.x != m_pose.x || w.y != m_pose.y)
        {
            m_pose.phi = std::atan2(w.y - m_pose.y, w.x - m_pose.x);
        }
    }
}

size_t TrajectoryFollower::stepsToEnd() const
{
    TrajectoryFollower f(*this);
    size_t n = 1;
    while (!f.finished())
    {
        f.step();
        n++;
    }
    return n;
}

}  // namespace semloc

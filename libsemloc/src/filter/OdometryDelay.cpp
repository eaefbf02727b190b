/* semloc — OdometryDelay: the increments of an odometry the vehicle follows late, re-cut over
 * the delayed interval in SE(2). */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <semloc/filter/OdometryDelay.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace semloc
{
namespace
{
/** sin(t) / t and (1 - cos(t)) / t, by their series near 0. */
void arcFactors(double t, double& a, double& b)
{
    if (std::abs(t) < 1e-4)
    {
        const double t2 = t * t;
        a = 1 - t2 / 6;
        b = t / 2 - t * t2 / 24;
        return;
    }
    a = std::sin(t) / t;
    b = (1 - std::cos(t)) / t;
}

/** p (+) u. */
mrpt::math::TPose2D compose(const mrpt::math::TPose2D& p, const mrpt::math::TPose2D& u)
{
    const double c = std::cos(p.phi), s = std::sin(p.phi);
    return {p.x + c * u.x - s * u.y, p.y + s * u.x + c * u.y,
            std::remainder(p.phi + u.phi, 2 * M_PI)};
}
}  // namespace

OdometryDelay::OdometryDelay(double delay_s) : m_delay(delay_s)
{
    if (!(delay_s >= 0 && delay_s <= kMaxDelay_s))
    {
        throw std::invalid_argument("odometry delay " + std::to_string(delay_s) +
                                    " s: must be in [0, " + std::to_string(kMaxDelay_s) + "]");
    }
}

void OdometryDelay::reset()
{
    m_started = false;
    m_last = 0;
    m_pieces.clear();
}

mrpt::math::TPose2D OdometryDelay::expTwist(double vx, double vy, double w, double s)
{
    const double t = w * s;
    double a = 0, b = 0;
    arcFactors(t, a, b);
    return {s * (a * vx - b * vy), s * (b * vx + a * vy), t};
}

void OdometryDelay::logIncrement(const mrpt::math::TPose2D& u, double& vx, double& vy, double& w)
{
    w = u.phi;
    double a = 0, b = 0;
    arcFactors(w, a, b);
    const double n = a * a + b * b;  // > 0 for |w| <= pi
    vx = (a * u.x + b * u.y) / n;
    vy = (-b * u.x + a * u.y) / n;
}

mrpt::math::TPose2D OdometryDelay::step(double t, const mrpt::math::TPose2D& u)
{
    if (!std::isfinite(t))
    {
        throw std::invalid_argument("odometry delay: a step's time is not finite");
    }
    if (!m_started)
    {
        m_started = true;
        m_last = t;
        return u;
    }
    if (t < m_last)
    {
        throw std::invalid_argument("odometry delay: a step's time goes back (" +
                                    std::to_string(t) + " s after " + std::to_string(m_last) +
                                    " s)");
    }
    if (m_delay == 0)
    {
        m_last = t;
        return u;
    }
    Piece piece{m_last, t, 0, 0, 0};
    logIncrement(u, piece.vx, piece.vy, piece.w);  // over the whole step
    m_pieces.push_back(piece);
    const double from = m_last - m_delay, to = t - m_delay;
    m_last = t;

    mrpt::math::TPose2D out{0, 0, 0};
    for (const Piece& p : m_pieces)
    {
        if (p.t1 <= from || p.t0 >= to)
        {
            // Outside (from, to]; a step of no duration is an increment at its time.
            if (!(p.t0 == p.t1 && p.t1 > from && p.t1 <= to))
            {
                continue;
            }
        }
        const double length = p.t1 - p.t0;
        const double f = length > 0 ? (std::min(p.t1, to) - std::max(p.t0, from)) / length : 1.0;
        out = compose(out, expTwist(p.vx, p.vy, p.w, f));
    }
    // The next step starts at `to`: what ends there is spent.
    while (!m_pieces.empty() && m_pieces.front().t1 <= to)
    {
        m_pieces.pop_front();
    }
    return out;
}

const mrpt::obs::CActionCollection& OdometryDelay::apply(const mrpt::obs::CActionCollection& acts,
                                                         const mrpt::obs::CSensoryFrame& sf,
                                                         mrpt::obs::CActionCollection& copy)
{
    const auto best = acts.getBestMovementEstimation();
    if (m_delay == 0 || !best)
    {
        return acts;
    }
    mrpt::Clock::time_point t = best->timestamp;
    if (t == INVALID_TIMESTAMP && sf.size() > 0)
    {
        t = sf.getObservationByIndex(0)->timestamp;
    }
    if (t == INVALID_TIMESTAMP)
    {
        THROW_EXCEPTION(
            "[MotionModel] odometry_delay_s > 0 needs timestamped steps: an action and its "
            "observations have no timestamp");
    }
    const auto* gauss = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(best->poseChange.get());
    if (!gauss)
    {
        THROW_EXCEPTION(
            "[MotionModel] odometry_delay_s > 0 needs Gaussian odometry (CPosePDFGaussian); "
            "this step's movement is a " +
            std::string(best->poseChange->GetRuntimeClass()->className));
    }
    mrpt::obs::CActionRobotMovement2D moved(*best);
    moved.poseChange = mrpt::poses::CPosePDF::Ptr(std::make_shared<mrpt::poses::CPosePDFGaussian>(
        mrpt::poses::CPose2D(step(mrpt::Clock::toDouble(t), gauss->mean.asTPose())), gauss->cov));
    copy.clear();
    copy.insert(moved);
    return copy;
}
}  // namespace semloc

/* semloc — an odometry that the vehicle follows late: the increments of a step re-cut so that
 * each covers what the vehicle did over the step, not what its odometry said then. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cstddef>
#include <deque>

namespace semloc
{
/** The increments of an odometry that the vehicle follows `delay` seconds late (commanded
 *  speeds executed after the controller's and the drive's latency, a log's clocks that differ).
 *
 *  The odometry's increment u_k covers the step (t_{k-1}, t_k]; what the vehicle did over it
 *  is what the odometry said over (t_{k-1} - delay, t_k - delay]. Within each step the
 *  odometry is taken to have turned and moved at a constant rate (its twist
 *  xi_k = log(u_k) / (t_k - t_{k-1}) in SE(2)), so the delayed increment is the composition of
 *  exp(xi_j s_j) over the parts s_j of that interval in step j. Before the first step the
 *  vehicle stands still. The steps kept are those that end after t_k - delay: a history of
 *  at most `delay` seconds, whatever the log's length.
 *
 *  With delay 0 every increment is returned as it came. */
class OdometryDelay
{
public:
    /** The largest delay [s] (MotionModelConfig's odometry_delay_s). */
    static constexpr double kMaxDelay_s = 5.0;

    /** `delay_s` in [0, kMaxDelay_s] (else std::invalid_argument). */
    explicit OdometryDelay(double delay_s = 0);

    double delay() const { return m_delay; }

    /** The increment the vehicle made over the step that ends at `t` [s] and whose odometry
     *  increment is `u` (in the frame of the step's start). The first step after reset() has
     *  no start: its `u` is returned as it came (a log's first increment is zero) and `t`
     *  starts the history. Throws std::invalid_argument when `t` is not finite or before the
     *  previous step's time. */
    mrpt::math::TPose2D step(double t, const mrpt::math::TPose2D& u);

    /** `acts` with its best 2D movement's mean re-cut by step() at the movement's time (else
     *  `sf`'s first observation's), its covariance kept, in `copy`; `acts` itself when the
     *  delay is 0 or it holds no 2D movement. Throws when the step has no timestamp or its
     *  movement is not a CPosePDFGaussian. What Localizer does before each prediction. */
    const mrpt::obs::CActionCollection& apply(const mrpt::obs::CActionCollection& acts,
                                              const mrpt::obs::CSensoryFrame& sf,
                                              mrpt::obs::CActionCollection& copy);

    /** Forgets the history (a new run). */
    void reset();
    /** Steps kept (those the next step may still need). */
    size_t history() const { return m_pieces.size(); }

    /** The increment of the twist (vx, vy, w) held for `s` seconds: exp in SE(2). */
    static mrpt::math::TPose2D expTwist(double vx, double vy, double w, double s);
    /** The twist (vx, vy, w) that makes the increment `u` in 1 s: log in SE(2). */
    static void logIncrement(const mrpt::math::TPose2D& u, double& vx, double& vy, double& w);

private:
    /** A step of the odometry: (t0, t1] and the twist (vx, vy, w) that makes its whole
     *  increment (a part f of the step is expTwist(vx, vy, w, f)). */
    struct Piece
    {
        double t0, t1, vx, vy, w;
    };
    double m_delay;
    bool m_started = false;
    double m_last = 0;
    std::deque<Piece> m_pieces;
};
}  // namespace semloc

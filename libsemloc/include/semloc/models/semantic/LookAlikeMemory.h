/* semloc — the detections of the last seconds, for the semantic map's look-alike persistence
 * (CSemanticMap's lookalike_persistence). */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

namespace semloc
{
class CSemanticMap;
class CObservationSemantic;

/** The detections of the last lookalike_window_s seconds of one semantic map's observations,
 *  in a fixed frame (the filter's: the vehicle's odometry frame; semloc-calibrate's: the
 *  map's), and what they make of a new observation's clutter.
 *
 *  A look-alike (an unmapped object detected under a map label) seen in one scan is likely
 *  seen again near the same place in the next: detection k of a new observation gets the
 *  clutter density kappa + rho r_k max_j N(p_k; p_j, S_kj), the max over the remembered
 *  detections j of its label from earlier scans, with p the positions in the fixed frame,
 *  S_kj = (v_k + v_j + (u dt)^2) I (v = sigma_rho^2 + rho^2 sigma_theta^2, u the look-alikes'
 *  speed, dt the time between the scans); the range r_k makes it a density over range x
 *  bearing. rho is the chance that a remembered detection is seen again as clutter (the
 *  Gaussian integrates to 1 over the plane). The odometry over a window of a second or two is
 *  precise enough for that, whatever it drifts over minutes; the factor is the same for every
 *  particle. */
class LookAlikeMemory
{
public:
    /** One detection placed in the fixed frame. */
    struct Point
    {
        double x = 0, y = 0;  ///< [m]
        double var = 0;       ///< sigma_rho^2 + rho^2 sigma_theta^2 [m^2]
        double t = 0;         ///< the scan's time [s]
        std::string label;
    };

    /** factors[k] = log(kappa_k / kappa) >= 0 for each detection of obs.detections (0 for
     *  those the map does not use), then remembers the detections the map uses. `odometry`
     *  is the vehicle's pose by its odometry at the observation (any fixed origin). Throws
     *  for an observation without a timestamp. */
    void note(const CObservationSemantic& obs, const CSemanticMap& map,
              const mrpt::math::TPose2D& odometry, std::vector<double>& factors);

    /** @name The steps of note(), for a caller that places the detections itself. @{ */
    /** Forgets the detections more than `window_s` before `t` (every one when `t` is before
     *  the last remembered: the log went back in time). */
    void forget(double t, double window_s);
    /** max_j N(p; p_j, S) over the remembered detections j of p's label from before p.t, with
     *  look-alikes moving at `speed_mps` (0 when there is none) [1/m^2]. */
    double nearestDensity(const Point& p, double speed_mps) const;
    /** Remembers `p` (its time not before the last remembered). */
    void remember(Point p) { m_points.push_back(std::move(p)); }
    /** @} */

    /** Forgets every detection (a new run). */
    void reset() { m_points.clear(); }
    /** Detections remembered, oldest first. */
    const std::deque<Point>& points() const { return m_points; }
    size_t size() const { return m_points.size(); }

private:
    std::deque<Point> m_points;  ///< oldest first
};
}  // namespace semloc

/* semloc — the detections of the last seconds, for the semantic map's look-alike persistence
 * (CSemanticMap's lookalike_persistence; private). */
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

namespace detail
{
/** The detections of the last lookalike_window_s seconds of one semantic map's observations,
 *  in the vehicle's odometry frame, and what they make of a new observation's clutter.
 *
 *  A look-alike (an unmapped object detected under a map label) seen in one scan is likely
 *  seen again near the same place in the next: detection k of a new observation gets the
 *  clutter density kappa + rho max_j N(p_k; p_j, S_kj), the max over the remembered
 *  detections j of its label from earlier scans, with p the positions in the odometry frame,
 *  S_kj = (v_k + v_j + (u dt)^2) I (v = sigma_rho^2 + rho^2 sigma_theta^2, u the look-alikes'
 *  speed, dt the time between the scans), times the range (the density over range x bearing).
 *  The odometry over a window of a second or two is precise enough for that, whatever it
 *  drifts over minutes; the factor is the same for every particle. */
class LookAlikeMemory
{
public:
    /** factors[k] = log(kappa_k / kappa) >= 0 for each detection of obs.detections (0 for
     *  those the map does not use), then remembers the detections the map uses. `odometry`
     *  is the vehicle's pose by its odometry at the observation (any fixed origin). Throws
     *  for an observation without a timestamp. */
    void note(const CObservationSemantic& obs, const CSemanticMap& map,
              const mrpt::math::TPose2D& odometry, std::vector<double>& factors);
    /** Forgets every detection (a new run). */
    void reset() { m_points.clear(); }
    /** Detections remembered. */
    size_t size() const { return m_points.size(); }

private:
    struct Point
    {
        double x = 0, y = 0;  ///< in the odometry frame [m]
        double var = 0;       ///< sigma_rho^2 + rho^2 sigma_theta^2 [m^2]
        double t = 0;         ///< the scan's time [s]
        std::string label;
    };
    std::deque<Point> m_points;  ///< oldest first
};
}  // namespace detail
}  // namespace semloc

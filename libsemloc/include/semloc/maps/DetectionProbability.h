/* semloc — the probabilistic detector's detection probability, one formula for the semantic
 * map's model and the simulator's detector. */
#pragma once

#include <algorithm>
#include <cmath>

namespace semloc
{
/** P_D of an object at range `rho` [m] and bearing `theta` [rad] in the sensor frame, for a
 *  detector of max range `R` [m] and field of view `fov` [rad]: linear from `pNear` at 0 to
 *  `pFar` at R, times 1 - (1 - edgeRatio) min(|theta| / (fov / 2), 1) when fov < 2 pi (a
 *  full circle has no edge). Not clamped: the callers keep it to the range they need. */
inline double detectionProbability(double pNear, double pFar, double edgeRatio, double rho,
                                   double R, double theta, double fov)
{
    double p = pNear + (pFar - pNear) * rho / R;
    if (edgeRatio < 1 && fov < 2 * M_PI)
    {
        p *= 1 - (1 - edgeRatio) * std::min(2 * std::abs(theta) / fov, 1.0);
    }
    return p;
}
}  // namespace semloc

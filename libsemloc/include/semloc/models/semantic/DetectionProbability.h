/* semloc — the probabilistic detector's detection probability and range bias, one formula each
 * for the semantic map's model and the simulator's detector. */
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

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

/** The most coefficients of rangeBias(). */
constexpr size_t kRangeBiasTerms = 4;

/** What a detector's range reads beyond the true one at bearing `theta` [rad] in the sensor
 *  frame, for a field of view `fov` [rad]: c[0] + c[1] u + c[2] u^2 + c[3] u^3 [m], u =
 *  theta / (fov / 2) the bearing over the half view (theta / pi for a full circle), so each
 *  coefficient is in metres and their sum is the bias at the view's edge (`theta` taken in
 *  [-pi, pi]). `c` holds up to
 *  kRangeBiasTerms coefficients (the others 0; none: no bias). A camera ranging by an
 *  object's apparent size reads short towards its image's border; a sonar's sound speed,
 *  long. */
/** The bearing `theta` [rad] (taken in [-pi, pi]) over half the field of view `fov` [rad]
 *  (over pi for a full circle): rangeBias()'s variable u. */
inline double bearingOverHalfView(double theta, double fov)
{
    const double wrapped =
        (theta >= -M_PI && theta <= M_PI) ? theta : std::remainder(theta, 2 * M_PI);
    return wrapped / (fov < 2 * M_PI ? 0.5 * fov : M_PI);
}

inline double rangeBias(const std::vector<double>& c, double theta, double fov)
{
    const double u = bearingOverHalfView(theta, fov);
    double b = 0;
    for (size_t k = c.size(); k-- > 0;)
    {
        b = b * u + c[k];
    }
    return b;
}

/** A detection's range `rho` [m] at bearing `theta` less rangeBias(c, theta, fov), kept
 *  within the coverage [0, R]; `rho` as it is without a bias (`c` empty). */
inline double rangeLessBias(const std::vector<double>& c, double rho, double theta, double R,
                            double fov)
{
    return c.empty() ? rho : std::clamp(rho - rangeBias(c, theta, fov), 0.0, R);
}
}  // namespace semloc

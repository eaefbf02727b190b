/* semloc — small numeric kernels for the per-particle loops (private). */
#pragma once

#include <cmath>

namespace semloc::detail
{
/** atan2 with |error| < 1e-7 rad (checked against std::atan2 in test_FastMath),
 *  about 4x cheaper than libm's. Used for predicted bearings, where the bearing
 *  noise sigma is ~1e-2 rad, so the error is far below anything the likelihood sees.
 *  Range reduction to [0, 1] and an odd minimax polynomial in z = min/max. */
inline double fastAtan2(double y, double x) noexcept
{
    const double ax = std::abs(x), ay = std::abs(y);
    const double mx = ax > ay ? ax : ay;
    const double mn = ax > ay ? ay : ax;
    if (mx == 0)
    {
        return std::atan2(y, x);  // signed zeros: let libm decide, rare
    }
    const double z = mn / mx;
    const double z2 = z * z;
    // Minimax coefficients for atan(z) on [0, 1] (odd, degree 15).
    double r = -0.0040540580;
    r = r * z2 + 0.0218612288;
    r = r * z2 - 0.0559098861;
    r = r * z2 + 0.0964200441;
    r = r * z2 - 0.1390853351;
    r = r * z2 + 0.1994653599;
    r = r * z2 - 0.3332985605;
    r = r * z2 + 0.9999993329;
    r *= z;
    if (ay > ax)
    {
        r = M_PI_2 - r;
    }
    if (x < 0)
    {
        r = M_PI - r;
    }
    return y < 0 ? -r : r;
}

/** Wraps an angle difference of two angles in [-pi, pi] into [-pi, pi]. */
inline double wrapDiff(double d) noexcept
{
    if (d > M_PI)
    {
        d -= 2 * M_PI;
    }
    else if (d < -M_PI)
    {
        d += 2 * M_PI;
    }
    return d;
}

}  // namespace semloc::detail

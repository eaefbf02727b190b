/* semloc — MRPT's angle wrapping without its fmod in the common case (private). */
#pragma once

#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace semloc::detail
{
/** mrpt::math::wrapToPi, bit for bit, without its fmod for angles within a turn of the
 *  range: fmod(t, 2 pi) is exactly t for 0 <= t < 2 pi, and exactly t - 2 pi for
 *  2 pi <= t < 4 pi (fmod is exact, and so is that subtraction: Sterbenz). The second case
 *  is MRPT's getCovarianceAndMean's, whose heading errors |phi - mean| are taken against a
 *  mean moved to [0, 2 pi). */
inline double wrapToPiExact(double a)
{
    const double t = a + M_PI;
    if (t >= 0 && t < 2 * M_PI)
    {
        return t - M_PI;
    }
    if (t >= 2 * M_PI && t < 4 * M_PI)
    {
        return (t - 2 * M_PI) - M_PI;
    }
    return mrpt::math::wrapToPi(a);
}
}  // namespace semloc::detail

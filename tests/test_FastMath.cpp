/* semloc tests — FastMath kernels against libm. */
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>

#include "FastMath.h"

using semloc::detail::fastAtan2;
using semloc::detail::wrapDiff;

TEST(FastMath, Atan2MatchesLibmEverywhere)
{
    mrpt::random::CRandomGenerator rng(42);
    double worst = 0;
    for (int i = 0; i < 200000; i++)
    {
        const double y = rng.drawUniform(-50.0, 50.0), x = rng.drawUniform(-50.0, 50.0);
        worst = std::max(worst, std::abs(fastAtan2(y, x) - std::atan2(y, x)));
    }
    // Axes, diagonals and the origin exactly.
    const double pts[][2] = {{0, 1},  {0, -1}, {1, 0}, {-1, 0},     {1, 1},      {-1, -1},
                             {1, -1}, {-1, 1}, {0, 0}, {1e-300, 1}, {1, 1e-300}, {-3, 1e-12}};
    for (const auto& p : pts)
    {
        worst = std::max(worst, std::abs(fastAtan2(p[0], p[1]) - std::atan2(p[0], p[1])));
    }
    EXPECT_LT(worst, 1e-7);
}

TEST(FastMath, WrapDiffStaysInPiRange)
{
    EXPECT_NEAR(wrapDiff(3.0 - (-3.0)), 6.0 - 2 * M_PI, 1e-15);
    EXPECT_NEAR(wrapDiff(-3.0 - 3.0), -6.0 + 2 * M_PI, 1e-15);
    EXPECT_DOUBLE_EQ(wrapDiff(0.5), 0.5);
}

/* semloc tests — FastMath kernels against libm. */
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <cstdint>
#include <cstring>

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

TEST(FastMath, SinCosMatchesLibm)
{
    mrpt::random::CRandomGenerator rng(43);
    double worst = 0;
    auto check = [&](double x)
    {
        double s = 0, c = 0;
        semloc::detail::fastSinCos(x, s, c);
        worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
    };
    for (int i = 0; i < 200000; i++)
    {
        check(rng.drawUniform(-10.0, 10.0));
        check(rng.drawUniform(-1e5, 1e5));
    }
    for (int k = -8; k <= 8; k++)
    {
        check(k * M_PI / 4);
        check(k * M_PI / 4 + 1e-12);
        check(k * M_PI / 4 - 1e-12);
    }
    EXPECT_LT(worst, 1e-14);
    double s = 0, c = 0;
    semloc::detail::fastSinCos(1e300, s, c);  // falls back to libm
    EXPECT_EQ(s, std::sin(1e300));
    semloc::detail::fastSinCos(std::nan(""), s, c);
    EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

namespace
{
/** |a - b| in units in the last place of b (b finite, non-zero). */
double ulpDiff(long double a, double b)
{
    const double ulp = std::nextafter(std::abs(b), INFINITY) - std::abs(b);
    return static_cast<double>(std::abs(a - static_cast<long double>(b)) / ulp);
}

/** Worst error of logFast in ulps, against libm's log and against logl (exact to ~2^-63). */
struct LogErr
{
    double vsLibm = 0, vsExact = 0;
    void check(double x)
    {
        const double y = semloc::detail::logFast(x), ref = std::log(x);
        if (ref == 0)
        {
            vsLibm = std::max(vsLibm, y == 0 ? 0.0 : INFINITY);
            return;
        }
        vsLibm = std::max(vsLibm, ulpDiff(y, ref));
        vsExact = std::max(vsExact, ulpDiff(std::log(static_cast<long double>(x)), y));
    }
};
}  // namespace

TEST(FastMath, LogWithinOneUlpOfLibm)
{
    mrpt::random::CRandomGenerator rng(44);
    LogErr err;
    for (int i = 0; i < 1000000; i++)
    {
        // Every binade of the normal range, log-uniform.
        err.check(std::exp(rng.drawUniform(-708.0, 709.0)));
        // The likelihood's arguments: P_D / (1 - P_D) in [1e-6, 1e6], products of 1 - P_D.
        err.check(std::exp(rng.drawUniform(-14.0, 14.0)));
        err.check(rng.drawUniform(1e-6, 1.0));
        // Around 1, where log x is small and the table's subintervals meet.
        err.check(1.0 + rng.drawUniform(-0.1, 0.1));
        err.check(1.0 + std::ldexp(rng.drawUniform(-1.0, 1.0), -static_cast<int>(i % 60)));
    }
    // Every subinterval's edges and centre, in a few binades.
    for (int e = -3; e <= 3; e++)
    {
        for (double z = 0.68; z < 1.38; z += 1.0 / 1024)
        {
            for (double v : {z, std::nextafter(z, 0.0), std::nextafter(z, 2.0)})
            {
                err.check(std::ldexp(v, e));
            }
        }
    }
    for (double x : {1.0, 2.0, 0.5, M_E, 1e-300, 2.2250738585072014e-308, 1.7976931348623157e308})
    {
        err.check(x);
    }
    EXPECT_LE(err.vsLibm, 1.0);
    EXPECT_LT(err.vsExact, 0.51);  // the final rounding plus < 0.01 ulp (FastMath.h)
    EXPECT_EQ(semloc::detail::logFast(1.0), 0.0);
}

TEST(FastMath, LogSpecialValuesAsLibm)
{
    using semloc::detail::logFast;
    for (double x : {4.9e-324, 1e-310, 2.225073858507201e-308})  // subnormals: libm's values
    {
        EXPECT_EQ(logFast(x), std::log(x)) << x;
    }
    EXPECT_EQ(logFast(0.0), -INFINITY);
    EXPECT_EQ(logFast(-0.0), -INFINITY);
    EXPECT_EQ(logFast(INFINITY), INFINITY);
    EXPECT_TRUE(std::isnan(logFast(-1.0)));
    EXPECT_TRUE(std::isnan(logFast(-INFINITY)));
    EXPECT_TRUE(std::isnan(logFast(std::nan(""))));
}

TEST(FastMath, LogTableAsGenerated)
{
    // The generator of kLogTable (FastMath.h), in long double.
    using semloc::detail::kLogTable;
    for (int i = 0; i < 128; i++)
    {
        const uint64_t mid = semloc::detail::kLogOff + (static_cast<uint64_t>(2 * i + 1) << 44);
        double c = 0;
        std::memcpy(&c, &mid, sizeof c);
        int e = 0;
        const double m = std::frexp(1.0 / c, &e);
        const double invc = std::ldexp(std::nearbyint(std::ldexp(m, 9)), e - 9);
        const long double logc = -std::log(static_cast<long double>(invc));
        const auto hi = static_cast<double>(std::nearbyint(logc * 0x1p32L) * 0x1p-32L);
        const auto lo = static_cast<double>(logc - static_cast<long double>(hi));
        EXPECT_EQ(kLogTable[i].invc, invc) << i;
        EXPECT_EQ(kLogTable[i].logcHi, hi) << i;
        EXPECT_EQ(kLogTable[i].logcLo, lo) << i;
        EXPECT_EQ(kLogTable[i].zMask,
                  invc == 1.0 ? semloc::detail::kLogZ53 : semloc::detail::kLogZ44)
            << i;
    }
}

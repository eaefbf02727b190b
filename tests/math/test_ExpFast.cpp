/* semloc tests — detail::expFast (private ExpFast.h) against libm's exp. */
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "math/ExpFast.h"

namespace
{
int64_t bitsOf(double v)
{
    int64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}
}  // namespace

TEST(ExpFast, WithinOneUlpOfLibm)
{
    std::mt19937_64 gen(11);
    // The weights' range (log-weights relative to the largest), near 0, and both signs.
    std::uniform_real_distribution<double> weights(-745, 0), nearZero(-5, 0), both(-700, 700);
    int64_t worst = 0;
    size_t differing = 0;
    for (int i = 0; i < 300000; i++)
    {
        for (const double x : {weights(gen), nearZero(gen), both(gen)})
        {
            const double a = std::exp(x), b = semloc::detail::expFast(x);
            // Positive doubles: the ulp distance is the distance of their bit patterns.
            const int64_t ulps = std::llabs(bitsOf(a) - bitsOf(b));
            worst = std::max(worst, ulps);
            differing += ulps > 0 ? 1 : 0;
        }
    }
    EXPECT_LE(worst, 1);
    EXPECT_LT(differing, 900000 / 100);  // libm is within ~0.5 ulp: rarely apart
}

TEST(ExpFast, SpecialValues)
{
    using semloc::detail::expFast;
    EXPECT_EQ(expFast(0.0), 1.0);
    EXPECT_EQ(expFast(-0.0), 1.0);
    EXPECT_EQ(expFast(-std::numeric_limits<double>::infinity()), 0.0);
    EXPECT_EQ(expFast(-800.0), std::exp(-800.0));  // libm's subnormal/zero range
    EXPECT_TRUE(std::isnan(expFast(std::numeric_limits<double>::quiet_NaN())));
    EXPECT_EQ(expFast(std::numeric_limits<double>::infinity()),
              std::numeric_limits<double>::infinity());
}

TEST(ExpFast, TwoLanesEqualOneAtATime)
{
    std::mt19937_64 gen(12);
    // Pairs over the weights' range, with one lane or both beyond expFast's range (libm).
    std::uniform_real_distribution<double> weights(-745, 0), wide(-800, 800);
    const double specials[] = {0.0,
                               -0.0,
                               -700.0,
                               700.0,
                               -std::numeric_limits<double>::infinity(),
                               std::numeric_limits<double>::quiet_NaN()};
    for (int i = 0; i < 200000; i++)
    {
        double a = weights(gen), b = i % 3 == 0 ? wide(gen) : weights(gen);
        if (i % 1000 == 0)
        {
            b = specials[(i / 1000) % 6];
        }
        double y0 = 0, y1 = 0;
        semloc::detail::expFast2(a, b, y0, y1);
        ASSERT_EQ(bitsOf(y0), bitsOf(semloc::detail::expFast(a))) << a;
        ASSERT_EQ(bitsOf(y1), bitsOf(semloc::detail::expFast(b))) << b;
    }
}

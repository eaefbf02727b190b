/* semloc tests — the ziggurat normal sampler (private Ziggurat.h) against N(0, 1). */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "math/Ziggurat.h"

namespace
{
/** splitmix64 from a fixed seed: a fixed, well-mixed stream of 64-bit words. */
struct SplitMix
{
    uint64_t state;
    uint64_t operator()()
    {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
};

double normalCdf(double x)
{
    return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

std::vector<double> draws(size_t n, uint64_t seed)
{
    SplitMix g{seed};
    std::vector<double> out(n);
    for (auto& x : out)
    {
        x = semloc::detail::Ziggurat::draw(g);
    }
    return out;
}
}  // namespace

TEST(Ziggurat, MomentsOfTheStandardNormal)
{
    const auto x = draws(2'000'000, 1);
    double m1 = 0, m2 = 0, m3 = 0, m4 = 0;
    for (const double v : x)
    {
        ASSERT_TRUE(std::isfinite(v));
        m1 += v;
        m2 += v * v;
        m3 += v * v * v;
        m4 += v * v * v * v;
    }
    const auto n = static_cast<double>(x.size());
    // Standard errors at n = 2e6: mean 7e-4, variance 1e-3, skewness 1.7e-3, 4th moment 7e-3.
    EXPECT_NEAR(m1 / n, 0.0, 0.004);
    EXPECT_NEAR(m2 / n, 1.0, 0.005);
    EXPECT_NEAR(m3 / n, 0.0, 0.01);
    EXPECT_NEAR(m4 / n, 3.0, 0.04);
}

TEST(Ziggurat, DistributionMatchesTheNormalCdfIncludingWedgesAndTail)
{
    // Chi-square over 64 equiprobable bins of N(0, 1), plus the tail beyond r = 3.4426 (the
    // base layer's own algorithm) and beyond 4.5 on each side.
    const auto x = draws(4'000'000, 7);
    constexpr int kBins = 64;
    std::vector<double> edges(kBins - 1);
    for (int b = 1; b < kBins; b++)
    {
        // Inverse CDF by bisection (test code: clarity over speed).
        double lo = -10, hi = 10;
        for (int it = 0; it < 100; it++)
        {
            const double mid = 0.5 * (lo + hi);
            (normalCdf(mid) < static_cast<double>(b) / kBins ? lo : hi) = mid;
        }
        edges[static_cast<size_t>(b - 1)] = lo;
    }
    std::vector<double> count(kBins, 0);
    double tailR = 0, tail45 = 0, neg = 0;
    for (const double v : x)
    {
        const auto b = std::upper_bound(edges.begin(), edges.end(), v) - edges.begin();
        count[static_cast<size_t>(b)]++;
        tailR += std::abs(v) > 3.442619855899 ? 1 : 0;
        tail45 += std::abs(v) > 4.5 ? 1 : 0;
        neg += v < 0 ? 1 : 0;
    }
    const auto n = static_cast<double>(x.size());
    double chi2 = 0;
    for (const double c : count)
    {
        const double e = n / kBins;
        chi2 += (c - e) * (c - e) / e;
    }
    // 63 degrees of freedom: mean 63, sd 11.2; 120 is p < 1e-6.
    EXPECT_LT(chi2, 120.0);
    const double pR = 2 * (1 - normalCdf(3.442619855899));  // 5.76e-4
    EXPECT_NEAR(tailR / n, pR, 5 * std::sqrt(pR / n));
    const double p45 = 2 * (1 - normalCdf(4.5));  // 6.8e-6
    EXPECT_NEAR(tail45 / n, p45, 5 * std::sqrt(p45 / n));
    EXPECT_NEAR(neg / n, 0.5, 5 * std::sqrt(0.25 / n));
}

TEST(Ziggurat, SameWordsSameDraws)
{
    EXPECT_EQ(draws(1000, 3), draws(1000, 3));
    EXPECT_NE(draws(1000, 3), draws(1000, 4));
}

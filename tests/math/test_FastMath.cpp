/* semloc tests — FastMath kernels against libm. */
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "math/FastMath.h"

using semloc::detail::fastAtan2;
using semloc::detail::wrapDiff;

namespace
{
/** a and b have the same bits (NaNs of one payload, +0 and -0 told apart). */
bool sameBits(double a, double b)
{
    uint64_t x = 0, y = 0;
    std::memcpy(&x, &a, sizeof a);
    std::memcpy(&y, &b, sizeof b);
    return x == y;
}
}  // namespace

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

TEST(FastMath, SinCosTwoAtATimeIsBitForBitOneAtATime)
{
    mrpt::random::CRandomGenerator rng(44);
    std::vector<double> xs;
    for (int i = 0; i < 100000; i++)
    {
        xs.push_back(rng.drawUniform(-4.0, 4.0));
        xs.push_back(rng.drawUniform(-1e6, 1e6));
    }
    for (int k = -9; k <= 9; k++)  // quadrant edges, both signs, signed zeros
    {
        for (const double d : {0.0, 1e-12, -1e-12})
        {
            xs.push_back(k * M_PI / 4 + d);
        }
    }
    xs.insert(xs.end(), {0.0, -0.0, 1e6, -1e6, 1e6 + 1, 1e300, -1e300, std::nan(""), INFINITY});
    size_t differ = 0;
    for (size_t i = 0; i + 1 < xs.size(); i++)  // each value in both lanes, beside others
    {
        semloc::detail::Vec2 s2, c2;
        semloc::detail::fastSinCos2(semloc::detail::Vec2{xs[i], xs[i + 1]}, s2, c2);
        for (int lane = 0; lane < 2; lane++)
        {
            double s = 0, c = 0;
            semloc::detail::fastSinCos(xs[i + lane], s, c);
            differ += sameBits(s2[lane], s) && sameBits(c2[lane], c) ? 0 : 1;
        }
    }
    EXPECT_EQ(differ, 0u);
}

TEST(FastMath, AbsAtan2TwoAtATimeIsBitForBitOneAtATime)
{
    mrpt::random::CRandomGenerator rng(45);
    std::vector<double> ys, xs;
    for (int i = 0; i < 100000; i++)
    {
        // Mostly within 45 degrees of +x (the short path, as gated pairs are), the rest
        // anywhere: lanes mix the two paths.
        const double a = i % 4 == 0 ? rng.drawUniform(-M_PI, M_PI) : rng.drawUniform(-0.8, 0.8);
        const double r = rng.drawUniform(1e-3, 60.0);
        ys.push_back(r * std::sin(a));
        xs.push_back(r * std::cos(a));
    }
    // Edges: the diagonal, the axes, signed zeros, huge, tiny, non-finite.
    const double edges[] = {0.0, -0.0, 1.0, -1.0, 1e-300, 1e300, HUGE_VAL, std::nan("")};
    for (const double y : edges)
    {
        for (const double x : edges)
        {
            ys.push_back(y);
            xs.push_back(x);
        }
    }
    size_t differ = 0;
    for (size_t i = 0; i + 1 < xs.size(); i++)  // each pair in both lanes, beside others
    {
        const semloc::detail::Vec2 got2 = semloc::detail::fastAbsAtan2x2(
            semloc::detail::Vec2{ys[i], ys[i + 1]}, semloc::detail::Vec2{xs[i], xs[i + 1]});
        for (int lane = 0; lane < 2; lane++)
        {
            const double got = got2[lane];
            const double want = semloc::detail::fastAbsAtan2(ys[i + lane], xs[i + lane]);
            differ += sameBits(got, want) ? 0 : 1;
        }
    }
    EXPECT_EQ(differ, 0u);
}

TEST(FastMath, LaneOperationsAreSse2sOnEveryBuild)
{
    using semloc::detail::Vec2;
    namespace d = semloc::detail;
    // Read at run time (volatile): the compiler may fold conversions of constants otherwise.
    volatile double vNan = std::nan(""), vHuge = 1e300, vLow = -2147483649.0;
    const double nan = vNan;
    auto same = [](double a, double b) { return sameBits(a, b); };
    // minpd / maxpd: the second operand when either is NaN, or when both are zeros.
    const Vec2 mn = d::minLanes(Vec2{nan, 1.0}, Vec2{2.0, nan});
    EXPECT_TRUE(same(mn[0], 2.0));
    EXPECT_TRUE(std::isnan(mn[1]));
    const Vec2 mx = d::maxLanes(Vec2{0.0, -3.0}, Vec2{-0.0, -4.0});
    EXPECT_TRUE(same(mx[0], -0.0));
    EXPECT_TRUE(same(mx[1], -3.0));
    // Masks: false for NaN; maskBits reads lane k into bit k.
    EXPECT_EQ(d::maskBits(d::lessEqualMask(Vec2{1.0, nan}, Vec2{1.0, 0.0})), 1);
    EXPECT_EQ(d::maskBits(d::lessMask(Vec2{1.0, -1.0}, Vec2{1.0, 0.0})), 2);
    EXPECT_EQ(d::maskBits(d::greaterEqualMask(Vec2{2.0, 1.0}, Vec2{1.0, nan})), 1);
    const Vec2 all = d::greaterEqualMask(Vec2{1.0, 1.0}, Vec2{0.0, 0.0});
    const Vec2 none = d::lessMask(Vec2{1.0, 1.0}, Vec2{0.0, 0.0});
    EXPECT_EQ(d::maskBits(d::orLanes(all, none)), 3);
    EXPECT_EQ(d::maskBits(d::andLanes(all, none)), 0);
    // A mask and a value: the value where set, +0 elsewhere.
    const Vec2 kept = d::andLanes(d::lessMask(Vec2{0.0, 1.0}, Vec2{1.0, 0.0}), Vec2{-5.0, -5.0});
    EXPECT_TRUE(same(kept[0], -5.0));
    EXPECT_TRUE(same(kept[1], 0.0));
    // cvttpd2dq: toward zero; INT32_MIN for NaN and out of range.
    int32_t a = 0, b = 0;
    d::truncToInt32(Vec2{-1.9, 2147483647.9}, a, b);
    EXPECT_EQ(a, -1);
    EXPECT_EQ(b, 2147483647);
    d::truncToInt32(Vec2{nan, vLow}, a, b);
    EXPECT_EQ(a, INT32_MIN);
    EXPECT_EQ(b, INT32_MIN);
    const Vec2 t = d::truncInt32Lanes(Vec2{-0.5, vHuge});
    EXPECT_TRUE(same(t[0], 0.0));
    EXPECT_TRUE(same(t[1], -2147483648.0));
    // sqrt, loads and stores.
    double buf[3] = {2.0, 3.0, 7.0};
    const Vec2 r = d::sqrtLanes(d::loadLanes(buf + 1));
    EXPECT_TRUE(same(r[0], std::sqrt(3.0)));
    EXPECT_TRUE(same(r[1], std::sqrt(7.0)));
    d::storeLanes(buf, r);
    EXPECT_TRUE(same(buf[0], std::sqrt(3.0)) && same(buf[1], std::sqrt(7.0)));
    d::storeLane1(buf + 2, Vec2{8.0, 9.0});
    d::storeLane0(buf, Vec2{10.0, 11.0});
    EXPECT_EQ(buf[0], 10.0);
    EXPECT_EQ(buf[2], 9.0);
}

#if defined(SEMLOC_HAVE_SSE2)
namespace
{
/** Doubles that tell lane operations apart: signed zeros, NaNs of both signs, infinities,
 *  subnormals, the int32 range's edges, halves (rounding), and random bit patterns. */
std::vector<double> laneValues()
{
    volatile double nan = std::nan("");  // read at run time: no folding of the conversions
    std::vector<double> v = {
        0.0,           -0.0,          1.0,           -1.0,      0.5,     -0.5,         1.5,
        -2.5,          3.0,           -3.0,          1e6,       -1e6,    nan,          -nan,
        HUGE_VAL,      -HUGE_VAL,     4.9e-324,      -4.9e-324, 1.7e308, 2147483647.9, 2147483648.0,
        -2147483648.0, -2147483648.9, -2147483649.0, 1e300,     -1e300};
    mrpt::random::CRandomGenerator rng(7);
    for (int i = 0; i < 40; i++)
    {
        v.push_back(rng.drawUniform(-1e3, 1e3));
        uint64_t bits =
            (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
        double d = 0;
        std::memcpy(&d, &bits, sizeof d);
        v.push_back(d);
    }
    return v;
}

/** Both lanes of a and b have the same bits. */
bool sameLanes(semloc::detail::Vec2 a, semloc::detail::Vec2 b)
{
    return sameBits(a[0], b[0]) && sameBits(a[1], b[1]);
}
}  // namespace

TEST(FastMath, PortableLaneOperationsGiveSse2sBits)
{
    using semloc::detail::Vec2;
    namespace p = semloc::detail::portable;
    namespace s = semloc::detail::sse2;
    const std::vector<double> vals = laneValues();
    size_t cases = 0;
    std::vector<std::string> differ;  // the operation and the lanes of each difference
    size_t i = 0, j = 0;
    auto check = [&](const char* op, bool same)
    {
        cases++;
        if (!same && differ.size() < 10)
        {
            differ.push_back(std::string(op) + " at " + std::to_string(i) + ", " +
                             std::to_string(j));
        }
    };
    for (i = 0; i + 1 < vals.size(); i++)
    {
        for (j = 0; j + 1 < vals.size(); j++)
        {
            const Vec2 a{vals[i], vals[i + 1]}, b{vals[j], vals[j + 1]};
            check("lessEqualBits", p::lessEqualBits(a, b) == s::lessEqualBits(a, b));
            check("lessBits", p::lessBits(a, b) == s::lessBits(a, b));
            check("lessEqualMask", sameLanes(p::lessEqualMask(a, b), s::lessEqualMask(a, b)));
            check("lessMask", sameLanes(p::lessMask(a, b), s::lessMask(a, b)));
            check("greaterEqualMask",
                  sameLanes(p::greaterEqualMask(a, b), s::greaterEqualMask(a, b)));
            check("minLanes", sameLanes(p::minLanes(a, b), s::minLanes(a, b)));
            check("maxLanes", sameLanes(p::maxLanes(a, b), s::maxLanes(a, b)));
            // Bitwise: any bits, masks or not.
            check("xorLanes", sameLanes(p::xorLanes(a, b), s::xorLanes(a, b)));
            check("andLanes", sameLanes(p::andLanes(a, b), s::andLanes(a, b)));
            check("orLanes", sameLanes(p::orLanes(a, b), s::orLanes(a, b)));
            check("negateLanes", sameLanes(p::negateLanes(a, b), s::negateLanes(a, b)));
            const Vec2 m = s::lessMask(a, b);
            check("selectLanes", sameLanes(p::selectLanes(m, a, b), s::selectLanes(m, a, b)));
            check("selectIf", sameBits(p::selectIf(vals[j] < 0, vals[i], vals[j]),
                                       s::selectIf(vals[j] < 0, vals[i], vals[j])));
        }
        const Vec2 a{vals[i], vals[i + 1]};
        check("maskBits", p::maskBits(a) == s::maskBits(a));
        check("absLanes", sameLanes(p::absLanes(a), s::absLanes(a)));
        check("sqrtLanes", sameLanes(p::sqrtLanes(a), s::sqrtLanes(a)));
        check("truncInt32Lanes", sameLanes(p::truncInt32Lanes(a), s::truncInt32Lanes(a)));
        int32_t p0 = 0, p1 = 0, s0 = 0, s1 = 0;
        p::truncToInt32(a, p0, p1);
        s::truncToInt32(a, s0, s1);
        check("truncToInt32", p0 == s0 && p1 == s1);
        check("negateIf", sameBits(p::negateIf(true, vals[i]), s::negateIf(true, vals[i])) &&
                              sameBits(p::negateIf(false, vals[i]), s::negateIf(false, vals[i])));
        if (!std::isnan(vals[i]) && !std::signbit(vals[i]))  // copySignLanes: a magnitude, +0 up
        {
            check("copySignLanes",
                  sameLanes(p::copySignLanes(vals[i], a), s::copySignLanes(vals[i], a)));
        }
        if (std::abs(vals[i]) < 2147483648.0 && std::abs(vals[i + 1]) < 2147483648.0)
        {
            Vec2 po, pt, so, st;  // truncLanes: |v| < 2^31
            check("truncLanes", sameLanes(p::truncLanes(a, po, pt), s::truncLanes(a, so, st)) &&
                                    sameLanes(po, so) && sameLanes(pt, st));
        }
        double pb[3] = {1, 2, 3}, sb[3] = {1, 2, 3};
        p::storeLanes(pb, p::loadLanes(&vals[i]));
        s::storeLanes(sb, s::loadLanes(&vals[i]));
        p::storeLane1(pb + 2, a);
        s::storeLane1(sb + 2, a);
        p::storeLane0(pb + 1, a);
        s::storeLane0(sb + 1, a);
        check("loadLanes/storeLanes/storeLane0/storeLane1",
              sameBits(pb[0], sb[0]) && sameBits(pb[1], sb[1]) && sameBits(pb[2], sb[2]));
    }
    EXPECT_TRUE(differ.empty()) << differ.size() << " of " << cases << " cases differ, first "
                                << (differ.empty() ? std::string() : differ.front());
    EXPECT_GT(cases, 100000u);
}
#endif

/* semloc — e^x for the particle weights (private). */
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "math/FastMath.h"

namespace semloc::detail
{
/** The parts of expFast() and expFast2(): the same operations on a double or on two. */
namespace expfast
{
constexpr int kN = 128;
constexpr double kInvLn2N = kN / 0.693147180559945309417232121458;
// ln 2 / N split (fdlibm's ln2_hi, ln2_lo) so that k * kLn2HiN is exact for |k| < 2^20.
constexpr double kLn2HiN = 6.93147180369123816490e-01 / kN;
constexpr double kLn2LoN = 1.90821492927058770002e-10 / kN;
// Round to nearest by the 1.5 * 2^52 shift (|x N / ln 2| < 2^51): no libm call, any ISA.
constexpr double kShift = 0x1.8p52;

/** 2^(j / N) as a double and its rounding error. */
struct Table
{
    std::array<double, kN> hi{}, lo{};
};

inline const Table& table()
{
    static const Table t = []
    {
        Table s;
        for (int j = 0; j < kN; j++)
        {
            const long double v = std::exp2(static_cast<long double>(j) / kN);
            s.hi[j] = static_cast<double>(v);
            s.lo[j] = static_cast<double>(v - static_cast<long double>(s.hi[j]));
        }
        return s;
    }();
    return t;
}

/** The constant v as a T (a double, or both lanes of a Vec2: one constant load). */
template <typename T>
T splat(double v) noexcept
{
    if constexpr (std::is_same_v<T, Vec2>)
    {
        return Vec2{v, v};
    }
    else
    {
        return v;
    }
}

/** k = round(x N / ln 2) as a double. */
template <typename T>
T roundedK(T x) noexcept
{
    return (x * splat<T>(kInvLn2N) + splat<T>(kShift)) - splat<T>(kShift);
}

/** e^r - 1 for r = x - k ln 2 / N. */
template <typename T>
T expm1Reduced(T x, T kd) noexcept
{
    const T r = (x - kd * splat<T>(kLn2HiN)) - kd * splat<T>(kLn2LoN);
    return r + r * r *
                   (splat<T>(0.5) + r * (splat<T>(1.0 / 6) +
                                         r * (splat<T>(1.0 / 24) + r * (splat<T>(1.0 / 120) +
                                                                        r * splat<T>(1.0 / 720)))));
}

/** 2^(k div N) 2^((k mod N) / N) (1 + p) without the last product: the table term m and
 *  the scale. */
inline double combine(double kd, double p, double& scale) noexcept
{
    const Table& t = table();
    const auto k = static_cast<int64_t>(kd);
    const auto j = static_cast<size_t>(k & (kN - 1));
    const int64_t e = k >> 7;  // floor(k / N): (k - j) / N exactly (arithmetic shift)
    static_assert(kN == 1 << 7);
    const uint64_t scaleBits = static_cast<uint64_t>(e + 1023) << 52;
    std::memcpy(&scale, &scaleBits, sizeof scale);
    return t.hi[j] + (t.lo[j] + t.hi[j] * p);
}

/** expFast's own range [-kRange, kRange]; libm beyond. */
constexpr double kRange = 700.0;
}  // namespace expfast

/** e^x within 1 ulp of the exact value (test_ExpFast compares it with libm's over the
 *  weights' range), inline and about half the instructions of a libm call: one per particle
 *  and step in the weights pass. Table method (Tang 1989): x = (k / N) ln 2 + r with
 *  |r| <= ln 2 / (2 N), N = 128, e^x = 2^(k div N) 2^((k mod N) / N) e^r, the middle factor
 *  from a table (as a double and its rounding error), e^r by its degree-6 Taylor polynomial
 *  (truncation < 1e-20). Outside [-700, 700] (and for NaN) libm's exp. */
inline double expFast(double x) noexcept
{
    if (!(x >= -expfast::kRange && x <= expfast::kRange))
    {
        return std::exp(x);
    }
    const double kd = expfast::roundedK(x);
    double scale = 0;
    const double m = expfast::combine(kd, expfast::expm1Reduced(x, kd), scale);
    return m * scale;
}

/** expFast of two values, bit for bit, the reduction and the polynomial of both in one
 *  pass of packed operations (the same IEEE operations lane by lane). */
inline void expFast2(double x0, double x1, double& y0, double& y1) noexcept
{
    const Vec2 x{x0, x1};
    using expfast::kRange;
    if ((lessEqualBits(Vec2{-kRange, -kRange}, x) & lessEqualBits(x, Vec2{kRange, kRange})) !=
        kBothLanes)
    {
        y0 = expFast(x0);
        y1 = expFast(x1);
        return;
    }
    const Vec2 kd = expfast::roundedK(x);
    const Vec2 p = expfast::expm1Reduced(x, kd);
    double s0 = 0, s1 = 0;
    const double m0 = expfast::combine(kd[0], p[0], s0);
    const double m1 = expfast::combine(kd[1], p[1], s1);
    const Vec2 y = Vec2{m0, m1} * Vec2{s0, s1};
    y0 = y[0];
    y1 = y[1];
}

}  // namespace semloc::detail

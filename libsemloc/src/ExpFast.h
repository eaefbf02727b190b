/* semloc — e^x for the particle weights (private). */
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace semloc::detail
{
/** e^x within 1 ulp of the exact value (test_ExpFast compares it with libm's over the
 *  weights' range), inline and about half the instructions of a libm call: one per particle
 *  and step in the weights pass. Table method (Tang 1989): x = (k / N) ln 2 + r with
 *  |r| <= ln 2 / (2 N), N = 128, e^x = 2^(k div N) 2^((k mod N) / N) e^r, the middle factor
 *  from a table (as a double and its rounding error), e^r by its degree-6 Taylor polynomial
 *  (truncation < 1e-20). Outside [-700, 700] (and for NaN) libm's exp. */
inline double expFast(double x) noexcept
{
    constexpr int kN = 128;
    if (!(x >= -700.0 && x <= 700.0))
    {
        return std::exp(x);
    }
    struct Table
    {
        std::array<double, kN> hi{}, lo{};
    };
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
    constexpr double kInvLn2N = kN / 0.693147180559945309417232121458;
    // ln 2 / N split (fdlibm's ln2_hi, ln2_lo) so that k * kLn2HiN is exact for |k| < 2^20.
    constexpr double kLn2HiN = 6.93147180369123816490e-01 / kN;
    constexpr double kLn2LoN = 1.90821492927058770002e-10 / kN;
    // Round to nearest by the 1.5 * 2^52 shift (|x N / ln 2| < 2^51): no libm call, any ISA.
    constexpr double kShift = 0x1.8p52;
    const double kd = (x * kInvLn2N + kShift) - kShift;
    const auto k = static_cast<int64_t>(kd);
    const double r = (x - kd * kLn2HiN) - kd * kLn2LoN;
    const double p =
        r + r * r * (0.5 + r * (1.0 / 6 + r * (1.0 / 24 + r * (1.0 / 120 + r * (1.0 / 720)))));
    const auto j = static_cast<size_t>(k & (kN - 1));
    const int64_t e = (k - static_cast<int64_t>(j)) / kN;
    const double m = t.hi[j] + (t.lo[j] + t.hi[j] * p);
    const uint64_t scaleBits = static_cast<uint64_t>(e + 1023) << 52;
    double scale = 0;
    std::memcpy(&scale, &scaleBits, sizeof scale);
    return m * scale;
}

}  // namespace semloc::detail

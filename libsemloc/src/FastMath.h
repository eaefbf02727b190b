/* semloc — small numeric kernels for the per-particle loops (private). */
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

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

/** sin and cos of x together, |error| < 1e-15 for |x| <= 1e6 (checked against libm in
 *  test_FastMath), several times cheaper than libm's sincos: one per particle. Cody-Waite
 *  reduction by pi/2, then Taylor polynomials on [-pi/4, pi/4] (truncation < 5e-17). */
inline void fastSinCos(double x, double& s, double& c) noexcept
{
    if (!(std::abs(x) <= 1e6))
    {
        s = std::sin(x);  // huge or NaN: rare, let libm handle it
        c = std::cos(x);
        return;
    }
    const double kd = x * M_2_PI;
    const long long k = static_cast<long long>(kd >= 0 ? kd + 0.5 : kd - 0.5);
    const double kf = static_cast<double>(k);
    // pi/2 split so that kf * kPio2Hi is exact for |k| < 2^20.
    constexpr double kPio2Hi = 1.57079632673412561417e+00;
    constexpr double kPio2Lo = 6.07710050650619224932e-11;
    const double r = (x - kf * kPio2Hi) - kf * kPio2Lo;
    const double r2 = r * r;
    const double sr =
        r + r * r2 *
                (-1.0 / 6 +
                 r2 * (1.0 / 120 +
                       r2 * (-1.0 / 5040 +
                             r2 * (1.0 / 362880 +
                                   r2 * (-1.0 / 39916800 +
                                         r2 * (1.0 / 6227020800 + r2 * (-1.0 / 1307674368000)))))));
    const double cr =
        1 + r2 * (-0.5 +
                  r2 * (1.0 / 24 + r2 * (-1.0 / 720 +
                                         r2 * (1.0 / 40320 +
                                               r2 * (-1.0 / 3628800 +
                                                     r2 * (1.0 / 479001600 +
                                                           r2 * (-1.0 / 87178291200 +
                                                                 r2 * (1.0 / 20922789888000))))))));
    switch (k & 3)
    {
        case 0:
            s = sr;
            c = cr;
            break;
        case 1:
            s = cr;
            c = -sr;
            break;
        case 2:
            s = -sr;
            c = -cr;
            break;
        default:
            s = -cr;
            c = sr;
            break;
    }
}

/** One of logFast's 128 subintervals of z: 1/c (9 bits) and -log(1/c) = logcHi + logcLo
 *  (logcHi a multiple of 2^-32), and the bits of z kept in z_hi. */
struct LogEntry
{
    double invc, logcHi, logcLo;
    uint64_t zMask;
};
constexpr uint64_t kLogZ44 = ~uint64_t{0x1ff}, kLogZ53 = ~uint64_t{0};
/** Generated with long double: the subinterval i of z is the doubles with bits in
 *  kLogOff + [i, i + 1) 2^45, 1/c is 1 / (its centre) rounded to 9 bits, log(1/c) by logl
 *  (test_FastMath recomputes the table). */
constexpr uint64_t kLogOff = 0x3fe6000000000000ULL - (uint64_t{1} << 44);
constexpr LogEntry kLogTable[128] = {
    {0x1.74p+0, -0x1.7eaf83b8p-2, -0x1.57e1b26p-37, kLogZ44},
    {0x1.72p+0, -0x1.792a55fcp-2, -0x1.d47a27c2p-34, kLogZ44},
    {0x1.7p+0, -0x1.739d7f6cp-2, 0x1.0bfe58c8p-36, kLogZ44},
    {0x1.6ep+0, -0x1.6e08eaa4p-2, 0x1.45e1c73ep-34, kLogZ44},
    {0x1.6cp+0, -0x1.686c81e8p-2, -0x1.b14aec44p-34, kLogZ44},
    {0x1.6ap+0, -0x1.62c82f2cp-2, 0x1.8e1ab42p-36, kLogZ44},
    {0x1.68p+0, -0x1.5d1bdbf4p-2, -0x1.809ca50ap-34, kLogZ44},
    {0x1.66p+0, -0x1.57677174p-2, -0x1.569b1528p-36, kLogZ44},
    {0x1.64p+0, -0x1.51aad874p-2, 0x1.207d2f64p-34, kLogZ44},
    {0x1.62p+0, -0x1.4be5f958p-2, 0x1.10ebe494p-35, kLogZ44},
    {0x1.6p+0, -0x1.4618bc2p-2, -0x1.c5ec27d2p-34, kLogZ44},
    {0x1.5ep+0, -0x1.40430868p-2, -0x1.a9f8ef48p-36, kLogZ44},
    {0x1.5dp+0, -0x1.3d54fa5cp-2, -0x1.f70f874p-38, kLogZ44},
    {0x1.5bp+0, -0x1.3772662cp-2, 0x1.3d286dp-41, kLogZ44},
    {0x1.59p+0, -0x1.31871c94p-2, -0x1.44184facp-34, kLogZ44},
    {0x1.57p+0, -0x1.2b9303acp-2, 0x1.d8b6d898p-36, kLogZ44},
    {0x1.55p+0, -0x1.2596010cp-2, -0x1.f7639efp-34, kLogZ44},
    {0x1.54p+0, -0x1.22941fbcp-2, -0x1.ef2cb448p-35, kLogZ44},
    {0x1.52p+0, -0x1.1c898c18p-2, 0x1.66605044p-34, kLogZ44},
    {0x1.5p+0, -0x1.1675cabcp-2, 0x1.459f1fc6p-34, kLogZ44},
    {0x1.4ep+0, -0x1.1058bf9cp-2, 0x1.1b52ae76p-34, kLogZ44},
    {0x1.4dp+0, -0x1.0d46b578p-2, -0x1.ab74b208p-34, kLogZ44},
    {0x1.4bp+0, -0x1.071b85fcp-2, -0x1.ab21a3a4p-35, kLogZ44},
    {0x1.49p+0, -0x1.00e6c45cp-2, 0x1.2afe3396p-34, kLogZ44},
    {0x1.48p+0, -0x1.fb9186d8p-3, 0x1.0e0eab95p-34, kLogZ44},
    {0x1.46p+0, -0x1.ef0adccp-3, 0x1.1d364d6fp-34, kLogZ44},
    {0x1.44p+0, -0x1.e27076ep-3, -0x1.57972f5p-34, kLogZ44},
    {0x1.43p+0, -0x1.dc1bca08p-3, -0x1.5f63eb07p-34, kLogZ44},
    {0x1.41p+0, -0x1.cf6354ep-3, -0x1.38bb891cp-36, kLogZ44},
    {0x1.4p+0, -0x1.c8ff7c78p-3, -0x1.a9a21ac2p-35, kLogZ44},
    {0x1.3ep+0, -0x1.bc28674p-3, -0x1.6c66b15p-34, kLogZ44},
    {0x1.3dp+0, -0x1.b5b519e8p-3, -0x1.f6b48dd4p-36, kLogZ44},
    {0x1.3bp+0, -0x1.a8becfc8p-3, -0x1.05e3185cp-36, kLogZ44},
    {0x1.3ap+0, -0x1.a23bc2p-3, 0x1.d4a9ce6cp-35, kLogZ44},
    {0x1.38p+0, -0x1.9525a9dp-3, 0x1.75297138p-36, kLogZ44},
    {0x1.37p+0, -0x1.8e928de8p-3, -0x1.0da8154cp-36, kLogZ44},
    {0x1.35p+0, -0x1.815c0a18p-3, 0x1.e540a94cp-34, kLogZ44},
    {0x1.34p+0, -0x1.7ab8902p-3, -0x1.0d9091bep-35, kLogZ44},
    {0x1.32p+0, -0x1.6d60fe7p-3, -0x1.9d21c8d6p-35, kLogZ44},
    {0x1.31p+0, -0x1.66acd428p-3, 0x1.aa55e424p-36, kLogZ44},
    {0x1.2fp+0, -0x1.59338d98p-3, -0x1.82085d34p-35, kLogZ44},
    {0x1.2ep+0, -0x1.526e5e38p-3, -0x1.0da1bd17p-34, kLogZ44},
    {0x1.2dp+0, -0x1.4ba36f38p-3, -0x1.a55e55a2p-35, kLogZ44},
    {0x1.2bp+0, -0x1.3dfc2b1p-3, 0x1.339d6356p-35, kLogZ44},
    {0x1.2ap+0, -0x1.371fc2p-3, -0x1.e8f743bep-35, kLogZ44},
    {0x1.29p+0, -0x1.303d719p-3, 0x1.b802d016p-35, kLogZ44},
    {0x1.27p+0, -0x1.2266f19p-3, -0x1.4b596facp-36, kLogZ44},
    {0x1.26p+0, -0x1.1b72ad5p-3, -0x1.7b3d0148p-34, kLogZ44},
    {0x1.25p+0, -0x1.14785848p-3, 0x1.8bd53976p-35, kLogZ44},
    {0x1.23p+0, -0x1.0671513p-3, 0x1.ad348eafp-34, kLogZ44},
    {0x1.22p+0, -0x1.fec9132p-4, 0x1.20aa2aaep-35, kLogZ44},
    {0x1.21p+0, -0x1.f0a30cp-4, -0x1.162a6618p-36, kLogZ44},
    {0x1.1fp+0, -0x1.d4313d6p-4, -0x1.b2cd7579p-34, kLogZ44},
    {0x1.1ep+0, -0x1.c5e548fp-4, -0x1.6f1d0c578p-34, kLogZ44},
    {0x1.1dp+0, -0x1.b78c82cp-4, 0x1.3c497bdfp-34, kLogZ44},
    {0x1.1cp+0, -0x1.a926d3ap-4, -0x1.2b558d948p-34, kLogZ44},
    {0x1.1ap+0, -0x1.8c345d6p-4, -0x1.8cd907aep-35, kLogZ44},
    {0x1.19p+0, -0x1.7da766dp-4, -0x1.ec4b3211p-34, kLogZ44},
    {0x1.18p+0, -0x1.6f0d28bp-4, 0x1.a94b4642p-36, kLogZ44},
    {0x1.17p+0, -0x1.60658a9p-4, -0x1.ba861d8fp-35, kLogZ44},
    {0x1.16p+0, -0x1.51b073fp-4, -0x1.860fda48p-38, kLogZ44},
    {0x1.15p+0, -0x1.42edcbfp-4, 0x1.66e43f11p-34, kLogZ44},
    {0x1.13p+0, -0x1.253f62fp-4, -0x1.4282df2p-37, kLogZ44},
    {0x1.12p+0, -0x1.16536efp-4, 0x1.72147c5e8p-34, kLogZ44},
    {0x1.11p+0, -0x1.0759836p-4, 0x1.9c6e3b3f8p-34, kLogZ44},
    {0x1.1p+0, -0x1.f0a30cp-5, -0x1.162a6618p-37, kLogZ44},
    {0x1.0fp+0, -0x1.d276b8ap-5, -0x1.b616a423cp-34, kLogZ44},
    {0x1.0ep+0, -0x1.b42dd72p-5, 0x1.cd1c827acp-34, kLogZ44},
    {0x1.0dp+0, -0x1.95c830ep-5, -0x1.91c7d6fbp-34, kLogZ44},
    {0x1.0bp+0, -0x1.58a5bbp-5, 0x1.b8d95b9cp-36, kLogZ44},
    {0x1.0ap+0, -0x1.39e87bap-5, 0x1.42a057p-41, kLogZ44},
    {0x1.09p+0, -0x1.1b0d98ap-5, 0x1.b84d007a4p-34, kLogZ44},
    {0x1.08p+0, -0x1.f829b1p-6, 0x1.87ccffb3p-34, kLogZ44},
    {0x1.07p+0, -0x1.b9fc028p-6, 0x1.41b9a0108p-36, kLogZ44},
    {0x1.06p+0, -0x1.7b91b08p-6, 0x1.52772ab6p-37, kLogZ44},
    {0x1.05p+0, -0x1.3cea444p-6, 0x1.72b516218p-35, kLogZ44},
    {0x1.04p+0, -0x1.fc0a8bp-7, -0x1.f807c79f4p-36, kLogZ44},
    {0x1.03p+0, -0x1.7dc476p-7, 0x1.fbd6248b8p-37, kLogZ44},
    {0x1.02p+0, -0x1.fe02a7p-8, 0x1.3be61dc0fp-34, kLogZ44},
    {0x1.01p+0, -0x1.ff00aap-9, -0x1.5885e0251p-36, kLogZ44},
    {0x1p+0, 0.0, 0.0, kLogZ53},
    {0x1.fcp-1, 0x1.0101578p-7, -0x1.3b90c76b9p-34, kLogZ44},
    {0x1.f8p-1, 0x1.0205658p-6, 0x1.26b08e94p-35, kLogZ44},
    {0x1.f4p-1, 0x1.8492528p-6, 0x1.91957d174p-35, kLogZ44},
    {0x1.fp-1, 0x1.0415d8ap-5, -0x1.8bbbb8fep-37, kLogZ44},
    {0x1.edp-1, 0x1.35c8bfap-5, 0x1.4260d5f58p-34, kLogZ44},
    {0x1.e9p-1, 0x1.788595ap-5, 0x1.abbdd3ccp-36, kLogZ44},
    {0x1.e5p-1, 0x1.bbcebfcp-5, 0x1.a3d080f3p-35, kLogZ44},
    {0x1.e2p-1, 0x1.eea31cp-5, 0x1.ae1eec2p-39, kLogZ44},
    {0x1.dep-1, 0x1.1973bd1p-4, 0x1.19559b458p-34, kLogZ44},
    {0x1.dbp-1, 0x1.333d7f8p-4, 0x1.83f4b6a6p-36, kLogZ44},
    {0x1.d7p-1, 0x1.55e1005p-4, 0x1.c07075dp-37, kLogZ44},
    {0x1.d4p-1, 0x1.700d30bp-4, -0x1.53f1f0b8p-36, kLogZ44},
    {0x1.d1p-1, 0x1.8a6477bp-4, -0x1.b88f5cfdp-34, kLogZ44},
    {0x1.cep-1, 0x1.a4e7641p-4, -0x1.390f215bp-34, kLogZ44},
    {0x1.cap-1, 0x1.c885802p-4, -0x1.0ed3725c8p-34, kLogZ44},
    {0x1.c7p-1, 0x1.e3707eep-4, 0x1.8243da14p-35, kLogZ44},
    {0x1.c4p-1, 0x1.fe8913ap-4, -0x1.2154d359p-35, kLogZ44},
    {0x1.c1p-1, 0x1.0ce7ecep-3, -0x1.99eb9ad2p-34, kLogZ44},
    {0x1.bep-1, 0x1.1aa2b7ep-3, 0x1.1fb94f1dp-34, kLogZ44},
    {0x1.bbp-1, 0x1.28753bcp-3, 0x1.1aba4a72p-35, kLogZ44},
    {0x1.b8p-1, 0x1.365fcbp-3, 0x1.590162fap-35, kLogZ44},
    {0x1.b5p-1, 0x1.4462b9ep-3, -0x1.b2612162p-34, kLogZ44},
    {0x1.b2p-1, 0x1.527e5e48p-3, 0x1.0dac67d2p-34, kLogZ44},
    {0x1.afp-1, 0x1.60b31008p-3, 0x1.84a3aea5p-34, kLogZ44},
    {0x1.acp-1, 0x1.6f0128b8p-3, -0x1.52a88c7p-36, kLogZ44},
    {0x1.aap-1, 0x1.7898d858p-3, -0x1.dd9c661p-34, kLogZ44},
    {0x1.a7p-1, 0x1.87121378p-3, -0x1.78b35c53p-34, kLogZ44},
    {0x1.a4p-1, 0x1.95a5addp-3, -0x1.1fd01bbp-36, kLogZ44},
    {0x1.a1p-1, 0x1.a454083p-3, -0x1.954fac42p-35, kLogZ44},
    {0x1.9fp-1, 0x1.ae2ca6f8p-3, -0x1.8d42b952p-35, kLogZ44},
    {0x1.9cp-1, 0x1.bd08738p-3, 0x1.dec56878p-34, kLogZ44},
    {0x1.9ap-1, 0x1.c6ffbc7p-3, -0x1.fe11ec7p-36, kLogZ44},
    {0x1.97p-1, 0x1.d60a17f8p-3, 0x1.035148fep-35, kLogZ44},
    {0x1.95p-1, 0x1.e020cc6p-3, 0x1.1ad5a9ffp-34, kLogZ44},
    {0x1.92p-1, 0x1.ef5ade5p-3, -0x1.1800d108p-34, kLogZ44},
    {0x1.9p-1, 0x1.f991c6c8p-3, 0x1.9d9bcbedp-34, kLogZ44},
    {0x1.8dp-1, 0x1.047e60ccp-2, 0x1.e83b7be2p-34, kLogZ44},
    {0x1.8bp-1, 0x1.09aa573p-2, -0x1.9392bd78p-34, kLogZ44},
    {0x1.88p-1, 0x1.1178e824p-2, -0x1.81b8421cp-34, kLogZ44},
    {0x1.86p-1, 0x1.16b5ccbcp-2, -0x1.3048ca64p-34, kLogZ44},
    {0x1.84p-1, 0x1.1bf99634p-2, 0x1.a6b94ddap-34, kLogZ44},
    {0x1.82p-1, 0x1.214456dp-2, 0x1.d71a87ep-35, kLogZ44},
    {0x1.7fp-1, 0x1.2941afbp-2, 0x1.86b7bcf6p-34, kLogZ44},
    {0x1.7dp-1, 0x1.2e9e2bdp-2, -0x1.edd79fe8p-34, kLogZ44},
    {0x1.7bp-1, 0x1.3401e12cp-2, -0x1.1345f1cep-34, kLogZ44},
    {0x1.79p-1, 0x1.396ce358p-2, 0x1.bbf53e32p-34, kLogZ44},
    {0x1.76p-1, 0x1.419b423cp-2, 0x1.5e8c721cp-34, kLogZ44},
};

/** Natural log within 1 ulp of libm's (test_FastMath: <= 1 ulp from std::log over millions
 *  of arguments; < 0.51 ulp from the exact value), inline and without libm's call. Positive
 *  normal finite x only on the fast path; 0, subnormals, negatives, inf and NaN go to
 *  std::log (its values and errno). Table method (as Tang 1990): x = 2^k z with z in
 *  [0.686, 1.371) and log x = k ln 2 - log(1/c) + log1p(z/c - 1), 128 subintervals of z
 *  (kLogTable) with 1/c = 1 on the one around z = 1, so that log x near 1 is log1p of an
 *  exact z - 1. z_hi / c - 1 is exact for z_hi = z to 44 bits; log1p(d) - d by its degree-8
 *  Taylor polynomial (|d| < 2^-7.6: truncation < 2^-9 ulp of the result); the sum
 *  k ln2_hi + log(1/c)_hi + d is exact in two doubles, so only the final add rounds at the
 *  result's ulp. */
inline double logFast(double x) noexcept
{
    constexpr uint64_t kMinNormal = 0x0010000000000000ULL, kInfBits = 0x7ff0000000000000ULL;
    uint64_t ix = 0;
    std::memcpy(&ix, &x, sizeof ix);
    if (ix - kMinNormal >= kInfBits - kMinNormal)
    {
        return std::log(x);
    }
    // fdlibm's ln 2 split: k * kLn2Hi is exact (32 bits times |k| < 2^11).
    constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
    const uint64_t tmp = ix - kLogOff;
    const LogEntry& en = kLogTable[(tmp >> 45) % 128];
    const auto k = static_cast<int64_t>(tmp) >> 52;
    const uint64_t iz = ix - (tmp & (0xfffULL << 52));
    const uint64_t izHi = iz & en.zMask;
    double z = 0, zHi = 0;
    std::memcpy(&z, &iz, sizeof z);
    std::memcpy(&zHi, &izHi, sizeof zHi);
    // z / c - 1 = d + dl: d exact (44 x 9 bits, then Sterbenz), |dl| < 2^-44.
    const double d = zHi * en.invc - 1.0;
    const double dl = (z - zHi) * en.invc;
    const double kd = static_cast<double>(k);
    const double w = kd * kLn2Hi + en.logcHi;  // exact: both multiples of 2^-32, |w| < 2^10
    const double hi = w + d;
    const double lo = (w - hi) + d;  // exact (|w| >= |d| or w = 0)
    const double d2 = d * d;
    // log1p(d) - d, and log1p(d + dl) - log1p(d) = dl (1 - d + d^2) to < 2^-68.
    const double p = d2 * ((-0.5 + d * (1.0 / 3)) + d2 * (-0.25 + d * 0.2) +
                           d2 * d2 * ((-1.0 / 6 + d * (1.0 / 7)) + d2 * -0.125));
    const double pl = dl - dl * (d - d2);
    return hi + (lo + (kd * kLn2Lo + en.logcLo) + (pl + p));
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

/* semloc — small numeric kernels for the per-particle loops (private). */
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
// SEMLOC_FORCE_SCALAR (CMake option): the portable code on any machine, to test it.
#if defined(__SSE2__) && defined(__x86_64__) && !defined(SEMLOC_FORCE_SCALAR)
#include <emmintrin.h>
#define SEMLOC_FASTMATH_SSE2 1
#endif

namespace semloc::detail
{
/** Two doubles operated on together (SSE2 on x86-64, plain code elsewhere): IEEE operations
 *  lane by lane, so the same bits as scalar code (no contraction into FMA: baseline ISA). */
using Vec2 = double __attribute__((vector_size(16)));
/** Lane-wise a <= b as bits (bit k for lane k; false for NaN, as the scalar comparison). */
inline int lessEqualBits(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_movemask_pd(_mm_cmple_pd(a, b));
#else
    return (a[0] <= b[0] ? 1 : 0) | (a[1] <= b[1] ? 2 : 0);
#endif
}

/** Lane-wise a < b as bits (bit k for lane k; false for NaN, as the scalar comparison). */
inline int lessBits(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_movemask_pd(_mm_cmplt_pd(a, b));
#else
    return (a[0] < b[0] ? 1 : 0) | (a[1] < b[1] ? 2 : 0);
#endif
}

/** Both lanes' bits. */
constexpr int kBothLanes = 3;

#if !defined(SEMLOC_FASTMATH_SSE2)
/** The bits of a double, and back (the portable lane masks). */
inline uint64_t bitsOf(double v) noexcept
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

inline double ofBits(uint64_t b) noexcept
{
    double v = 0;
    std::memcpy(&v, &b, sizeof v);
    return v;
}
#endif

/** m ? a : b lane by lane, for a lane mask m (each lane all ones or all zeros). */
inline Vec2 selectLanes(Vec2 m, Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b));
#else
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        const uint64_t mi = bitsOf(m[i]);
        r[i] = ofBits((mi & bitsOf(a[i])) | (~mi & bitsOf(b[i])));
    }
    return r;
#endif
}

/** m ? -v : v lane by lane (the sign bit flipped), for a lane mask m. */
inline Vec2 negateLanes(Vec2 m, Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_xor_pd(v, _mm_and_pd(m, _mm_set1_pd(-0.0)));
#else
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        r[i] = ofBits(bitsOf(v[i]) ^ (bitsOf(m[i]) & bitsOf(-0.0)));
    }
    return r;
#endif
}

/** The lane masks of a != b (of two lane masks: exclusive or). */
inline Vec2 xorLanes(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_xor_pd(a, b);
#else
    return Vec2{ofBits(bitsOf(a[0]) ^ bitsOf(b[0])), ofBits(bitsOf(a[1]) ^ bitsOf(b[1]))};
#endif
}

/** copysign(mag, s) lane by lane, for mag >= 0. */
inline Vec2 copySignLanes(double mag, Vec2 s) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_or_pd(_mm_and_pd(_mm_set1_pd(-0.0), s), _mm_set1_pd(mag));
#else
    return Vec2{std::copysign(mag, s[0]), std::copysign(mag, s[1])};
#endif
}

/** v truncated toward zero lane by lane (|v| < 2^31), as doubles; `odd` and `two` are the
 *  lane masks of bit 0 and of bit 1 of the truncated integers (a quadrant's reflections). */
inline Vec2 truncLanes(Vec2 v, Vec2& odd, Vec2& two) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    const __m128i k = _mm_cvttpd_epi32(v);  // k0, k1 in the low two 32-bit lanes
    // k0 k0 k1 k1 as 32-bit lanes, then the masks of bit 0 and of bit 1 per 64-bit lane.
    const __m128i kk = _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 1, 0, 0));
    const __m128i one = _mm_set1_epi32(1), bit1 = _mm_set1_epi32(2);
    odd = _mm_castsi128_pd(_mm_cmpeq_epi32(_mm_and_si128(kk, one), one));
    two = _mm_castsi128_pd(_mm_cmpeq_epi32(_mm_and_si128(kk, bit1), bit1));
    return _mm_cvtepi32_pd(k);
#else
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        const auto k = static_cast<long long>(v[i]);
        odd[i] = ofBits((k & 1) != 0 ? ~uint64_t{0} : 0);
        two[i] = ofBits((k & 2) != 0 ? ~uint64_t{0} : 0);
        r[i] = static_cast<double>(k);
    }
    return r;
#endif
}

/** |v| lane by lane (the sign bits cleared). */
inline Vec2 absLanes(Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_andnot_pd(_mm_set1_pd(-0.0), v);
#else
    return Vec2{std::abs(v[0]), std::abs(v[1])};
#endif
}

/** The two doubles at p (no alignment needed). */
inline Vec2 loadLanes(const double* p) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_loadu_pd(p);
#else
    return Vec2{p[0], p[1]};
#endif
}

/** Stores both lanes at p (no alignment needed). */
inline void storeLanes(double* p, Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    _mm_storeu_pd(p, v);
#else
    p[0] = v[0];
    p[1] = v[1];
#endif
}

/** Stores lane 0 at p. */
inline void storeLane0(double* p, Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    _mm_storel_pd(p, v);
#else
    *p = v[0];
#endif
}

/** Stores lane 1 at p. */
inline void storeLane1(double* p, Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    _mm_storeh_pd(p, v);
#else
    *p = v[1];
#endif
}

/** a < b ? a : b lane by lane (SSE2's minpd: b when either is NaN). */
inline Vec2 minLanes(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_min_pd(a, b);
#else
    return Vec2{a[0] < b[0] ? a[0] : b[0], a[1] < b[1] ? a[1] : b[1]};
#endif
}

/** a > b ? a : b lane by lane (SSE2's maxpd: b when either is NaN). */
inline Vec2 maxLanes(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_max_pd(a, b);
#else
    return Vec2{a[0] > b[0] ? a[0] : b[0], a[1] > b[1] ? a[1] : b[1]};
#endif
}

/** The square roots of both lanes (IEEE, correctly rounded as std::sqrt). */
inline Vec2 sqrtLanes(Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_sqrt_pd(v);
#else
    return Vec2{std::sqrt(v[0]), std::sqrt(v[1])};
#endif
}

#if !defined(SEMLOC_FASTMATH_SSE2)
/** The lane mask of a condition: all ones if c, else all zeros. */
inline double laneMask(bool c) noexcept
{
    return ofBits(c ? ~uint64_t{0} : 0);
}
#endif

/** The lane masks of a <= b (false for NaN, as the scalar comparison). */
inline Vec2 lessEqualMask(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_cmple_pd(a, b);
#else
    return Vec2{laneMask(a[0] <= b[0]), laneMask(a[1] <= b[1])};
#endif
}

/** The lane masks of a < b (false for NaN). */
inline Vec2 lessMask(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_cmplt_pd(a, b);
#else
    return Vec2{laneMask(a[0] < b[0]), laneMask(a[1] < b[1])};
#endif
}

/** The lane masks of a >= b (false for NaN). */
inline Vec2 greaterEqualMask(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_cmpge_pd(a, b);
#else
    return Vec2{laneMask(a[0] >= b[0]), laneMask(a[1] >= b[1])};
#endif
}

/** The bits of a and b (two lane masks: both conditions; a mask and a value: the value where
 *  the mask is set, else +0). */
inline Vec2 andLanes(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_and_pd(a, b);
#else
    return Vec2{ofBits(bitsOf(a[0]) & bitsOf(b[0])), ofBits(bitsOf(a[1]) & bitsOf(b[1]))};
#endif
}

/** The bits of a or b (two lane masks: either condition). */
inline Vec2 orLanes(Vec2 a, Vec2 b) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_or_pd(a, b);
#else
    return Vec2{ofBits(bitsOf(a[0]) | bitsOf(b[0])), ofBits(bitsOf(a[1]) | bitsOf(b[1]))};
#endif
}

/** The lanes of a lane mask as bits (bit k for lane k: its sign bit). */
inline int maskBits(Vec2 m) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_movemask_pd(m);
#else
    return static_cast<int>(bitsOf(m[0]) >> 63) | static_cast<int>((bitsOf(m[1]) >> 63) << 1);
#endif
}

/** Both lanes truncated toward zero to 32-bit integers, into i0 and i1: INT32_MIN for NaN
 *  and for values outside the int32 range (SSE2's cvttpd2dq), never an undefined conversion. */
inline void truncToInt32(Vec2 v, int32_t& i0, int32_t& i1) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    const __m128i k = _mm_cvttpd_epi32(v);
    i0 = _mm_cvtsi128_si32(k);
    i1 = _mm_cvtsi128_si32(_mm_srli_si128(k, 4));
#else
    auto one = [](double x)
    { return x > -2147483649.0 && x < 2147483648.0 ? static_cast<int32_t>(x) : INT32_MIN; };
    i0 = one(v[0]);
    i1 = one(v[1]);
#endif
}

/** Both lanes truncated toward zero through 32-bit integers, as doubles (SSE2's cvttpd2dq
 *  then cvtdq2pd: -2^31 for NaN and values outside the int32 range). */
inline Vec2 truncInt32Lanes(Vec2 v) noexcept
{
#if defined(SEMLOC_FASTMATH_SSE2)
    return _mm_cvtepi32_pd(_mm_cvttpd_epi32(v));
#else
    int32_t i0 = 0, i1 = 0;
    truncToInt32(v, i0, i1);
    return Vec2{static_cast<double>(i0), static_cast<double>(i1)};
#endif
}

/** Branch-free selections for the per-particle kernels: branches on data that is random
 *  per particle (a quadrant, a pair that gains or not) were mispredicted about every other
 *  time. The values are those of the plain expressions, bit for bit. */
#if defined(SEMLOC_FASTMATH_SSE2)
/** A mask of all ones if c, in the low lane. */
inline __m128d maskOf(bool c) noexcept
{
    return _mm_castsi128_pd(_mm_cvtsi64_si128(-static_cast<long long>(c)));
}

/** m ? a : b for a mask m of all ones or zeros. */
inline double blend(__m128d m, double a, double b) noexcept
{
    return _mm_cvtsd_f64(_mm_or_pd(_mm_and_pd(m, _mm_set_sd(a)), _mm_andnot_pd(m, _mm_set_sd(b))));
}

/** c ? a : b. */
inline double selectIf(bool c, double a, double b) noexcept
{
    return blend(maskOf(c), a, b);
}

/** c ? -v : v. */
inline double negateIf(bool c, double v) noexcept
{
    return _mm_cvtsd_f64(_mm_xor_pd(_mm_set_sd(v), _mm_and_pd(maskOf(c), _mm_set_sd(-0.0))));
}
#else
inline double selectIf(bool c, double a, double b) noexcept
{
    return c ? a : b;
}

inline double negateIf(bool c, double v) noexcept
{
    return c ? -v : v;
}
#endif

/** atan(z) for z in [0, 1]: fastAtan2's polynomial, for a double or two (Vec2, lane by
 *  lane): the same operations in the same order. */
template <typename T>
inline T atanUnit(T z) noexcept
{
    const T z2 = z * z;
    // Minimax coefficients for atan(z) on [0, 1] (odd, degree 15).
    T r = z2 * -0.0040540580 + 0.0218612288;
    r = r * z2 - 0.0559098861;
    r = r * z2 + 0.0964200441;
    r = r * z2 - 0.1390853351;
    r = r * z2 + 0.1994653599;
    r = r * z2 - 0.3332985605;
    r = r * z2 + 0.9999993329;
    return r * z;
}

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
    double r = atanUnit(mn / mx);
    // Branches here measured faster than blends (the likelihood's bearing differences).
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

/** |fastAtan2(y, x)|, bit for bit, with a short path for |angle| <= 45 degrees (x > 0,
 *  |y| <= x): there fastAtan2 takes atanUnit(|y| / x) and no reflection. */
inline double fastAbsAtan2(double y, double x) noexcept
{
    const double ay = std::abs(y);
    return x > 0 && ay <= x ? atanUnit(ay / x) : std::abs(fastAtan2(y, x));
}

/** fastAbsAtan2 of two (y, x) at once, bit for bit: both lanes' short paths in the two
 *  lanes of a Vec2 (one division, one polynomial chain for both), else lane by lane. */
inline Vec2 fastAbsAtan2x2(Vec2 y, Vec2 x) noexcept
{
    const Vec2 ay = absLanes(y);
    if ((lessBits(Vec2{0, 0}, x) & lessEqualBits(ay, x)) == kBothLanes)
    {
        return atanUnit(ay / x);
    }
    return Vec2{fastAbsAtan2(y[0], x[0]), fastAbsAtan2(y[1], x[1])};
}

/** pi/2 split so that kf * kPio2Hi is exact for |k| < 2^20 (fastSinCos' reduction). */
constexpr double kPio2Hi = 1.57079632673412561417e+00;
constexpr double kPio2Lo = 6.07710050650619224932e-11;

/** sin(r) and cos(r) on [-pi/4, pi/4] (r2 = r * r): Taylor polynomials, truncation < 5e-17,
 *  for a double or two (Vec2, lane by lane): the same operations in the same order. */
template <typename T>
inline T sinReduced(T r, T r2) noexcept
{
    return r + r * r2 *
                   (-1.0 / 6 +
                    r2 * (1.0 / 120 +
                          r2 * (-1.0 / 5040 +
                                r2 * (1.0 / 362880 + r2 * (-1.0 / 39916800 +
                                                           r2 * (1.0 / 6227020800 +
                                                                 r2 * (-1.0 / 1307674368000)))))));
}

template <typename T>
inline T cosReduced(T r2) noexcept
{
    return 1.0 +
           r2 * (-0.5 +
                 r2 * (1.0 / 24 + r2 * (-1.0 / 720 +
                                        r2 * (1.0 / 40320 +
                                              r2 * (-1.0 / 3628800 +
                                                    r2 * (1.0 / 479001600 +
                                                          r2 * (-1.0 / 87178291200 +
                                                                r2 * (1.0 / 20922789888000))))))));
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
    // Rounded half away from zero (kd + 0.5 or kd - 0.5 by the sign bit: no branch).
    const long long k = static_cast<long long>(kd + std::copysign(0.5, kd));
    const double kf = static_cast<double>(k);
    const double r = (x - kf * kPio2Hi) - kf * kPio2Lo;
    const double r2 = r * r;
    const double sr = sinReduced(r, r2);
    const double cr = cosReduced(r2);
    // Quadrant q = k mod 4: (s, c) = (sr, cr), (cr, -sr), (-sr, -cr), (-cr, sr).
    const auto q = static_cast<unsigned>(k & 3);
    const bool swap = (q & 1u) != 0;
    s = negateIf((q & 2u) != 0, selectIf(swap, cr, sr));
    c = negateIf(((q ^ (q >> 1)) & 1u) != 0, selectIf(swap, sr, cr));
}

/** fastSinCos of two angles at once, lane by lane, bit for bit: the same IEEE operations in
 *  the same order on both lanes (half the instructions, and the two polynomial chains, whose
 *  latency bound the per-particle loops, side by side). A lane outside |x| <= 1e6 (or NaN)
 *  sends both to the scalar function. */
inline void fastSinCos2(Vec2 x, Vec2& s, Vec2& c) noexcept
{
    auto scalarLanes = [](Vec2 a, Vec2& sa, Vec2& ca)
    {
        double s0 = 0, c0 = 0, s1 = 0, c1 = 0;
        fastSinCos(a[0], s0, c0);
        fastSinCos(a[1], s1, c1);
        sa = Vec2{s0, s1};
        ca = Vec2{c0, c1};
    };
    if (lessEqualBits(absLanes(x), Vec2{1e6, 1e6}) != kBothLanes)
    {
        scalarLanes(x, s, c);
        return;
    }
    const Vec2 kd = x * M_2_PI;
    // Rounded half away from zero, then truncated toward zero as the scalar cast.
    Vec2 swap, negS;
    const Vec2 kf = truncLanes(kd + copySignLanes(0.5, kd), swap, negS);
    const Vec2 r = (x - kf * kPio2Hi) - kf * kPio2Lo;
    const Vec2 r2 = r * r;
    const Vec2 sr = sinReduced(r, r2);
    const Vec2 cr = cosReduced(r2);
    // Quadrant q = k mod 4: swap on bit 0, sin negated on bit 1, cos on bit 0 xor bit 1.
    s = negateLanes(negS, selectLanes(swap, cr, sr));
    c = negateLanes(xorLanes(swap, negS), selectLanes(swap, sr, cr));
}

/** Calls f(i, sin, cos) for i in [0, n) with the sin and cos of angle(i), computed two at a
 *  time (fastSinCos2), the last one alone when n is odd: the same bits as one at a time.
 *  angle(i + 1) is read before f(i) runs. */
template <typename Angle, typename F>
inline void forEachSinCos(size_t n, Angle&& angle, F&& f)
{
    size_t i = 0;
    for (; i + 1 < n; i += 2)
    {
        Vec2 s, c;
        fastSinCos2(Vec2{angle(i), angle(i + 1)}, s, c);
        f(i, s[0], c[0]);
        f(i + 1, s[1], c[1]);
    }
    if (i < n)
    {
        double s = 0, c = 0;
        fastSinCos(angle(i), s, c);
        f(i, s, c);
    }
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

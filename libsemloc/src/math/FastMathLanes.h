/* semloc — the lane operations under the per-particle kernels (private): SSE2 on x86-64, the
 * same bits in portable code elsewhere. */
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#define SEMLOC_HAVE_SSE2 1
#endif

namespace semloc::detail
{
/** Two doubles operated on together (SSE2 on x86-64, plain code elsewhere): IEEE operations
 *  lane by lane, so the same bits as scalar code (no contraction into FMA: baseline ISA). */
using Vec2 = double __attribute__((vector_size(16)));

/** Both lanes' bits. */
constexpr int kBothLanes = 3;

/** The lane operations in portable code: what a build without SSE2 runs. Each gives the bits
 *  of its SSE2 twin (test_FastMath compares the two on every x86-64 build). */
namespace portable
{
/** The bits of a double, and back. */
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

/** The lane mask of a condition: all ones if c, else all zeros. */
inline double laneMask(bool c) noexcept
{
    return ofBits(c ? ~uint64_t{0} : 0);
}

inline int lessEqualBits(Vec2 a, Vec2 b) noexcept
{
    return (a[0] <= b[0] ? 1 : 0) | (a[1] <= b[1] ? 2 : 0);
}

inline int lessBits(Vec2 a, Vec2 b) noexcept
{
    return (a[0] < b[0] ? 1 : 0) | (a[1] < b[1] ? 2 : 0);
}

inline Vec2 selectLanes(Vec2 m, Vec2 a, Vec2 b) noexcept
{
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        const uint64_t mi = bitsOf(m[i]);
        r[i] = ofBits((mi & bitsOf(a[i])) | (~mi & bitsOf(b[i])));
    }
    return r;
}

inline Vec2 negateLanes(Vec2 m, Vec2 v) noexcept
{
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        r[i] = ofBits(bitsOf(v[i]) ^ (bitsOf(m[i]) & bitsOf(-0.0)));
    }
    return r;
}

inline Vec2 xorLanes(Vec2 a, Vec2 b) noexcept
{
    return Vec2{ofBits(bitsOf(a[0]) ^ bitsOf(b[0])), ofBits(bitsOf(a[1]) ^ bitsOf(b[1]))};
}

inline Vec2 copySignLanes(double mag, Vec2 s) noexcept
{
    return Vec2{std::copysign(mag, s[0]), std::copysign(mag, s[1])};
}

inline Vec2 truncLanes(Vec2 v, Vec2& odd, Vec2& two) noexcept
{
    Vec2 r{};
    for (int i = 0; i < 2; i++)
    {
        const auto k = static_cast<long long>(v[i]);
        odd[i] = laneMask((k & 1) != 0);
        two[i] = laneMask((k & 2) != 0);
        r[i] = static_cast<double>(k);
    }
    return r;
}

inline Vec2 absLanes(Vec2 v) noexcept
{
    return Vec2{std::abs(v[0]), std::abs(v[1])};
}

inline Vec2 loadLanes(const double* p) noexcept
{
    return Vec2{p[0], p[1]};
}

inline void storeLanes(double* p, Vec2 v) noexcept
{
    p[0] = v[0];
    p[1] = v[1];
}

inline void storeLane0(double* p, Vec2 v) noexcept
{
    *p = v[0];
}

inline void storeLane1(double* p, Vec2 v) noexcept
{
    *p = v[1];
}

inline Vec2 minLanes(Vec2 a, Vec2 b) noexcept
{
    return Vec2{a[0] < b[0] ? a[0] : b[0], a[1] < b[1] ? a[1] : b[1]};
}

inline Vec2 maxLanes(Vec2 a, Vec2 b) noexcept
{
    return Vec2{a[0] > b[0] ? a[0] : b[0], a[1] > b[1] ? a[1] : b[1]};
}

inline Vec2 sqrtLanes(Vec2 v) noexcept
{
    return Vec2{std::sqrt(v[0]), std::sqrt(v[1])};
}

inline Vec2 lessEqualMask(Vec2 a, Vec2 b) noexcept
{
    return Vec2{laneMask(a[0] <= b[0]), laneMask(a[1] <= b[1])};
}

inline Vec2 lessMask(Vec2 a, Vec2 b) noexcept
{
    return Vec2{laneMask(a[0] < b[0]), laneMask(a[1] < b[1])};
}

inline Vec2 greaterEqualMask(Vec2 a, Vec2 b) noexcept
{
    return Vec2{laneMask(a[0] >= b[0]), laneMask(a[1] >= b[1])};
}

inline Vec2 andLanes(Vec2 a, Vec2 b) noexcept
{
    return Vec2{ofBits(bitsOf(a[0]) & bitsOf(b[0])), ofBits(bitsOf(a[1]) & bitsOf(b[1]))};
}

inline Vec2 orLanes(Vec2 a, Vec2 b) noexcept
{
    return Vec2{ofBits(bitsOf(a[0]) | bitsOf(b[0])), ofBits(bitsOf(a[1]) | bitsOf(b[1]))};
}

inline int maskBits(Vec2 m) noexcept
{
    return static_cast<int>(bitsOf(m[0]) >> 63) | static_cast<int>((bitsOf(m[1]) >> 63) << 1);
}

inline void truncToInt32(Vec2 v, int32_t& i0, int32_t& i1) noexcept
{
    auto one = [](double x)
    { return x > -2147483649.0 && x < 2147483648.0 ? static_cast<int32_t>(x) : INT32_MIN; };
    i0 = one(v[0]);
    i1 = one(v[1]);
}

inline Vec2 truncInt32Lanes(Vec2 v) noexcept
{
    int32_t i0 = 0, i1 = 0;
    truncToInt32(v, i0, i1);
    return Vec2{static_cast<double>(i0), static_cast<double>(i1)};
}

inline double selectIf(bool c, double a, double b) noexcept
{
    return c ? a : b;
}

inline double negateIf(bool c, double v) noexcept
{
    return c ? -v : v;
}
}  // namespace portable

#if defined(SEMLOC_HAVE_SSE2)
/** The lane operations in SSE2 (documented where they are chosen, below). */
namespace sse2
{
inline int lessEqualBits(Vec2 a, Vec2 b) noexcept
{
    return _mm_movemask_pd(_mm_cmple_pd(a, b));
}

inline int lessBits(Vec2 a, Vec2 b) noexcept
{
    return _mm_movemask_pd(_mm_cmplt_pd(a, b));
}

inline Vec2 selectLanes(Vec2 m, Vec2 a, Vec2 b) noexcept
{
    return _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b));
}

inline Vec2 negateLanes(Vec2 m, Vec2 v) noexcept
{
    return _mm_xor_pd(v, _mm_and_pd(m, _mm_set1_pd(-0.0)));
}

inline Vec2 xorLanes(Vec2 a, Vec2 b) noexcept
{
    return _mm_xor_pd(a, b);
}

inline Vec2 copySignLanes(double mag, Vec2 s) noexcept
{
    return _mm_or_pd(_mm_and_pd(_mm_set1_pd(-0.0), s), _mm_set1_pd(mag));
}

inline Vec2 truncLanes(Vec2 v, Vec2& odd, Vec2& two) noexcept
{
    const __m128i k = _mm_cvttpd_epi32(v);  // k0, k1 in the low two 32-bit lanes
    // k0 k0 k1 k1 as 32-bit lanes, then the masks of bit 0 and of bit 1 per 64-bit lane.
    const __m128i kk = _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 1, 0, 0));
    const __m128i one = _mm_set1_epi32(1), bit1 = _mm_set1_epi32(2);
    odd = _mm_castsi128_pd(_mm_cmpeq_epi32(_mm_and_si128(kk, one), one));
    two = _mm_castsi128_pd(_mm_cmpeq_epi32(_mm_and_si128(kk, bit1), bit1));
    return _mm_cvtepi32_pd(k);
}

inline Vec2 absLanes(Vec2 v) noexcept
{
    return _mm_andnot_pd(_mm_set1_pd(-0.0), v);
}

inline Vec2 loadLanes(const double* p) noexcept
{
    return _mm_loadu_pd(p);
}

inline void storeLanes(double* p, Vec2 v) noexcept
{
    _mm_storeu_pd(p, v);
}

inline void storeLane0(double* p, Vec2 v) noexcept
{
    _mm_storel_pd(p, v);
}

inline void storeLane1(double* p, Vec2 v) noexcept
{
    _mm_storeh_pd(p, v);
}

inline Vec2 minLanes(Vec2 a, Vec2 b) noexcept
{
    return _mm_min_pd(a, b);
}

inline Vec2 maxLanes(Vec2 a, Vec2 b) noexcept
{
    return _mm_max_pd(a, b);
}

inline Vec2 sqrtLanes(Vec2 v) noexcept
{
    return _mm_sqrt_pd(v);
}

inline Vec2 lessEqualMask(Vec2 a, Vec2 b) noexcept
{
    return _mm_cmple_pd(a, b);
}

inline Vec2 lessMask(Vec2 a, Vec2 b) noexcept
{
    return _mm_cmplt_pd(a, b);
}

inline Vec2 greaterEqualMask(Vec2 a, Vec2 b) noexcept
{
    return _mm_cmpge_pd(a, b);
}

inline Vec2 andLanes(Vec2 a, Vec2 b) noexcept
{
    return _mm_and_pd(a, b);
}

inline Vec2 orLanes(Vec2 a, Vec2 b) noexcept
{
    return _mm_or_pd(a, b);
}

inline int maskBits(Vec2 m) noexcept
{
    return _mm_movemask_pd(m);
}

inline void truncToInt32(Vec2 v, int32_t& i0, int32_t& i1) noexcept
{
    const __m128i k = _mm_cvttpd_epi32(v);
    i0 = _mm_cvtsi128_si32(k);
    i1 = _mm_cvtsi128_si32(_mm_srli_si128(k, 4));
}

inline Vec2 truncInt32Lanes(Vec2 v) noexcept
{
    return _mm_cvtepi32_pd(_mm_cvttpd_epi32(v));
}

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

inline double selectIf(bool c, double a, double b) noexcept
{
    return blend(maskOf(c), a, b);
}

inline double negateIf(bool c, double v) noexcept
{
    return _mm_cvtsd_f64(_mm_xor_pd(_mm_set_sd(v), _mm_and_pd(maskOf(c), _mm_set_sd(-0.0))));
}
}  // namespace sse2
#endif

// The kernels' lane operations: SSE2 on x86-64; SEMLOC_FORCE_SCALAR (CMake option) takes the
// portable code there too.
#if defined(SEMLOC_HAVE_SSE2) && !defined(SEMLOC_FORCE_SCALAR)
namespace lanes = sse2;
#else
namespace lanes = portable;
#endif

/** Lane-wise a <= b as bits (bit k for lane k; false for NaN, as the scalar comparison). */
using lanes::lessEqualBits;
/** Lane-wise a < b as bits (bit k for lane k; false for NaN, as the scalar comparison). */
using lanes::lessBits;
/** m ? a : b lane by lane, for a lane mask m (each lane all ones or all zeros). */
using lanes::selectLanes;
/** m ? -v : v lane by lane (the sign bit flipped), for a lane mask m. */
using lanes::negateLanes;
/** The lane masks of a != b (of two lane masks: exclusive or). */
using lanes::xorLanes;
/** copysign(mag, s) lane by lane, for mag >= +0 (its sign bit clear: not -0). */
using lanes::copySignLanes;
/** v truncated toward zero lane by lane (|v| < 2^31), as doubles; `odd` and `two` are the
 *  lane masks of bit 0 and of bit 1 of the truncated integers (a quadrant's reflections). */
using lanes::truncLanes;
/** |v| lane by lane (the sign bits cleared). */
using lanes::absLanes;
/** The two doubles at p (no alignment needed). */
using lanes::loadLanes;
/** Stores both lanes at p (no alignment needed). */
using lanes::storeLanes;
/** Stores lane 0 at p. */
using lanes::storeLane0;
/** Stores lane 1 at p. */
using lanes::storeLane1;
/** a < b ? a : b lane by lane (SSE2's minpd: b when either is NaN). */
using lanes::minLanes;
/** a > b ? a : b lane by lane (SSE2's maxpd: b when either is NaN). */
using lanes::maxLanes;
/** The square roots of both lanes (IEEE, correctly rounded as std::sqrt). */
using lanes::sqrtLanes;
/** The lane masks of a <= b (false for NaN, as the scalar comparison). */
using lanes::lessEqualMask;
/** The lane masks of a < b (false for NaN). */
using lanes::lessMask;
/** The lane masks of a >= b (false for NaN). */
using lanes::greaterEqualMask;
/** The bits of a and b (two lane masks: both conditions; a mask and a value: the value where
 *  the mask is set, else +0). */
using lanes::andLanes;
/** The bits of a or b (two lane masks: either condition). */
using lanes::orLanes;
/** The lanes of a lane mask as bits (bit k for lane k: its sign bit). */
using lanes::maskBits;
/** Both lanes truncated toward zero to 32-bit integers, into i0 and i1: INT32_MIN for NaN
 *  and for values outside the int32 range (SSE2's cvttpd2dq), never an undefined conversion. */
using lanes::truncToInt32;
/** Both lanes truncated toward zero through 32-bit integers, as doubles (SSE2's cvttpd2dq
 *  then cvtdq2pd: -2^31 for NaN and values outside the int32 range). */
using lanes::truncInt32Lanes;
/** c ? a : b and c ? -v : v, branch-free where it matters: branches on data that is random
 *  per particle (a quadrant, a pair that gains or not) were mispredicted about every other
 *  time. The values are those of the plain expressions, bit for bit. */
using lanes::negateIf;
using lanes::selectIf;

}  // namespace semloc::detail

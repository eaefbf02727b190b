/* semloc — the particles' log-weights: extremes, normalization, effective sample size and
 * log-sum-exp. */
#include "filter/Weights.h"

#include <semloc/filter/ParallelExecutor.h>

#include <cmath>
#include <type_traits>

#include "math/ExpFast.h"

namespace semloc::detail
{
namespace
{
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
/** Smallest range a thread claims of a loop of a few nanoseconds per particle (max/min scans,
 *  weight shifts): the pool's threads poll between the calls of a step, so a call costs a
 *  microsecond or two, a few thousand particles' worth (the results are the same either
 *  way). */
constexpr size_t kCheapLoopGrain = 2048;
/** Loops with an exp() per particle (~20 ns) are worth splitting from this many on. */
constexpr size_t kExpLoopChunk = 4096;

/** The weights exp(log_w - maxW) of the particles [b, e) into `out` (if writeOut), and
 *  their sum and sum of squares in particle order. */
template <bool writeOut>
void weightSums(const ParticleList& particles, size_t b, size_t e, double maxW, double* out,
                double& sum, double& sumSq)
{
    double s = 0, s2 = 0;
    forEachRun(particles, b, e,
               [&](const auto* p, size_t i0, size_t n)
               {
                   // Two at a time (expFast2), the sums in particle order.
                   size_t k = 0;
                   for (; k + 1 < n; k += 2)
                   {
                       double w0 = 0, w1 = 0;
                       expFast2(p[k].log_w - maxW, p[k + 1].log_w - maxW, w0, w1);
                       if constexpr (writeOut)
                       {
                           out[i0 + k] = w0;
                           out[i0 + k + 1] = w1;
                       }
                       s = (s + w0) + w1;
                       s2 = (s2 + w0 * w0) + w1 * w1;
                   }
                   if (k < n)
                   {
                       const double w = expFast(p[k].log_w - maxW);
                       if constexpr (writeOut)
                       {
                           out[i0 + k] = w;
                       }
                       s += w;
                       s2 += w * w;
                   }
               });
    sum = s;
    sumSq = s2;
}
}  // namespace

WeightRange minMaxLogWeights(const ParticleList& particles, ParallelExecutor& ex, size_t count)
{
    std::vector<WeightRange> partial(ex.threads());
    ex.forEachRange(
        std::min(count, particles.size()),
        [&](size_t b, size_t e, size_t thread)
        {
            // Even and odd particles apart: two dependency chains, the same extremes.
            WeightRange even, odd;
            forEachRun(particles, b, e,
                       [&](const auto* p, size_t, size_t n)
                       { addExtremes(n, even, odd, [&](size_t k) { return p[k].log_w; }); });
            partial[thread].add(even);
            partial[thread].add(odd);
        },
        kCheapLoopGrain);
    WeightRange r;
    for (const auto& p : partial)
    {
        r.add(p);
    }
    return r;
}

void shiftLogWeights(ParticleList& particles, ParallelExecutor& ex, double maxW)
{
    ex.forEachRange(
        particles.size(),
        [&](size_t b, size_t e, size_t)
        {
            forEachRun(particles, b, e,
                       [&](auto* p, size_t, size_t n)
                       {
                           for (size_t k = 0; k < n; k++)
                           {
                               p[k].log_w -= maxW;
                           }
                       });
        },
        kCheapLoopGrain);
}

double logSumExpWeights(const ParticleList& particles, ParallelExecutor& ex, size_t count)
{
    const size_t n = std::min(count, particles.size());
    double maxW = kNegInf;
    for (size_t i = 0; i < n; i++)
    {
        maxW = std::max(maxW, particles[i].log_w);
    }
    if (!(maxW > kNegInf))
    {
        return maxW;
    }
    const double sum = ex.reduceBlocks(
        n,
        [&](size_t b, size_t e)
        {
            double s = 0;
            for (size_t i = b; i < e; i++)
            {
                s += std::exp(particles[i].log_w - maxW);
            }
            return s;
        },
        kExpLoopChunk / ParallelExecutor::kReduceBlock);
    return maxW + std::log(sum);
}

double weightsAndESS(const ParticleList& particles, ParallelExecutor& ex, const WeightRange& range,
                     std::vector<double>* linW)
{
    // ESS = (sum w)^2 / (M sum w^2), shift-invariant: computed relative to the largest
    // log-weight, over fixed blocks (same bits for any thread count).
    const size_t M = particles.size();
    if (M == 0)
    {
        return 0;
    }
    const double maxW = range.max, minW = range.min;
    if (!(maxW > kNegInf) || std::isinf(maxW))
    {
        return 0;
    }
    if (linW)
    {
        linW->resize(M);
    }
    if (minW == maxW)
    {
        if (linW)
        {
            std::fill(linW->begin(), linW->end(), 1.0);
        }
        return 1;  // equal weights (e.g. just resampled): what the sums below give exactly
    }
    double* out = linW ? linW->data() : nullptr;
    constexpr size_t kBlock = ParallelExecutor::kReduceBlock;
    const size_t blocks = (M + kBlock - 1) / kBlock;
    std::vector<double> sumW(blocks), sumW2(blocks);
    ex.forEachChunk(
        blocks,
        [&](size_t b0, size_t b1)
        {
            for (size_t blk = b0; blk < b1; blk++)
            {
                const size_t b = blk * kBlock, e = std::min(M, b + kBlock);
                if (out)
                {
                    weightSums<true>(particles, b, e, maxW, out, sumW[blk], sumW2[blk]);
                }
                else
                {
                    weightSums<false>(particles, b, e, maxW, out, sumW[blk], sumW2[blk]);
                }
            }
        },
        kExpLoopChunk / kBlock);
    double s = 0, s2 = 0;
    for (size_t blk = 0; blk < blocks; blk++)
    {
        s += sumW[blk];
        s2 += sumW2[blk];
    }
    return s2 > 0 ? s * s / (static_cast<double>(M) * s2) : 0;
}
}  // namespace semloc::detail

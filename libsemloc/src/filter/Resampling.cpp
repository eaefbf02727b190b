/* semloc — resampling: systematic resampling in blocks, substitution by indices. */
#include "filter/Resampling.h"

#include <mrpt/core/exceptions.h>
#include <semloc/filter/ParallelExecutor.h>

#include <algorithm>
#include <cmath>

namespace semloc::detail
{
namespace
{
/** Loops that copy a particle or do a little more per particle (~10 ns). */
constexpr size_t kCopyLoopGrain = 1024;
}  // namespace

void SystematicResampling::setWeights(const std::vector<double>& w)
{
    m_w = &w;
    const size_t M = w.size();
    const size_t blocks = (M + kBlock - 1) / kBlock;
    m_blockCum.resize(blocks + 1);
    double total = 0;
    for (size_t blk = 0; blk < blocks; blk++)
    {
        m_blockCum[blk] = total;  // c_{s-1} of the block's first particle s (0 for s = 0)
        const size_t e = std::min(M, (blk + 1) * kBlock);
        for (size_t i = blk * kBlock; i < e; i++)
        {
            total += w[i];
        }
    }
    m_blockCum[blocks] = total;
    ASSERT_(total > 0);
    m_total = total;
    m_last = M - 1;  // the last particle of positive weight: no pointer goes beyond it
    while (m_last > 0 && !(w[m_last] > 0))
    {
        m_last--;
    }
}

void SystematicResampling::findFirstPointers(double u, double step)
{
    const size_t M = m_w->size();
    const size_t blocks = m_blockCum.size() - 1;
    const auto pointer = [&](size_t i) { return (u + static_cast<double>(i)) * step; };
    // The block of the last particle of positive weight takes every pointer from its first
    // on, the blocks after it none.
    const size_t lastBlock = m_last / kBlock;
    m_blockFirstPointer.resize(blocks + 1);
    m_blockFirstPointer[0] = 0;
    for (size_t blk = 1; blk <= blocks; blk++)
    {
        if (blk > lastBlock)
        {
            m_blockFirstPointer[blk] = M;
            continue;
        }
        // The first i with t_i >= c (t_i is non-decreasing in i): a guess, then corrected.
        const double c = m_blockCum[blk];
        const double guess = std::ceil(c / step - u);
        size_t i = guess <= 0 ? 0 : std::min<size_t>(M, static_cast<size_t>(guess));
        while (i > 0 && pointer(i - 1) >= c)
        {
            i--;
        }
        while (i < M && pointer(i) < c)
        {
            i++;
        }
        m_blockFirstPointer[blk] = i;
    }
}

void SystematicResampling::copyBlock(size_t blk, double u, double step, const ParticleList& from,
                                     ParticleList& to, const CarriedValues* carried) const
{
    const size_t i0 = m_blockFirstPointer[blk], i1 = m_blockFirstPointer[blk + 1];
    if (i0 >= i1)
    {
        return;
    }
    const std::vector<double>& w = *m_w;
    const size_t M = w.size();
    size_t j = blk * kBlock;
    const size_t jEnd = std::min(m_last, std::min(M, (blk + 1) * kBlock) - 1);
    double cum = m_blockCum[blk] + w[j];
    auto src = from.cbegin() + static_cast<ptrdiff_t>(j);
    forEachRun(to, i0, i1,
               [&](auto* dst, size_t d0, size_t n)
               {
                   // pointer(i) with i counted as a double (exact below 2^53).
                   double di = static_cast<double>(d0);
                   for (size_t k = 0; k < n; k++, di += 1)
                   {
                       const double t = (u + di) * step;
                       while (t >= cum && j < jEnd)
                       {
                           cum += w[++j];
                           ++src;
                       }
                       dst[k].d = src->d;
                       dst[k].log_w = 0;  // equal weights after resampling
                       if (carried)
                       {
                           carried->copy(j, d0 + k);
                       }
                   }
               });
}

void SystematicResampling::resample(double u, const ParticleList& from, ParticleList& to,
                                    ParallelExecutor& ex, const CarriedValues* carried)
{
    const size_t M = m_w->size();
    const double step = m_total / static_cast<double>(M);
    findFirstPointers(u, step);
    to.resize(M);
    ex.forEachRange(
        m_blockCum.size() - 1,
        [&](size_t b0, size_t b1, size_t)
        {
            for (size_t blk = b0; blk < b1; blk++)
            {
                copyBlock(blk, u, step, from, to, carried);
            }
        },
        1);
}

void substituteParticles(const std::vector<size_t>& idx, const ParticleList& from, ParticleList& to,
                         ParallelExecutor& ex, const CarriedValues* carried)
{
    const size_t M = idx.size();
    to.resize(M);
    ex.forEachRange(
        M,
        [&](size_t b, size_t e, size_t)
        {
            auto dst = to.begin() + static_cast<ptrdiff_t>(b);
            for (size_t i = b; i < e; i++, ++dst)
            {
                dst->d = from[idx[i]].d;
                dst->log_w = 0;  // equal weights after resampling
                if (carried)
                {
                    carried->copy(idx[i], i);
                }
            }
        },
        kCopyLoopGrain);
}
std::vector<size_t> systematicResamplingIndices(const std::vector<double>& w, double u,
                                                size_t count)
{
    const size_t M = count > 0 ? count : w.size();
    double total = 0;
    for (const double wi : w)
    {
        total += wi;
    }
    ASSERT_(total > 0);
    size_t last = w.size() - 1;
    while (last > 0 && !(w[last] > 0))
    {
        last--;
    }
    const double step = total / static_cast<double>(M);
    std::vector<size_t> idx(M);
    size_t j = 0;
    double c = w[0];  // c_j
    for (size_t i = 0; i < M; i++)
    {
        const double t = (u + static_cast<double>(i)) * step;
        while (t >= c && j < last)
        {
            j++;
            c += w[j];
        }
        idx[i] = j;
    }
    return idx;
}

}  // namespace semloc::detail

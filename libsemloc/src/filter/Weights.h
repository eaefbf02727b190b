/* semloc — the particles' log-weights: extremes, normalization, effective sample size and
 * log-sum-exp, on the executor's threads with results independent of the thread count
 * (private). */
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "filter/ParticleStore.h"

namespace semloc
{
class ParallelExecutor;
}

namespace semloc::detail
{
/** Smallest and largest log-weight (NaN ignored). */
struct WeightRange
{
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    void add(double w)
    {
        max = std::max(max, w);
        min = std::min(min, w);
    }
    void add(const WeightRange& o)
    {
        max = std::max(max, o.max);
        min = std::min(min, o.min);
    }
};

/** Adds logW(k) for k in [0, n) to `even` (k even) or `odd` (k odd): two dependency chains
 *  of max and min instead of one, the same extremes. */
template <typename Range, typename LogW>
inline void addExtremes(size_t n, Range& even, Range& odd, LogW&& logW)
{
    size_t k = 0;
    for (; k + 1 < n; k += 2)
    {
        even.add(logW(k));
        odd.add(logW(k + 1));
    }
    if (k < n)
    {
        even.add(logW(k));
    }
}

/** Extremes of the log-weights (of the first `count` particles only, if fewer). */
WeightRange minMaxLogWeights(const ParticleList& particles, ParallelExecutor& ex,
                             size_t count = std::numeric_limits<size_t>::max());

/** Subtracts `maxW` from every log-weight. */
void shiftLogWeights(ParticleList& particles, ParallelExecutor& ex, double maxW);

/** log(sum_i exp(log_w_i)), computed relative to the largest log-weight (-inf when every
 *  weight is zero); over the first `count` particles only, if fewer. */
double logSumExpWeights(const ParticleList& particles, ParallelExecutor& ex,
                        size_t count = std::numeric_limits<size_t>::max());

/** The effective sample size fraction (sum w)^2 / (M sum w^2) from the log-weights'
 *  extremes `range` (0 when every weight is zero or one is infinite); with `linW`, also each
 *  particle's weight relative to the largest (expFast). */
double weightsAndESS(const ParticleList& particles, ParallelExecutor& ex, const WeightRange& range,
                     std::vector<double>* linW);
}  // namespace semloc::detail

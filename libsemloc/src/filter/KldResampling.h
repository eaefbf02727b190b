/* semloc — KLD-sampling at the resampling steps: the sample size of Fox's bound, drawn
 * without resampling at every step (private). */
#pragma once

#include <mrpt/slam/TKLDParams.h>

#include <cstddef>
#include <vector>

#include "filter/ParticleStore.h"

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc::detail
{
/** Fox's KLD bound (Fox, "Adapting the sample size in particle filters through
 *  KLD-sampling", IJRR 2003; MRPT's): the particles that keep the Kullback–Leibler divergence
 *  between the sample and the true posterior below KLD_epsilon with probability
 *  1 - KLD_delta when they occupy `bins` bins, 0.5 / KLD_epsilon chi2inv(1 - KLD_delta, bins - 1)
 *  (0 for one bin). */
size_t kldBound(size_t bins, const mrpt::slam::TKLDParams& p);

/** KLD-sampling from weighted particles, as the resampling of a step: KLD_maxSampleSize
 *  candidates by systematic resampling of the linear weights `w` (offset `u` in [0, 1)),
 *  taken in a random order (a partial Fisher–Yates shuffle, one draw of `rng` per particle
 *  taken) until the particles taken reach max(KLD_minSampleSize, kldBound(bins they
 *  occupy)), Fox's stopping rule, or every candidate. Bins: KLD_binSize_XY in x and y,
 *  KLD_binSize_PHI in the heading. Writes the indices into `particles` to `idx` (in the
 *  order taken); sequential, so the same for any thread count. */
void kldResample(const std::vector<double>& w, const ParticleList& particles,
                 const mrpt::slam::TKLDParams& p, double u, mrpt::random::CRandomGenerator& rng,
                 std::vector<size_t>& idx);
}  // namespace semloc::detail

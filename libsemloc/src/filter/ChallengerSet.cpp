/* semloc — injected particles kept apart from the cloud until the evidence favours them. */
#include "filter/ChallengerSet.h"

#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <vector>

#include "filter/Resampling.h"
#include "filter/Weights.h"

namespace semloc::detail
{
ParticleStore& ChallengerSet::start()
{
    clear();
    return m_set;
}

void ChallengerSet::clear()
{
    m_set.clear();
    m_logSumPrior = m_sumCloud = m_sumSet = m_logOdds = 0;
    m_frames = 0;
}

void ChallengerSet::attach(ParticleStore& store, ParallelExecutor& ex)
{
    m_logSumPrior = logSumExpWeights(m_set.particles, ex);
    store.append(m_set);
}

void ChallengerSet::detach(ParticleStore& store)
{
    store.splitTail(store.particles.size() - m_set.particles.size(), m_set);
}

ChallengerSet::Verdict ChallengerSet::weigh(double cloudLogWAvg, double logPriorOdds,
                                            size_t maxFrames, double beta, ParallelExecutor& ex)
{
    const double logSum = logSumExpWeights(m_set.particles, ex);
    m_sumCloud += cloudLogWAvg;
    m_sumSet += logSum - m_logSumPrior;
    m_logOdds = logPriorOdds + m_sumSet - m_sumCloud;
    m_frames++;
    if (m_logOdds >= 0)
    {
        return Verdict::Merge;
    }
    if (!(m_logOdds > 2 * logPriorOdds) || m_frames >= maxFrames)  // NaN: dropped too
    {
        return Verdict::Drop;
    }
    // Resampled among themselves when degenerate (CParticleFilter's ESS test).
    std::vector<double> w(m_set.particles.size());
    double sum = 0, sumSq = 0;
    for (size_t i = 0; i < w.size(); i++)
    {
        w[i] = std::exp(m_set.particles[i].log_w - logSum);
        sum += w[i];
        sumSq += w[i] * w[i];
    }
    if (sum * sum < beta * static_cast<double>(w.size()) * sumSq)
    {
        const double u = mrpt::random::getRandomGenerator().drawUniform(0.0, 1.0);
        const auto idx = systematicResamplingIndices(w, u, w.size());
        substituteParticles(idx, m_set.particles, m_set.resampled, ex, m_set.carried(w.size()));
        m_set.swapResampled();
    }
    return Verdict::Keep;
}
}  // namespace semloc::detail

/* semloc — the filter's failure handling: the recovery triggers, injected particles drawn from
 * the detections or the free space, and the re-initialization when every weight vanished. */
#include "filter/RecoveryPolicy.h"

#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/SensoryFrameLikelihood.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "filter/Estimate.h"
#include "filter/SensorModels.h"

namespace semloc::detail
{
using mrpt::math::TPose2D;

namespace
{
/** Draws from the detections before falling back to a uniform pose: a detection near the
 *  map's border or an object leaves most of its circle in the free space. */
constexpr int kDetectionTries = 10;
}  // namespace

bool RecoveryPolicy::watches(const SensoryFrameLikelihood& lik) const
{
    const auto& ro = m_augmented.options();
    return ro.enabled() && lik.measures() &&
           (ro.trigger != RecoveryTrigger::Evidence || lik.withoutObjects().detections > 0);
}

double RecoveryPolicy::trigger(double logWAvg, const SensoryFrameLikelihood& lik, double powFactor)
{
    const double pInject =
        m_augmented.options().trigger == RecoveryTrigger::Evidence
            // On the likelihoods' own scale: tempered ones carry powFactor of each frame's
            // evidence, which the margin and the threshold are not.
            ? m_augmented.updateEvidence((logWAvg - powFactor * lik.withoutObjects().logLik) /
                                         powFactor)
            : m_augmented.update(logWAvg);
    m_lastPInject = pInject;
    return m_sampler ? pInject : 0;
}

void RecoveryPolicy::startChallengers(const ParticleStore& cloud, double share,
                                      const mrpt::obs::CSensoryFrame& sf,
                                      const mrpt::maps::CMetricMap* map)
{
    const size_t M = cloud.particles.size();
    const auto K =
        std::max<size_t>(1, static_cast<size_t>(std::lround(share * static_cast<double>(M))));
    const auto detections = detectionSampler(sf, map);
    ParticleStore& set = m_challengers.start();
    set.particles.resize(K);
    size_t fromDet = 0;
    for (size_t k = 0; k < K; k++)
    {
        fromDet += drawRecoveryPose(detections.get(), set.particles[k].d) ? 1 : 0;
        set.particles[k].log_w = 0;
        cloud.copyState(k * M / K, set, k);
    }
    m_stats.injection_steps++;
    m_stats.injected_particles += K;
    m_stats.injected_from_detections += fromDet;
}

ChallengerSet::Verdict RecoveryPolicy::judgeChallengers(double cloudLogWAvg, double beta,
                                                        ParallelExecutor& ex)
{
    const auto& o = m_augmented.options();
    const auto verdict = m_challengers.weigh(cloudLogWAvg, std::log(o.injected_weight),
                                             o.challenger_frames, beta, ex);
    if (verdict == ChallengerSet::Verdict::Drop)
    {
        m_challengers.clear();
    }
    return verdict;
}

void RecoveryPolicy::merged()
{
    m_stats.challenger_merges++;
    m_challengers.clear();
    m_augmented.reset();
}

void RecoveryPolicy::restart()
{
    m_challengers.clear();
    m_augmented.reset();
    m_lastPInject = 0;
}

void RecoveryPolicy::reinitialize(ParticleStore& store, const mrpt::obs::CSensoryFrame& sf,
                                  const mrpt::maps::CMetricMap* map)
{
    m_stats.reinitializations++;
    if (m_sampler)
    {
        // With recovery on, from the frame's detections too (the frame that killed every
        // particle is the best evidence of where the vehicle is).
        const auto detections = detectionSampler(sf, map);
        for (auto& p : store.particles)
        {
            m_stats.reinitialized_from_detections +=
                drawRecoveryPose(detections.get(), p.d) ? 1 : 0;
            p.log_w = 0;
        }
    }
    else
    {
        for (auto& p : store.particles)
        {
            p.log_w = 0;
        }
    }
    m_augmented.reset();
    m_challengers.clear();
    m_lastPInject = 0;
}

std::unique_ptr<BatchLikelihood::PoseProposal> RecoveryPolicy::detectionSampler(
    const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap* map) const
{
    if (m_augmented.options().enabled() && m_augmented.options().from_detections > 0)
    {
        return poseProposal(sf, map);
    }
    return nullptr;
}

bool RecoveryPolicy::drawRecoveryPose(const BatchLikelihood::PoseProposal* detections,
                                      TPose2D& out) const
{
    auto& rng = mrpt::random::getRandomGenerator();
    if (detections && rng.drawUniform(0.0, 1.0) < m_augmented.options().from_detections)
    {
        for (int t = 0; t < kDetectionTries; t++)
        {
            const TPose2D q = detections->draw(rng);
            if (m_sampler->contains(q.x, q.y))
            {
                out = q;
                return true;
            }
        }
    }
    out = m_sampler->draw(rng);
    return false;
}

bool RecoveryPolicy::reseedable(const mrpt::obs::CSensoryFrame& sf,
                                const mrpt::maps::CMetricMap* map) const
{
    return m_augmented.options().lost_var_xy_m2 > 0 && m_sampler &&
           detectionSampler(sf, map) != nullptr;
}

bool RecoveryPolicy::spread(const ParticleList& particles, ParallelExecutor& ex) const
{
    std::vector<double> w;
    const auto [cov, mean] = covarianceAndMean(particles, ex, w);
    (void)mean;
    return cov(0, 0) + cov(1, 1) > m_augmented.options().lost_var_xy_m2;
}

void RecoveryPolicy::inject(ParticleStore& store, double pInject,
                            const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap* map,
                            bool lost)
{
    // Table 8.3: each particle of the resampled set is, with probability p_inject, a
    // random pose instead.
    auto& rng = mrpt::random::getRandomGenerator();
    const auto detections = detectionSampler(sf, map);
    size_t injected = 0, fromDet = 0;
    const double logW = lost ? 0.0 : std::log(m_augmented.options().injected_weight);
    for (auto& p : store.particles)
    {
        if (rng.drawUniform(0.0, 1.0) < pInject)
        {
            injected++;
            fromDet += drawRecoveryPose(detections.get(), p.d) ? 1 : 0;
            p.log_w = logW;  // the resampled ones have 0
        }
    }
    if (injected > 0)
    {
        m_stats.injection_steps++;
        m_stats.injected_particles += injected;
        m_stats.injected_from_detections += fromDet;
        m_stats.lost_injection_steps += lost ? 1 : 0;
    }
}
}  // namespace semloc::detail

/* semloc — what the filter does when localization fails: the recovery triggers, augmented
 * MCL's injected particles and the re-initialization when every weight vanished (private). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/filter/AugmentedMCL.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/models/BatchLikelihood.h>

#include <memory>

#include "filter/ChallengerSet.h"
#include "filter/ParticleStore.h"

namespace mrpt::maps
{
class CMetricMap;
}
namespace mrpt::obs
{
class CSensoryFrame;
}

namespace semloc
{
class FreeSpaceSampler;
class ParallelExecutor;
class SensoryFrameLikelihood;
}  // namespace semloc

namespace semloc::detail
{
/** The failure handling of CParallelMonteCarloLocalization2D (see its "Never NaN, never empty"
 *  and "Recovery"): the trigger (AugmentedMCL: Thrun's averages or the evidence CUSUM), the
 *  poses of injected and re-initialized particles (from the frame's detections or uniform
 *  over the free space) and their counters. The filter asks it, per weighted frame, whether
 *  the frame feeds the trigger (watches), feeds it (trigger) and lets it replace particles
 *  (inject, reinitialize); the resampling before an injection is the filter's. A particle
 *  it moves keeps its motion state (the state is the vehicle's sensors', not the pose's). */
class RecoveryPolicy
{
public:
    using TStats = CParallelMonteCarloLocalization2D::TRecoveryStats;

    void setOptions(const AugmentedMCL::TOptions& o) { m_augmented = AugmentedMCL(o); }
    const AugmentedMCL::TOptions& options() const { return m_augmented.options(); }
    /** Where recovery poses come from (none: a re-initialization keeps the poses, nothing
     *  is injected). */
    void setSampler(std::shared_ptr<const FreeSpaceSampler> sampler)
    {
        m_sampler = std::move(sampler);
    }
    const std::shared_ptr<const FreeSpaceSampler>& sampler() const { return m_sampler; }

    /** True when the planned frame of `lik` feeds the trigger: recovery on, a frame that
     *  measures something and, for the evidence trigger, holds a reading of the maps
     *  (augmented MCL averages the likelihood of measurements: a frame that measures
     *  nothing would count as a perfect fit). */
    bool watches(const SensoryFrameLikelihood& lik) const;
    /** Feeds the trigger with the frame's log w_avg (the prior-weighted average likelihood,
     *  raised to `powFactor`); the share of the particles to replace (0: none; 0 too when
     *  there is no sampler to draw from). */
    double trigger(double logWAvg, const SensoryFrameLikelihood& lik, double powFactor);
    /** A weighted frame that does not feed the trigger (lastInjectionProbability() 0). */
    void noTrigger() { m_lastPInject = 0; }
    /** Replaces each particle of `store` (just resampled) with probability `pInject` by a
     *  recovery pose of log-weight log(injected_weight), or 0 (a resampled particle's) when
     *  `lost` (the sensor resetting while lost, counted as such). */
    void inject(ParticleStore& store, double pInject, const mrpt::obs::CSensoryFrame& sf,
                const mrpt::maps::CMetricMap* map, bool lost = false);
    /** The sensor resetting while lost could act on `sf` (lost_var_xy_m2 > 0, a sampler, a
     *  detection the map can place); whether it does is spread()'s. */
    bool reseedable(const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap* map) const;
    /** The weighted x-y variance of `particles` (log-weights of maximum 0) is above
     *  lost_var_xy_m2: the cloud is lost. */
    bool spread(const ParticleList& particles, ParallelExecutor& ex) const;
    /** True when injected particles form a challenger set (challenger_frames > 0) instead of
     *  replacing particles of the cloud. */
    bool challenges() const { return m_augmented.options().challenger_frames > 0; }
    /** The challenger set (empty when none lives). */
    ChallengerSet& challengers() { return m_challengers; }
    /** Draws a challenger set of share `share` of `cloud`'s particles (at least one) from
     *  the recovery poses, each with the motion state of a cloud particle (evenly spaced). */
    void startChallengers(const ParticleStore& cloud, double share,
                          const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap* map);
    /** After a weighted frame (the set detached): the set's verdict (ChallengerSet::weigh). */
    ChallengerSet::Verdict judgeChallengers(double cloudLogWAvg, double beta, ParallelExecutor& ex);
    /** The challengers joined the cloud: counted, the set forgotten, the trigger restarted. */
    void merged();
    /** A new run: the trigger forgets its averages and shortfall, a live challenger set is
     *  dropped; the counters keep counting. */
    void restart();
    /** Every weight vanished: every particle re-drawn (with a sampler; else the poses
     *  stay), log-weights 0; the trigger forgets its averages. */
    void reinitialize(ParticleStore& store, const mrpt::obs::CSensoryFrame& sf,
                      const mrpt::maps::CMetricMap* map);

    /** The share injected at the last trigger() (0 when off or after a re-initialization). */
    double lastInjectionProbability() const { return m_lastPInject; }
    /** The evidence trigger's shortfall (AugmentedMCL::shortfall()). */
    double shortfall() const { return m_augmented.shortfall(); }
    const TStats& stats() const { return m_stats; }
    /** Counts particles the free-space prior found outside the free space. */
    void countOutside(size_t n) { m_stats.outside_free_space += n; }

private:
    /** The poses the frame's observations place, to draw recovery poses from (recovery on,
     *  from_detections > 0, a sensor model that proposes poses from the frame:
     *  BatchLikelihood::proposal()), else none. */
    std::unique_ptr<BatchLikelihood::PoseProposal> detectionSampler(
        const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap* map) const;
    /** A recovery pose into `out`: with probability from_detections one from `detections`
     *  (if any) in the free space (true), else uniform over the free space (false). */
    bool drawRecoveryPose(const BatchLikelihood::PoseProposal* detections,
                          mrpt::math::TPose2D& out) const;

    AugmentedMCL m_augmented;
    std::shared_ptr<const FreeSpaceSampler> m_sampler;
    TStats m_stats;
    double m_lastPInject = 0;
    ChallengerSet m_challengers;
};
}  // namespace semloc::detail

/* semloc — injected particles kept apart from the cloud until the evidence favours them
 * (private). */
#pragma once

#include <cstddef>

#include "filter/ParticleStore.h"

namespace semloc
{
class ParallelExecutor;
}

namespace semloc::detail
{
/** The challengers of AugmentedMCL::TOptions::challenger_frames: recovery poses that compete
 *  with the cloud as a hypothesis of their own instead of as members of it.
 *
 *  The filter holds the mixture "the vehicle is where the cloud M is" : "it is where the
 *  challengers C are", with prior odds w_0 (`injected_weight`) when C is drawn. Each weighted
 *  frame multiplies each part's probability by its own prior-weighted mean likelihood, the
 *  frame's evidence for it (log w_avg): L_M and L_C are their sums since C was drawn, and the
 *  posterior odds are w_0 e^(L_C - L_M). Injected particles that compete inside the cloud
 *  lose that sum at every resampling: a look-alike place explains one frame as well as the
 *  truth, so a particle injected at the truth gains a few nats per frame and falls to the
 *  next resampling with its weight w_0. Kept apart, C (resampled among themselves) gathers
 *  the evidence of many frames; it joins the cloud when the odds reach 1 (the union
 *  resampled with those part weights) and is dropped when they fall to w_0^2 or after
 *  `maxFrames` weighted frames.
 *
 *  The filter appends C to its store for the step's pass (the same motion model, particle
 *  indices after the cloud's, the same likelihood) and takes it back after. */
class ChallengerSet
{
public:
    /** What the evidence says after a frame. */
    enum class Verdict
    {
        Keep,   ///< undecided
        Merge,  ///< the odds reached 1: C joins the cloud
        Drop    ///< the odds fell to w_0^2, or C lived its frames
    };

    bool alive() const { return !m_set.particles.empty(); }
    size_t size() const { return m_set.particles.size(); }

    /** A new set: the store to fill (particles of log-weight 0 and their states), the sums
     *  at 0. */
    ParticleStore& start();
    /** Forgets the set. */
    void clear();

    /** Appends the set to `store` (the cloud) for the step's pass. */
    void attach(ParticleStore& store, ParallelExecutor& ex);
    /** Takes the set back from `store` after the pass. */
    void detach(ParticleStore& store);

    /** After a weighted frame (the set detached): adds the cloud's log w_avg and the set's to
     *  their sums, resamples the set when its effective sample size is below `beta` (one
     *  uniform draw of MRPT's generator) and judges the odds with prior odds `logPriorOdds`
     *  (log w_0 < 0) after at most `maxFrames` frames. */
    Verdict weigh(double cloudLogWAvg, double logPriorOdds, size_t maxFrames, double beta,
                  ParallelExecutor& ex);
    /** log of the posterior odds, log w_0 + L_C - L_M, of the last weigh(). */
    double logOdds() const { return m_logOdds; }
    /** The set (for a merge). */
    const ParticleStore& particles() const { return m_set; }

private:
    ParticleStore m_set;
    double m_logSumPrior = 0;  ///< the set's log-sum of weights before the pass
    double m_sumCloud = 0, m_sumSet = 0;
    double m_logOdds = 0;
    size_t m_frames = 0;
};
}  // namespace semloc::detail

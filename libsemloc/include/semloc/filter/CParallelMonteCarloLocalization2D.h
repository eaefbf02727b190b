/* semloc — MRPT's 2D Monte Carlo localization with the observation likelihood evaluated on
 * several threads (bit-identical for any thread count), and failure recovery. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>
#include <semloc/filter/AugmentedMCL.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/ParticleMotionModel.h>
#include <semloc/filter/SensoryFrameLikelihood.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

namespace semloc
{
class ParallelExecutor;
class OdometryMotionModel;
class ParticleMotionModel;
namespace detail
{
class ParticleStore;
class RecoveryPolicy;
class SystematicResampling;
struct WeightRange;
}  // namespace detail

/** mrpt::slam::CMonteCarloLocalization2D whose standard-proposal step (PF_algorithm = 0,
 *  pfStandardProposal) runs the per-particle work through a ParallelExecutor. Drive it with
 *  mrpt::bayes::CParticleFilter::executeOn like its base class.
 *
 *  ## The step (pfStandardProposal)
 *  The step takes the particles from MRPT's list (m_particles, where MRPT's methods and the
 *  filter's users read and write them between steps) into a contiguous store where each
 *  particle also carries its motion state, works there, and gives them back at its end.
 *  - Prediction, fixed sample size: the motion model (setMotionModel(); by default
 *    OdometryMotionModel) prepares the step on this thread, then moves the particles on the
 *    executor's threads. The odometry's: with Gaussian odometry (CPosePDFGaussian) one 64-bit
 *    key per step from MRPT's global generator (mrpt::random::getRandomGenerator(), so the
 *    seed decides it), then each particle's increment from its own counter-based stream
 *    (splitmix64 of key and particle index, ziggurat normals, MRPT's CPoseRandomSampler
 *    transform mean + Z sqrt(D) n), composed in 2D; other odometry (Thrun's particles, 3D
 *    actions): MRPT's sampler on this thread, composed on the executor's threads.
 *  - Prediction, adaptive sample size (KLD, `adaptiveSampleSize = 1`): MRPT's own sequential
 *    implementation, which draws a new set from the weights at every step; with
 *    setKldAtResampling() the Gaussian prediction above instead, the sample size changing
 *    only at the resampling steps (see "Resampling").
 *  - Update: every particle's log-likelihood on the executor's threads
 *    (SensoryFrameLikelihood: MRPT's value, its fast paths, and the sensor models' state
 *    from frame to frame: the detector's outages), added to the log-weight times
 *    `powFactor`, exactly as MRPT.
 *  The other algorithms (pfAuxiliaryPFStandard, pfAuxiliaryPFOptimal) run MRPT's code
 *  unchanged, sequential and without recovery.
 *
 *  The results never depend on the number of threads: each particle's values are written
 *  to its own slot, and the few sums (ESS, the likelihood average) are taken over blocks
 *  fixed by the particle count (ParallelExecutor::reduceBlocks).
 *
 *  ## Free-space prior (setFreeSpacePrior, off by default)
 *  A particle outside the free space (FreeSpaceSampler::contains) has zero prior probability:
 *  its weight is set to zero at the update. A wrong hypothesis that drives out of the map
 *  then dies instead of surviving where no map predicts anything.
 *
 *  ## Never NaN, never empty
 *  When every particle's weight is zero after an update (all log-likelihoods -inf or NaN),
 *  the particles are re-initialized uniformly over the free space (the FreeSpaceSampler) and
 *  the event is counted (TRecoveryStats::reinitializations). With recovery on, the
 *  re-initialized particles are drawn as injected ones (`from_detections` of them from the
 *  frame's detections).
 *
 *  ## Recovery (off by default)
 *  A policy of its own (detail::RecoveryPolicy) decides and draws; the step resamples.
 *  Augmented MCL (AugmentedMCL): when p_inject > 0 the particles are resampled at once
 *  (`resamplingMethod`) and each is replaced, with probability p_inject, by a random pose:
 *  with probability `from_detections` one consistent with a detection of the frame (the
 *  first proposal of the sensor models of options.metricMap, BatchLikelihood::proposal(): the
 *  semantic map's DetectionPoseSampler; up to kDetectionTries draws until one lies in the
 *  free space), else (or when no model places the frame, or no draw was free) one from the
 *  FreeSpaceSampler.
 *  Uniform injection over a 50 x 50 m map almost never lands within a metre and a few degrees
 *  of the truth; a detection of an object at range r leaves a circle of radius r per
 *  candidate object, so after a kidnapping some injected particles start near the truth.
 *  An injected particle's log-weight is log(`injected_weight`), a resampled one's 0. A
 *  re-initialized or injected particle keeps its motion state (e.g. its heading drift rate:
 *  the odometry's, not the lost pose's).
 *  With AugmentedMCL::TOptions::challenger_frames > 0 the injected poses do not replace
 *  particles of the cloud: they form a challenger set beside it (detail::ChallengerSet),
 *  moved and weighed in the same pass after the cloud's particles, which joins the cloud
 *  (the union resampled into the cloud's size) once the frames since it was drawn favour it
 *  by 1 / injected_weight, and is dropped when the cloud is favoured by as much or after
 *  challenger_frames weighted frames; the cloud, and the estimate, are untouched meanwhile
 *  (TRecoveryStats::challenger_merges).
 *  All draws come from MRPT's global generator on the calling thread: deterministic, the
 *  same for any thread count.
 *
 *  ## Resampling
 *  With a fixed sample size, or KLD at the resampling steps (setKldAtResampling), the step
 *  resamples at its own end when ESS() < BETA (the test
 *  of CParticleFilter::executeOn): `resamplingMethod` 3 (systematic) by its own
 *  implementation, from the weights of the ESS pass, with one uniform draw of MRPT's
 *  generator as MRPT's; the others by MRPT's computeResampling(). This avoids executeOn's
 *  per-particle virtual getW()/setW() calls and its extra weight passes (executeOn then
 *  finds equal weights and leaves them). Hence
 *  executeOn's TParticleFilterStats::ESS_beforeResample reads 1 after a resampling step:
 *  read essBeforeResampling() instead.
 *  With KLD at the resampling steps the new set is drawn by KLD-sampling instead
 *  (detail::kldResample: systematic candidates taken in a random order until Fox's bound
 *  for the bins they occupy is reached), so its size follows the spread of the cloud but
 *  only changes when the weights have degenerated: a step that measured nothing keeps every
 *  particle, and an injected particle keeps its small weight until it has earned more, as
 *  with a fixed size (MRPT's KLD resamples at every step, which drops it at once).
 *  performSubstitution() gives every resampled particle the log-weight 0: MRPT 2.5.8's
 *  CParticleFilterCapable::performResampling() keeps the old weights when called with the
 *  default particle count, as CParticleFilter::executeOn does (fixed upstream by MRPT commit
 *  8c341ad5b), which counts the last likelihood twice. */
class CParallelMonteCarloLocalization2D : public mrpt::slam::CMonteCarloLocalization2D
{
public:
    /** Counters of the failure handling. */
    struct TRecoveryStats
    {
        /** Updates after which every weight was zero: the particles were re-initialized. */
        size_t reinitializations = 0;
        /** Particles of re-initializations drawn from a detection (a model's proposal;
         *  recovery on). */
        size_t reinitialized_from_detections = 0;
        /** Particles replaced by random poses by the recovery (its trigger, or while lost). */
        size_t injected_particles = 0;
        /** Of injected_particles, those drawn from a detection (a model's proposal). */
        size_t injected_from_detections = 0;
        /** Updates in which the recovery injected particles. */
        size_t injection_steps = 0;
        /** Challenger sets that joined the cloud (AugmentedMCL::TOptions::challenger_frames;
         *  each set drawn counts once in injection_steps, its particles in
         *  injected_particles). */
        size_t challenger_merges = 0;
        /** Of injection_steps, those of the sensor resetting while lost
         *  (AugmentedMCL::TOptions::lost_var_xy_m2). */
        size_t lost_injection_steps = 0;
        /** Particle updates that found the particle outside the free space (prior on). */
        size_t outside_free_space = 0;
    };

    /** `M` particles; the executor runs on one thread until setExecutor(). */
    explicit CParallelMonteCarloLocalization2D(size_t M = 1);
    ~CParallelMonteCarloLocalization2D() override;

    /** @name Configuration
     *  @{ */
    /** The threads of the per-particle work (shared: several filters may use one pool,
     *  one at a time). */
    void setExecutor(std::shared_ptr<ParallelExecutor> executor);
    /** The threads of the per-particle work. */
    ParallelExecutor& executor() const { return *m_executor; }
    /** Where re-initialized and injected particles come from. Without one, a
     *  re-initialization keeps the poses and only resets the weights. */
    void setFreeSpaceSampler(std::shared_ptr<const FreeSpaceSampler> sampler);
    /** Augmented MCL parameters (off by default). */
    void setRecoveryOptions(const AugmentedMCL::TOptions& o);
    /** Free-space prior (off by default): a particle the FreeSpaceSampler does not contain
     *  (outside the world's bounds, inside an object) gets weight zero at each update. */
    void setFreeSpacePrior(bool on) { m_freeSpacePrior = on; }
    /** With `adaptiveSampleSize = 1`: KLD-sampling at the resampling steps (true) instead of
     *  MRPT's at every prediction (false, the default); see "Resampling". */
    void setKldAtResampling(bool on) { m_kldAtResampling = on; }
    /** The prediction's motion model (by default an OdometryMotionModel without heading
     *  drift); every particle's state is drawn again from its prior (resetMotionState()). */
    void setMotionModel(std::shared_ptr<ParticleMotionModel> model);
    /** The prediction's motion model. */
    const ParticleMotionModel& motionModel() const { return *m_motion; }
    /** The odometry's heading drift as a state of every particle (OdometryMotionModel's;
     *  [MotionModel] heading_drift_std_deg_per_min, heading_drift_walk_deg_per_min): each
     *  particle's rate starts from N(0, priorStd²) [rad/s] and walks by N(0, walkStd² dt)
     *  [rad/s per sqrt(s)]. Both 0: off. Sets a new OdometryMotionModel with that drift
     *  (setMotionModel()). */
    void setHeadingDrift(double priorStd, double walkStd);
    /** @} */

    /** Every particle's motion state from the model's prior again, and the model's memory
     *  forgotten (a new run; e.g. the heading drift's clock); a live challenger set is
     *  dropped. */
    void resetMotionState();
    /** The particles as m_particles holds them now keep their motion states: poses a program
     *  moved itself between steps that should not get new states from the prior (as a
     *  re-initialization keeps them). Without this, a particle whose pose changed outside
     *  the filter gets a new state at the next step. */
    void adoptParticles();
    /** Every particle's motion state after the last step (the motion model's stateSize()
     *  values per particle, particle after particle, in the particles' order). */
    std::vector<double> motionStates() const;
    /** The particles' weighted mean motion state after the last step (stateSize() values;
     *  empty when the model keeps no state). */
    std::vector<double> meanMotionState() const;
    /** The particles' weighted mean heading drift rate [rad/s] after the last step: what the
     *  odometry's heading gains per second beyond the truth (0 when the drift is off). */
    double headingDriftRate() const;
    /** Every particle's heading drift rate [rad/s] after the last step, in the particles'
     *  order (empty when the drift is off). */
    std::vector<double> headingDriftRates() const;

    /** @name Statistics
     *  @{ */
    /** What the observations contained (skipped observations, invalid detections...). */
    SensoryFrameLikelihood::TStats likelihoodStats() const;
    /** Re-initializations and injections so far. */
    const TRecoveryStats& recoveryStats() const;
    /** Augmented MCL's p_inject at the last update (0 when off). */
    double lastInjectionProbability() const;
    /** The evidence trigger's shortfall S [nats] after the last frame (AugmentedMCL; 0 with
     *  another trigger and after resetRecoveryTrigger()). */
    double recoveryShortfall() const;
    /** The probability that the detector is out after the last frame (the outage model of
     *  SensoryFrameLikelihood::outageTerms(): the semantic map's outage_every_s > 0; 0 while
     *  it has seen no frame). */
    double detectorOutageProbability() const;
    /** Forgets the sensor models' state from frame to frame (a new run): the detector's
     *  outage probability and the models' memories (BatchLikelihood::Memory: the semantic
     *  map's look-alikes). */
    void resetDetectorOutage();
    /** Forgets the recovery trigger's state (a new run): its averages or evidence shortfall,
     *  and a live challenger set; recoveryStats() keeps counting. */
    void resetRecoveryTrigger();
    /** ESS() at the end of the last step, before its resampling (see "Resampling"). */
    double essBeforeResampling() const { return m_essBeforeResampling; }
    /** @} */

    /** Sets up the sensor model for options.metricMap now (else at the first update): the
     *  one-off cache filling of SensoryFrameLikelihood::prepare() stays out of step timings. */
    void prepareLikelihood();

    /** Re-draws every particle from the FreeSpaceSampler with log-weight 0 (requires one). */
    void resetFromSampler(size_t particleCount);

    // CMonteCarloLocalization2D / CParticleFilterCapable
    /** One step: predicts from the odometry (in parallel; MRPT's own KLD sampling if
     *  PF_options.adaptiveSampleSize), weights by the frame with options.metricMap, then
     *  resamples when ESS < BETA (fixed sample size; see "Resampling"). */
    void prediction_and_update_pfStandardProposal(
        const mrpt::obs::CActionCollection* action, const mrpt::obs::CSensoryFrame* observation,
        const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options) override;
    /** Shifts the log-weights so the largest is 0; returns max/min weight ratio. */
    double normalizeWeights(double* out_max_log_w = nullptr) override;
    /** Effective sample size fraction (sum w)^2 / (M sum w^2), thread-count independent. */
    double ESS() const override;
    /** Replaces the particles by those at the (sorted) resampled indices, in parallel. */
    void performSubstitution(const std::vector<size_t>& indx) override;
    /** Log-weight of particle i. MRPT's base reaches the particles through a dynamic_cast
     *  per call, and its performResampling() calls this once per particle. */
    double getW(size_t i) const override { return m_particles.at(i).log_w; }
    /** Sets the log-weight of particle i (without the base's dynamic_cast per call). */
    void setW(size_t i, double w) override { m_particles.at(i).log_w = w; }
    /** Number of particles (without the base's dynamic_cast per call). */
    size_t particlesCount() const override { return m_particles.size(); }

    // CPosePDFParticles
    /** The weighted mean pose, MRPT's CPosePDFParticles::getMean bit for bit (the same
     *  libm calls, the sums in the same order), faster: the headings' cos and sin and the
     *  weights' exp on the executor's threads, no exp() for a log-weight of 0 (every weight
     *  after a resampling; exp(0) is 1 exactly), no deque indexing per particle. Throws as
     *  MRPT's when every weight is zero. Another thread may call it between steps (while
     *  the executor runs another call, it computes on its own thread); its buffers are kept
     *  per calling thread. */
    void getMean(mrpt::poses::CPose2D& mean) const override;
    /** Covariance and mean, MRPT's CPosePDFParticles::getCovarianceAndMean bit for bit
     *  (with getMean() above): one exp() per particle at most instead of three, no fmod()
     *  per particle. */
    std::tuple<cov_mat_t, type_value> getCovarianceAndMean() const override;
    /** getCovarianceAndMean() and, from the same pass over the particles, the covariance of
     *  (x, y, phi) with signed heading errors wrapToPi(phi - mean phi): the pose covariance
     *  (MRPT's x-phi and y-phi terms take the heading error's absolute value and lose its
     *  sign; the other entries are the same). The same values for any thread count. */
    std::tuple<cov_mat_t, cov_mat_t, type_value> covariancesAndMean() const;

private:
    /** The per-particle pass (prediction if `move`; with a frame likelihood, free-space prior
     *  and weight update; then the handling of vanished weights and the recovery) over the
     *  store: its first `cloud` particles, then the challengers if any (taken back after the
     *  pass). True, with the cloud's log-weights' extremes in `range`, when they are known at
     *  the end (a frame, no injection). */
    bool predictAndUpdate(bool move, const mrpt::obs::CSensoryFrame* sf,
                          const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options,
                          size_t cloud, detail::WeightRange& range);
    /** After a frame's update, the recovery: the challengers judged (`challenged`: they were
     *  weighed with the cloud) and merged or dropped; the trigger fed with the cloud's log
     *  w_avg when it `watched` the frame; particles injected into the cloud or a challenger
     *  set drawn. True when the log-weights' extremes of the update still hold. */
    bool recoverAfterUpdate(const mrpt::obs::CSensoryFrame& sf,
                            const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options,
                            bool watched, bool challenged, double logWAvg);
    /** The challengers join the cloud (their odds reached 1): the union resampled into the
     *  cloud's size with each part's posterior probability. */
    void mergeChallengers();
    /** Moves the particles (`move`) and, with `weigh`, weights them by the frame planned in
     *  m_likelihood (`chunkwise`: the likelihood per range of particles); the log-weights'
     *  extremes (with `weigh`). */
    detail::WeightRange updateParticles(bool move, bool weigh, bool chunkwise, double powFactor);
    /** Every weight vanished: the recovery policy re-draws the particles. */
    void reinitialize(const mrpt::obs::CSensoryFrame& sf);
    /** MRPT's KLD sampling (redraws every step), not KLD at the resampling steps. */
    bool mrptKld(const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o) const
    {
        return o.adaptiveSampleSize && !m_kldAtResampling;
    }
    /** CParticleFilter::executeOn's resampling test (ESS < BETA) and the resampling. */
    void resampleIfDegenerate(const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o);
    /** The store's weights normalized and resampled by `resamplingMethod` (MRPT's
     *  computeResampling), as MRPT's performResampling(). */
    void resampleStore(const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o);
    /** The store's particles replaced by those at indices `indx` (sorted here if needed). */
    void substituteStore(const std::vector<size_t>& indx);

    std::shared_ptr<ParallelExecutor> m_executor;
    std::unique_ptr<SensoryFrameLikelihood> m_likelihood;
    const mrpt::maps::CMetricMap* m_likelihoodMap = nullptr;
    std::unique_ptr<detail::RecoveryPolicy> m_recovery;
    bool m_freeSpacePrior = false;
    bool m_kldAtResampling = false;
    /** The motion model (by default an OdometryMotionModel). */
    std::shared_ptr<ParticleMotionModel> m_motion;
    /** The particles of a step, with their motion states. */
    std::unique_ptr<detail::ParticleStore> m_store;

    /** The vehicle's pose by its odometry (the actions' mean increments composed from the
     *  first step): the look-alike persistence's frame. */
    mrpt::math::TPose2D m_deadReckoning{0, 0, 0};

    /** Per-step buffers, reused (no allocation per step once sized). */
    std::vector<mrpt::math::TPose2D> m_poses;
    std::vector<double> m_logLik;
    std::vector<size_t> m_resampleIdx;
    /** Systematic resampling's buffers. */
    std::unique_ptr<detail::SystematicResampling> m_systematic;
    /** The weights relative to the largest, of the last ESS (the systematic resampling's). */
    std::vector<double> m_linW;
    double m_essBeforeResampling = 1;
};

}  // namespace semloc

/* semloc — CParallelMonteCarloLocalization2D: MRPT's MCL step with per-particle work on a
 * thread pool, a never-empty particle set and augmented-MCL recovery. The step's parts are
 * units of their own: MotionSampling, Weights, Resampling, KldResampling, Estimate, and the
 * re-initialization and injection in ParticleRecovery.cpp. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "filter/Estimate.h"
#include "filter/KldResampling.h"
#include "filter/ParticleStore.h"
#include "filter/RecoveryPolicy.h"
#include "filter/Resampling.h"
#include "filter/Weights.h"

namespace semloc
{
using detail::WeightRange;
using mrpt::math::TPose2D;

namespace
{
/** Smallest range of the prediction + likelihood pass a thread claims (~1 us per particle):
 *  small enough for the threads to finish within a few tens of microseconds of each other. */
constexpr size_t kParticleGrain = 128;
/** What one thread's ranges of the update pass found. */
struct alignas(64) PassPartial
{
    WeightRange range;
    size_t outside = 0, nonfinite = 0;
};

/** The per-particle pass over a range of particles: the prediction (or the poses' copy),
 *  the likelihood and the weight update with the free-space prior, reducing the weights'
 *  extremes and the counters per thread (exact whatever the ranges). */
struct UpdatePass
{
    detail::ParticleStore& store;
    TPose2D* poses;
    double* logLik;
    const ParticleMotionModel* motion;  ///< the prediction's, or nullptr
    const SensoryFrameLikelihood* likelihood;
    const FreeSpaceSampler* prior;  ///< the free-space prior's, or nullptr
    double pow;
    std::vector<PassPartial>& partial;

    /** Copies the poses of particles [b, e) to `poses` and moves them (with a motion
     *  model). */
    void movePoses(size_t b, size_t e) const
    {
        detail::Particle* p = store.particles.data();
        for (size_t i = b; i < e; i++)
        {
            poses[i] = p[i].d;
        }
        if (motion)
        {
            motion->move(b, e - b, poses + b, store.dim() ? store.state(b) : nullptr);
            for (size_t i = b; i < e; i++)
            {
                p[i].d = poses[i];
            }
        }
    }

    /** Weights the particles [b, e) by their likelihoods and the prior. */
    void weigh(size_t b, size_t e, size_t thread) const
    {
        PassPartial& acc = partial[thread];
        acc.nonfinite += likelihood->evaluateChunk(poses, b, e, logLik);
        if (prior)
        {
            acc.outside += prior->excludeOutside(poses + b, e - b, logLik + b);
        }
        // Even and odd particles' extremes apart: two dependency chains.
        WeightRange even = acc.range, odd;
        detail::Particle* p = store.particles.data() + b;
        const double* l = logLik + b;
        detail::addExtremes(e - b, even, odd, [&](size_t k) { return p[k].log_w += l[k] * pow; });
        even.add(odd);
        acc.range = even;
    }

    /** One pass over every particle on the executor's threads. */
    void run(ParallelExecutor& ex, bool move, bool weight) const
    {
        ex.forEachRange(
            store.particles.size(),
            [&](size_t b, size_t e, size_t thread)
            {
                if (move)
                {
                    movePoses(b, e);
                }
                if (weight)
                {
                    weigh(b, e, thread);
                }
            },
            kParticleGrain);
    }
};

/** `pose` moved by the actions' mean odometry increment (unchanged without one). */
TPose2D composeIncrement(const TPose2D& pose, const mrpt::obs::CActionCollection& actions)
{
    mrpt::poses::CPose2D increment;
    if (const auto m2 = actions.getBestMovementEstimation(); m2 && m2->poseChange)
    {
        increment = m2->poseChange->getMeanVal();
    }
    else if (const auto m3 = actions.getActionByClass<mrpt::obs::CActionRobotMovement3D>())
    {
        increment = mrpt::poses::CPose2D(m3->poseChange.getMeanVal());
    }
    return (mrpt::poses::CPose2D(pose) + increment).asTPose();
}
}  // namespace

CParallelMonteCarloLocalization2D::CParallelMonteCarloLocalization2D(size_t M)
    : CMonteCarloLocalization2D(M),
      m_executor(std::make_shared<ParallelExecutor>(1)),
      m_recovery(std::make_unique<detail::RecoveryPolicy>()),
      m_motion(std::make_shared<OdometryMotionModel>()),
      m_store(std::make_unique<detail::ParticleStore>()),
      m_systematic(std::make_unique<detail::SystematicResampling>())
{
    setLoggerName("CParallelMonteCarloLocalization2D");
}

CParallelMonteCarloLocalization2D::~CParallelMonteCarloLocalization2D() = default;

void CParallelMonteCarloLocalization2D::setExecutor(std::shared_ptr<ParallelExecutor> executor)
{
    ASSERT_(executor);
    m_executor = std::move(executor);
}

void CParallelMonteCarloLocalization2D::setFreeSpaceSampler(
    std::shared_ptr<const FreeSpaceSampler> sampler)
{
    m_recovery->setSampler(std::move(sampler));
}

void CParallelMonteCarloLocalization2D::setRecoveryOptions(const AugmentedMCL::TOptions& o)
{
    m_recovery->setOptions(o);
}

const CParallelMonteCarloLocalization2D::TRecoveryStats&
CParallelMonteCarloLocalization2D::recoveryStats() const
{
    return m_recovery->stats();
}

double CParallelMonteCarloLocalization2D::lastInjectionProbability() const
{
    return m_recovery->lastInjectionProbability();
}

double CParallelMonteCarloLocalization2D::recoveryShortfall() const
{
    return m_recovery->shortfall();
}

double CParallelMonteCarloLocalization2D::detectorOutageProbability() const
{
    return m_likelihood ? m_likelihood->detectorOutageProbability() : 0;
}

void CParallelMonteCarloLocalization2D::resetDetectorOutage()
{
    if (m_likelihood)
    {
        m_likelihood->resetState();
    }
    m_deadReckoning = TPose2D(0, 0, 0);
}

void CParallelMonteCarloLocalization2D::resetRecoveryTrigger()
{
    m_recovery->restart();
}

SensoryFrameLikelihood::TStats CParallelMonteCarloLocalization2D::likelihoodStats() const
{
    return m_likelihood ? m_likelihood->stats() : SensoryFrameLikelihood::TStats{};
}

void CParallelMonteCarloLocalization2D::prepareLikelihood()
{
    ASSERTMSG_(options.metricMap, "CParallelMonteCarloLocalization2D: no options.metricMap");
    if (!m_likelihood || m_likelihoodMap != options.metricMap.get())
    {
        m_likelihoodMap = options.metricMap.get();
        m_likelihood = std::make_unique<SensoryFrameLikelihood>(*m_likelihoodMap);
    }
    m_likelihood->prepare(*m_executor);
}

void CParallelMonteCarloLocalization2D::resetFromSampler(size_t particleCount)
{
    const auto& sampler = m_recovery->sampler();
    ASSERTMSG_(sampler, "resetFromSampler: no FreeSpaceSampler was set");
    ASSERT_(particleCount > 0);
    m_particles.resize(particleCount);
    auto& rng = mrpt::random::getRandomGenerator();
    for (auto& p : m_particles)
    {
        p.d = sampler->draw(rng);
        p.log_w = 0;
    }
    resetMotionState();
}

void CParallelMonteCarloLocalization2D::prediction_and_update_pfStandardProposal(
    const mrpt::obs::CActionCollection* actions, const mrpt::obs::CSensoryFrame* sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options)
{
    MRPT_START
    if (sf)
    {
        ASSERTMSG_(options.metricMap,
                   "CParallelMonteCarloLocalization2D needs options.metricMap (one map for "
                   "every particle)");
    }
    auto& rng = mrpt::random::getRandomGenerator();
    if (actions && mrptKld(PF_options))
    {
        // KLD sampling: MRPT's own implementation (prediction only, no frame).
        ASSERTMSG_(dynamic_cast<const OdometryMotionModel*>(m_motion.get()) && m_store->dim() == 0,
                   "a motion model with a state of its particles (heading drift, a model of "
                   "one's own) needs the filter's prediction: adaptiveSampleSize = 1 only with "
                   "KLD at the resampling steps (setKldAtResampling)");
        CMonteCarloLocalization2D::prediction_and_update_pfStandardProposal(actions, nullptr,
                                                                            PF_options);
    }
    m_store->syncFrom(m_particles, *m_motion, rng);
    if (actions)
    {
        m_deadReckoning = composeIncrement(m_deadReckoning, *actions);
    }
    const bool move = actions && !mrptKld(PF_options);
    const size_t cloud = m_store->particles.size();
    auto& challengers = m_recovery->challengers();
    if (challengers.alive() && (move || sf) && !mrptKld(PF_options))
    {
        // Moved and weighed with the cloud, after it: the challengers' particle indices.
        challengers.attach(*m_store, *m_executor);
    }
    if (move)
    {
        m_motion->prepare({*actions, sf, m_store->particles.size(), m_store->states()}, rng);
    }
    WeightRange range;
    const bool rangeKnown = (move || sf) && predictAndUpdate(move, sf, PF_options, cloud, range);
    // CParticleFilter::executeOn's resampling test, done here where the weights are at hand:
    // executeOn then finds equal weights (its normalizeWeights() and ESS() are a max/min
    // pass) and does not resample again.
    auto& particles = m_store->particles;
    m_essBeforeResampling = detail::weightsAndESS(
        particles, *m_executor,
        rangeKnown ? range : detail::minMaxLogWeights(particles, *m_executor), &m_linW);
    if (!mrptKld(PF_options) && m_essBeforeResampling < PF_options.BETA)
    {
        resampleIfDegenerate(PF_options);
    }
    m_store->syncTo(m_particles);
    MRPT_END
}

void CParallelMonteCarloLocalization2D::resampleIfDegenerate(
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o)
{
    auto& particles = m_store->particles;
    if (o.adaptiveSampleSize)  // KLD at the resampling steps (MRPT's KLD never gets here)
    {
        auto& rng = mrpt::random::getRandomGenerator();
        const double u = rng.drawUniform(0.0, 1.0);
        detail::kldResample(m_linW, particles, options.KLD_params, u, rng, m_resampleIdx);
        substituteStore(m_resampleIdx);
        return;
    }
    // Either branch takes the random numbers MRPT's performResampling() would, at the same
    // point of the sequence (the systematic one a single uniform draw, as MRPT's).
    if (o.resamplingMethod == mrpt::bayes::CParticleFilter::prSystematic)
    {
        m_systematic->setWeights(m_linW);
        const double u = mrpt::random::getRandomGenerator().drawUniform(0.0, 1.0);
        m_systematic->resample(u, particles, m_store->resampled, *m_executor,
                               m_store->carried(particles.size()));
        m_store->swapResampled();
        return;
    }
    resampleStore(o);
}

void CParallelMonteCarloLocalization2D::resampleStore(
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o)
{
    // MRPT's performResampling(): the log-weights, computeResampling(), the substitution.
    auto& particles = m_store->particles;
    std::vector<double> logW(particles.size());
    for (size_t i = 0; i < logW.size(); i++)
    {
        logW[i] = particles[i].log_w;
    }
    computeResampling(o.resamplingMethod, logW, m_resampleIdx);
    substituteStore(m_resampleIdx);
}

void CParallelMonteCarloLocalization2D::substituteStore(const std::vector<size_t>& indx)
{
    // MRPT sorts the indices first (the particle order after resampling); every resampling
    // method of computeResampling() already returns them sorted, so sort only if needed.
    std::vector<size_t> sorted;
    const std::vector<size_t>* idx = &indx;
    if (!std::is_sorted(indx.begin(), indx.end()))
    {
        sorted = indx;
        std::sort(sorted.begin(), sorted.end());
        idx = &sorted;
    }
    detail::substituteParticles(*idx, m_store->particles, m_store->resampled, *m_executor,
                                m_store->carried(idx->size()));
    m_store->swapResampled();
}

bool CParallelMonteCarloLocalization2D::predictAndUpdate(
    bool move, const mrpt::obs::CSensoryFrame* sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options, size_t cloud,
    WeightRange& range)
{
    auto& particles = m_store->particles;
    const size_t M = particles.size();  // the cloud, then the challengers if any
    auto& challengers = m_recovery->challengers();
    m_poses.resize(M);
    if (!sf)
    {
        updateParticles(move, false, false, PF_options.powFactor);  // prediction only
        if (M > cloud)
        {
            challengers.detach(*m_store);
        }
        return false;
    }
    ASSERTMSG_(M > 0, "the particle set is empty");
    prepareLikelihood();
    const bool chunkwise = m_likelihood->plan(*sf, *m_executor);
    const bool recovery = m_recovery->watches(*m_likelihood);
    const bool challenging = M > cloud;
    const double lsePrior =
        recovery || challenging ? detail::logSumExpWeights(particles, *m_executor, cloud) : 0;
    m_logLik.resize(M);
    m_likelihood->beginUpdate(M, &m_deadReckoning);
    range = updateParticles(move, true, chunkwise, PF_options.powFactor);
    if (m_likelihood->updatesState())
    {
        for (size_t i = 0; i < M; i++)
        {
            m_logLik[i] = particles[i].log_w;
        }
    }
    m_likelihood->endUpdate(m_logLik.data(), cloud);  // the cloud's: the filter's estimate
    if (challenging)
    {
        challengers.detach(*m_store);
        range = detail::minMaxLogWeights(particles, *m_executor);
    }
    if (!std::isfinite(range.max))
    {
        // Every weight vanished: nothing left to normalize. Start over from the free space.
        reinitialize(*sf);
        range = WeightRange{0, 0};
        return true;
    }
    // w_avg = sum_i w_prior_i p(z | x_i) / sum_i w_prior_i (§8.3.5, with weights).
    const double logWAvg =
        recovery || challenging ? detail::logSumExpWeights(particles, *m_executor) - lsePrior : 0;
    return recoverAfterUpdate(*sf, PF_options, recovery, challenging, logWAvg);
}

bool CParallelMonteCarloLocalization2D::recoverAfterUpdate(
    const mrpt::obs::CSensoryFrame& sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options, bool watched,
    bool challenged, double logWAvg)
{
    auto& particles = m_store->particles;
    auto& challengers = m_recovery->challengers();
    if (challenged && m_likelihood->measures() &&
        m_recovery->judgeChallengers(logWAvg, PF_options.BETA, *m_executor) ==
            detail::ChallengerSet::Verdict::Merge)
    {
        mergeChallengers();
        return false;
    }
    if (!watched)
    {
        m_recovery->noTrigger();
        return true;
    }
    const double pInject = m_recovery->trigger(logWAvg, *m_likelihood, PF_options.powFactor);
    // MRPT's own KLD moves the cloud itself, not the challengers: injection into the cloud.
    if (pInject > 0 && m_recovery->challenges() && !mrptKld(PF_options))
    {
        if (!challengers.alive())
        {
            m_recovery->startChallengers(*m_store, pInject, sf, options.metricMap.get());
        }
        return true;
    }
    const bool mayReseed = pInject == 0 && m_recovery->reseedable(sf, options.metricMap.get());
    if (pInject == 0 && !mayReseed)
    {
        return true;
    }
    // Table 8.3: the set resampled, then each particle replaced with probability p_inject.
    detail::shiftLogWeights(particles, *m_executor,
                            detail::minMaxLogWeights(particles, *m_executor).max);
    const bool lost = mayReseed && m_recovery->spread(particles, *m_executor);
    if (!lost && pInject == 0)
    {
        return true;
    }
    resampleStore(PF_options);
    m_recovery->inject(*m_store, lost ? m_recovery->options().inject_share : pInject, sf,
                       options.metricMap.get(), lost);
    return false;  // resampled and partly replaced: scan the weights again
}

void CParallelMonteCarloLocalization2D::mergeChallengers()
{
    // The union resampled into the cloud's size with the parts' posterior probabilities
    // (odds o: the cloud 1 / (1 + o), the challengers o / (1 + o)), each part's weights
    // normalized within it.
    auto& particles = m_store->particles;
    const size_t cloud = particles.size();
    const auto& set = m_recovery->challengers();
    const double logOdds = set.logOdds();
    const double log1pOdds =
        logOdds > 0 ? logOdds + std::log1p(std::exp(-logOdds)) : std::log1p(std::exp(logOdds));
    const double shiftCloud = -detail::logSumExpWeights(particles, *m_executor) - log1pOdds;
    const double shiftSet =
        -detail::logSumExpWeights(set.particles().particles, *m_executor) + logOdds - log1pOdds;
    m_store->append(set.particles());
    std::vector<double> w(particles.size());
    for (size_t i = 0; i < w.size(); i++)
    {
        w[i] = std::exp(particles[i].log_w + (i < cloud ? shiftCloud : shiftSet));
    }
    const double u = mrpt::random::getRandomGenerator().drawUniform(0.0, 1.0);
    substituteStore(detail::systematicResamplingIndices(w, u, cloud));
    m_recovery->merged();
}

void CParallelMonteCarloLocalization2D::reinitialize(const mrpt::obs::CSensoryFrame& sf)
{
    const auto& sampler = m_recovery->sampler();
    MRPT_LOG_WARN_STREAM("every particle weight is zero after the update: re-initializing "
                         << m_store->particles.size() << " particles over the "
                         << (sampler ? sampler->description() : "same poses"));
    m_recovery->reinitialize(*m_store, sf, options.metricMap.get());
}

WeightRange CParallelMonteCarloLocalization2D::updateParticles(bool move, bool weigh,
                                                               bool chunkwise, double powFactor)
{
    // One pass per particle range: the prediction (or the poses' copy), the likelihood and
    // the weight update. A likelihood that needs every pose first (generic MRPT maps) takes
    // a pass of its own after the prediction. Without `weigh` (no frame), the prediction
    // alone.
    ParallelExecutor& ex = *m_executor;
    std::vector<PassPartial> partial(ex.threads());
    const UpdatePass pass{
        *m_store,           m_poses.data(),
        m_logLik.data(),    move ? m_motion.get() : nullptr,
        m_likelihood.get(), m_freeSpacePrior ? m_recovery->sampler().get() : nullptr,
        powFactor,          partial};
    if (!weigh)
    {
        pass.run(ex, true, false);
        return {};
    }
    if (!chunkwise)
    {
        pass.run(ex, true, false);
        m_likelihood->preEvaluate(m_poses.data(), m_store->particles.size());
    }
    pass.run(ex, chunkwise, true);

    WeightRange range;
    size_t nonfinite = 0, outside = 0;
    for (const PassPartial& p : partial)
    {
        range.add(p.range);
        outside += p.outside;
        nonfinite += p.nonfinite;
    }
    m_recovery->countOutside(outside);
    m_likelihood->addNonfinite(nonfinite);
    return range;
}

double CParallelMonteCarloLocalization2D::normalizeWeights(double* out_max_log_w)
{
    if (m_particles.empty())
    {
        return 0;
    }
    // MRPT's loop starts from the first weight: a NaN there stays (std::max/min never pick
    // a NaN later on).
    WeightRange r;
    for (const auto& p : m_particles)
    {
        r.add(p.log_w);
    }
    const double first = m_particles[0].log_w;
    const double maxW = std::isnan(first) ? first : r.max;
    const double minW = std::isnan(first) ? first : r.min;
    if (out_max_log_w)
    {
        *out_max_log_w = maxW == 0 ? 0 : maxW;
    }
    if (maxW != 0)  // else already normalized (e.g. just resampled): nothing to subtract
    {
        for (auto& p : m_particles)
        {
            p.log_w -= maxW;
        }
    }
    return std::exp(maxW - minW);
}

double CParallelMonteCarloLocalization2D::ESS() const
{
    thread_local detail::ParticleList copy;  // this thread's calls' buffer
    copy.assign(m_particles.begin(), m_particles.end());
    return detail::weightsAndESS(copy, *m_executor, detail::minMaxLogWeights(copy, *m_executor),
                                 nullptr);
}

void CParallelMonteCarloLocalization2D::performSubstitution(const std::vector<size_t>& indx)
{
    m_store->syncFrom(m_particles, *m_motion, mrpt::random::getRandomGenerator());
    substituteStore(indx);
    m_store->syncTo(m_particles);
}

void CParallelMonteCarloLocalization2D::getMean(mrpt::poses::CPose2D& mean) const
{
    thread_local std::vector<double> w;  // this thread's calls' buffers
    thread_local detail::ParticleList copy;
    copy.assign(m_particles.begin(), m_particles.end());
    double weightSum = 0;
    mean = detail::meanAndWeights(copy, *m_executor, w, weightSum);
}

std::tuple<CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::type_value>
CParallelMonteCarloLocalization2D::getCovarianceAndMean() const
{
    thread_local std::vector<double> w;  // this thread's calls' buffers
    thread_local detail::ParticleList copy;
    copy.assign(m_particles.begin(), m_particles.end());
    return detail::covarianceAndMean(copy, *m_executor, w);
}

std::tuple<CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::type_value>
CParallelMonteCarloLocalization2D::covariancesAndMean() const
{
    thread_local std::vector<double> w;  // this thread's calls' buffers
    thread_local detail::ParticleList copy;
    copy.assign(m_particles.begin(), m_particles.end());
    cov_mat_t poseCov;
    auto [cov, mean] = detail::covarianceAndMean(copy, *m_executor, w, &poseCov);
    return {cov, poseCov, mean};
}

}  // namespace semloc

/* semloc — CParallelMonteCarloLocalization2D: MRPT's MCL step with per-particle work on a
 * thread pool, a never-empty particle set and augmented-MCL recovery. The step's parts are
 * units of their own: MotionSampling, Weights, Resampling, KldResampling, Estimate, and the
 * re-initialization and injection in ParticleRecovery.cpp. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "filter/DetectorOutage.h"
#include "filter/Estimate.h"
#include "filter/HeadingDrift.h"
#include "filter/KldResampling.h"
#include "filter/MotionSampling.h"
#include "filter/ParticleRuns.h"
#include "filter/Resampling.h"
#include "filter/Weights.h"

namespace semloc
{
using detail::forEachRun;
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
    detail::ParticleList& particles;
    TPose2D* poses;
    double* logLik;
    const detail::GaussianIncrementDrawer* drawer;
    uint64_t key;
    const detail::DriftStep* drift;  ///< the heading drift, or nullptr
    const SensoryFrameLikelihood* likelihood;
    const FreeSpaceSampler* prior;    ///< the free-space prior's, or nullptr
    const detail::OutageMix* outage;  ///< the outage mixture, or nullptr
    double* outageLik;                ///< its per-particle terms (with outage)
    double pow;
    std::vector<PassPartial>& partial;

    /** Moves the particles [b, e) (with a drawer) and copies their poses to `poses`. */
    void movePoses(size_t b, size_t e) const
    {
        forEachRun(particles, b, e,
                   [&](auto* p, size_t i0, size_t n)
                   {
                       TPose2D* out = poses + i0;
                       if (drawer)
                       {
                           detail::movePoses(*drawer, key, p, i0, n, out, drift);
                           return;
                       }
                       for (size_t k = 0; k < n; k++)
                       {
                           out[k] = p[k].d;
                       }
                   });
    }

    /** Weights the particles [b, e) by their likelihoods and the prior. */
    void weigh(size_t b, size_t e, size_t thread) const
    {
        PassPartial& acc = partial[thread];
        acc.nonfinite +=
            likelihood->evaluateChunk(poses, b, e, logLik, outage ? outageLik : nullptr);
        if (outage)
        {
            detail::DetectorOutage::apply(*outage, logLik + b, outageLik + b, e - b);
        }
        if (prior)
        {
            acc.outside += prior->excludeOutside(poses + b, e - b, logLik + b);
        }
        // Even and odd particles' extremes apart: two dependency chains.
        WeightRange even = acc.range, odd;
        forEachRun(particles, b, e,
                   [&](auto* p, size_t i0, size_t n)
                   {
                       const double* l = logLik + i0;
                       detail::addExtremes(n, even, odd,
                                           [&](size_t k) { return p[k].log_w += l[k] * pow; });
                   });
        even.add(odd);
        acc.range = even;
    }

    /** One pass over every particle on the executor's threads. */
    void run(ParallelExecutor& ex, bool move, bool weight) const
    {
        ex.forEachRange(
            particles.size(),
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
}  // namespace

CParallelMonteCarloLocalization2D::CParallelMonteCarloLocalization2D(size_t M)
    : CMonteCarloLocalization2D(M),
      m_executor(std::make_shared<ParallelExecutor>(1)),
      m_systematic(std::make_unique<detail::SystematicResampling>()),
      m_outage(std::make_unique<detail::DetectorOutage>()),
      m_drift(std::make_unique<detail::HeadingDrift>()),
      m_driftStep(std::make_unique<detail::DriftStep>())
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
    m_sampler = std::move(sampler);
}

void CParallelMonteCarloLocalization2D::setRecoveryOptions(const AugmentedMCL::TOptions& o)
{
    m_augmented = AugmentedMCL(o);
}

double CParallelMonteCarloLocalization2D::detectorOutageProbability() const
{
    return m_outage->probability();
}

void CParallelMonteCarloLocalization2D::resetDetectorOutage()
{
    m_outage->reset();
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
    ASSERTMSG_(m_sampler, "resetFromSampler: no FreeSpaceSampler was set");
    ASSERT_(particleCount > 0);
    m_particles.resize(particleCount);
    auto& rng = mrpt::random::getRandomGenerator();
    for (auto& p : m_particles)
    {
        p.d = m_sampler->draw(rng);
        p.log_w = 0;
    }
    resetHeadingDrift();
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
    std::optional<detail::GaussianIncrementDrawer> drawer;
    uint64_t key = 0;
    m_stepDrift = false;
    if (actions && !mrptKld(PF_options))
    {
        prepareDrift(*actions, sf);
    }
    if (actions)
    {
        if (mrptKld(PF_options))
        {
            // KLD sampling: MRPT's own implementation (prediction only, no frame).
            CMonteCarloLocalization2D::prediction_and_update_pfStandardProposal(actions, nullptr,
                                                                                PF_options);
        }
        else if (const auto gauss = detail::gaussianMotion(*actions))
        {
            // One key per step from MRPT's generator (the seed decides it); each particle's
            // numbers from (key, index), drawn and applied on every thread.
            auto& rng = mrpt::random::getRandomGenerator();
            key = (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
            drawer.emplace(*gauss);
        }
        else
        {
            predictOtherMotion(*actions);
        }
    }
    WeightRange range;
    const bool rangeKnown =
        (drawer || sf) && predictAndUpdate(drawer ? &*drawer : nullptr, key, sf, PF_options, range);
    // CParticleFilter::executeOn's resampling test, done here where the weights are at hand:
    // executeOn then finds equal weights (its normalizeWeights() and ESS() are a max/min
    // pass) and does not resample again.
    m_essBeforeResampling = detail::weightsAndESS(
        m_particles, *m_executor,
        rangeKnown ? range : detail::minMaxLogWeights(m_particles, *m_executor), &m_linW);
    if (!mrptKld(PF_options) && m_essBeforeResampling < PF_options.BETA)
    {
        resampleIfDegenerate(PF_options);
    }
    MRPT_END
}

void CParallelMonteCarloLocalization2D::resampleIfDegenerate(
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o)
{
    if (o.adaptiveSampleSize)  // KLD at the resampling steps (MRPT's KLD never gets here)
    {
        auto& rng = mrpt::random::getRandomGenerator();
        const double u = rng.drawUniform(0.0, 1.0);
        detail::kldResample(m_linW, m_particles, options.KLD_params, u, rng, m_resampleIdx);
        performSubstitution(m_resampleIdx);
        return;
    }
    // Either branch takes the random numbers MRPT's performResampling() would, at the same
    // point of the sequence (the systematic one a single uniform draw, as MRPT's).
    if (o.resamplingMethod == mrpt::bayes::CParticleFilter::prSystematic)
    {
        m_systematic->setWeights(m_linW);
        const double u = mrpt::random::getRandomGenerator().drawUniform(0.0, 1.0);
        const auto carried = carriedDrift(m_particles.size());
        m_systematic->resample(u, m_particles, m_resampled, *m_executor,
                               carried ? &*carried : nullptr);
        swapResampled(carried.has_value());
        return;
    }
    std::vector<double> logW(m_particles.size());
    for (size_t i = 0; i < logW.size(); i++)
    {
        logW[i] = m_particles[i].log_w;
    }
    computeResampling(o.resamplingMethod, logW, m_resampleIdx);
    performSubstitution(m_resampleIdx);
}

void CParallelMonteCarloLocalization2D::predictOtherMotion(
    const mrpt::obs::CActionCollection& actions)
{
    // Any other motion model (MRPT's Thrun particles, 3D actions): MRPT's sampler and its
    // 3D composition, as PF_SLAM_implementation_pfStandardProposal.
    const size_t M = m_particles.size();
    const auto mov2D = actions.getBestMovementEstimation();
    if (mov2D)
    {
        ASSERT_(mov2D->poseChange);
        m_movementDrawer.setPosePDF(*mov2D->poseChange);
    }
    else if (const auto mov3D = actions.getActionByClass<mrpt::obs::CActionRobotMovement3D>())
    {
        m_movementDrawer.setPosePDF(mov3D->poseChange);
    }
    else
    {
        THROW_EXCEPTION(
            "Action list does not contain any CActionRobotMovement2D or CActionRobotMovement3D "
            "object!");
    }
    std::vector<mrpt::poses::CPose3D> incr(M);
    auto& rng = mrpt::random::getRandomGenerator();
    for (size_t i = 0; i < M; i++)
    {
        m_movementDrawer.drawSample(incr[i]);
        if (m_stepDrift)
        {
            // The heading drift (prepareDrift): the rate off the increment's yaw, then its walk.
            double& rate = m_driftStep->rates[i];
            incr[i].setYawPitchRoll(incr[i].yaw() - rate * m_driftStep->dt, incr[i].pitch(),
                                    incr[i].roll());
            rate += m_driftStep->walk * rng.drawGaussian1D_normalized();
        }
    }
    m_executor->forEachChunk(
        M,
        [&](size_t b, size_t e)
        {
            for (size_t i = b; i < e; i++)
            {
                const mrpt::poses::CPose3D p(mrpt::math::TPose3D(m_particles[i].d));
                m_particles[i].d = TPose2D((p + incr[i]).asTPose());
            }
        });
}

bool CParallelMonteCarloLocalization2D::predictAndUpdate(
    const detail::GaussianIncrementDrawer* drawer, uint64_t key, const mrpt::obs::CSensoryFrame* sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options, WeightRange& range)
{
    const size_t M = m_particles.size();
    m_poses.resize(M);
    if (!sf)
    {
        updateParticles(drawer, key, false, false, PF_options.powFactor);  // prediction only
        return false;
    }
    ASSERTMSG_(M > 0, "the particle set is empty");
    prepareLikelihood();
    const bool chunkwise = m_likelihood->plan(*sf, *m_executor);
    // Augmented MCL averages the likelihood of measurements: a frame that measures nothing
    // (an odometry-only step of an imported log) would count as a perfect fit.
    const auto& ro = m_augmented.options();
    const bool recovery =
        ro.enabled() && m_likelihood->measures() &&
        (ro.trigger != RecoveryTrigger::Evidence || m_likelihood->withoutObjects().detections > 0);
    const double lsePrior = recovery ? detail::logSumExpWeights(m_particles, *m_executor) : 0;
    m_logLik.resize(M);
    std::optional<detail::OutageMix> mix;
    if (m_likelihood->outageTerms().present)
    {
        mix = m_outage->predict(m_likelihood->outageTerms());
        m_outageLik.resize(mix ? M : 0);
    }
    range =
        updateParticles(drawer, key, true, chunkwise, PF_options.powFactor, mix ? &*mix : nullptr);
    if (mix)
    {
        m_outage->update(m_particles, m_outageLik.data());
    }
    if (!std::isfinite(range.max))
    {
        // Every weight vanished: nothing left to normalize. Start over from the free space.
        reinitialize(*sf);
        range = WeightRange{0, 0};
        return true;
    }
    m_lastPInject = 0;
    if (recovery)
    {
        // w_avg = sum_i w_prior_i p(z | x_i) / sum_i w_prior_i (§8.3.5, with weights).
        const double logWAvg = detail::logSumExpWeights(m_particles, *m_executor) - lsePrior;
        const double pInject =
            ro.trigger == RecoveryTrigger::Evidence
                ? m_augmented.updateEvidence(logWAvg - PF_options.powFactor *
                                                           m_likelihood->withoutObjects().logLik)
                : m_augmented.update(logWAvg);
        m_lastPInject = pInject;
        if (pInject > 0 && m_sampler)
        {
            injectRandomParticles(pInject, *sf, PF_options);
            return false;  // resampled and partly replaced: scan the weights again
        }
    }
    return true;
}

WeightRange CParallelMonteCarloLocalization2D::updateParticles(
    const detail::GaussianIncrementDrawer* drawer, uint64_t key, bool weigh, bool chunkwise,
    double powFactor, const detail::OutageMix* outage)
{
    // One pass per particle range: the prediction (or the poses' copy), the likelihood and
    // the weight update. A likelihood that needs every pose first (generic MRPT maps) takes
    // a pass of its own after the prediction. Without `weigh` (no frame), the prediction
    // alone.
    ParallelExecutor& ex = *m_executor;
    std::vector<PassPartial> partial(ex.threads());
    const UpdatePass pass{m_particles,
                          m_poses.data(),
                          m_logLik.data(),
                          drawer,
                          key,
                          m_stepDrift ? m_driftStep.get() : nullptr,
                          m_likelihood.get(),
                          m_freeSpacePrior ? m_sampler.get() : nullptr,
                          outage,
                          m_outageLik.data(),
                          powFactor,
                          partial};
    if (!weigh)
    {
        pass.run(ex, true, false);
        return {};
    }
    if (!chunkwise)
    {
        pass.run(ex, true, false);
        m_likelihood->preEvaluate(m_poses.data(), m_particles.size());
    }
    pass.run(ex, chunkwise, true);

    WeightRange range;
    size_t nonfinite = 0;
    for (const PassPartial& p : partial)
    {
        range.add(p.range);
        m_recoveryStats.outside_free_space += p.outside;
        nonfinite += p.nonfinite;
    }
    m_likelihood->addNonfinite(nonfinite);
    return range;
}

double CParallelMonteCarloLocalization2D::normalizeWeights(double* out_max_log_w)
{
    if (m_particles.empty())
    {
        return 0;
    }
    const WeightRange r = detail::minMaxLogWeights(m_particles, *m_executor);
    // MRPT's loop starts from the first weight: a NaN there stays (std::max/min never pick
    // a NaN later on).
    const double first = m_particles[0].log_w;
    const double maxW = std::isnan(first) ? first : r.max;
    const double minW = std::isnan(first) ? first : r.min;
    if (maxW == 0)
    {
        // Already normalized (e.g. just resampled): subtracting 0 changes nothing.
        if (out_max_log_w)
        {
            *out_max_log_w = 0;
        }
        return std::exp(-minW);
    }
    detail::shiftLogWeights(m_particles, *m_executor, maxW);
    if (out_max_log_w)
    {
        *out_max_log_w = maxW;
    }
    return std::exp(maxW - minW);
}

double CParallelMonteCarloLocalization2D::ESS() const
{
    return detail::weightsAndESS(m_particles, *m_executor,
                                 detail::minMaxLogWeights(m_particles, *m_executor), nullptr);
}

void CParallelMonteCarloLocalization2D::performSubstitution(const std::vector<size_t>& indx)
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
    const auto carried = carriedDrift(idx->size());
    detail::substituteParticles(*idx, m_particles, m_resampled, *m_executor,
                                carried ? &*carried : nullptr);
    swapResampled(carried.has_value());
}

void CParallelMonteCarloLocalization2D::getMean(mrpt::poses::CPose2D& mean) const
{
    thread_local std::vector<double> w;  // this thread's calls' buffer
    double weightSum = 0;
    mean = detail::meanAndWeights(m_particles, *m_executor, w, weightSum);
}

std::tuple<CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::type_value>
CParallelMonteCarloLocalization2D::getCovarianceAndMean() const
{
    thread_local std::vector<double> w;  // this thread's calls' buffer
    return detail::covarianceAndMean(m_particles, *m_executor, w);
}

std::tuple<CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::type_value>
CParallelMonteCarloLocalization2D::covariancesAndMean() const
{
    thread_local std::vector<double> w;  // this thread's calls' buffer
    cov_mat_t poseCov;
    auto [cov, mean] = detail::covarianceAndMean(m_particles, *m_executor, w, &poseCov);
    return {cov, poseCov, mean};
}

}  // namespace semloc

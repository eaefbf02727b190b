/* semloc — CParallelMonteCarloLocalization2D's failure handling: re-initialization when every
 * weight vanished, and augmented MCL's injected particles, drawn from the detections or the
 * free space. */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/DetectionPoseSampler.h>
#include <semloc/maps/CSemanticMap.h>

#include <cmath>
#include <optional>

namespace semloc
{
using mrpt::math::TPose2D;

namespace
{
/** Draws from the detections before falling back to a uniform pose: a detection near the
 *  map's border or an object leaves most of its circle in the free space. */
constexpr int kDetectionTries = 10;

/** The first CSemanticMap of `map` (itself, or in a CMultiMetricMap), else nullptr. */
const CSemanticMap* semanticMapOf(const mrpt::maps::CMetricMap* map)
{
    if (const auto* sem = dynamic_cast<const CSemanticMap*>(map))
    {
        return sem;
    }
    if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(map))
    {
        return multi->mapByClass<CSemanticMap>().get();
    }
    return nullptr;
}
}  // namespace

void CParallelMonteCarloLocalization2D::reinitialize(const mrpt::obs::CSensoryFrame& sf)
{
    m_recoveryStats.reinitializations++;
    MRPT_LOG_WARN_STREAM("every particle weight is zero after the update: re-initializing "
                         << m_particles.size() << " particles over the "
                         << (m_sampler ? m_sampler->description() : "same poses"));
    if (m_sampler)
    {
        // With recovery on, from the frame's detections too (the frame that killed every
        // particle is the best evidence of where the vehicle is).
        const auto detections = detectionSampler(sf);
        for (auto& p : m_particles)
        {
            m_recoveryStats.reinitialized_from_detections +=
                drawRecoveryPose(detections, p.d) ? 1 : 0;
            p.log_w = 0;
        }
        // The heading drift rates stay: they are the odometry's, not the lost poses'.
    }
    else
    {
        for (auto& p : m_particles)
        {
            p.log_w = 0;
        }
    }
    m_augmented.reset();
    m_lastPInject = 0;
}

std::optional<DetectionPoseSampler> CParallelMonteCarloLocalization2D::detectionSampler(
    const mrpt::obs::CSensoryFrame& sf) const
{
    std::optional<DetectionPoseSampler> out;
    if (m_augmented.options().enabled() && m_augmented.options().from_detections > 0)
    {
        const auto* semMap = semanticMapOf(options.metricMap.get());
        const auto obs = sf.getObservationByClass<CObservationSemantic>();
        if (semMap && obs)
        {
            out.emplace(*semMap, *obs);
            if (out->empty())
            {
                out.reset();
            }
        }
    }
    return out;
}

bool CParallelMonteCarloLocalization2D::drawRecoveryPose(
    const std::optional<DetectionPoseSampler>& detections, TPose2D& out) const
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

void CParallelMonteCarloLocalization2D::injectRandomParticles(
    double pInject, const mrpt::obs::CSensoryFrame& sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o)
{
    // Table 8.3: each particle of the resampled set is, with probability p_inject, a
    // random pose instead.
    normalizeWeights();
    performResampling(o);
    auto& rng = mrpt::random::getRandomGenerator();
    const auto detections = detectionSampler(sf);
    size_t injected = 0, fromDet = 0;
    const double logW = std::log(m_augmented.options().injected_weight);
    // An injected particle keeps the heading drift rate of the resampled particle it replaces:
    // a draw of the rates' posterior (the drift is the odometry's, not the pose's).
    for (auto& p : m_particles)
    {
        if (rng.drawUniform(0.0, 1.0) < pInject)
        {
            injected++;
            fromDet += drawRecoveryPose(detections, p.d) ? 1 : 0;
            p.log_w = logW;  // the resampled ones have 0
        }
    }
    if (injected > 0)
    {
        m_recoveryStats.injection_steps++;
        m_recoveryStats.injected_particles += injected;
        m_recoveryStats.injected_from_detections += fromDet;
    }
}

}  // namespace semloc

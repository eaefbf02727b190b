/* semloc — CParallelMonteCarloLocalization2D's heading drift: every particle's drift rate
 * (HeadingDrift), set up, reset, averaged, and prepared for a step's prediction. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/system/datetime.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>

#include <algorithm>
#include <cmath>

#include "filter/HeadingDrift.h"
#include "filter/MotionSampling.h"
#include "filter/Resampling.h"
#include "filter/Weights.h"

namespace semloc
{
void CParallelMonteCarloLocalization2D::setHeadingDrift(double priorStd, double walkStd)
{
    ASSERT_(std::isfinite(priorStd) && priorStd >= 0 && std::isfinite(walkStd) && walkStd >= 0);
    m_drift->setOptions({priorStd, walkStd});
    resetHeadingDrift();
}

void CParallelMonteCarloLocalization2D::resetHeadingDrift()
{
    if (m_drift->enabled())
    {
        m_drift->reset(m_particles.size(), mrpt::random::getRandomGenerator());
    }
    m_drift->forgetClock();
}

std::optional<detail::CarriedValues> CParallelMonteCarloLocalization2D::carriedDrift(size_t count)
{
    if (!m_drift->enabled() || m_drift->rateVector().size() != m_particles.size())
    {
        return std::nullopt;
    }
    return detail::CarriedValues{m_drift->rates(), m_drift->resampledBuffer(count)};
}

void CParallelMonteCarloLocalization2D::swapResampled(bool drift)
{
    m_particles.swap(m_resampled);
    if (drift)
    {
        m_drift->swapResampled();
    }
}

double CParallelMonteCarloLocalization2D::headingDriftRate() const
{
    const auto& r = m_drift->rateVector();
    if (!m_drift->enabled() || r.size() != m_particles.size() || r.empty())
    {
        return 0;
    }
    const double maxW = detail::minMaxLogWeights(m_particles, *m_executor).max;
    double sum = 0, sumW = 0;
    for (size_t i = 0; i < r.size(); i++)
    {
        const double w = std::exp(m_particles[i].log_w - maxW);
        sum += w * r[i];
        sumW += w;
    }
    return sumW > 0 ? sum / sumW : 0;
}

const std::vector<double>& CParallelMonteCarloLocalization2D::headingDriftRates() const
{
    static const std::vector<double> kNone;
    return m_drift->enabled() ? m_drift->rateVector() : kNone;
}

void CParallelMonteCarloLocalization2D::prepareDrift(const mrpt::obs::CActionCollection& actions,
                                                     const mrpt::obs::CSensoryFrame* sf)
{
    m_stepDrift = false;
    if (!m_drift->enabled())
    {
        return;
    }
    mrpt::Clock::time_point t = INVALID_TIMESTAMP;
    if (sf && sf->size() > 0)
    {
        t = sf->getObservationByIndex(0)->timestamp;
    }
    if (t == INVALID_TIMESTAMP && actions.size() > 0)
    {
        t = actions.get(0).timestamp;
    }
    const double dt = m_drift->elapsed(t);
    m_drift->match(m_particles.size(), mrpt::random::getRandomGenerator());
    *m_driftStep = {m_drift->rates(), dt, m_drift->options().walk_std * std::sqrt(dt)};
    m_stepDrift = true;
}
}  // namespace semloc

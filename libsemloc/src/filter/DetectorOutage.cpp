/* semloc — DetectorOutage: the detector's outages marginalized by the filter. */
#include "filter/DetectorOutage.h"

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace semloc::detail
{
bool DetectorOutage::predict(const SensoryFrameLikelihood::TOutageTerms& terms)
{
    if (terms.t == INVALID_TIMESTAMP)
    {
        THROW_EXCEPTION(
            "a semantic observation without a timestamp: the detector outage model "
            "(outage_every_s > 0) needs the time between frames");
    }
    const double a = 1 / terms.every_s, b = 1 / terms.mean_s;
    const double stationary = a / (a + b);
    if (!m_known)
    {
        m_p = stationary;
        m_known = true;
    }
    else
    {
        // The two-state chain over dt: the probability relaxes to the stationary one.
        const double dt = std::max(0.0, mrpt::system::timeDifference(m_t, terms.t));
        m_p = stationary + (m_p - stationary) * std::exp(-(a + b) * dt);
    }
    m_t = terms.t;
    if (!terms.silent)
    {
        m_p = 0;  // a detection: the detector is on
        return false;
    }
    // Never exactly 0 or 1: both hypotheses stay open.
    const double p = std::clamp(m_p, 1e-12, 1 - 1e-12);
    m_mix = OutageMix{std::log(p), std::log1p(-p)};
    return true;
}

void DetectorOutage::apply(const OutageMix& mix, double* logLik, double* outage, size_t n)
{
    for (size_t i = 0; i < n; i++)
    {
        if (!std::isfinite(logLik[i]))
        {
            outage[i] = 0;  // no weight (a non-finite term is already -inf in logLik)
            continue;
        }
        const double on = mix.logOn + outage[i];
        const double hi = std::max(mix.logOut, on);
        const double mixed = hi + std::log(std::exp(mix.logOut - hi) + std::exp(on - hi));
        logLik[i] += mixed - outage[i];
        outage[i] = mix.logOut - mixed;
    }
}

void DetectorOutage::update(const double* logW, const double* outage, size_t n)
{
    double maxW = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; i++)
    {
        maxW = std::max(maxW, logW[i]);
    }
    if (!std::isfinite(maxW))
    {
        return;  // no weight left: the prediction stands
    }
    double sumW = 0, sumOut = 0;
    for (size_t i = 0; i < n; i++)
    {
        const double w = std::exp(logW[i] - maxW);
        sumW += w;
        sumOut += w * std::exp(outage[i]);
    }
    m_p = std::clamp(sumOut / sumW, 0.0, 1.0);
}
}  // namespace semloc::detail

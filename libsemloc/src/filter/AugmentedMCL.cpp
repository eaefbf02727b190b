/* semloc — AugmentedMCL: w_slow / w_fast in the log domain. */
#include <semloc/filter/AugmentedMCL.h>

#include <algorithm>
#include <cmath>

namespace semloc
{
namespace
{
/** log(e^a + e^b) without overflow; -inf stays -inf. */
double logAddExp(double a, double b)
{
    const double m = std::max(a, b);
    if (std::isinf(m) && m < 0)
    {
        return m;
    }
    return m + std::log(std::exp(a - m) + std::exp(b - m));
}

/** log(w + alpha (w_avg - w)) = log((1 - alpha) w + alpha w_avg). */
double blend(double logW, double alpha, double logWAvg)
{
    return logAddExp(std::log1p(-alpha) + logW, std::log(alpha) + logWAvg);
}
}  // namespace

double AugmentedMCL::update(double logWAvg)
{
    if (!m_options.enabled() || m_options.trigger != RecoveryTrigger::Amcl || std::isnan(logWAvg))
    {
        return 0;
    }
    m_logSlow = blend(m_logSlow, m_options.alpha_slow, logWAvg);
    m_logFast = blend(m_logFast, m_options.alpha_fast, logWAvg);
    if (std::isinf(m_logSlow) && m_logSlow < 0)
    {
        return 0;  // nothing observed yet: no evidence of a failure
    }
    // Table 8.3, line 16: max(0, 1 - w_fast / w_slow)
    return std::max(0.0, 1.0 - std::exp(m_logFast - m_logSlow));
}

double AugmentedMCL::updateEvidence(double logBayesFactor)
{
    if (m_options.trigger != RecoveryTrigger::Evidence || std::isnan(logBayesFactor))
    {
        return 0;
    }
    // One frame adds at most half the threshold: a single misread frame cannot trigger.
    const double h = m_options.evidence_threshold;
    const double add = std::min(m_options.evidence_margin - logBayesFactor, 0.5 * h);
    m_shortfall = std::max(0.0, m_shortfall + add);
    return m_shortfall >= h ? m_options.inject_share : 0.0;
}

void AugmentedMCL::reset()
{
    m_logSlow = m_logFast = -std::numeric_limits<double>::infinity();
    m_shortfall = 0;
}

}  // namespace semloc

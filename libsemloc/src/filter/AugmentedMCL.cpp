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
    if (!m_options.enabled() || std::isnan(logWAvg))
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

void AugmentedMCL::reset()
{
    m_logSlow = m_logFast = -std::numeric_limits<double>::infinity();
}

}  // namespace semloc

/* semloc — RunMetrics: docs/design.md's convergence and error figures. */
#include <mrpt/math/wrap2pi.h>
#include <semloc/experiment/RunMetrics.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace semloc
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double TStepRecord::errXY() const
{
    return gt ? std::hypot(est.x - gt->x, est.y - gt->y) : kNaN;
}

double TStepRecord::errPhi() const
{
    return gt ? mrpt::math::wrapToPi(est.phi - gt->phi) : kNaN;
}

RunMetrics RunMetrics::compute(const std::vector<TStepRecord>& r, const TConvergenceCriterion& c,
                               long kidnapStep)
{
    RunMetricsAccumulator acc(c, kidnapStep);
    for (const auto& s : r)
    {
        acc.add(s);
    }
    return acc.result();
}

void RunMetricsAccumulator::Settling::add(const TStepRecord& r, bool ok, size_t minSteps)
{
    if (!settled && !ok)
    {
        candidate.reset();  // the run of good steps is broken before it settled
        length = 0;
        errSum = 0;
        errCount = 0;
        return;
    }
    if (!candidate)
    {
        candidate = r.step;
        candidateT = r.t;
    }
    length++;
    settled = settled || length >= minSteps;
    if (r.gt)
    {
        errSum += r.errXY();
        errCount++;
    }
}

RunMetricsAccumulator::RunMetricsAccumulator(const RunMetrics::TConvergenceCriterion& criterion,
                                             long kidnapStep)
    : m_criterion(criterion), m_kidnapStep(kidnapStep)
{
    m_m.convergence_time_s = m_m.mean_err_after_conv_m = m_m.rmse_m = m_m.final_err_m = kNaN;
}

void RunMetricsAccumulator::add(const TStepRecord& r)
{
    const auto& c = m_criterion;
    const bool ok = r.gt && r.errXY() < c.max_err_xy_m && r.var_xy < c.max_var_xy_m2;
    const auto minSteps = static_cast<size_t>(std::max(1, c.min_steps));
    if (!m_any)
    {
        m_any = true;
        m_firstT = r.t;
    }
    m_m.steps++;
    m_convergence.add(r, ok, minSteps);
    if (m_kidnapStep >= 0 && static_cast<long>(r.step) >= m_kidnapStep)
    {
        m_recovery.add(r, ok, minSteps);
    }
    m_updates += r.update_us;
    m_particleUpdates += static_cast<double>(r.n_particles);
    if (r.gt)
    {
        const double e = r.errXY();
        m_m.steps_with_ground_truth++;
        m_sum2 += e * e;
        m_m.final_err_m = e;
    }
}

RunMetrics RunMetricsAccumulator::result() const
{
    RunMetrics m = m_m;
    if (const auto conv = m_convergence.step())
    {
        m.converged = true;
        m.convergence_step = static_cast<long>(*conv);
        m.convergence_time_s = m_convergence.candidateT - m_firstT;
        m.mean_err_after_conv_m =
            m_convergence.errSum / static_cast<double>(m_convergence.errCount);
    }
    if (m_kidnapStep >= 0)
    {
        m.kidnap_step = m_kidnapStep;
        m.recovery_steps =
            m_recovery.step() ? static_cast<long>(*m_recovery.step()) - m_kidnapStep : -1L;
    }
    if (m.steps_with_ground_truth > 0)
    {
        m.rmse_m = std::sqrt(m_sum2 / static_cast<double>(m.steps_with_ground_truth));
    }
    m.total_update_s = m_updates * 1e-6;
    m.mean_update_us_per_particle = m_particleUpdates > 0 ? m_updates / m_particleUpdates : kNaN;
    return m;
}

}  // namespace semloc

/* semloc — RunMetrics: docs/design.md's convergence and error figures. */
#include <semloc/experiment/RunMetrics.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace semloc
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/** The median of `v` (not empty): of an even count, the mean of the middle two. */
double median(std::vector<double> v)
{
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    if (v.size() % 2 == 1)
    {
        return *mid;
    }
    return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

/** The larger of a and b, NaN if either is. */
double maxOrNaN(double a, double b)
{
    return std::isnan(a) || std::isnan(b) ? kNaN : std::max(a, b);
}
}  // namespace

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

RunMetricsAccumulator::Lost::Lost() : firstT(kNaN) {}

void RunMetricsAccumulator::Lost::add(const TStepRecord& r, bool lost)
{
    if (lost)
    {
        if (steps++ == 0)
        {
            firstT = r.t;
        }
        if (!open)
        {
            open = true;
            openT = r.t;
            episodes++;
        }
    }
    else if (open)
    {
        open = false;
        endedS += r.t - openT;
        longestS = maxOrNaN(longestS, r.t - openT);
    }
}

double RunMetricsAccumulator::Lost::totalS(double lastT) const
{
    return open ? endedS + (lastT - openT) : endedS;
}

double RunMetricsAccumulator::Lost::longest(double lastT) const
{
    return open ? maxOrNaN(longestS, lastT - openT) : longestS;
}

void RunMetricsAccumulator::Settling::add(const TStepRecord& r, bool ok, bool isLost,
                                          size_t minSteps)
{
    if (!settled && !ok)
    {
        *this = Settling();  // the run of good steps is broken before it settled
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
    lost.add(r, isLost);
}

RunMetricsAccumulator::RunMetricsAccumulator(const RunMetrics::TConvergenceCriterion& criterion,
                                             long kidnapStep)
    : m_criterion(criterion), m_kidnapStep(kidnapStep)
{
    m_m.convergence_time_s = m_m.mean_err_after_conv_m = m_m.rmse_m = m_m.final_err_m = kNaN;
    m_m.nees_mean = m_m.nees_inside_share = m_m.nees_median = kNaN;
    m_m.nees_well_conditioned_share = m_m.nees_mean_well_conditioned = kNaN;
    m_m.lost_after_convergence_s = m_m.first_lost_after_convergence_s = m_m.longest_lost_s = kNaN;
}

void RunMetricsAccumulator::add(const TStepRecord& r)
{
    const auto& c = m_criterion;
    const double err = r.errXY();  // NaN without ground truth: neither good nor lost
    const bool ok = err < c.max_err_xy_m && r.var_xy < c.max_var_xy_m2;
    const bool lost = err > c.max_err_xy_m;
    const auto minSteps = static_cast<size_t>(std::max(1, c.min_steps));
    if (!m_any)
    {
        m_any = true;
        m_firstT = r.t;
    }
    m_lastT = r.t;
    m_m.steps++;
    m_convergence.add(r, ok, lost, minSteps);
    if (m_kidnapStep >= 0 && static_cast<long>(r.step) >= m_kidnapStep)
    {
        m_recovery.add(r, ok, lost, minSteps);
    }
    m_updates += r.update_us;
    m_particleUpdates += static_cast<double>(r.n_particles);
    if (r.gt)
    {
        m_m.steps_with_ground_truth++;
        m_sum2 += err * err;
        m_m.final_err_m = err;
        if (const double n = r.nees(); !std::isnan(n))
        {
            m_neesSum += n;
            m_neesCount++;
            m_neesInside += n <= RunMetrics::kNeesChi2_95 ? 1 : 0;
            m_nees.push_back(n);
            if (r.neesWellConditioned())
            {
                m_neesWellConditionedSum += n;
                m_neesWellConditioned++;
            }
        }
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
        const Lost& lost = m_convergence.lost;
        m.lost_after_convergence_steps = lost.steps;
        m.lost_episodes = lost.episodes;
        m.lost_after_convergence_s = lost.totalS(m_lastT);
        m.longest_lost_s = lost.longest(m_lastT);
        m.first_lost_after_convergence_s = lost.firstT - m_firstT;
    }
    if (m_neesCount > 0)
    {
        const auto n = static_cast<double>(m_neesCount);
        m.nees_mean = m_neesSum / n;
        m.nees_inside_share = static_cast<double>(m_neesInside) / n;
        m.nees_median = median(m_nees);
        m.nees_well_conditioned_share = static_cast<double>(m_neesWellConditioned) / n;
        m.nees_mean_well_conditioned =
            m_neesWellConditioned > 0
                ? m_neesWellConditionedSum / static_cast<double>(m_neesWellConditioned)
                : kNaN;
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

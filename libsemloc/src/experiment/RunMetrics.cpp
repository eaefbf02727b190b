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

/** The convergence criterion over the records of a run. */
class Criterion
{
public:
    Criterion(const std::vector<TStepRecord>& r, const RunMetrics::TConvergenceCriterion& c)
        : m_r(r), m_c(c)
    {
    }

    /** Index in the records of the first step at or after index `from` from which the
     *  criterion holds for the rest of the run or for min_steps steps; the records' size if
     *  none. */
    size_t settled(size_t from) const
    {
        for (size_t k = from; k < m_r.size();)
        {
            if (!ok(m_r[k]))
            {
                k++;
                continue;
            }
            size_t e = k;
            while (e < m_r.size() && ok(m_r[e]))
            {
                e++;
            }
            if (e == m_r.size() || e - k >= static_cast<size_t>(std::max(1, m_c.min_steps)))
            {
                return k;
            }
            k = e;
        }
        return m_r.size();
    }

private:
    bool ok(const TStepRecord& s) const
    {
        return s.gt && s.errXY() < m_c.max_err_xy_m && s.var_xy < m_c.max_var_xy_m2;
    }

    const std::vector<TStepRecord>& m_r;
    const RunMetrics::TConvergenceCriterion& m_c;
};

/** Steps from `kidnapStep` to the first step at or after it from which the criterion holds
 *  again; -1 if never. */
long recoverySteps(const std::vector<TStepRecord>& r, const Criterion& criterion, long kidnapStep)
{
    size_t from = 0;
    while (from < r.size() && static_cast<long>(r[from].step) < kidnapStep)
    {
        from++;
    }
    const size_t back = criterion.settled(from);
    return back < r.size() ? static_cast<long>(r[back].step) - kidnapStep : -1L;
}

/** The errors (RMSE, final, mean after the convergence step of index `conv`) and the
 *  update times of `m`. */
void errorsAndTimes(const std::vector<TStepRecord>& r, size_t conv, RunMetrics& m)
{
    double sum2 = 0, after = 0, updates = 0, particleUpdates = 0;
    size_t nAfter = 0;
    for (size_t k = 0; k < r.size(); k++)
    {
        const TStepRecord& s = r[k];
        updates += s.update_us;
        particleUpdates += static_cast<double>(s.n_particles);
        if (!s.gt)
        {
            continue;
        }
        const double e = s.errXY();
        m.steps_with_ground_truth++;
        sum2 += e * e;
        m.final_err_m = e;
        if (m.converged && k >= conv)
        {
            after += e;
            nAfter++;
        }
    }
    if (m.steps_with_ground_truth > 0)
    {
        m.rmse_m = std::sqrt(sum2 / static_cast<double>(m.steps_with_ground_truth));
    }
    if (m.converged)
    {
        m.mean_err_after_conv_m = after / static_cast<double>(nAfter);
        m.convergence_time_s = r[conv].t - r.front().t;
    }
    m.total_update_s = updates * 1e-6;
    m.mean_update_us_per_particle = particleUpdates > 0 ? updates / particleUpdates : kNaN;
}
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
    RunMetrics m;
    m.steps = r.size();
    m.convergence_time_s = m.mean_err_after_conv_m = m.rmse_m = m.final_err_m = kNaN;

    const Criterion criterion(r, c);
    const size_t conv = criterion.settled(0);  // index in `r` of the convergence step
    if (conv < r.size())
    {
        m.converged = true;
        m.convergence_step = static_cast<long>(r[conv].step);
    }
    if (kidnapStep >= 0)
    {
        m.kidnap_step = kidnapStep;
        m.recovery_steps = recoverySteps(r, criterion, kidnapStep);
    }
    errorsAndTimes(r, conv, m);
    return m;
}

}  // namespace semloc

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
    RunMetrics m;
    m.steps = r.size();
    m.convergence_time_s = m.mean_err_after_conv_m = m.rmse_m = m.final_err_m = kNaN;

    auto ok = [&](const TStepRecord& s)
    { return s.gt && s.errXY() < c.max_err_xy_m && s.var_xy < c.max_var_xy_m2; };
    // Index in `r` of the first step at or after index `from` from which `ok` holds for the
    // rest of the run or for min_steps steps; r.size() if none.
    auto settled = [&](size_t from)
    {
        for (size_t k = from; k < r.size();)
        {
            if (!ok(r[k]))
            {
                k++;
                continue;
            }
            size_t e = k;
            while (e < r.size() && ok(r[e]))
            {
                e++;
            }
            if (e == r.size() || e - k >= static_cast<size_t>(std::max(1, c.min_steps)))
            {
                return k;
            }
            k = e;
        }
        return r.size();
    };
    const size_t conv = settled(0);  // index in `r` of the convergence step
    if (conv < r.size())
    {
        m.converged = true;
        m.convergence_step = static_cast<long>(r[conv].step);
    }
    if (kidnapStep >= 0)
    {
        m.kidnap_step = kidnapStep;
        size_t from = 0;
        while (from < r.size() && static_cast<long>(r[from].step) < kidnapStep)
        {
            from++;
        }
        const size_t back = settled(from);
        if (back < r.size())
        {
            m.recovery_steps = static_cast<long>(r[back].step) - kidnapStep;
        }
    }

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
    return m;
}

}  // namespace semloc

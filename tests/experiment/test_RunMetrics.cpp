/* semloc tests — RunMetrics: docs/design.md's convergence definition and the run's figures. */
#include <gtest/gtest.h>
#include <semloc/experiment/RunMetrics.h>

#include <cmath>
#include <vector>

using mrpt::math::TPose2D;

namespace
{
semloc::TStepRecord rec(size_t step, double err, double var)
{
    semloc::TStepRecord r;
    r.step = step;
    r.t = 100.0 + static_cast<double>(step);
    r.gt = TPose2D(0, 0, 0);
    r.est = TPose2D(err, 0, 0);
    r.var_xy = var;
    r.n_particles = 100;
    r.update_us = 50;
    return r;
}
}  // namespace

TEST(RunMetrics, ConvergenceAsDesignDefinesIt)
{
    semloc::RunMetrics::TConvergenceCriterion c;
    std::vector<semloc::TStepRecord> r;
    for (size_t k = 0; k < 40; k++)
    {
        // Lost, then 5 good steps, a relapse, then good for 12 steps, lost again.
        const bool good = (k >= 5 && k < 10) || (k >= 12 && k < 24);
        r.push_back(rec(k, good ? 0.5 : 3.0, good ? 0.2 : 5.0));
    }
    auto m = semloc::RunMetrics::compute(r, c);
    EXPECT_TRUE(m.converged);
    EXPECT_EQ(m.convergence_step, 12) << "5 good steps do not count; 12 consecutive do";
    EXPECT_DOUBLE_EQ(m.convergence_time_s, 12.0);
    EXPECT_EQ(m.steps_with_ground_truth, 40u);
    EXPECT_DOUBLE_EQ(m.final_err_m, 3.0);
    EXPECT_DOUBLE_EQ(m.mean_err_after_conv_m, (12 * 0.5 + 16 * 3.0) / 28);
    EXPECT_DOUBLE_EQ(m.total_update_s, 40 * 50e-6);
    EXPECT_DOUBLE_EQ(m.mean_update_us_per_particle, 0.5);

    // Good to the end, even if shorter than min_steps, converges.
    for (size_t k = 35; k < 40; k++)
    {
        r[k] = rec(k, 0.1, 0.1);
    }
    for (size_t k = 12; k < 24; k++)
    {
        r[k] = rec(k, 3.0, 0.1);
    }
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_EQ(m.convergence_step, 35);
    c.max_err_xy_m = 0.05;
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_FALSE(m.converged);
    EXPECT_EQ(m.convergence_step, -1);
    EXPECT_TRUE(std::isnan(m.convergence_time_s));

    // A step without ground truth breaks a run of good steps.
    r.assign(20, rec(0, 0.1, 0.1));
    for (size_t k = 0; k < 20; k++)
    {
        r[k].step = k;
    }
    r[8].gt.reset();
    c = {};
    EXPECT_EQ(semloc::RunMetrics::compute(r, c).convergence_step, 9);
    EXPECT_EQ(semloc::RunMetrics::compute(r, c).steps_with_ground_truth, 19u);
}

TEST(RunMetrics, RecoveryStepsCountFromTheKidnapping)
{
    semloc::RunMetrics::TConvergenceCriterion c;
    std::vector<semloc::TStepRecord> r;
    for (size_t k = 0; k < 100; k++)
    {
        // Localized from step 5, kidnapped at 40, back from 63 on (a 4-step blip at 55).
        const bool good = (k >= 5 && k < 40) || (k >= 55 && k < 59) || k >= 63;
        r.push_back(rec(k, good ? 0.2 : 8.0, good ? 0.1 : 30.0));
    }
    auto m = semloc::RunMetrics::compute(r, c);
    EXPECT_EQ(m.kidnap_step, -1);
    EXPECT_EQ(m.recovery_steps, -1) << "no kidnapping given";
    m = semloc::RunMetrics::compute(r, c, 40);
    EXPECT_EQ(m.convergence_step, 5);
    EXPECT_EQ(m.kidnap_step, 40);
    EXPECT_EQ(m.recovery_steps, 23);
    for (size_t k = 63; k < 100; k++)
    {
        r[k] = rec(k, 8.0, 30.0);
    }
    EXPECT_EQ(semloc::RunMetrics::compute(r, c, 40).recovery_steps, -1) << "never recovered";
}

/* semloc — what a localization run achieved: convergence, errors, timing (docs/design.md). */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace semloc
{
/** One filter step, a row of steps.csv. */
struct TStepRecord
{
    /** Step index, from 0. */
    size_t step = 0;
    /** Time of the step's observations [s] (mrpt::Clock::toDouble); NaN if unknown. */
    double t = 0;
    /** Ground-truth pose at t, if any. */
    std::optional<mrpt::math::TPose2D> gt;
    /** Weighted mean of the particles. */
    mrpt::math::TPose2D est;
    /** Trace of the particles' x-y covariance [m^2]. */
    double var_xy = 0;
    /** Effective sample size before resampling, in [0, 1]. */
    double ess = 1;
    /** Particles after the step. */
    size_t n_particles = 0;
    /** Filter update time [us]. */
    double update_us = 0;

    /** Position error to the ground truth [m]; NaN without one. */
    double errXY() const;
    /** Heading error to the ground truth, wrapped to [-pi, pi] [rad]; NaN without one. */
    double errPhi() const;
};

/** Summary of a run. Values that cannot be computed (no ground truth, no convergence) are NaN
 *  (`convergence_step` -1). */
struct RunMetrics
{
    /** docs/design.md: the run has converged at the first step from which err_xy < max_err_xy_m and
     *  var_xy < max_var_xy_m2 hold for the rest of the run or for at least `min_steps`
     *  consecutive steps. A step without ground truth does not satisfy it. */
    struct TConvergenceCriterion
    {
        /** Position error bound [m]. */
        double max_err_xy_m = 1.0;
        /** Bound of the trace of the x-y covariance [m^2]. */
        double max_var_xy_m2 = 1.0;
        /** Consecutive steps that suffice when the run goes on afterwards. */
        int min_steps = 10;
    };

    /** Filter steps run. */
    size_t steps = 0;
    /** Steps that have a ground-truth pose. */
    size_t steps_with_ground_truth = 0;
    /** Whether the run converged (TConvergenceCriterion). */
    bool converged = false;
    /** Index of the convergence step, -1 if none. */
    long convergence_step = -1;
    /** Time from the first step to the convergence step [s]. */
    double convergence_time_s = 0;
    /** Mean err_xy from the convergence step to the end [m]. */
    double mean_err_after_conv_m = 0;
    /** Root mean square err_xy over every step with ground truth [m]. */
    double rmse_m = 0;
    /** err_xy of the last step that has ground truth [m]. */
    double final_err_m = 0;
    /** Sum of the update times [s]. */
    double total_update_s = 0;
    /** Total update time / total particle updates [us]. */
    double mean_update_us_per_particle = 0;
    /** @name Recovery from a kidnapping (only when compute() is given the kidnap step)
     *  @{ */
    /** Step at which the vehicle was kidnapped, -1 if none. */
    long kidnap_step = -1;
    /** Steps from the kidnapping to the first step at or after it from which the convergence
     *  criterion holds again (for the rest of the run or `min_steps` steps); -1 if never. */
    long recovery_steps = -1;
    /** @} */

    /** The metrics of `records` (in step order); `kidnapStep` >= 0: also the recovery from
     *  a kidnapping at that step. */
    static RunMetrics compute(const std::vector<TStepRecord>& records,
                              const TConvergenceCriterion& criterion, long kidnapStep = -1);
};

/** RunMetrics::compute() one record at a time, in step order, in constant memory: what a run of any
 *  length keeps of its steps. */
class RunMetricsAccumulator
{
public:
    explicit RunMetricsAccumulator(const RunMetrics::TConvergenceCriterion& criterion,
                                   long kidnapStep = -1);
    /** The next record. */
    void add(const TStepRecord& r);
    /** The metrics of the records added so far (as compute() gives them). */
    RunMetrics result() const;

private:
    /** Where the criterion settles from a start step on: the first step of a run of
     *  steps that satisfy it for `min_steps` steps or to the end. */
    struct Settling
    {
        std::optional<size_t> candidate;  // first step of the current run of good steps
        double candidateT = 0;
        size_t length = 0;
        bool settled = false;
        /** Errors (steps with ground truth) from the candidate on. */
        double errSum = 0;
        size_t errCount = 0;
        void add(const TStepRecord& r, bool ok, size_t minSteps);
        /** The settling step, if any (a run of good steps to the end counts). */
        std::optional<size_t> step() const { return candidate; }
    };

    RunMetrics::TConvergenceCriterion m_criterion;
    long m_kidnapStep;
    Settling m_convergence, m_recovery;
    RunMetrics m_m;
    double m_firstT = 0, m_sum2 = 0, m_updates = 0, m_particleUpdates = 0;
    bool m_any = false;
};

}  // namespace semloc

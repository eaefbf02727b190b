/* semloc — what a localization run achieved: convergence, errors, timing (docs/design.md). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/filter/StepRecord.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace semloc
{
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
    /** @name Consistency (docs/design.md, "Consistency"): TStepRecord::nees() over the steps
     *  with ground truth
     *  @{ */
    /** The chi-square distribution's 95 % quantile with 3 degrees of freedom. */
    static constexpr double kNeesChi2_95 = 7.814727903251178;
    /** Mean NEES; NaN if no step has ground truth. One step of a degenerate covariance (a
     *  cloud collapsed on one particle: NEES up to |e|^2 / 1e-12) sets it, so the outputs give
     *  the median and the mean over the well-conditioned steps instead (the calibration's
     *  consistency stage still shows it). */
    double nees_mean = 0;
    /** The chi-square distribution's median with 3 degrees of freedom. */
    static constexpr double kNeesChi2Median = 2.365973884375338;
    /** Median NEES (of an even count, the mean of the middle two): ~kNeesChi2Median for a
     *  consistent filter; NaN if no step has ground truth. */
    double nees_median = 0;
    /** Share of the steps whose covariance is well conditioned (TStepRecord::
     *  neesWellConditioned(): enough effective particles, the covariance neither at the floor
     *  nor near singular), in [0, 1]; NaN if no step has ground truth. */
    double nees_well_conditioned_share = 0;
    /** Mean NEES over those steps: ~3 for a consistent filter; NaN if there are none. */
    double nees_mean_well_conditioned = 0;
    /** Share of the steps whose NEES <= kNeesChi2_95, in [0, 1]: the one-sided upper bound a
     *  consistent filter's NEES stays under 95 % of the time, so ~0.95 for a consistent filter,
     *  less for an overconfident one (a spread too small for its errors); NaN if no step has
     *  ground truth. */
    double nees_inside_share = 0;
    /** @} */
    /** @name Lost again: from the convergence step on, a step with ground truth whose err_xy
     *  > max_err_xy_m is lost; an episode is a maximal run of consecutive lost steps, lasting
     *  from its first step's time to that of the first step after it that is not lost (or of
     *  the run's last step). Without convergence: counts 0, times NaN.
     *  @{ */
    /** Lost steps. */
    size_t lost_after_convergence_steps = 0;
    /** Total time of the episodes [s]. */
    double lost_after_convergence_s = 0;
    /** Episodes. */
    size_t lost_episodes = 0;
    /** Time from the run's first step to the first lost step [s]; NaN if none. */
    double first_lost_after_convergence_s = 0;
    /** Time of the longest episode [s] (0 if none). */
    double longest_lost_s = 0;
    /** @} */
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

/** RunMetrics::compute() one record at a time, in step order: what a run of any length keeps of
 *  its steps, the NEES of each (for its median) and otherwise constant memory. */
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
    /** The lost steps and their episodes (RunMetrics' "lost again") from a step on. */
    struct Lost
    {
        size_t steps = 0, episodes = 0;
        /** The episodes that ended: total and longest time [s]. */
        double endedS = 0, longestS = 0;
        /** Time of the first lost step; NaN if none. */
        double firstT = 0;
        /** Whether the last step was lost, and the time of its episode's first step. */
        bool open = false;
        double openT = 0;
        Lost();
        void add(const TStepRecord& r, bool lost);
        /** Total and longest time with the open episode ended at `lastT`. */
        double totalS(double lastT) const;
        double longest(double lastT) const;
    };

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
        /** The lost steps from the candidate on. A lost step is not a good one: before the
         *  candidate settles it ends the run of good steps, and these start again with the
         *  next candidate; so they are those from the settling step on. */
        Lost lost;
        void add(const TStepRecord& r, bool ok, bool lost, size_t minSteps);
        /** The settling step, if any (a run of good steps to the end counts). */
        std::optional<size_t> step() const { return candidate; }
    };

    RunMetrics::TConvergenceCriterion m_criterion;
    long m_kidnapStep;
    Settling m_convergence, m_recovery;
    RunMetrics m_m;
    double m_firstT = 0, m_lastT = 0, m_sum2 = 0, m_updates = 0, m_particleUpdates = 0;
    double m_neesSum = 0, m_neesWellConditionedSum = 0;
    size_t m_neesCount = 0, m_neesInside = 0, m_neesWellConditioned = 0;
    /** Every NEES, for the median: the one thing kept per step (8 bytes). */
    std::vector<double> m_nees;
    bool m_any = false;
};

}  // namespace semloc

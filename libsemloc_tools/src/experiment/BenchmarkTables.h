/* semloc — Benchmark's result tables: results.csv, curves.csv, scenarios.csv and the
 * statistics per variant the report's tables are made of (private). */
#pragma once

#include <semloc/experiment/Benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace semloc::detail
{
/** The NEES figures of RunMetrics over runs, each run's taken once it has ground truth (its
 *  nees_mean_well_conditioned only if it has a well-conditioned step). */
struct NeesOverRuns
{
    std::vector<double> median, inside, meanWellConditioned, wellConditionedShare;
    void add(const RunMetrics& m);
    /** The median of the medians; NaN without a run. */
    double medianOfMedians() const;
};

/** What the runs of one variant measured. */
struct VariantStatistics
{
    size_t runs = 0, converged = 0;
    /** Per converged run: time to convergence [s], mean error after convergence [m]. */
    std::vector<double> convTime, errAfter;
    /** Per converged run with a detector bound: the bound over the same steps [m]. */
    std::vector<double> boundAfter;
    /** var_xy of every step of every run [m^2]. */
    std::vector<double> var;
    /** The consistency over the runs (TScenarioSummary's NEES fields). */
    NeesOverRuns nees;
    /** Per run: filter time [s], filter time per particle-step [us], wall time [s]. */
    std::vector<double> filter, perParticle, wall;
};

/** The statistics of `runs` per variant name. */
std::map<std::string, VariantStatistics> variantStatistics(
    const std::vector<Benchmark::TRunResult>& runs);

/** The variant times are compared to: "semantic" if present, else the first. */
std::string referenceVariant(const std::vector<std::string>& variants);

/** results.csv: one row per run and variant. */
std::string resultsCsv(const std::vector<Benchmark::TRunResult>& runs);

/** curves.csv: per variant (in the order of `variants`) and step, the mean and 10/50/90 %
 *  percentiles of err_xy and var_xy over the runs. */
std::string curvesCsv(const std::vector<Benchmark::TRunResult>& runs,
                      const std::vector<std::string>& variants);

/** scenarios.csv: one row per scenario and variant. */
std::string scenariosCsv(const std::vector<Benchmark::TScenarioSummary>& summaries);

}  // namespace semloc::detail

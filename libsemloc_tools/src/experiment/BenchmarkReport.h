/* semloc — Benchmark's report: report.md (one benchmark, or the scenarios) and the figures
 * (figures.gp drawn by gnuplot, world_paths.png) (private). */
#pragma once

#include <semloc/experiment/Benchmark.h>
#include <semloc/io/StagedDirectory.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** A warning on one series of a benchmark's runs. */
struct TSeriesNote
{
    std::string scenario, series, text;
};

/** The series of `runs` driven by the active policy (`policy`) whose decisions cost more than
 *  the budget (ActivePolicy::kBudgetFilterSteps) on average over all their runs' decisions:
 *  one note each (costlySeriesNote), in the runs' order. */
std::vector<TSeriesNote> costlySeries(const std::vector<Benchmark::TRunResult>& runs,
                                      const ActivePolicy::TOptions& policy);

/** Benchmark::SetStageReporter()'s reporter, told `what` (nothing without one). */
void reportStage(const std::string& what);

/** Writes figures.gp (the paper's Fig. 3 from curves.csv, one curve per variant), draws
 *  fig_variance.png and fig_error.png with gnuplot and writes world_paths.png (the world of
 *  `simulation`, run 1's true path and each variant's estimate) in `out`; returns the figures
 *  gnuplot could not draw (left out). With more than 9 series (a sweep), the figures draw 9 of
 *  them, evenly spread from the first to the last, so that they stay readable and drawable;
 *  report.md says so, and its tables and curves.csv have every series. Each figure is a
 *  stage (reportStage), its text after `stagePrefix`. */
std::vector<TFigureWarning> writeFigures(const StagedDirectory& out,
                                         const std::vector<std::string>& variants,
                                         const TSimulatorOptions& simulation,
                                         const std::vector<Benchmark::TRunResult>& runs,
                                         const std::string& stagePrefix = {});

/** report.md of benchmark `b`, whose runs (`jobs` at once) gave `res` (runs, table,
 *  summaries, wall time); `kidnapStep` -1 without a kidnapping. */
std::string reportMarkdown(const Benchmark& b, const Benchmark::TResult& res, size_t jobs,
                           long kidnapStep);

/** report.md of a benchmark with scenarios (`b.scenarios()`), whose results are `res`. */
std::string scenariosReportMarkdown(const Benchmark& b, const Benchmark::TResult& res);

}  // namespace semloc::detail

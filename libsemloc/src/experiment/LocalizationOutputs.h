/* semloc — the outputs of a localization run: steps.csv and summary.yaml (docs/design.md,
 * "Output contract of semloc-localize") (private). */
#pragma once

#include <semloc/experiment/LocalizationExperiment.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** steps.csv: one row per step, numbers in their shortest round-trip text, empty cells for
 *  unknown values. */
std::string stepsCsv(const std::vector<TStepRecord>& records);

/** summary.yaml of the run `res` configured by `o`; unknown values are `null`. */
std::string summaryYaml(const LocalizationExperiment::TResult& res,
                        const LocalizationExperiment::TOptions& o);

}  // namespace semloc::detail

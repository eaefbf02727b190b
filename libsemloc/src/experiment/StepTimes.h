/* semloc — the steps a localization run makes of a rawlog and their times, and the ground
 * truth matched to them by time (private). */
#pragma once

#include <mrpt/obs/CRawlog.h>
#include <semloc/experiment/GroundTruth.h>

#include <cstddef>
#include <string>
#include <vector>

namespace semloc::detail
{
/** A step as LocalizationExperiment::run() groups the rawlog: the entry it starts at and
 *  its time (its first observation's; for a sensory frame without observations, its
 *  action's: actionTime(); NaN without a timestamp). */
struct StepTime
{
    size_t entry = 0;
    double t = 0;
};

/** The time [s] of an action collection: its first action's timestamp (NaN if it has none). */
double actionTime(const mrpt::obs::CActionCollection& actions);

/** The steps run() makes of `rawlog`: action / sensory-frame pairs, or consecutive
 *  observations with one timestamp. */
std::vector<StepTime> stepTimes(const mrpt::obs::CRawlog& rawlog);

/** The ground-truth row of each step time (null: none): the nearest row within half the
 *  median step period (the rows' median period if the steps have none). */
std::vector<const GroundTruthRow*> matchGroundTruth(const GroundTruth& gt,
                                                    const std::vector<double>& times);

/** With ground truth matched by time: the times of the steps run (from rawlog_offset on)
 *  must increase, and at least one must match a row; throws naming both files otherwise. */
void checkGroundTruthTimes(const std::vector<StepTime>& steps, const GroundTruth& gt,
                           const std::string& gtPath, const std::string& rawlogPath);

}  // namespace semloc::detail

/* semloc — the steps a localization run makes of a rawlog and their times, and the ground
 * truth matched to them by time (private). */
#pragma once

#include <mrpt/obs/CRawlog.h>
#include <semloc/experiment/GroundTruth.h>

#include <mrpt/core/Clock.h>

#include <cstddef>
#include <limits>
#include <optional>
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

/** The steps run() makes of a rawlog, entry by entry: action / sensory-frame pairs, or
 *  consecutive observations with one timestamp. */
class StepTimer
{
public:
    /** Entry `i`. */
    void add(const mrpt::serialization::CSerializable::Ptr& entry, size_t i);
    /** After the last entry: the steps. */
    std::vector<StepTime> finish();

private:
    void flush();
    std::vector<StepTime> m_steps;
    std::optional<StepTime> m_group;  // observations-only: one timestamp, one step
    mrpt::Clock::time_point m_groupStamp;
    double m_actionT = std::numeric_limits<double>::quiet_NaN();  // the pending action's time
};

/** The steps run() makes of `rawlog` (StepTimer over its entries). */
std::vector<StepTime> stepTimes(const mrpt::obs::CRawlog& rawlog);

/** How far from a step's time its ground-truth row may be: half the median step period of
 *  `times` (the rows' median period if the steps have none). */
double groundTruthTolerance(const GroundTruth& gt, const std::vector<double>& times);

/** The ground-truth row of each step time (null: none): the nearest row within
 *  groundTruthTolerance(). */
std::vector<const GroundTruthRow*> matchGroundTruth(const GroundTruth& gt,
                                                    const std::vector<double>& times);

/** With ground truth matched by time: the times of the steps run (from rawlog_offset on)
 *  must increase, and at least one must match a row; throws naming both files otherwise. */
void checkGroundTruthTimes(const std::vector<StepTime>& steps, const GroundTruth& gt,
                           const std::string& gtPath, const std::string& rawlogPath);

}  // namespace semloc::detail

/* semloc — the steps of a rawlog and their times; the ground truth matched to them. */
#include "experiment/StepTimes.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "experiment/Statistics.h"

namespace semloc::detail
{
namespace
{
/** A time as steps.csv writes it. */
std::string timeText(double t)
{
    return mrpt::format("%.6f", t);
}

double timeOf(const mrpt::obs::CObservation& obs)
{
    return obs.timestamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(obs.timestamp)
                                              : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double actionTime(const mrpt::obs::CActionCollection& actions)
{
    return actions.size() > 0 && actions.get(0).timestamp != INVALID_TIMESTAMP
               ? mrpt::Clock::toDouble(actions.get(0).timestamp)
               : std::numeric_limits<double>::quiet_NaN();
}

std::vector<StepTime> stepTimes(const mrpt::obs::CRawlog& rawlog)
{
    std::vector<StepTime> steps;
    std::optional<StepTime> group;  // observations-only: one timestamp, one step
    mrpt::Clock::time_point groupStamp;
    double actionT = std::numeric_limits<double>::quiet_NaN();  // the pending action's time
    auto flush = [&]
    {
        if (group)
        {
            steps.push_back(*group);
            group.reset();
        }
    };
    for (size_t i = 0; i < rawlog.size(); i++)
    {
        switch (rawlog.getType(i))
        {
            case mrpt::obs::CRawlog::etActionCollection:
                flush();
                actionT = actionTime(*rawlog.getAsAction(i));
                break;
            case mrpt::obs::CRawlog::etSensoryFrame:
            {
                flush();
                const auto sf = rawlog.getAsObservations(i);
                steps.push_back(
                    {i, sf->size() > 0 ? timeOf(*sf->getObservationByIndex(0)) : actionT});
                actionT = std::numeric_limits<double>::quiet_NaN();
                break;
            }
            case mrpt::obs::CRawlog::etObservation:
            {
                const auto obs = rawlog.getAsObservation(i);
                if (obs && IS_CLASS(*obs, mrpt::obs::CObservationOdometry))
                {
                    flush();
                }
                else if (obs)
                {
                    if (group && groupStamp != obs->timestamp)
                    {
                        flush();
                    }
                    if (!group)
                    {
                        group = StepTime{i, timeOf(*obs)};
                        groupStamp = obs->timestamp;
                    }
                }
                break;
            }
            default:
                break;
        }
    }
    flush();
    return steps;
}

/** The ground-truth row of each step time (null: none): the nearest row within half the
 *  median step period (the rows' median period if the steps have none). */
std::vector<const GroundTruthRow*> matchGroundTruth(const GroundTruth& gt,
                                                    const std::vector<double>& times)
{
    std::vector<const GroundTruthRow*> rows(times.size(), nullptr);
    if (gt.empty())
    {
        return rows;
    }
    std::vector<double> dt;
    for (size_t k = 1; k < times.size(); k++)
    {
        const double d = times[k] - times[k - 1];
        if (std::isfinite(d) && d > 0)
        {
            dt.push_back(d);
        }
    }
    double tol = 0.5 * (dt.empty() ? gt.medianPeriod() : median(dt));
    if (!(tol > 0))
    {
        tol = 1e-6;
    }
    for (size_t k = 0; k < times.size(); k++)
    {
        rows[k] = gt.nearest(times[k], tol);
    }
    return rows;
}

/** With ground truth matched by time: the times of the steps run (from rawlog_offset on)
 *  must increase, and at least one must match a row. */
void checkGroundTruthTimes(const std::vector<StepTime>& steps, const GroundTruth& gt,
                           const std::string& gtPath, const std::string& rawlogPath)
{
    const StepTime* prev = nullptr;
    std::vector<double> times;
    double tMin = std::numeric_limits<double>::infinity(), tMax = -tMin;
    for (const auto& s : steps)
    {
        times.push_back(s.t);
        if (std::isnan(s.t))
        {
            continue;  // no timestamp: no ground truth for that step
        }
        if (prev && !(s.t > prev->t))
        {
            THROW_EXCEPTION(mrpt::format(
                "rawlog '%s': entry %zu: time %s is not after %s, the time of entry %zu (the "
                "step before): ground truth ('%s') is matched by time, so step times must "
                "increase",
                rawlogPath.c_str(), s.entry, timeText(s.t).c_str(), timeText(prev->t).c_str(),
                prev->entry, gtPath.c_str()));
        }
        prev = &s;
        tMin = std::min(tMin, s.t);
        tMax = std::max(tMax, s.t);
    }
    const auto rows = matchGroundTruth(gt, times);
    if (std::none_of(rows.begin(), rows.end(), [](const GroundTruthRow* r) { return r; }))
    {
        THROW_EXCEPTION(mrpt::format(
            "ground truth '%s' (%zu rows, times %s to %s) matches no step of rawlog '%s' (%s): "
            "are both in seconds of the same clock?",
            gtPath.c_str(), gt.size(), timeText(gt.rows().front().t).c_str(),
            timeText(gt.rows().back().t).c_str(), rawlogPath.c_str(),
            prev ? mrpt::format("%zu steps, times %s to %s", steps.size(), timeText(tMin).c_str(),
                                timeText(tMax).c_str())
                       .c_str()
                 : "no step has a timestamp"));
    }
}

}  // namespace semloc::detail

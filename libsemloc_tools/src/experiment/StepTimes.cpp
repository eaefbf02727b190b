/* semloc — the steps of a rawlog and their times; the ground truth matched to them. */
#include "experiment/StepTimes.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>

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

void StepTimer::flush()
{
    if (m_group)
    {
        m_steps.push_back(*m_group);
        m_group.reset();
    }
}

void StepTimer::add(const mrpt::serialization::CSerializable::Ptr& entry, size_t i)
{
    if (const auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(entry))
    {
        flush();
        m_actionT = actionTime(*acts);
    }
    else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(entry))
    {
        flush();
        m_steps.push_back({i, sf->size() > 0 ? timeOf(*sf->getObservationByIndex(0)) : m_actionT});
        m_actionT = std::numeric_limits<double>::quiet_NaN();
    }
    else if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(entry))
    {
        if (IS_CLASS(*obs, mrpt::obs::CObservationOdometry))
        {
            flush();
            return;
        }
        if (m_group && m_groupStamp != obs->timestamp)
        {
            flush();
        }
        if (!m_group)
        {
            m_group = StepTime{i, timeOf(*obs)};
            m_groupStamp = obs->timestamp;
        }
    }
}

std::vector<StepTime> StepTimer::finish()
{
    flush();
    return std::move(m_steps);
}

std::vector<StepTime> stepTimes(const mrpt::obs::CRawlog& rawlog)
{
    StepTimer timer;
    for (size_t i = 0; i < rawlog.size(); i++)
    {
        timer.add(rawlog.getAsGeneric(i), i);
    }
    return timer.finish();
}

double groundTruthTolerance(const GroundTruth& gt, const std::vector<double>& times)
{
    std::vector<double> dt;
    for (size_t k = 1; k < times.size(); k++)
    {
        const double d = times[k] - times[k - 1];
        if (std::isfinite(d) && d > 0)
        {
            dt.push_back(d);
        }
    }
    const double tol = 0.5 * (dt.empty() ? gt.medianPeriod() : median(dt));
    return tol > 0 ? tol : 1e-6;
}

std::vector<const GroundTruthRow*> matchGroundTruth(const GroundTruth& gt,
                                                    const std::vector<double>& times)
{
    std::vector<const GroundTruthRow*> rows(times.size(), nullptr);
    if (gt.empty())
    {
        return rows;
    }
    const double tol = groundTruthTolerance(gt, times);
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

/* semloc — the rawlog checks of a localization run: finite odometry that [MotionModel] can use,
 * usable observations. */
#include "experiment/RawlogChecks.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <cmath>
#include <set>

#include "world/Geometry2D.h"

namespace semloc::detail
{
namespace
{
bool finiteMatrix(const mrpt::math::CMatrixDouble33& m)
{
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 3; c++)
        {
            if (!std::isfinite(m(r, c)))
            {
                return false;
            }
        }
    }
    return true;
}

/** What a rawlog holds, entry by entry: its odometry and its observations. */
class RawlogInventory
{
public:
    RawlogInventory(const std::string& path, const mrpt::maps::CMetricMap& maps,
                    const MotionModelConfig& motion)
        : m_path(path), m_maps(maps), m_motion(motion)
    {
    }

    /** Entry `i` of the rawlog; throws at non-finite odometry or odometry [MotionModel] cannot
     *  re-derive. */
    void add(const mrpt::serialization::CSerializable::Ptr& obj, size_t i);
    /** Throws when the run could not use the rawlog. */
    void check(const Localizer::TOptions& filter) const;

private:
    void addActions(mrpt::obs::CActionCollection& acts, size_t i);
    void addObservation(const mrpt::obs::CObservation& obs, size_t entry);
    [[noreturn]] void badOdometry(size_t i) const
    {
        THROW_EXCEPTION(
            mrpt::format("rawlog '%s': entry %zu: the odometry is not finite", m_path.c_str(), i));
    }

    const std::string& m_path;
    const mrpt::maps::CMetricMap& m_maps;
    const MotionModelConfig& m_motion;
    bool m_odometry = false;
    size_t m_observations = 0, m_usable = 0, m_invalid = 0;
    std::string m_firstInvalid;
    std::set<std::string> m_classes;
};

void RawlogInventory::add(const mrpt::serialization::CSerializable::Ptr& obj, size_t i)
{
    if (const auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
    {
        addActions(*acts, i);
    }
    else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
    {
        for (const auto& obs : *sf)
        {
            if (obs)
            {
                addObservation(*obs, i);
            }
        }
    }
    else if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj))
    {
        m_odometry = true;
        if (!finitePose(odo->odometry.asTPose()))
        {
            badOdometry(i);
        }
    }
    else if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
    {
        addObservation(*obs, i);
    }
}

void RawlogInventory::addActions(mrpt::obs::CActionCollection& acts, size_t i)
{
    for (size_t k = 0; k < acts.size(); k++)
    {
        const auto a = acts.get(k);
        if (const auto m2 = std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(a))
        {
            m_odometry = true;
            if (!m2->poseChange || !finitePose(m2->poseChange->getMeanVal().asTPose()) ||
                !finiteMatrix(m2->poseChange->getCovariance()))
            {
                badOdometry(i);
            }
        }
        m_odometry = m_odometry || IS_CLASS(*a, mrpt::obs::CActionRobotMovement3D);
    }
    if (const std::string why = m_motion.problem(acts); !why.empty())
    {
        THROW_EXCEPTION(mrpt::format(
            "rawlog '%s': entry %zu: [MotionModel] source = gaussian cannot re-derive its "
            "odometry noise: %s (source = rawlog uses the rawlog's own noise)",
            m_path.c_str(), i, why.c_str()));
    }
}

void RawlogInventory::addObservation(const mrpt::obs::CObservation& obs, size_t entry)
{
    m_observations++;
    m_classes.insert(obs.GetRuntimeClass()->className);
    if (const std::string why = Localizer::invalidObservation(obs, m_maps); !why.empty())
    {
        if (m_invalid++ == 0)
        {
            m_firstInvalid = mrpt::format("entry %zu, a %s: %s", entry,
                                          obs.GetRuntimeClass()->className, why.c_str());
        }
        return;
    }
    m_usable += m_maps.canComputeObservationLikelihood(obs) ? 1 : 0;
}

void RawlogInventory::check(const Localizer::TOptions& filter) const
{
    if (!m_odometry && !filter.allow_no_odometry)
    {
        THROW_EXCEPTION("rawlog '" + m_path +
                        "' holds no odometry (no CActionRobotMovement2D/3D, no "
                        "CObservationOdometry); set [DummyOdometryParams] allow_no_odometry = "
                        "true to localize it with zero motion plus minStdXY/minStdPHI noise");
    }
    if (m_usable == 0)
    {
        std::string list;
        for (const auto& c : m_classes)
        {
            list += (list.empty() ? "" : ", ") + c;
        }
        THROW_EXCEPTION(mrpt::format(
            "rawlog '%s': none of its %zu observations (%s) can be used by the maps in "
            "[MetricMap]%s",
            m_path.c_str(), m_observations, m_observations ? list.c_str() : "none",
            m_invalid ? mrpt::format("; %zu cannot be scored at all (the first: %s)", m_invalid,
                                     m_firstInvalid.c_str())
                            .c_str()
                      : ""));
    }
}
}  // namespace

void checkRawlog(const mrpt::obs::CRawlog& rawlog, const std::string& path,
                 const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter)
{
    size_t i = 0;
    checkRawlog([&] { return i < rawlog.size() ? rawlog.getAsGeneric(i++) : nullptr; },
                [](const mrpt::serialization::CSerializable::Ptr&, size_t) {}, path, maps, filter);
}

size_t checkRawlog(
    const std::function<mrpt::serialization::CSerializable::Ptr()>& next,
    const std::function<void(const mrpt::serialization::CSerializable::Ptr&, size_t)>& visit,
    const std::string& path, const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter)
{
    const MotionModelConfig motion(filter.motion_model);
    RawlogInventory inventory(path, maps, motion);
    size_t i = 0;
    for (auto obj = next(); obj; obj = next(), i++)
    {
        inventory.add(obj, i);
        visit(obj, i);
    }
    inventory.check(filter);
    return i;
}

}  // namespace semloc::detail

/* semloc — [MotionModel]: the odometry noise as the rawlog carries it, or re-derived from each
 * raw increment with MRPT's Gaussian motion model. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/filter/MotionModelRegistry.h>
#include <semloc/filter/OdometryDelay.h>
#include <semloc/io/ConfigHelpers.h>

#include <cmath>

#include "io/ExactConfigWrite.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
using mrpt::obs::CActionRobotMovement2D;

const std::vector<std::string> kSources = {"rawlog", "gaussian"};

/** Largest a1..a4 and minStdXY accepted (the odometry of a step of kilometres stays finite). */
constexpr double kMaxCoefficient = 1e3;
/** Largest heading drift rate and walk accepted [deg/min] (a turn a second). */
constexpr double kMaxDriftDegPerMin = 21600;

/** True when `m` holds no raw increment although it moved: MRPT's default (0, 0, 0) left in
 *  rawOdometryIncrementReading by a writer that set the pose change only. */
bool missingRawIncrement(const CActionRobotMovement2D& m)
{
    const auto& raw = m.rawOdometryIncrementReading;
    if (raw.x() != 0 || raw.y() != 0 || raw.phi() != 0 || !m.poseChange)
    {
        return false;
    }
    const auto mean = m.poseChange->getMeanVal();
    constexpr double kTiny = 1e-12;
    return std::abs(mean.x()) > kTiny || std::abs(mean.y()) > kTiny || std::abs(mean.phi()) > kTiny;
}
}  // namespace

config::TValueRange MotionModelConfig::TOptions::range(const std::string& key)
{
    if (key == "minStdPHI")
    {
        return {0, 360};
    }
    if (key == "heading_drift_std_deg_per_min" || key == "heading_drift_walk_deg_per_min")
    {
        return {0, kMaxDriftDegPerMin};
    }
    if (key == "odometry_delay_s")
    {
        return {0, OdometryDelay::kMaxDelay_s};
    }
    if (key == "a1" || key == "a2" || key == "a3" || key == "a4" || key == "minStdXY")
    {
        return {0, kMaxCoefficient};
    }
    THROW_EXCEPTION("[" + std::string(kSection) + "] '" + key + "' is not a numeric key");
}

void MotionModelConfig::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                     const std::string& s)
{
    using namespace semloc::config;
    rejectUnknownKeys(
        c, s,
        {"kind", "source", "a1", "a2", "a3", "a4", "minStdXY", "minStdPHI",
         "heading_drift_std_deg_per_min", "heading_drift_walk_deg_per_min", "odometry_delay_s"});
    kind = detail::trimValue(c.read_string(s, "kind", kind));
    if (!MotionModelRegistry::has(kind))
    {
        std::string known;
        for (const auto& n : MotionModelRegistry::names())
        {
            known += (known.empty() ? "" : ", ") + n;
        }
        THROW_EXCEPTION("ini [" + s + "] kind: unknown motion model '" + kind +
                        "' (registered: " + known + ")");
    }
    std::string src = kSources[static_cast<size_t>(source)];
    readChoice(c, s, "source", src, kSources);
    source = src == "gaussian" ? Source::Gaussian : Source::Rawlog;
    readDouble(c, s, "a1", a1, range("a1"));
    readDouble(c, s, "a2", a2, range("a2"));
    readDouble(c, s, "a3", a3, range("a3"));
    readDouble(c, s, "a4", a4, range("a4"));
    readDouble(c, s, "minStdXY", minStdXY, range("minStdXY"));
    readDouble(c, s, "minStdPHI", minStdPHI, range("minStdPHI"));
    readDouble(c, s, "heading_drift_std_deg_per_min", heading_drift_std_deg_per_min,
               range("heading_drift_std_deg_per_min"));
    readDouble(c, s, "heading_drift_walk_deg_per_min", heading_drift_walk_deg_per_min,
               range("heading_drift_walk_deg_per_min"));
    readDouble(c, s, "odometry_delay_s", odometry_delay_s, range("odometry_delay_s"));
}

void MotionModelConfig::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                   const std::string& s) const
{
    detail::writeText(c, s, "kind", kind,
                      "the prediction's motion model: odometry | a registered one");
    detail::writeText(c, s, "source", kSources[static_cast<size_t>(source)],
                      "rawlog: the rawlog's noise | gaussian: a1..minStdPHI");
    detail::writeExact(c, s, "a1", a1, "position std per metre travelled [m/m]");
    detail::writeExact(c, s, "a2", a2, "position std per degree turned [m/deg]");
    detail::writeExact(c, s, "a3", a3, "heading std per metre travelled [deg/m]");
    detail::writeExact(c, s, "a4", a4, "heading std per degree turned [deg/deg]");
    detail::writeExact(c, s, "minStdXY", minStdXY, "minimum position std per increment [m]");
    detail::writeExact(c, s, "minStdPHI", minStdPHI, "minimum heading std per increment [deg]");
    detail::writeExact(c, s, "heading_drift_std_deg_per_min", heading_drift_std_deg_per_min,
                       "heading drift state: std of a particle's initial rate [deg/min]; 0: off");
    detail::writeExact(c, s, "heading_drift_walk_deg_per_min", heading_drift_walk_deg_per_min,
                       "heading drift state: std of a rate's change over a minute [deg/min]");
    detail::writeExact(c, s, "odometry_delay_s", odometry_delay_s,
                       "how late the vehicle follows its odometry [s]; 0: as it comes");
}

CActionRobotMovement2D::TMotionModelOptions MotionModelConfig::gaussian() const
{
    // TOptions_GaussianModel holds a2 in m/rad, a3 in rad/m, minStdPHI in rad (its defaults:
    // RAD2DEG(0.001), DEG2RAD(1.0), DEG2RAD(0.2)); MRPT applies a2 and a4 to |phi| in rad.
    CActionRobotMovement2D::TMotionModelOptions m;
    m.modelSelection = CActionRobotMovement2D::mmGaussian;
    m.gaussianModel.a1 = m_options.a1;
    m.gaussianModel.a2 = mrpt::RAD2DEG(m_options.a2);
    m.gaussianModel.a3 = mrpt::DEG2RAD(m_options.a3);
    m.gaussianModel.a4 = m_options.a4;
    m.gaussianModel.minStdXY = m_options.minStdXY;
    m.gaussianModel.minStdPHI = mrpt::DEG2RAD(m_options.minStdPHI);
    return m;
}

std::string MotionModelConfig::problem(const mrpt::obs::CActionCollection& acts) const
{
    if (!rederives())
    {
        return "";
    }
    for (size_t k = 0; k < acts.size(); k++)
    {
        const auto& a = acts.get(k);
        if (const auto* m = dynamic_cast<const CActionRobotMovement2D*>(&a))
        {
            if (m->estimationMethod != CActionRobotMovement2D::emOdometry)
            {
                return "its CActionRobotMovement2D is a scan-matching estimate "
                       "(estimationMethod emScan2DMatching), not odometry: it has no raw "
                       "odometry increment to re-derive the noise from";
            }
            const auto& raw = m->rawOdometryIncrementReading;
            if (!std::isfinite(raw.x()) || !std::isfinite(raw.y()) || !std::isfinite(raw.phi()))
            {
                return "its CActionRobotMovement2D's raw odometry increment is not finite";
            }
            if (missingRawIncrement(*m))
            {
                const auto mean = m->poseChange->getMeanVal();
                return mrpt::format(
                    "its CActionRobotMovement2D moves by (%g, %g, %g) but holds no raw odometry "
                    "increment (rawOdometryIncrementReading is 0, 0, 0)",
                    mean.x(), mean.y(), mean.phi());
            }
        }
        else if (dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&a))
        {
            return "it holds a CActionRobotMovement3D: only 2D odometry "
                   "(CActionRobotMovement2D) is re-derived";
        }
    }
    return "";
}

const mrpt::obs::CActionCollection& MotionModelConfig::apply(
    const mrpt::obs::CActionCollection& acts, mrpt::obs::CActionCollection& copy) const
{
    if (!rederives())
    {
        return acts;
    }
    if (const std::string why = problem(acts); !why.empty())
    {
        THROW_EXCEPTION("[MotionModel] source = gaussian: the action " + why);
    }
    const auto model = gaussian();
    copy.clear();
    for (size_t k = 0; k < acts.size(); k++)
    {
        const auto& a = acts.get(k);
        if (const auto* m = dynamic_cast<const CActionRobotMovement2D*>(&a))
        {
            CActionRobotMovement2D moved(*m);
            moved.computeFromOdometry(m->rawOdometryIncrementReading, model);
            copy.insert(moved);
        }
        else
        {
            copy.insert(a);
        }
    }
    return copy;
}

}  // namespace semloc

/* semloc — MotionModelRegistry: the prediction's motion models by name. */
#include <mrpt/core/exceptions.h>
#include <semloc/filter/DvlMotionModel.h>
#include <semloc/filter/MotionModelRegistry.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace semloc
{
namespace
{
/** semloc's odometry model with the section's heading drift (deg/min to rad/s; the walk per
 *  minute to per sqrt(s)). */
std::shared_ptr<ParticleMotionModel> odometryModel(const MotionModelConfig::TOptions& o)
{
    auto m = std::make_shared<OdometryMotionModel>();
    m->setHeadingDrift(
        o.heading_drift_std_deg_per_min * kRadPerSecondPerDegPerMinute,
        o.heading_drift_walk_deg_per_min * kRadPerSecondPerDegPerMinute / std::sqrt(60.0));
    return m;
}

/** The DVL's body-frame model with the section's a1, a3, a4, minStdXY, minStdPHI. */
std::shared_ptr<ParticleMotionModel> dvlModel(const MotionModelConfig::TOptions& o)
{
    if (o.headingDrift() || o.odometry_delay_s != 0)
    {
        THROW_EXCEPTION(
            "[MotionModel] kind = dvl: heading_drift_* and odometry_delay_s are the odometry "
            "model's (kind = odometry); a compass (compassMap) holds a DVL's heading");
    }
    DvlMotionModel::TNoise noise;
    noise.a1 = o.a1;
    noise.a3_deg = o.a3;
    noise.a4 = o.a4;
    noise.minStdXY = o.minStdXY;
    noise.minStdPHI_deg = o.minStdPHI;
    return std::make_shared<DvlMotionModel>(noise);
}

std::vector<std::pair<std::string, MotionModelRegistry::Factory>>& registry()
{
    static std::vector<std::pair<std::string, MotionModelRegistry::Factory>> models = {
        {MotionModelConfig::kOdometryModel, odometryModel}, {"dvl", dvlModel}};
    return models;
}
}  // namespace

void MotionModelRegistry::add(const std::string& name, Factory factory)
{
    ASSERTMSG_(factory, "MotionModelRegistry::add: no factory");
    auto& models = registry();
    const auto same =
        std::find_if(models.begin(), models.end(), [&](const auto& m) { return m.first == name; });
    if (same != models.end())
    {
        same->second = std::move(factory);
        return;
    }
    models.emplace_back(name, std::move(factory));
}

bool MotionModelRegistry::has(const std::string& name)
{
    const auto& models = registry();
    return std::any_of(models.begin(), models.end(),
                       [&](const auto& m) { return m.first == name; });
}

std::vector<std::string> MotionModelRegistry::names()
{
    std::vector<std::string> out;
    for (const auto& m : registry())
    {
        out.push_back(m.first);
    }
    return out;
}

std::shared_ptr<ParticleMotionModel> MotionModelRegistry::create(
    const MotionModelConfig::TOptions& options)
{
    for (const auto& m : registry())
    {
        if (m.first == options.kind)
        {
            auto model = m.second(options);
            ASSERTMSG_(model,
                       "MotionModelRegistry: the factory of '" + options.kind + "' made no model");
            return model;
        }
    }
    THROW_EXCEPTION("ini [MotionModel] kind: unknown motion model '" + options.kind + "'");
}

}  // namespace semloc

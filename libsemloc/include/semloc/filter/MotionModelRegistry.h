/* semloc — the motion models of the filter's prediction by name ([MotionModel] kind). */
#pragma once

#include <semloc/filter/MotionModelConfig.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace semloc
{
/** The prediction's motion models, each created by name from `[MotionModel] kind = <name>`
 *  with the section's options (MotionModelConfig::TOptions). semloc's "odometry" (the
 *  default: OdometryMotionModel with the section's heading drift) and "dvl" (DvlMotionModel
 *  with the section's a1, a3, a4, minStdXY, minStdPHI) are registered when the registry is
 *  first used; a program (or a test) registers its own with add() before it
 *  loads an ini (not safe against add() from another thread). */
class MotionModelRegistry
{
public:
    /** Makes the model from the section's options; throws (naming the [MotionModel] key) for
     *  options it cannot use. */
    using Factory =
        std::function<std::shared_ptr<ParticleMotionModel>(const MotionModelConfig::TOptions&)>;

    /** Registers `factory` as `name` (replacing one of that name). */
    static void add(const std::string& name, Factory factory);
    /** True when `name` is registered. */
    static bool has(const std::string& name);
    /** The registered names, semloc's first ("odometry", "dvl"), then in registration
     *  order. */
    static std::vector<std::string> names();
    /** The model `options.kind` names, made by its factory (throws for an unknown name). */
    static std::shared_ptr<ParticleMotionModel> create(const MotionModelConfig::TOptions& options);
};

}  // namespace semloc

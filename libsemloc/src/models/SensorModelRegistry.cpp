/* semloc — SensorModelRegistry: the kinds of map by name. */
#include <semloc/models/SensorModelRegistry.h>

#include <algorithm>

#include "models/BuiltinKinds.h"

namespace semloc
{
namespace
{
std::vector<std::shared_ptr<const SensorModelKind>>& registry()
{
    static std::vector<std::shared_ptr<const SensorModelKind>> kinds = {
        detail::semanticMapKind(),      detail::structureMapKind(), detail::occupancyGridKind(),
        detail::beaconMapKind(),        detail::sideScanMapKind(),  detail::forwardSonarMapKind(),
        detail::bearingCameraMapKind(), detail::compassMapKind(),   detail::poseFixMapKind()};
    return kinds;
}

const SensorModelKind* ofClass(const mrpt::rtti::TRuntimeClassId* cls)
{
    for (const auto& k : registry())
    {
        if (cls && cls->derivedFrom(k->mapClass()))
        {
            return k.get();
        }
    }
    return nullptr;
}
}  // namespace

void SensorModelRegistry::add(std::shared_ptr<const SensorModelKind> kind)
{
    auto& kinds = registry();
    const auto same = std::find_if(kinds.begin(), kinds.end(),
                                   [&](const auto& k) { return k->name() == kind->name(); });
    if (same != kinds.end())
    {
        *same = std::move(kind);
        return;
    }
    kinds.push_back(std::move(kind));
}

const std::vector<std::shared_ptr<const SensorModelKind>>& SensorModelRegistry::kinds()
{
    return registry();
}

const SensorModelKind* SensorModelRegistry::of(const mrpt::maps::CMetricMap& map)
{
    return ofClass(map.GetRuntimeClass());
}

const SensorModelKind* SensorModelRegistry::of(const mrpt::maps::TMetricMapInitializer& definition)
{
    return ofClass(definition.getMetricMapClassType().get());
}

}  // namespace semloc

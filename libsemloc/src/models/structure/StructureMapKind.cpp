/* semloc — the structure (sonar ray-casting) map as a kind of [MetricMap]
 * (structureMap_count). */
#include <semloc/models/structure/CStructureMap.h>

#include "io/ExactConfigWrite.h"
#include "models/BuiltinKinds.h"
#include "models/WorldMapFill.h"

namespace semloc::detail
{
namespace
{
class StructureMapKind final : public SensorModelKind
{
public:
    std::string name() const override { return "structureMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override { return CLASS_ID(CStructureMap); }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return "geometric"; }

    void fill(TFill& f) const override
    {
        const auto& d = dynamic_cast<const CStructureMap::TMapDefinition&>(f.definition);
        auto& map = dynamic_cast<CStructureMap&>(f.map);
        fillWorldMap(f, d.world_file, "structure",
                     [&](const World& w)
                     { map.loadFromWorld(w, d.cylinder_tolerance_m, d.raycast_cell_m); });
    }

    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string& worldFile) const override
    {
        const auto& d = dynamic_cast<const CStructureMap::TMapDefinition&>(definition);
        const std::string sc = prefix + "_creationOpts";
        out.write(sc, "world_file", worldFile);
        writeExact(out, sc, "cylinder_tolerance_m", d.cylinder_tolerance_m, "");
        writeExact(out, sc, "raycast_cell_m", d.raycast_cell_m, "");
        d.likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
    }

    void writeReference(mrpt::config::CConfigFileBase& out,
                        const std::string& prefix) const override
    {
        const std::string sc = prefix + "_creationOpts";
        const CStructureMap::TMapDefinition d;
        out.write(sc, "world_file", std::string("maps/paper_50x50.yaml"), 24, 24,
                  "world YAML whose outlines are loaded");
        writeExact(out, sc, "cylinder_tolerance_m", d.cylinder_tolerance_m,
                   "max gap between a cylinder and its polygon [m]");
        writeExact(out, sc, "raycast_cell_m", d.raycast_cell_m,
                   "ray-casting grid cell [m] (>= 0.01), 0 = automatic");
        CStructureMap::TLikelihoodOptions().saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> structureMapKind()
{
    return std::make_shared<StructureMapKind>();
}
}  // namespace semloc::detail

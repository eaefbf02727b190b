/* semloc — the semantic map as a kind of [MetricMap] (semanticMap_count). */
#include <mrpt/core/format.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cmath>

#include "models/BuiltinKinds.h"
#include "models/WorldMapFill.h"

namespace semloc::detail
{
namespace
{
class SemanticMapKind final : public SensorModelKind
{
public:
    std::string name() const override { return "semanticMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override { return CLASS_ID(CSemanticMap); }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return "semantic"; }

    void fill(TFill& f) const override
    {
        const auto& d = dynamic_cast<const CSemanticMap::TMapDefinition&>(f.definition);
        auto& map = dynamic_cast<CSemanticMap&>(f.map);
        fillWorldMap(f, d.world_file, "semantic", [&](const World& w) { map.loadFromWorld(w); });
    }

    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string& worldFile) const override
    {
        const auto& d = dynamic_cast<const CSemanticMap::TMapDefinition&>(definition);
        out.write(prefix + "_creationOpts", "world_file", worldFile);
        d.likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
        d.insertionOpts.saveToConfigFile(out, prefix + "_insertOpts");
    }

    void writeReference(mrpt::config::CConfigFileBase& out,
                        const std::string& prefix) const override
    {
        out.write(prefix + "_creationOpts", "world_file", std::string("maps/paper_50x50.yaml"), 24,
                  24, "world YAML (relative to the cwd, else to the ini)");
        CSemanticMap::TLikelihoodOptions().saveToConfigFile(out, prefix + "_likelihoodOpts");
        CSemanticMap::TInsertionOptions().saveToConfigFile(out, prefix + "_insertOpts");
    }

    /** A detector's coverage that is not a finite range and angle (whatever the maps: the
     *  observation cannot be read). */
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap&) const override
    {
        const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs);
        if (!sem)
        {
            return {};
        }
        if (!std::isfinite(sem->maxRange_m) || sem->maxRange_m < 0)
        {
            return mrpt::format("its maxRange_m %g is not a finite range >= 0", sem->maxRange_m);
        }
        if (!std::isfinite(sem->fov_rad) || sem->fov_rad < 0)
        {
            return mrpt::format("its fov_rad %g is not a finite angle >= 0", sem->fov_rad);
        }
        return {};
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> semanticMapKind()
{
    return std::make_shared<SemanticMapKind>();
}
}  // namespace semloc::detail

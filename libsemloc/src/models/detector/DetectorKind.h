/* semloc — a detector model as a kind of [MetricMap]: filled from the world, its options written
 * back, a depth reading it cannot use refused (private; the kinds' rooms instantiate it). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/SensorModelRegistry.h>
#include <semloc/models/detector/CObjectDetectorMap.h>
#include <semloc/observation/CObservationDepth.h>

#include <string>

#include "models/MapOfClass.h"
#include "models/WorldMapFill.h"

namespace semloc::detail
{
/** Reads a detector map's `_creationOpts` (world_file) and `_likelihoodOpts` sections. */
template <typename Definition>
void loadDetectorDefinition(Definition& d, const mrpt::config::CConfigFileBase& source,
                            const std::string& prefix)
{
    const std::string creation = prefix + "_creationOpts";
    config::rejectUnknownKeys(source, creation, {"world_file"});
    d.world_file = source.read_string(creation, "world_file", d.world_file);
    d.likelihoodOpts.loadFromConfigFile(source, prefix + "_likelihoodOpts");
}

/** The kind of `Map` (a CObjectDetectorMap with a TMapDefinition holding world_file and
 *  likelihoodOpts), named `name` in [MetricMap] and `variant` in a variant. */
template <typename Map>
class DetectorKind final : public SensorModelKind
{
public:
    DetectorKind(std::string name, std::string variant, std::string noun)
        : m_name(std::move(name)), m_variant(std::move(variant)), m_noun(std::move(noun))
    {
    }
    std::string name() const override { return m_name; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override { return CLASS_ID(Map); }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return m_variant; }

    void fill(TFill& f) const override
    {
        const auto& d = dynamic_cast<const typename Map::TMapDefinition&>(f.definition);
        auto& map = dynamic_cast<Map&>(f.map);
        fillWorldMap(f, d.world_file, m_noun.c_str(),
                     [&](const World& w) { map.loadFromWorld(w); });
    }

    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string& worldFile) const override
    {
        const auto& d = dynamic_cast<const typename Map::TMapDefinition&>(definition);
        out.write(prefix + "_creationOpts", "world_file", worldFile);
        d.likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
    }

    void writeReference(mrpt::config::CConfigFileBase& out,
                        const std::string& prefix) const override
    {
        out.write(prefix + "_creationOpts", "world_file", std::string("maps/seabed_200x200.yaml"),
                  24, 24, "world YAML (relative to the cwd, else to the ini; empty: map_file)");
        typename Map::TLikelihoodOptions().saveToConfigFile(out, prefix + "_likelihoodOpts");
    }

    /** A depth reading that is not a depth, where the filter holds a detector map. */
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap& map) const override
    {
        const auto* depth = dynamic_cast<const CObservationDepth*>(&obs);
        if (!depth || !mapOfClass<CObjectDetectorMap>(map))
        {
            return {};
        }
        return depth->problem();
    }

private:
    std::string m_name, m_variant, m_noun;
};
}  // namespace semloc::detail

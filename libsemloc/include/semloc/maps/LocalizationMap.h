/* semloc — the maps a localizer runs on: [MetricMap] of an ini, filled from a map file. */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <semloc/world/World.h>

#include <optional>
#include <string>

namespace semloc
{
/** The CMultiMetricMap of a `[MetricMap]` section (any mix of semanticMap, structureMap,
 *  occupancyGrid and MRPT's other maps: the mix is the variant), its contents loaded from a
 *  map file as MRPT's pf-localization does, plus world YAML files:
 *  - `*.yaml`: a World. Each semanticMap and structureMap without a `world_file` of its own
 *    loads it; each occupancyGrid becomes World::makeOccupancyGrid() at the grid's
 *    `resolution` (its likelihood and insertion options are kept); each beaconMap (MRPT's
 *    CBeaconMap, range-only acoustic beacons) gets the world's `beacons` (a world without
 *    any is an error naming `beaconMap_count` and the world file);
 *  - `*.simplemap[.gz]`: every map is built from the simple map
 *    (CMultiMetricMap::loadFromProbabilisticPosesAndObservations);
 *  - `*.gridmap[.gz]`: the first occupancyGrid is read from it; its options stay those of
 *    the ini (pf-localization takes the file's);
 *  - empty: each map loads its own `world_file` (semanticMap, structureMap).
 *
 *  Strict, unlike MRPT (which ignores what it does not know): a `<name>_count` key whose name
 *  is not a registered map (mrpt::maps::internal::TMetricMapTypesRegistry), any other
 *  unknown key of [MetricMap], a `[MetricMap_<name>_<NN>_...]` section of an unknown map or
 *  of an index beyond its count, a missing map file and a semantic or structure map left
 *  empty are errors that name the section and key or the file. */
class LocalizationMap
{
public:
    /** Reads `[section]` (normally "MetricMap") of `ini` and fills the maps from `mapFile`
     *  (resolved by the caller; may be empty). An error about the ini names its file, the
     *  section and the key once: "ini 'loc.ini': [MetricMap_semanticMap_00_likelihoodOpts]
     *  sigma_range_m: ..." ("ini [...] ..." for an ini that came from no file). */
    static LocalizationMap FromConfig(const mrpt::config::CConfigFileBase& ini,
                                      const std::string& mapFile,
                                      const std::string& section = "MetricMap");
    /** The same with the map file `worldFile`, a world YAML, already loaded as `world` (for a
     *  caller that builds the maps of many configurations on one world). */
    static LocalizationMap FromConfig(const mrpt::config::CConfigFileBase& ini, const World& world,
                                      const std::string& worldFile,
                                      const std::string& section = "MetricMap");

    /** The maps. */
    mrpt::maps::CMultiMetricMap::Ptr map;
    /** The world of a `*.yaml` map file, or of the first semantic/structure map's own
     *  world_file: the free space of the initial cloud and of recovery, and the beacon
     *  maps' beacons. */
    std::optional<World> world;
    /** The map definitions read from the ini, in the order of `map->maps`. */
    mrpt::maps::TSetOfMetricMapInitializers definitions;

    /** The variant name (docs/design.md): "semantic", "geometric", "grid_lf", "grid_rt",
     *  "fused" (semantic + geometric), else the map kinds joined by '+'. */
    std::string variant() const;

    /** The effective `[MetricMap...]` sections as ini text: every key of our maps' options
     *  (defaults included, world_file resolved), the occupancy grids' creation options, and
     *  the other keys of `input`'s map sections (the counts, MRPT's options) as given. */
    std::string effectiveConfig(const mrpt::config::CConfigFileBase& input,
                                const std::string& section = "MetricMap") const;

    /** Checks the names of [section] and of its map sections (see the class doc). */
    static void validateSections(const mrpt::config::CConfigFileBase& ini,
                                 const std::string& section = "MetricMap");

    /** The map's kind as used in `<kind>_count` keys ("semanticMap", "occupancyGrid"...). */
    static std::string kindOf(const mrpt::maps::CMetricMap& m);

private:
    /** FromConfig without the ini's file in its messages, the map file's world already
     *  loaded if `world` is not null. */
    static LocalizationMap build(const mrpt::config::CConfigFileBase& ini,
                                 const std::string& mapFile, const std::string& section,
                                 const World* world);
    /** build() with the ini's file named in a message about the ini. */
    static LocalizationMap buildNamingTheIni(const mrpt::config::CConfigFileBase& ini,
                                             const std::string& mapFile, const std::string& section,
                                             const World* world);

    /** Map file actually used for each semantic/structure map (for the effective ini). */
    std::vector<std::string> m_worldFiles;
};

}  // namespace semloc

/* semloc — LocalizationMap: [MetricMap] strictly, and the map file as pf-localization reads it. */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/TMetricMapTypesRegistry.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>
#include <mrpt/system/string_utils.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/InputFile.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/SensorModelRegistry.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <regex>
#include <set>

#include "io/Text.h"
#include "models/grid/GridCells.h"

namespace semloc
{
using mrpt::maps::COccupancyGridMap2D;

namespace
{
/** Keys of [MetricMap] other than `<name>_count` that MRPT's sample configurations carry
 *  (read by MRPT 1.x, ignored by 2.x). */
const std::vector<std::string> kLegacyKeys = {
    "likelihoodMapSelection",   "enableInsertion_pointsMap",   "enableInsertion_landmarksMap",
    "enableInsertion_gridMaps", "enableInsertion_gasGridMaps", "enableInsertion_beaconMap"};

const std::string kCount = "_count";

std::set<std::string> registeredNames()
{
    std::set<std::string> names;
    for (const auto& [name, functors] :
         mrpt::maps::internal::TMetricMapTypesRegistry::Instance().getAllRegistered())
    {
        names.insert(name);
    }
    return names;
}

/** (alias, index) of each definition, in the order TSetOfMetricMapInitializers creates them:
 *  registry names in order, `<alias>_count` maps each. */
std::vector<std::pair<std::string, unsigned>> definitionAliases(
    const mrpt::config::CConfigFileBase& ini, const std::string& section)
{
    std::vector<std::pair<std::string, unsigned>> out;
    for (const auto& name : registeredNames())
    {
        const auto n = ini.read_uint64_t(section, name + kCount, 0);
        for (unsigned i = 0; i < n; i++)
        {
            out.emplace_back(name, i);
        }
    }
    return out;
}

/** `message` of a map definition that rejected its sections, as "ini [section] key: message":
 *  MRPT's messages name the key (`key='likelihoodMethod'`), not the section; ours name both
 *  already and are kept as they are. */
std::string mapSectionError(const mrpt::config::CConfigFileBase& ini, const std::string& prefix,
                            const std::string& message)
{
    if (message.rfind("ini [", 0) == 0)
    {
        return message;
    }
    std::smatch m;
    if (std::regex_search(message, m, std::regex("key='([^']+)'")))
    {
        std::vector<std::string> sections;
        ini.getAllSections(sections);
        for (const auto& s : sections)
        {
            if (s.rfind(prefix + "_", 0) == 0 && ini.keyExists(s, m[1].str()))
            {
                return "ini [" + s + "] " + shownValue(m[1].str()) + ": " + message;
            }
        }
    }
    return "ini [" + prefix + "_*]: " + message;
}

/** "ini 'FILE': [section] key: ..." for the message "ini [section] key: ..." of an ini that
 *  came from a file; "" for any other (kept as it is). */
std::string namingTheIni(const mrpt::config::CConfigFileBase& ini, const std::string& message)
{
    const std::string file = config::iniFileOf(ini);
    if (file.empty() || message.rfind("ini [", 0) != 0)
    {
        return {};
    }
    return "ini '" + file + "': " + message.substr(4);
}

/** What TSetOfMetricMapInitializers::loadFromConfigFile does, owning each definition from its
 *  creation: MRPT's own loop holds it by a raw pointer while the definition reads its sections,
 *  and loses it when that reading throws (a bad value in a map's section). */
mrpt::maps::TSetOfMetricMapInitializers loadDefinitions(const mrpt::config::CConfigFileBase& ini,
                                                        const std::string& section)
{
    const auto& reg = mrpt::maps::internal::TMetricMapTypesRegistry::Instance();
    mrpt::maps::TSetOfMetricMapInitializers out;
    for (const auto& [name, index] : definitionAliases(ini, section))
    {
        std::unique_ptr<mrpt::maps::TMetricMapInitializer> def(reg.factoryMapDefinition(name));
        ASSERT_(def);
        const std::string prefix = mrpt::format("%s_%s_%02u", section.c_str(), name.c_str(), index);
        try
        {
            def->loadFromConfigFile(ini, prefix);
        }
        catch (const std::exception& e)
        {
            THROW_EXCEPTION(mapSectionError(ini, prefix, errorMessage(e)));
        }
        out.push_back(mrpt::maps::TMetricMapInitializer::Ptr(def.release()));
    }
    return out;
}

/** "mrpt::maps::COccupancyGridMap2D" -> "COccupancyGridMap2D". */
std::string stripNamespace(const std::string& cls)
{
    const auto p = cls.rfind("::");
    return p == std::string::npos ? cls : cls.substr(p + 2);
}

std::string creationSection(const std::string& prefix)
{
    return prefix + "_creationOpts";
}

/** MRPT reads its maps' numbers leniently (NaN and inf would pass): refuses them in `s`. */
void refuseNonFiniteNumbers(const mrpt::config::CConfigFileBase& ini, const std::string& s)
{
    std::vector<std::string> mapKeys;
    ini.getAllKeys(s, mapKeys);
    for (const auto& key : mapKeys)
    {
        const std::string v = detail::trimValue(ini.read_string(s, key, ""));
        char* end = nullptr;
        const double d = v.empty() ? 0 : std::strtod(v.c_str(), &end);
        if (!v.empty() && end == v.c_str() + v.size() && !std::isfinite(d))
        {
            THROW_EXCEPTION(
                mrpt::format("ini [%s] %s: '%s' is not a finite number", shownValue(s).c_str(),
                             shownValue(detail::trimValue(key)).c_str(), shownValue(v).c_str()));
        }
    }
}
}  // namespace

void LocalizationMap::validateSections(const mrpt::config::CConfigFileBase& ini,
                                       const std::string& section)
{
    const auto names = registeredNames();
    std::string known;
    for (const auto& n : names)
    {
        if (n.find("::") == std::string::npos)
        {
            known.append(known.empty() ? "" : ", ").append(n);
        }
    }
    std::vector<std::string> keys;
    ini.getAllKeys(section, keys);
    for (auto key : keys)
    {
        key = detail::trimValue(key);
        if (key.size() > kCount.size() &&
            key.compare(key.size() - kCount.size(), kCount.size(), kCount) == 0)
        {
            const std::string name = key.substr(0, key.size() - kCount.size());
            if (!names.count(name))
            {
                THROW_EXCEPTION(mrpt::format(
                    "ini [%s] %s: unknown map '%s' (MRPT would ignore it silently); known maps: %s",
                    section.c_str(), shownValue(key).c_str(), shownValue(name).c_str(),
                    known.c_str()));
            }
            int n = 0;
            config::readInt(ini, section, key, n, 0, 99);
        }
        else if (std::find(kLegacyKeys.begin(), kLegacyKeys.end(), key) == kLegacyKeys.end())
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s] %s: unknown key (expected <map>_count, e.g. semanticMap_count = 1)",
                section.c_str(), shownValue(key).c_str()));
        }
    }

    // [<section>_<name>_<NN>_<kind>] must belong to a map that is created.
    // What follows "<section>_" (compiled once: compiling is costlier than matching).
    static const std::regex re("^(.+)_([0-9]+)_([A-Za-z0-9]+)$");
    std::vector<std::string> sections;
    ini.getAllSections(sections);
    for (const auto& s : sections)
    {
        if (s.rfind(section + "_", 0) != 0)
        {
            continue;
        }
        refuseNonFiniteNumbers(ini, s);
        const std::string rest = s.substr(section.size() + 1);
        std::smatch m;
        if (!std::regex_match(rest, m, re) || !names.count(m[1].str()))
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s]: unknown section (map sections are [%s_<map>_<NN>_<creationOpts|"
                "likelihoodOpts|insertOpts|...>] with a known map: %s)",
                shownValue(s).c_str(), section.c_str(), known.c_str()));
        }
        const auto count = ini.read_uint64_t(section, m[1].str() + kCount, 0);
        if (static_cast<uint64_t>(std::stoul(m[2].str())) >= count)
        {
            THROW_EXCEPTION(mrpt::format("ini [%s]: section of %s #%s, but [%s] %s%s = %u",
                                         s.c_str(), m[1].str().c_str(), m[2].str().c_str(),
                                         section.c_str(), m[1].str().c_str(), kCount.c_str(),
                                         static_cast<unsigned>(count)));
        }
    }
}

namespace
{
/** Reads `mapFile` (may be empty) by its extension: a world (`.yaml`, `.yml`) into
 *  `lm.world`, a simple map into every map, a grid map into the first occupancy grid. True
 *  for a world. */
bool loadMapFile(LocalizationMap& lm, const std::string& mapFile, const std::string& section,
                 const World* loaded)
{
    const std::string ext =
        mapFile.empty()
            ? ""
            : mrpt::system::lowerCase(mrpt::system::extractFileExtension(mapFile, true));
    if (!mapFile.empty())
    {
        (void)checkInputFile(mapFile, "map_file", InputKind::World);
    }
    const bool fromWorld = ext == "yaml" || ext == "yml";
    if (fromWorld)
    {
        lm.world = loaded ? *loaded : World::FromFile(mapFile);
    }
    else if (ext == "simplemap")
    {
        mrpt::maps::CSimpleMap sm;
        mrpt::io::CFileGZInputStream f(mapFile);
        mrpt::serialization::archiveFrom(f) >> sm;
        if (sm.empty())
        {
            THROW_EXCEPTION("map_file '" + mapFile + "': the simple map is empty");
        }
        lm.map->loadFromProbabilisticPosesAndObservations(sm);
    }
    else if (ext == "gridmap")
    {
        const auto grid = lm.map->mapByClass<COccupancyGridMap2D>();
        if (!grid)
        {
            THROW_EXCEPTION("map_file '" + mapFile + "' is a grid map, but [" + section +
                            "] creates no occupancyGrid");
        }
        COccupancyGridMap2D cells;
        mrpt::io::CFileGZInputStream f(mapFile);
        mrpt::serialization::archiveFrom(f) >> cells;
        detail::replaceGridCells(*grid, cells);
    }
    else if (!mapFile.empty())
    {
        THROW_EXCEPTION("map_file '" + mapFile +
                        "': unknown kind (expected .yaml, .simplemap or .gridmap, optionally .gz)");
    }

    return fromWorld;
}

/** Fills each map of `lm` by its kind (SensorModelKind::fill(), pass 0 in definition order,
 *  then pass 1). Returns the world file each map was filled from ("" for none). */
std::vector<std::string> fillMaps(LocalizationMap& lm,
                                  const std::vector<std::pair<std::string, unsigned>>& aliases,
                                  const std::string& mapFile, const std::string& section,
                                  bool fromWorld)
{
    std::vector<std::string> worldFiles(lm.map->maps.size());
    for (int pass = 0; pass < 2; pass++)
    {
        size_t k = 0;
        for (const auto& def : lm.definitions)
        {
            auto& m = *lm.map->maps[k];
            const auto* kind = SensorModelRegistry::of(m);
            if (kind && kind->fillPass() == pass)
            {
                SensorModelKind::TFill f{
                    m,
                    *def,
                    section + "_" + aliases[k].first + mrpt::format("_%02u", aliases[k].second),
                    "ini [" + section + "] " + aliases[k].first + "_count: ",
                    mapFile,
                    fromWorld,
                    lm.world};
                kind->fill(f);
                worldFiles[k] = f.worldFile;
            }
            k++;
        }
    }
    return worldFiles;
}
}  // namespace

LocalizationMap LocalizationMap::FromConfig(const mrpt::config::CConfigFileBase& ini,
                                            const std::string& mapFile, const std::string& section)
{
    return buildNamingTheIni(ini, mapFile, section, nullptr);
}

LocalizationMap LocalizationMap::FromConfig(const mrpt::config::CConfigFileBase& ini,
                                            const World& world, const std::string& worldFile,
                                            const std::string& section)
{
    const std::string ext =
        mrpt::system::lowerCase(mrpt::system::extractFileExtension(worldFile, true));
    ASSERTMSG_(ext == "yaml" || ext == "yml",
               "LocalizationMap::FromConfig: a loaded world stands for a world YAML file");
    return buildNamingTheIni(ini, worldFile, section, &world);
}

LocalizationMap LocalizationMap::buildNamingTheIni(const mrpt::config::CConfigFileBase& ini,
                                                   const std::string& mapFile,
                                                   const std::string& section, const World* world)
{
    try
    {
        return build(ini, mapFile, section, world);
    }
    catch (const std::exception& e)
    {
        if (const std::string m = namingTheIni(ini, errorMessage(e)); !m.empty())
        {
            THROW_EXCEPTION(m);
        }
        throw;  // not about the ini (a map file, an interrupt): as it is
    }
}

LocalizationMap LocalizationMap::build(const mrpt::config::CConfigFileBase& ini,
                                       const std::string& mapFile, const std::string& section,
                                       const World* world)
{
    validateSections(ini, section);
    LocalizationMap lm;
    lm.definitions = loadDefinitions(ini, section);
    if (lm.definitions.size() == 0)
    {
        THROW_EXCEPTION("ini [" + section +
                        "]: no map (e.g. semanticMap_count = 1, structureMap_count = 1, "
                        "occupancyGrid_count = 1)");
    }
    lm.map = mrpt::maps::CMultiMetricMap::Create();
    lm.map->setListOfMaps(lm.definitions);
    const auto aliases = definitionAliases(ini, section);
    ASSERT_EQUAL_(aliases.size(), lm.map->maps.size());

    const bool fromWorld = loadMapFile(lm, mapFile, section, world);
    lm.m_worldFiles = fillMaps(lm, aliases, mapFile, section, fromWorld);
    return lm;
}

std::string LocalizationMap::kindOf(const mrpt::maps::CMetricMap& m)
{
    const std::string cls = m.GetRuntimeClass()->className;
    const auto& reg = mrpt::maps::internal::TMetricMapTypesRegistry::Instance();
    for (const auto& name : registeredNames())
    {
        if (name.find("::") != std::string::npos || name == stripNamespace(cls))
        {
            continue;
        }
        const std::unique_ptr<mrpt::maps::TMetricMapInitializer> def(
            reg.factoryMapDefinition(name));
        if (def && def->getMetricMapClassType()->className == cls)
        {
            return name;
        }
    }
    return stripNamespace(cls);
}

std::string LocalizationMap::variant() const
{
    std::vector<std::string> kinds;
    for (const auto& m : map->maps)
    {
        const auto* kind = SensorModelRegistry::of(*m);
        kinds.push_back(kind ? kind->variant(*m) : kindOf(*m));
    }
    if (kinds.size() == 2 && std::count(kinds.begin(), kinds.end(), "semantic") == 1 &&
        std::count(kinds.begin(), kinds.end(), "geometric") == 1)
    {
        return "fused";
    }
    std::string v;
    for (const auto& k : kinds)
    {
        v += (v.empty() ? "" : "+") + k;
    }
    return v;
}

std::string LocalizationMap::effectiveConfig(const mrpt::config::CConfigFileBase& input,
                                             const std::string& section) const
{
    // Every key of the options we know, defaults included...
    mrpt::config::CConfigFileMemory ours;
    const auto aliases = definitionAliases(input, section);
    size_t k = 0;
    for (const auto& def : definitions)
    {
        const std::string prefix =
            section + "_" + aliases[k].first + mrpt::format("_%02u", aliases[k].second);
        const std::string sc = creationSection(prefix);
        def->genericMapParams.saveToConfigFile(ours, sc);
        if (const auto* kind = SensorModelRegistry::of(*def))
        {
            kind->writeOptions(*def, ours, prefix, m_worldFiles[k]);
        }
        k++;
    }
    // ...(re-read: MRPT pads the keys it writes), then the input's other keys of the map
    // sections as given: MRPT's map options cannot all be written back.
    mrpt::config::CConfigFileMemory out;
    out.setContent(ours.getContent());
    std::vector<std::string> sections;
    input.getAllSections(sections);
    for (const auto& s : sections)
    {
        if (s != section && s.rfind(section + "_", 0) != 0)
        {
            continue;
        }
        std::vector<std::string> keys;
        input.getAllKeys(s, keys);
        for (auto key : keys)
        {
            key = detail::trimValue(key);
            if (!out.keyExists(s, key))
            {
                out.write(s, key, detail::trimValue(input.read_string(s, key, "")));
            }
        }
    }
    return out.getContent();
}

}  // namespace semloc

/* semloc — Benchmark: which map each variant localizes against, compared with the world the
 * runs are simulated in (map_from_world). */
#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>

#include <filesystem>

#include "io/Text.h"

namespace semloc
{
namespace
{
/** What a map has to agree on with the simulated world: bounds and objects (not the name,
 *  the trajectory or the file's comments). */
std::string contents(World w)
{
    w.name.clear();
    w.source.clear();
    w.trajectory.reset();
    return w.toYamlText();
}

std::string changesText(const TWorldChanges& c)
{
    return mrpt::format("world_shift_sigma_m = %s, world_removed_share = %s, world_added = %d",
                        detail::shortestText(c.shift_sigma_m).c_str(),
                        detail::shortestText(c.removed_share).c_str(), c.added);
}

bool sameFile(const std::string& a, const std::string& b)
{
    std::error_code ec;
    return std::filesystem::equivalent(a, b, ec) && !ec;
}
}  // namespace

bool Benchmark::mapFromWorld() const
{
    return m_scenario.map_from_world.value_or(m_options.map_from_world);
}

void Benchmark::checkMaps()
{
    m_mapWarnings.clear();
    const std::string& worldFile = m_simulation.simulation.world_file;
    const std::string simulated = contents(World::FromFile(worldFile));
    const std::string key = std::string("map_from_world = ") + (mapFromWorld() ? "true" : "false");
    for (const auto& v : m_variants)
    {
        const std::string mapFile =
            std::filesystem::path(v.options.map_file).lexically_normal().string();
        const std::string head =
            "variant '" + v.name() + "' localizes against '" + mapFile + "' (" + key + "), ";
        if (!v.maps.world)
        {
            m_mapWarnings.push_back(head +
                                    "not a world file: it cannot be compared with the "
                                    "simulated world '" +
                                    worldFile + "'");
        }
        else if (m_changedWorld)
        {
            m_mapWarnings.push_back(head + "while the runs are simulated in '" + worldFile +
                                    "' changed by the scenario (" +
                                    changesText(m_scenario.world_changes) + ")");
        }
        else if (contents(*v.maps.world) != simulated)
        {
            m_mapWarnings.push_back(head + "whose objects or bounds differ from those of the " +
                                    "simulated world '" + worldFile + "'");
        }
        else if (!sameFile(mapFile, worldFile))
        {
            m_mapWarnings.push_back(head + "another file than the simulated world '" + worldFile +
                                    "' (with the same bounds and objects)");
        }
    }
}

std::vector<std::string> Benchmark::mapWarnings() const
{
    std::vector<std::string> all = m_mapWarnings;
    for (const auto& sc : m_scenarios)
    {
        for (const auto& w : sc.mapWarnings())
        {
            all.push_back("scenario '" + sc.m_scenario.name + "': " + w);
        }
    }
    return all;
}

}  // namespace semloc

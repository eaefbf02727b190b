/* semloc — filling a map of the world's objects (the semantic and structure kinds; private). */
#pragma once

#include <mrpt/core/exceptions.h>
#include <semloc/models/SensorModelRegistry.h>

#include <string>

namespace semloc::detail
{
/** Fills `f.map`, a map of the world's objects named `noun` ("semantic"), with `load(world)`
 *  from the map file's world, unless its definition names its own `worldFile` (which the
 *  definition has read, and whose world then becomes the filter's when it has none). A map
 *  left empty is an error naming the map file, or the map's world_file key. */
template <typename Load>
void fillWorldMap(SensorModelKind::TFill& f, const std::string& worldFile, const char* noun,
                  const Load& load)
{
    const std::string creation = f.prefix + "_creationOpts";
    f.worldFile = worldFile;
    if (worldFile.empty() && f.world)
    {
        load(*f.world);
        f.worldFile = f.mapFile;
    }
    if (!f.world && !worldFile.empty())
    {
        f.world = World::FromFile(worldFile);
    }
    if (f.map.isEmpty() && worldFile.empty() && !f.mapFile.empty())
    {
        THROW_EXCEPTION("map_file '" + f.mapFile + "': the world holds no object for the " + noun +
                        " map of [" + creation + "]");
    }
    if (f.map.isEmpty())
    {
        THROW_EXCEPTION("ini [" + creation + "] world_file: the " + noun +
                        " map is empty (set world_file, or a world YAML as map_file)");
    }
}
}  // namespace semloc::detail

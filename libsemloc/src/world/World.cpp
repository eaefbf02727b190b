/* semloc — World: the names of shapes and the lookup of objects by id. Reading and writing
 * world files, the geometry and the rasters are in WorldReader.cpp, WorldWriter.cpp,
 * WorldGeometry.cpp, WorldFreeRaster.cpp and WorldOccupancyGrid.cpp. */
#include <semloc/world/World.h>

namespace semloc
{
const char* shapeName(ShapeType s)
{
    switch (s)
    {
        case ShapeType::Box:
            return "box";
        case ShapeType::Cylinder:
            return "cylinder";
        case ShapeType::Polygon:
            return "polygon";
        case ShapeType::Point:
            return "point";
    }
    return "?";
}

int World::indexOfId(int id) const
{
    for (size_t i = 0; i < objects.size(); i++)
    {
        if (objects[i].id == id)
        {
            return static_cast<int>(i);
        }
    }
    return -1;
}

}  // namespace semloc

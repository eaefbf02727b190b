/* semloc — World: the names of shapes, the lookup of objects by id and the check of a class
 * distribution. Reading and writing
 * world files, the geometry and the rasters are in WorldReader.cpp, WorldWriter.cpp,
 * WorldGeometry.cpp, WorldFreeRaster.cpp and WorldOccupancyGrid.cpp. */
#include <mrpt/core/format.h>
#include <semloc/observation/Labels.h>
#include <semloc/world/World.h>

#include <cmath>

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

std::string classesProblem(const std::vector<std::pair<std::string, double>>& classes,
                           const std::string& label)
{
    if (classes.empty())
    {
        return "";
    }
    double sum = 0;
    bool own = false;
    for (size_t i = 0; i < classes.size(); i++)
    {
        const auto& [name, p] = classes[i];
        if (std::string problem = labelProblem(name); !problem.empty())
        {
            return problem.insert(0, "label '" + name + "': ");
        }
        if (i > 0 && !(classes[i - 1].first < name))
        {
            return "label '" + name + "' listed twice or out of order";
        }
        if (!(p > 0 && p <= 1))
        {
            return "probability of '" + name + "' must be in (0, 1]";
        }
        sum += p;
        own = own || name == label;
    }
    if (std::abs(sum - 1) > 1e-6)
    {
        return mrpt::format("the probabilities sum to %.9g, not 1", sum);
    }
    if (!own)
    {
        return "must include the object's label '" + label + "'";
    }
    return "";
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

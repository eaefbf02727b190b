/* semloc — MRPT's occupancy grid as a kind of [MetricMap] (occupancyGrid_count): rasterized
 * from a world map file, named by its likelihood method. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <semloc/io/ErrorMessage.h>

#include "models/BuiltinKinds.h"
#include "models/MapOfClass.h"
#include "models/grid/GridCells.h"

namespace semloc::detail
{
namespace
{
using mrpt::maps::COccupancyGridMap2D;

std::string gridMethodName(const COccupancyGridMap2D& g)
{
    switch (g.likelihoodOptions.likelihoodMethod)
    {
        case COccupancyGridMap2D::lmMeanInformation:
            return "grid_mi";
        case COccupancyGridMap2D::lmRayTracing:
            return "grid_rt";
        case COccupancyGridMap2D::lmConsensus:
            return "grid_consensus";
        case COccupancyGridMap2D::lmCellsDifference:
            return "grid_cells";
        case COccupancyGridMap2D::lmLikelihoodField_Thrun:
            return "grid_lf";
        case COccupancyGridMap2D::lmLikelihoodField_II:
            return "grid_lf2";
        case COccupancyGridMap2D::lmConsensusOWA:
            return "grid_owa";
    }
    return "grid";
}

/** A float as text that reads back as the same float. */
std::string floatText(float v)
{
    return mrpt::format("%.9g", static_cast<double>(v));
}

bool holdsGrid(const mrpt::maps::CMetricMap& map)
{
    return mapOfClass<COccupancyGridMap2D>(map) != nullptr;
}

class OccupancyGridKind final : public SensorModelKind
{
public:
    std::string name() const override { return "occupancyGrid"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override
    {
        return CLASS_ID(COccupancyGridMap2D);
    }
    std::string variant(const mrpt::maps::CMetricMap& map) const override
    {
        return gridMethodName(dynamic_cast<const COccupancyGridMap2D&>(map));
    }

    /** With a world YAML as map file: World::makeOccupancyGrid() at the grid's resolution
     *  (its likelihood and insertion options kept). */
    void fill(TFill& f) const override
    {
        if (!f.mapFileIsWorld)
        {
            return;
        }
        const auto& d = dynamic_cast<const COccupancyGridMap2D::TMapDefinition&>(f.definition);
        COccupancyGridMap2D cells;
        try
        {
            cells = f.world->makeOccupancyGrid(d.resolution);
        }
        catch (const std::exception& e)
        {
            THROW_EXCEPTION("ini [" + f.prefix + "_creationOpts] resolution: " + errorMessage(e));
        }
        replaceGridCells(dynamic_cast<COccupancyGridMap2D&>(f.map), cells);
    }

    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string&) const override
    {
        const auto& d = dynamic_cast<const COccupancyGridMap2D::TMapDefinition&>(definition);
        const std::string sc = prefix + "_creationOpts";
        out.write(sc, "min_x", floatText(d.min_x));
        out.write(sc, "max_x", floatText(d.max_x));
        out.write(sc, "min_y", floatText(d.min_y));
        out.write(sc, "max_y", floatText(d.max_y));
        out.write(sc, "resolution", floatText(d.resolution));
    }

    /** A one-beam scan where `map` holds a grid: MRPT scores a scan with at least 2. */
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap& map) const override
    {
        const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs);
        if (scan && scan->getScanSize() == 1 && holdsGrid(map))
        {
            return "it has 1 beam; MRPT's occupancy grid ([MetricMap] occupancyGrid) needs at "
                   "least 2";
        }
        return {};
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> occupancyGridKind()
{
    return std::make_shared<OccupancyGridKind>();
}
}  // namespace semloc::detail

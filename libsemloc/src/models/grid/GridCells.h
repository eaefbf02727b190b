/* semloc — an occupancy grid's cells replaced from elsewhere (private). */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

namespace semloc::detail
{
/** Replaces a grid's cells by `cells`, keeping the options the ini gave it. */
inline void replaceGridCells(mrpt::maps::COccupancyGridMap2D& grid,
                             const mrpt::maps::COccupancyGridMap2D& cells)
{
    const auto insertion = grid.insertionOptions;
    const auto likelihood = grid.likelihoodOptions;
    const auto generic = grid.genericMapParams;
    grid = cells;
    grid.insertionOptions = insertion;
    grid.likelihoodOptions = likelihood;
    grid.genericMapParams = generic;
}
}  // namespace semloc::detail

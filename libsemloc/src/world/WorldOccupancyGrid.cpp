/* semloc — a world rendered as MRPT's occupancy grid (the grid_lf and grid_rt variants,
 * docs/design.md, "Large worlds"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "world/ObjectShape.h"

namespace semloc
{
using mrpt::math::TPoint2D;

namespace
{
/** Cells are tested slightly inflated: MRPT maps coordinates to cells in float, so a point
 *  within ~1e-5 m of a cell border may land in either neighbour. */
constexpr double kInflate_m = 5e-5;
/** An edge farther than this [m] above or below a row of cells (inflated) cannot touch them,
 *  whatever the rounding of the touch test (its error is ~1e-9 m at 1e7 m coordinates). */
constexpr double kRowMargin_m = 1e-6;

/** Throws, naming the bounds and the resolution and suggesting one that fits, if a grid over
 *  the world's bounds at `resolution_m` would have more than kMaxOccupancyGridCells cells. */
void checkGridCells(const World& world, double resolution_m)
{
    const auto& bounds = world.bounds;
    const double w = bounds.x_max - bounds.x_min, h = bounds.y_max - bounds.y_min;
    const double cells = (std::ceil(w / resolution_m) + 1) * (std::ceil(h / resolution_m) + 1);
    const auto maxCells = static_cast<double>(kMaxOccupancyGridCells);
    if (!(cells <= maxCells))
    {
        // The resolution r at which (w / r + 1) (h / r + 1) = maxCells, a little coarser.
        const double a = w * h, bq = w + h, c = 1 - maxCells;
        const double u = (-bq + std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
        THROW_EXCEPTION(mrpt::format(
            "world '%s': an occupancy grid over its bounds x [%g, %g], y [%g, %g] at "
            "resolution %g m would have %.3g cells, more than the %zu allowed: use a "
            "resolution of %.3g m or coarser",
            (world.source.empty() ? world.name : world.source).c_str(), bounds.x_min, bounds.x_max,
            bounds.y_min, bounds.y_max, resolution_m, cells, kMaxOccupancyGridCells, 1.001 / u));
    }
}

/** Marks occupied (0) the cells of `grid` whose centre is inside `o` or that an edge of its
 *  outline `poly` touches, within the box of its extent and its outline. */
void markObject(mrpt::maps::COccupancyGridMap2D& grid, const WorldObject& o,
                const std::vector<TPoint2D>& poly)
{
    const double gx0 = grid.getXMin(), gy0 = grid.getYMin(), res = grid.getResolution();
    const int nx = static_cast<int>(grid.getSizeX()), ny = static_cast<int>(grid.getSizeY());
    auto clampIdx = [](double v, int n)
    { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
    double xmin = o.center.x - o.extent_m, xmax = o.center.x + o.extent_m;
    double ymin = o.center.y - o.extent_m, ymax = o.center.y + o.extent_m;
    for (const auto& p : poly)
    {
        xmin = std::min(xmin, p.x);
        xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
    }
    const int ix0 = clampIdx((xmin - kInflate_m - gx0) / res, nx);
    const int ix1 = clampIdx((xmax + kInflate_m - gx0) / res, nx);
    const int iy0 = clampIdx((ymin - kInflate_m - gy0) / res, ny);
    const int iy1 = clampIdx((ymax + kInflate_m - gy0) / res, ny);
    std::vector<size_t> rowEdges;  // the edges that may touch a cell of the row
    for (int iy = iy0; iy <= iy1; iy++)
    {
        const double cy0 = gy0 + iy * res;
        rowEdges.clear();
        for (size_t i = 0; i < poly.size(); i++)
        {
            const double ya = poly[i].y, yb = poly[(i + 1) % poly.size()].y;
            if (std::max(ya, yb) >= cy0 - kInflate_m - kRowMargin_m &&
                std::min(ya, yb) <= cy0 + res + kInflate_m + kRowMargin_m)
            {
                rowEdges.push_back(i);
            }
        }
        for (int ix = ix0; ix <= ix1; ix++)
        {
            const double cx0 = gx0 + ix * res;
            bool occupied = detail::insideObject(o, TPoint2D(cx0 + 0.5 * res, cy0 + 0.5 * res));
            for (size_t j = 0; !occupied && j < rowEdges.size(); j++)
            {
                const auto& a = poly[rowEdges[j]];
                const auto& b = poly[(rowEdges[j] + 1) % poly.size()];
                occupied = detail::segmentTouchesBox(a.x, a.y, b.x, b.y, cx0 - kInflate_m,
                                                     cy0 - kInflate_m, cx0 + res + kInflate_m,
                                                     cy0 + res + kInflate_m);
            }
            if (occupied)
            {
                grid.setCell(ix, iy, 0.0f);
            }
        }
    }
}
}  // namespace

mrpt::maps::COccupancyGridMap2D World::makeOccupancyGrid(double resolution_m) const
{
    ASSERTMSG_(resolution_m > 0 && std::isfinite(resolution_m),
               "World::makeOccupancyGrid: resolution must be a finite number > 0");
    checkGridCells(*this, resolution_m);
    mrpt::maps::COccupancyGridMap2D grid;
    grid.setSize(static_cast<float>(bounds.x_min), static_cast<float>(bounds.x_max),
                 static_cast<float>(bounds.y_min), static_cast<float>(bounds.y_max),
                 static_cast<float>(resolution_m), 1.0f);
    for (const auto& o : objects)
    {
        const auto poly = outlinePolygon(o);
        if (poly.empty())
        {
            continue;
        }
        markObject(grid, o, poly);
    }
    return grid;
}

}  // namespace semloc

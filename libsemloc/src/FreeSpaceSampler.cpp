/* semloc — FreeSpaceSampler: uniform poses over a world's, a grid's or a box's free space. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/FreeSpaceSampler.h>

#include <algorithm>
#include <cmath>

namespace semloc
{
namespace
{
constexpr int kMaxDraws = 100000;
/** Cell of the rasterized world that answers contains() before the exact test [m]. */
constexpr double kWorldCell_m = 0.1;

bool fullCircle(const TSamplingArea& a)
{
    return a.yaw_min == -M_PI && a.yaw_max == M_PI;
}
}  // namespace

FreeSpaceSampler FreeSpaceSampler::FromWorld(const World& world, const TSamplingArea& area)
{
    FreeSpaceSampler s;
    s.m_kind = Kind::World;
    s.m_world = std::make_shared<const World>(world);
    s.m_bounds = world.bounds;
    s.m_area = area;
    const auto& b = world.bounds;
    if (area.hasBox())
    {
        s.m_area.x_min = std::max(area.x_min, b.x_min);
        s.m_area.x_max = std::min(area.x_max, b.x_max);
        s.m_area.y_min = std::max(area.y_min, b.y_min);
        s.m_area.y_max = std::min(area.y_max, b.y_max);
        if (!s.m_area.hasBox())
        {
            THROW_EXCEPTION(mrpt::format(
                "the box x [%g, %g], y [%g, %g] does not overlap the bounds of world '%s'",
                area.x_min, area.x_max, area.y_min, area.y_max, world.name.c_str()));
        }
    }
    s.m_description =
        "free space of world '" + world.name + "'" + (area.hasBox() ? " in a box" : "");
    s.m_raster = FreeRaster(world.makeOccupancyGrid(kWorldCell_m), 0.5);
    return s;
}

FreeSpaceSampler FreeSpaceSampler::FromGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                            const TSamplingArea& area, double freeThreshold)
{
    FreeSpaceSampler s;
    s.m_kind = Kind::Grid;
    s.m_area = area;
    s.m_resolution = grid.getResolution();
    // The cell scan of CMonteCarloLocalization2D::resetUniformFreeSpace (same order).
    const int sizeX = static_cast<int>(grid.getSizeX()), sizeY = static_cast<int>(grid.getSizeY());
    const bool box = area.hasBox();
    const int x1 = (box && area.x_min > grid.getXMin()) ? std::max(0, grid.x2idx(area.x_min)) : 0;
    const int x2 = (box && area.x_max < grid.getXMax())
                       ? std::min(sizeX - 1, grid.x2idx(area.x_max))
                       : sizeX - 1;
    const int y1 = (box && area.y_min > grid.getYMin()) ? std::max(0, grid.y2idx(area.y_min)) : 0;
    const int y2 = (box && area.y_max < grid.getYMax())
                       ? std::min(sizeY - 1, grid.y2idx(area.y_max))
                       : sizeY - 1;
    for (int x = x1; x <= x2; x++)
    {
        for (int y = y1; y <= y2; y++)
        {
            if (grid.getCell(x, y) >= freeThreshold)
            {
                s.m_cellX.push_back(grid.idx2x(x));
                s.m_cellY.push_back(grid.idx2y(y));
            }
        }
    }
    if (s.m_cellX.empty())
    {
        THROW_EXCEPTION("the occupancy grid has no free cell (free probability >= " +
                        mrpt::format("%g", freeThreshold) + ")" + (box ? " in the box" : ""));
    }
    s.m_description = mrpt::format("%zu free cells of the occupancy grid", s.m_cellX.size());
    s.m_raster = FreeRaster(grid, freeThreshold);
    return s;
}

FreeSpaceSampler FreeSpaceSampler::FromBox(const TSamplingArea& area)
{
    if (!area.hasBox())
    {
        THROW_EXCEPTION(mrpt::format("empty box x [%g, %g], y [%g, %g]", area.x_min, area.x_max,
                                     area.y_min, area.y_max));
    }
    FreeSpaceSampler s;
    s.m_kind = Kind::Box;
    s.m_area = area;
    s.m_description =
        mrpt::format("box x [%g, %g] y [%g, %g]", area.x_min, area.x_max, area.y_min, area.y_max);
    return s;
}

FreeSpaceSampler::FreeRaster::FreeRaster(const mrpt::maps::COccupancyGridMap2D& grid,
                                         double freeThreshold)
    : sizeX(static_cast<int>(grid.getSizeX())),
      sizeY(static_cast<int>(grid.getSizeY())),
      x0(grid.getXMin()),
      y0(grid.getYMin()),
      resolution(grid.getResolution())
{
    free.resize(static_cast<size_t>(sizeX) * static_cast<size_t>(sizeY));
    for (int cy = 0; cy < sizeY; cy++)
    {
        for (int cx = 0; cx < sizeX; cx++)
        {
            free[static_cast<size_t>(cx) + static_cast<size_t>(cy) * static_cast<size_t>(sizeX)] =
                grid.getCell(cx, cy) >= freeThreshold ? 1 : 0;
        }
    }
}

bool FreeSpaceSampler::worldIsFree(double x, double y) const
{
    return m_world->isFree(x, y);
}

mrpt::math::TPose2D FreeSpaceSampler::draw(mrpt::random::CRandomGenerator& rng) const
{
    const TSamplingArea& a = m_area;
    switch (m_kind)
    {
        case Kind::Box:
        {
            // CPosePDFParticles::resetUniform's order: x, y, phi.
            const double x = rng.drawUniform(a.x_min, a.x_max);
            const double y = rng.drawUniform(a.y_min, a.y_max);
            return {x, y, rng.drawUniform(a.yaw_min, a.yaw_max)};
        }
        case Kind::Grid:
        {
            const double n = static_cast<double>(m_cellX.size());
            const auto idx = static_cast<size_t>(std::lround(rng.drawUniform(0.0, n - 1.001)));
            const double x = m_cellX[idx] + rng.drawUniform(-m_resolution, m_resolution);
            const double y = m_cellY[idx] + rng.drawUniform(-m_resolution, m_resolution);
            return {x, y, rng.drawUniform(a.yaw_min, a.yaw_max)};
        }
        case Kind::World:
        {
            if (!a.hasBox() && fullCircle(a))
            {
                return m_world->sampleFreePose(rng);
            }
            const auto& b = m_world->bounds;
            const double x0 = a.hasBox() ? a.x_min : b.x_min, x1 = a.hasBox() ? a.x_max : b.x_max;
            const double y0 = a.hasBox() ? a.y_min : b.y_min, y1 = a.hasBox() ? a.y_max : b.y_max;
            for (int i = 0; i < kMaxDraws; i++)
            {
                const double x = rng.drawUniform(x0, x1);
                const double y = rng.drawUniform(y0, y1);
                if (m_world->isFree(x, y))
                {
                    return {x, y, rng.drawUniform(a.yaw_min, a.yaw_max)};
                }
            }
            THROW_EXCEPTION(mrpt::format("no free space in %s: none of %d draws was free",
                                         m_description.c_str(), kMaxDraws));
        }
    }
    return {};
}

}  // namespace semloc

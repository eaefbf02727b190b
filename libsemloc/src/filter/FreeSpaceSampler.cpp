/* semloc — FreeSpaceSampler: uniform poses over a world's, a grid's or a box's free space. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/FreeSpaceSampler.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "math/FastMath.h"

namespace semloc
{
namespace
{
constexpr int kMaxDraws = 100000;
/** Finest cell of the rasterized world that answers contains() before the exact test [m];
 *  doubled until the raster has at most FreeSpaceSampler::kMaxWorldRasterCells cells. */
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
    // The raster covers the bounds from (x_min, y_min); points outside it, or in a cell an
    // object may touch, get the exact test.
    double cell = kWorldCell_m;
    const double w = b.x_max - b.x_min, h = b.y_max - b.y_min;
    auto cellsAlong = [&](double len) { return std::max(1.0, std::ceil(len / cell)); };
    while (cellsAlong(w) * cellsAlong(h) > static_cast<double>(kMaxWorldRasterCells))
    {
        cell *= 2;
    }
    FreeRaster& r = s.m_raster;
    r.sizeX = static_cast<int>(cellsAlong(w));
    r.sizeY = static_cast<int>(cellsAlong(h));
    r.x0 = b.x_min;
    r.y0 = b.y_min;
    r.resolution = cell;
    r.free = world.freeRaster(r.x0, r.y0, cell, static_cast<size_t>(r.sizeX),
                              static_cast<size_t>(r.sizeY));
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

/** contains() of one sampler with its fields in a value of its own: the loops of
 *  excludeOutside() keep them in registers (stores to the likelihoods cannot alias them).
 *  Coordinates go in pairs (x, y) through packed compares and one packed division, the
 *  same IEEE operations as one coordinate at a time: the same decisions, bit for bit. */
struct FreeSpaceSampler::Region
{
    /** The box (Box) or the world's bounds (World). */
    detail::Vec2 lo{}, hi{};
    /** The raster's origin, resolution and size in cells. */
    detail::Vec2 origin{}, size{};
    double resolution = 1;
    const uint8_t* free = nullptr;
    size_t stride = 0;
    const World* world = nullptr;

    /** What the box and the raster say of a point. */
    enum class Verdict
    {
        Inside,
        Outside,
        /** World: inside the bounds, in a cell an outline touches: World::isFree decides. */
        Exact
    };

    /** Lanes of xy inside [lo, hi]. */
    int inBox(const detail::Vec2& xy) const
    {
        return detail::lessEqualBits(lo, xy) & detail::lessEqualBits(xy, hi);
    }

    /** A free raster cell, if the lanes `also` are both set too. int(q) is in [0, size)
     *  exactly when q is in (-1, size): no out-of-range cast. */
    bool rasterFree(const detail::Vec2& xy, int also) const
    {
        const detail::Vec2 q = (xy - origin) / resolution;
        const int inRaster = detail::lessBits(detail::Vec2{-1, -1}, q) & detail::lessBits(q, size);
        return (also & inRaster) == detail::kBothLanes &&
               free[static_cast<size_t>(static_cast<int>(q[0])) +
                    static_cast<size_t>(static_cast<int>(q[1])) * stride] != 0;
    }

    template <Kind K>
    Verdict verdict(double x, double y) const
    {
        const detail::Vec2 xy{x, y};
        bool inside = false;
        if constexpr (K == Kind::Box)
        {
            inside = inBox(xy) == detail::kBothLanes;
        }
        else if constexpr (K == Kind::Grid)
        {
            inside = rasterFree(xy, detail::lessEqualBits(origin, xy));
        }
        else
        {
            // A free raster cell: no outline touches it and its centre is free.
            const int inBounds = inBox(xy);
            if (!rasterFree(xy, inBounds))
            {
                return inBounds == detail::kBothLanes ? Verdict::Exact : Verdict::Outside;
            }
            inside = true;
        }
        return inside ? Verdict::Inside : Verdict::Outside;
    }

    template <Kind K>
    bool contains(double x, double y) const
    {
        const Verdict v = verdict<K>(x, y);
        return v == Verdict::Inside || (v == Verdict::Exact && world->isFree(x, y));
    }

    template <Kind K>
    size_t excludeOutside(const mrpt::math::TPose2D* poses, size_t n, double* logLik) const
    {
        constexpr double kNegInf = -std::numeric_limits<double>::infinity();
        // Blocks: the exact tests (calls) after each block's loop, so that the loop keeps
        // the region in registers.
        constexpr size_t kBlock = 64;
        size_t outside = 0;
        for (size_t b = 0; b < n; b += kBlock)
        {
            const size_t e = std::min(n, b + kBlock);
            std::array<uint32_t, kBlock> exact;
            size_t nExact = 0;
            for (size_t i = b; i < e; i++)
            {
                if (logLik[i] == kNegInf)
                {
                    continue;
                }
                const Verdict v = verdict<K>(poses[i].x, poses[i].y);
                if (v == Verdict::Outside)
                {
                    logLik[i] = kNegInf;
                    outside++;
                }
                else if (v == Verdict::Exact)
                {
                    exact[nExact++] = static_cast<uint32_t>(i - b);
                }
            }
            for (size_t k = 0; k < nExact; k++)
            {
                const size_t i = b + exact[k];
                if (!world->isFree(poses[i].x, poses[i].y))
                {
                    logLik[i] = kNegInf;
                    outside++;
                }
            }
        }
        return outside;
    }
};

FreeSpaceSampler::Region FreeSpaceSampler::region() const
{
    Region r;
    if (m_kind == Kind::Box)
    {
        r.lo = detail::Vec2{m_area.x_min, m_area.y_min};
        r.hi = detail::Vec2{m_area.x_max, m_area.y_max};
    }
    else if (m_kind == Kind::World)
    {
        r.lo = detail::Vec2{m_bounds.x_min, m_bounds.y_min};
        r.hi = detail::Vec2{m_bounds.x_max, m_bounds.y_max};
        r.world = m_world.get();
    }
    r.origin = detail::Vec2{m_raster.x0, m_raster.y0};
    r.size = detail::Vec2{static_cast<double>(m_raster.sizeX), static_cast<double>(m_raster.sizeY)};
    r.resolution = m_raster.resolution;
    r.free = m_raster.free.data();
    r.stride = static_cast<size_t>(m_raster.sizeX);
    return r;
}

bool FreeSpaceSampler::contains(double x, double y) const
{
    const Region r = region();
    switch (m_kind)
    {
        case Kind::Box:
            return r.contains<Kind::Box>(x, y);
        case Kind::Grid:
            return r.contains<Kind::Grid>(x, y);
        case Kind::World:
            return r.contains<Kind::World>(x, y);
    }
    return false;
}

size_t FreeSpaceSampler::excludeOutside(const mrpt::math::TPose2D* poses, size_t n,
                                        double* logLik) const
{
    const Region r = region();
    switch (m_kind)
    {
        case Kind::Box:
            return r.excludeOutside<Kind::Box>(poses, n, logLik);
        case Kind::Grid:
            return r.excludeOutside<Kind::Grid>(poses, n, logLik);
        case Kind::World:
            return r.excludeOutside<Kind::World>(poses, n, logLik);
    }
    return 0;
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

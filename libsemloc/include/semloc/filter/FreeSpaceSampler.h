/* semloc — random vehicle poses uniform over the free space: initial clouds and recovery. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/world/World.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace mrpt::maps
{
class COccupancyGridMap2D;
}
namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** Where a FreeSpaceSampler draws: an axis-aligned box [m] and a heading interval [rad]. */
struct TSamplingArea
{
    /** Box min x [m]. */
    double x_min = 0;
    /** Box max x [m]. */
    double x_max = 0;
    /** Box min y [m]. */
    double y_min = 0;
    /** Box max y [m]. */
    double y_max = 0;
    /** Heading interval min [rad]. */
    double yaw_min = -M_PI;
    /** Heading interval max [rad]. */
    double yaw_max = M_PI;
    /** False for an empty box (x_min >= x_max or y_min >= y_max): "no restriction". */
    bool hasBox() const { return x_min < x_max && y_min < y_max; }
};

/** Draws poses uniformly over the area a vehicle may occupy, with a heading uniform in
 *  [yaw_min, yaw_max), from one of three descriptions of that area:
 *  - a World: inside its bounds and outside every outline (World::isFree), optionally
 *    restricted to a box (World::sampleFreePose when there is no box and the full circle);
 *  - an occupancy grid: its cells with a free probability >= 0.7 within an optional box,
 *    drawn exactly as MRPT's CMonteCarloLocalization2D::resetUniformFreeSpace does;
 *  - a box: uniform in it (CPosePDFParticles::resetUniform).
 *  Deterministic for a given generator state. */
class FreeSpaceSampler
{
public:
    /** The free space of `world`, within `area`'s box if it has one. */
    static FreeSpaceSampler FromWorld(const World& world, const TSamplingArea& area = {});
    /** The free cells (>= `freeThreshold`, 0.7f as pf-localization passes it) of `grid`,
     *  within `area`'s box if it has one.
     *  Throws if there is none. */
    static FreeSpaceSampler FromGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                     const TSamplingArea& area = {}, double freeThreshold = 0.7f);
    /** Uniform in `area`'s box, which must not be empty. */
    static FreeSpaceSampler FromBox(const TSamplingArea& area);

    /** One pose. */
    mrpt::math::TPose2D draw(mrpt::random::CRandomGenerator& rng) const;
    /** True if a vehicle may be at (x, y): World::isFree (exactly; a raster of at most
     *  kMaxWorldRasterCells answers first for the cells no object touches), a free grid
     *  cell, or inside the box. The box of FromWorld()/FromGrid() restricts draw() only.
     *  Safe from many threads. */
    bool contains(double x, double y) const;
    /** The free-space prior of n poses: each logLik[i] that is not -inf already becomes -inf
     *  if poses[i] is outside (not contains()); returns how many did. The filter calls it
     *  once per range of particles: one dispatch on the kind per call, not per pose. Safe
     *  from many threads. */
    size_t excludeOutside(const mrpt::math::TPose2D* poses, size_t n, double* logLik) const;
    /** A short description for logs ("free space of world 'paper_50x50'", ...). */
    const std::string& description() const { return m_description; }
    /** Bytes of the raster that answers contains() first (0 for a box). */
    size_t rasterBytes() const { return m_raster.free.size(); }

    /** Most cells of a world's raster (one byte each): its cell, 0.1 m on small worlds, is
     *  doubled until the bounds fit, so memory stays within 16 MiB whatever the area (a
     *  20 x 20 km world gets 6.4 m cells); the exact test answers for the cells an object
     *  may touch. */
    static constexpr size_t kMaxWorldRasterCells = size_t{1} << 24;

private:
    enum class Kind
    {
        World,
        Grid,
        Box
    };
    /** The fields contains() reads, copied into one value (FreeSpaceSampler.cpp). */
    struct Region;
    Region region() const;

    Kind m_kind = Kind::Box;
    TSamplingArea m_area;
    std::shared_ptr<const World> m_world;
    /** m_world's bounds (World: contains() reads them without the indirection). */
    WorldBounds m_bounds;
    /** Free cells as a byte raster (1 = free), row-major from (x0, y0). World: the cells
     *  no object touches (World::freeRaster) over the bounds; Grid: the grid's cells, what
     *  COccupancyGridMap2D::getCell(x2idx(x), y2idx(y)) >= threshold answers, without the
     *  log-odds lookup. */
    struct FreeRaster
    {
        std::vector<uint8_t> free;
        int sizeX = 0, sizeY = 0;
        /** Origin and cell side (Grid: the grid's float values, widened as x2idx(double)
         *  does). */
        double x0 = 0, y0 = 0, resolution = 1;
        FreeRaster() = default;
        FreeRaster(const mrpt::maps::COccupancyGridMap2D& grid, double freeThreshold);
    };
    FreeRaster m_raster;
    std::vector<double> m_cellX, m_cellY;
    double m_resolution = 0;
    std::string m_description;
};

}  // namespace semloc

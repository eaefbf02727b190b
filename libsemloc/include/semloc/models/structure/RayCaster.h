/* semloc — exact 2D ray casting against line segments. */
#pragma once

#include <mrpt/math/TSegment2D.h>

#include <cstdint>
#include <vector>

namespace semloc
{
/** Exact ray casting against a fixed set of 2D segments (the sonar's expected range).
 *
 *  A ray from (x, y) with direction angle `a` hits segment [p, q] at the smallest t >= 0
 *  with (x, y) + t (cos a, sin a) on [p, q]; a ray collinear with a segment hits it at its
 *  nearest point (t = 0 if the origin lies on it). The answer is analytic, not sampled.
 *
 *  **Nothing hit**: every cast returns `maxRange` when no segment is hit at t <= maxRange
 *  (a hit exactly at maxRange also returns maxRange), so callers test `r >= maxRange`.
 *
 *  **Acceleration**: the segments are bucketed in a uniform grid (a segment goes to every
 *  cell it touches, cells inflated by 1e-6 m), walked along the ray by the DDA of
 *  Amanatides & Woo (1987), "A fast voxel traversal algorithm for ray tracing". All
 *  segments of each visited cell are tested with the same predicate castBruteForce uses,
 *  and the walk stops once the nearest hit is not beyond the current cell's exit
 *  distance: any nearer hit lies in a cell already visited, so cast() and castBruteForce()
 *  return the same double (also for rays along edges and through vertices or grid
 *  corners).
 *
 *  Const methods allocate nothing, make no virtual calls, and are safe to call from many
 *  threads at once. */
class RayCaster
{
public:
    /** An empty caster: every cast returns maxRange. */
    RayCaster() = default;
    /** Builds the grid over `segments`; `cellSize_m` <= 0 picks it automatically. */
    explicit RayCaster(const std::vector<mrpt::math::TSegment2D>& segments, double cellSize_m = 0);

    /** Replaces the segments and rebuilds the grid; `cellSize_m` <= 0 picks it
     *  automatically (half the side of the square holding one segment on average over the
     *  segments' bounding box, clamped to [0.25, 8] m; the cell is doubled until the grid
     *  has at most 2^20 cells, and at most 4096 along its width plus height).
     *  Degenerate (zero-length) segments are kept as points. */
    void setSegments(const std::vector<mrpt::math::TSegment2D>& segments, double cellSize_m = 0);

    /** Distance [m] to the first segment hit from (x, y) along angle `angle` [rad], or
     *  `maxRange` if none within it. */
    double cast(double x, double y, double angle, double maxRange) const;

    /** As cast(x, y, angle, maxRange) with the unit direction (dx, dy) given, for callers
     *  that step directions incrementally; |(dx, dy)| must be 1. */
    double castDir(double x, double y, double dx, double dy, double maxRange) const;

    /** Reference result: tests every segment, no grid. Same conventions as cast(). */
    double castBruteForce(double x, double y, double angle, double maxRange) const;

    /** The segments, as given. */
    const std::vector<mrpt::math::TSegment2D>& segments() const { return m_input; }
    /** True if there are no segments. */
    bool empty() const { return m_input.empty(); }
    /** Side of a grid cell [m]. */
    double cellSize() const { return m_cell; }
    /** Grid size in cells. */
    int gridCellsX() const { return m_nx; }
    /** Grid size in cells. */
    int gridCellsY() const { return m_ny; }

    /** A segment as origin + edge vector (what the intersection test reads). */
    struct Seg
    {
        /** Origin x [m]. */
        double ax;
        /** Origin y [m]. */
        double ay;
        /** Edge vector x [m]. */
        double ex;
        /** Edge vector y [m]. */
        double ey;
    };

private:
    std::vector<mrpt::math::TSegment2D> m_input;
    std::vector<Seg> m_segs;            // all segments, input order (brute force)
    std::vector<uint32_t> m_cellStart;  // m_nx * m_ny + 1 offsets into m_cellSegs
    std::vector<Seg> m_cellSegs;        // copies, grouped by cell (contiguous per cell)
    double m_x0 = 0, m_y0 = 0, m_cell = 1, m_invCell = 1;
    int m_nx = 0, m_ny = 0;
};

}  // namespace semloc

/* semloc — the world's free-space raster: which cells of a grid no object touches (the first
 * answer of "is this particle in free space?", docs/design.md, "Large worlds"). */
#include <mrpt/core/exceptions.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "world/ObjectShape.h"

namespace semloc
{
using mrpt::math::TPoint2D;

namespace
{
/** Cells i of a raster axis (origin v0, side c, n cells) with floor((lo - v0) / c) <= i <=
 *  floor((hi - v0) / c), clamped to [0, n); false if there is none. */
bool cellSpan(double lo, double hi, double v0, double c, size_t n, size_t& i0, size_t& i1)
{
    const double a = std::floor((lo - v0) / c), b = std::floor((hi - v0) / c);
    const double last = static_cast<double>(n) - 1;
    if (!(b >= 0) || !(a <= last) || !(a <= b))
    {
        return false;
    }
    i0 = static_cast<size_t>(std::max(a, 0.0));
    i1 = static_cast<size_t>(std::min(b, last));
    return true;
}

/** The raster being filled: nx x ny cells of side `cell` from (x0, y0), row-major, 1 free. */
struct Raster
{
    double x0, y0, cell;
    size_t nx, ny;
    std::vector<uint8_t>& free;

    /** Cells [i0, i1] of row j are not free. */
    void clear(size_t i0, size_t i1, size_t j) const
    {
        std::fill(free.begin() + static_cast<ptrdiff_t>(i0 + j * nx),
                  free.begin() + static_cast<ptrdiff_t>(i1 + j * nx + 1), 0);
    }
};

/** Cells [i0, i1] of one row. */
struct Run
{
    size_t i0, i1;
};

/** A cylinder, or an outline without its points: every cell whose box widened by `m` meets
 *  the disc of radius r + m (an outline without its points: the disc of its extent). */
void clearDisc(const WorldObject& o, double m, double pad, const Raster& r)
{
    const double R = (o.shape == ShapeType::Cylinder ? o.radius : o.extent_m) * (1 + 1e-12) + m;
    size_t j0 = 0, j1 = 0;
    if (!cellSpan(o.center.y - R - pad, o.center.y + R + pad, r.y0, r.cell, r.ny, j0, j1))
    {
        return;
    }
    for (size_t j = j0; j <= j1; j++)
    {
        const double b0 = r.y0 + static_cast<double>(j) * r.cell - m;
        const double b1 = r.y0 + static_cast<double>(j + 1) * r.cell + m;
        const double dy = std::max({0.0, b0 - o.center.y, o.center.y - b1});
        if (dy > R)
        {
            continue;
        }
        const double hw = std::sqrt(R * R - dy * dy);
        size_t i0 = 0, i1 = 0;
        if (cellSpan(o.center.x - hw - pad, o.center.x + hw + pad, r.x0, r.cell, r.nx, i0, i1))
        {
            r.clear(i0, i1, j);
        }
    }
}

/** For each row j of [bj0, bj1] (rows[j - bj0]) that the edge [a, b] crosses, the run of
 *  cells the edge touches: its x extent within the row's band widened by `pad`. */
void addEdgeRuns(const TPoint2D& a, const TPoint2D& b, double pad, const Raster& r, size_t bj0,
                 size_t bj1, std::vector<std::vector<Run>>& rows)
{
    size_t j0 = 0, j1 = 0;
    if (!cellSpan(std::min(a.y, b.y) - pad, std::max(a.y, b.y) + pad, r.y0, r.cell, r.ny, j0, j1))
    {
        return;
    }
    for (size_t j = std::max(j0, bj0); j <= std::min(j1, bj1); j++)
    {
        const double lo = r.y0 + static_cast<double>(j) * r.cell - pad;
        const double hi = r.y0 + static_cast<double>(j + 1) * r.cell + pad;
        double xa = std::min(a.x, b.x), xb = std::max(a.x, b.x);
        if (a.y != b.y)
        {
            const double ta = (lo - a.y) / (b.y - a.y), tb = (hi - a.y) / (b.y - a.y);
            const double t0 = std::max(0.0, std::min(ta, tb));
            const double t1 = std::min(1.0, std::max(ta, tb));
            if (t0 > t1)
            {
                continue;
            }
            const double u0 = a.x + t0 * (b.x - a.x), u1 = a.x + t1 * (b.x - a.x);
            xa = std::min(u0, u1);
            xb = std::max(u0, u1);
        }
        size_t i0 = 0, i1 = 0;
        if (cellSpan(xa - pad, xb + pad, r.x0, r.cell, r.nx, i0, i1))
        {
            rows[j - bj0].push_back({i0, i1});
        }
    }
}

/** Row j of an object's bounding box [bi0, bi1]: the runs its edges touch are not free; each
 *  run of untouched cells between them is wholly inside or wholly outside the object, told by
 *  one exact test of its first cell's centre. */
void clearRow(const WorldObject& o, const Raster& r, size_t j, size_t bi0, size_t bi1,
              std::vector<Run>& runs)
{
    std::sort(runs.begin(), runs.end(), [](const Run& l, const Run& q) { return l.i0 < q.i0; });
    const double cy = r.y0 + (static_cast<double>(j) + 0.5) * r.cell;
    size_t next = bi0;                            // first cell of the row not yet classified
    auto untouched = [&](size_t from, size_t to)  // cells [from, to] of row j
    {
        const double cx = r.x0 + (static_cast<double>(from) + 0.5) * r.cell;
        if (from <= to && detail::insideObject(o, TPoint2D(cx, cy)))
        {
            r.clear(from, to, j);
        }
    };
    for (const auto& run : runs)
    {
        if (run.i0 > next)
        {
            untouched(next, std::min(run.i0 - 1, bi1));
        }
        r.clear(run.i0, run.i1, j);
        next = std::max(next, run.i1 + 1);
    }
    if (next <= bi1)
    {
        untouched(next, bi1);
    }
}

/** Box or polygon: the cells its edges touch (per row, the x extent of each edge within the
 *  row's widened band), then per row each run of untouched cells of the bounding box is wholly
 *  inside or wholly outside: one exact test of a cell centre. `rows` is scratch space. */
void clearPolygon(const WorldObject& o, double pad, const Raster& r,
                  std::vector<std::vector<Run>>& rows)
{
    const auto& poly = o.points;
    double xmin = poly[0].x, xmax = xmin, ymin = poly[0].y, ymax = ymin;
    for (const auto& p : poly)
    {
        xmin = std::min(xmin, p.x);
        xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
    }
    size_t bi0 = 0, bi1 = 0, bj0 = 0, bj1 = 0;
    if (!cellSpan(xmin - pad, xmax + pad, r.x0, r.cell, r.nx, bi0, bi1) ||
        !cellSpan(ymin - pad, ymax + pad, r.y0, r.cell, r.ny, bj0, bj1))
    {
        return;
    }
    rows.assign(bj1 - bj0 + 1, {});
    for (size_t e = 0; e < poly.size(); e++)
    {
        addEdgeRuns(poly[e], poly[(e + 1) % poly.size()], pad, r, bj0, bj1, rows);
    }
    for (size_t j = bj0; j <= bj1; j++)
    {
        clearRow(o, r, j, bi0, bi1, rows[j - bj0]);
    }
}
}  // namespace

std::vector<uint8_t> World::freeRaster(double x0, double y0, double cell_m, size_t nx,
                                       size_t ny) const
{
    ASSERTMSG_(cell_m > 0 && std::isfinite(cell_m) && std::isfinite(x0) && std::isfinite(y0),
               "World::freeRaster: the origin must be finite and the cell a finite number > 0");
    std::vector<uint8_t> free(nx * ny, 1);
    if (free.empty())
    {
        return free;
    }
    const Raster raster{x0, y0, cell_m, nx, ny, free};
    std::vector<std::vector<Run>> rows;
    for (const auto& o : objects)
    {
        if (o.shape == ShapeType::Point)
        {
            continue;
        }
        // The margin by which cells are widened: far above the rounding of a cell lookup
        // ((x - x0) / cell) and of the exact tests' tolerances (relative 1e-12), so that a
        // point that is not free never looks up a cell marked free.
        const double m = 1e-4 + 1e-11 * (std::abs(o.center.x) + std::abs(o.center.y) + o.extent_m +
                                         std::abs(x0) + std::abs(y0));
        const double pad = 2 * m;
        if (o.shape == ShapeType::Cylinder || o.points.size() < 3)
        {
            clearDisc(o, m, pad, raster);
        }
        else
        {
            clearPolygon(o, pad, raster, rows);
        }
    }
    return free;
}

}  // namespace semloc

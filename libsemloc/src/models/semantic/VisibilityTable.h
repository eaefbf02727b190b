/* semloc — CSemanticMap's visibility candidate table (private). */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "math/FastMath.h"
#include "models/semantic/SemanticIndex.h"
#include "models/semantic/SemanticSensorGeometry.h"

namespace semloc::detail
{
/** Whether CSemanticMap's likelihoods may use (and build) visibility candidate tables;
 *  on by default. Off: every particle scans the object grid. The outputs are the same
 *  either way (tests compare them). Process-wide; set it before concurrent calls. */
void setVisibilityTableEnabled(bool enabled);
bool visibilityTableEnabled();

/** Bytes of the last visibility table built in this process (0: none yet, or the last
 *  attempt chose the grid scan because a table would have been too large). */
size_t lastVisibilityTableBytes();

/** The visibility candidate table of one (index build, range R, FOV): for a square cell of
 *  sensor positions and a heading bin, the objects that may be inside range and FOV from
 *  some position of the cell with some heading of the bin (a superset), in increasing
 *  sorted index, i.e. in the order the grid scan visits them (docs/performance.md, "How the
 *  semantic likelihood is computed"). */
struct VisTable
{
    double x0 = 0, y0 = 0, inv = 0;  // origin and 1 / cell side of the table's grid
    double ox = 0, oy = 0;           // the origin less one cell (visRange)
    uint32_t nx = 0, ny = 0, bins = 1;
    /** bins / 4 (0 with one bin): bins are uniform in the "diamond angle" [0, 4). */
    double binScale = 0, lastBin = 0;
    /** cells * bins + 1: the candidates of list i are [start[i], start[i + 1]). */
    std::vector<uint32_t> start;
    std::vector<uint16_t> c16;  // the candidates (sorted indices) when there are < 65536
    std::vector<uint32_t> c32;  // objects, else here; either has one padding element
    size_t bytes = 0;
};

/** The tables of one index build, per (R, FOV); filled lazily under the mutex. A null
 *  table: one would be too large, the grid scan serves those calls. */
struct VisCache
{
    std::mutex mu;
    struct Entry
    {
        double R, fov;
        std::shared_ptr<const VisTable> table;
    };
    std::vector<Entry> entries;
};

/** The table a thread used last, kept (with its key) so that calls with the same index
 *  build, R and FOV lock nothing. */
struct VisTableHandle
{
    std::shared_ptr<const VisTable> hold;
    uint64_t stamp = 0;
    double R = 0, fov = 0;
};

/** Builds the visibility table of index ix for range R and FOV fov (cells of R / 10, 32
 *  heading bins; one with a full FOV), or null when it would be too large (then the grid
 *  scan serves). */
std::shared_ptr<const VisTable> buildVisTable(const CSemanticMap::Index& ix, double R, double fov);

/** The table of (R, fov) for index ix (built on first use, kept in ix.vis), or null: grid
 *  scan (tables disabled, no objects, or too large). */
const VisTable* visTableFor(const CSemanticMap::Index& ix, double R, double fov,
                            VisTableHandle& handle);

/** The table's candidates [a, b) for the particle's sensor position and heading; false if
 *  the position is outside the table or (c, s) is not a unit vector to 1e-12 (the table's
 *  angle margin assumes it: fastSinCos is exact to ~1e-15 for |phi| <= 1e6): then the grid
 *  scan serves it. */
inline bool visRange(const VisTable& t, const semantic::Geom& g, uint32_t& a, uint32_t& b)
{
    // Cell + 1 (truncation toward 0 maps (-1, 1) to 0: outside, as are NaN and huge values:
    // truncToInt32 gives INT32_MIN for those, no undefined conversion).
    int32_t ix = 0, iy = 0;
    truncToInt32((Vec2{g.sx, g.sy} - Vec2{t.ox, t.oy}) * Vec2{t.inv, t.inv}, ix, iy);
    const uint32_t cx = static_cast<uint32_t>(ix) - 1u;
    const uint32_t cy = static_cast<uint32_t>(iy) - 1u;
    if (cx >= t.nx || cy >= t.ny)
    {
        return false;
    }
    if (!(std::abs(g.c * g.c + g.s * g.s - 1) < 1e-12))
    {
        return false;
    }
    const double q = g.s / (std::abs(g.c) + std::abs(g.s));
    const double ad = (g.c >= 0 ? q : 2 - q) + 1;  // diamond angle + 1, in [0, 4]
    const auto bin = static_cast<uint32_t>(std::min(ad * t.binScale, t.lastBin));
    const uint32_t list = (cy * t.nx + cx) * t.bins + bin;
    a = t.start[list];
    b = t.start[list + 1];
    return true;
}

/** A particle's candidate list in the visibility table: [a, b) if `table`, else none (the
 *  grid scan serves it). */
struct ListRange
{
    uint32_t a = 0, b = 0;
    bool table = false;
};

/** visRange() of geometry g in table vt (null: none). */
inline ListRange listOf(const VisTable* vt, const semantic::Geom& g)
{
    ListRange r;
    r.table = vt != nullptr && visRange(*vt, g, r.a, r.b);
    return r;
}
}  // namespace semloc::detail

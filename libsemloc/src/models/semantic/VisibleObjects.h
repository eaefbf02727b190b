/* semloc — the visible objects z^k of a particle: the map objects inside the detector's range
 * and field of view (private; inline: the kernels' innermost loop). */
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "math/FastMath.h"
#include "models/semantic/SemanticIndex.h"
#include "models/semantic/SemanticSensorGeometry.h"
#include "models/semantic/VisibilityTable.h"

namespace semloc::semantic
{
using detail::Vec2;

/** The cells [cx0, cx1] x [cy0, cy1] of the grid that the bounding box of the FOV sector
 *  overlaps (apex, both arc ends, and the arc's extreme points along the axes that lie
 *  inside the FOV); empty when the box misses the grid. Branch-free, x and y together. */
inline void sectorCells(const CSemanticMap::Index& ix, const Geom& g, int& cx0, int& cx1, int& cy0,
                        int& cy1)
{
    using namespace detail;
    const Vec2 p{g.sx, g.sy};
    const Vec2 R{g.R, g.R};
    Vec2 lo = p, hi = p;
    if (g.fov < 2 * M_PI)
    {
        const double ch = g.cosHalf, sh = g.sinHalf;
        const Vec2 e1 = p + R * Vec2{g.c * ch - g.s * sh, g.s * ch + g.c * sh};
        const Vec2 e2 = p + R * Vec2{g.c * ch + g.s * sh, g.s * ch - g.c * sh};
        lo = minLanes(lo, minLanes(e1, e2));
        hi = maxLanes(hi, maxLanes(e1, e2));
        // The arc reaches +R (-R) along an axis if that direction is inside the FOV.
        const Vec2 dir{g.c, g.s}, vch{ch, ch};
        hi = maxLanes(hi, p + andLanes(greaterEqualMask(dir, vch), R));
        lo = minLanes(lo, p - andLanes(greaterEqualMask(Vec2{0.0, 0.0} - dir, vch), R));
    }
    else
    {
        lo = p - R;
        hi = p + R;
    }
    const Vec2 origin{ix.x0, ix.y0}, inv{ix.inv_cell, ix.inv_cell};
    const Vec2 last{ix.nx - 1.0, ix.ny - 1.0};
    // low: clamp to [0, n-1], truncate; high: clamp to [-1, n-1], floor (-1: box before
    // the grid, then the range is empty).
    truncToInt32(minLanes(last, maxLanes((lo - origin) * inv, Vec2{0.0, 0.0})), cx0, cy0);
    const Vec2 h = minLanes(last, maxLanes((hi - origin) * inv, Vec2{-1.0, -1.0}));
    const Vec2 t = truncInt32Lanes(h);
    truncToInt32(t - andLanes(lessMask(h, t), Vec2{1.0, 1.0}), cx1, cy1);
}

/** Calls step2(k0, k1, lanes, adjacent) for the candidates of a particle two at a time: the
 *  visibility table's list lr if lr.table, else the grid rows under the FOV sector's box
 *  (sectorCells), each a contiguous range of sorted indices; both in increasing sorted
 *  index. lanes: 3 both, 1 the first only (the arrays have one padding element for the
 *  second lane); adjacent: std::true_type when k1 = k0 + 1 (loaded as one pair). */
template <typename Step2>
inline void forEachCandidatePair(const CSemanticMap::Index& ix, const Geom& g,
                                 const detail::VisTable* vt, const detail::ListRange lr,
                                 Step2& step2)
{
    if (lr.table)
    {
        auto list = [&](const auto* C)
        {
            for (uint32_t j = lr.a; j < lr.b; j += 2)
            {
                step2(C[j], C[j + 1], lr.b - j >= 2 ? 3u : 1u, std::false_type());
            }
        };
        if (vt->c16.empty())
        {
            list(vt->c32.data());
        }
        else
        {
            list(vt->c16.data());
        }
        return;
    }
    const uint32_t* cellStart = ix.cellStart.data();
    const auto nx = static_cast<size_t>(ix.nx);
    int cx0 = 0, cx1 = -1, cy0 = 0, cy1 = -1;
    sectorCells(ix, g, cx0, cx1, cy0, cy1);
    for (int cy = cy0; cy <= cy1 && cx0 <= cx1; cy++)
    {
        const size_t row = static_cast<size_t>(cy) * nx;
        const uint32_t a = cellStart[row + static_cast<size_t>(cx0)];
        const uint32_t b = cellStart[row + static_cast<size_t>(cx1) + 1];
        for (uint32_t k = a; k < b; k += 2)
        {
            step2(k, k + 1, b - k >= 2 ? 3u : 1u, std::true_type());
        }
    }
}

/** The field-of-view test lx >= cos(fov/2) * d, squared without the sqrt, for a FOV of at
 *  most 180 degrees (cos(fov/2) >= 0), lane by lane. */
struct NarrowFov
{
    Vec2 ch2;
    Vec2 operator()(Vec2 lx, Vec2 d2) const
    {
        return detail::andLanes(detail::greaterEqualMask(lx, Vec2{0.0, 0.0}),
                                detail::greaterEqualMask(lx * lx, ch2 * d2));
    }
};

/** The same for a FOV wider than 180 degrees. */
struct WideFov
{
    Vec2 ch2;
    Vec2 operator()(Vec2 lx, Vec2 d2) const
    {
        return detail::orLanes(detail::greaterEqualMask(lx, Vec2{0.0, 0.0}),
                               detail::lessEqualMask(lx * lx, ch2 * d2));
    }
};

/** The FOV test of a full circle (fov >= 2 pi, as the reference's): every direction. The
 *  wide test would leave out, by a rounding, an object straight behind (lx^2 > d2 by an
 *  ulp). d2 >= 0 always holds (a finite pose, finite objects). */
struct FullFov
{
    Vec2 operator()(Vec2 /*lx*/, Vec2 d2) const
    {
        return detail::greaterEqualMask(d2, Vec2{0.0, 0.0});
    }
};

/** Where scanVisible() writes z^k, compacted: sorted indices and squared ranges and, with
 *  kFrame, the positions in the sensor frame (lx ahead, ly to the left) and `partId` (the
 *  particle's index in its block) in `part`. Every array must have room for the number of
 *  objects + 1 (entries are written always, kept if visible). */
struct VisOut
{
    uint32_t* hits;
    double* d2;
    double* lx;
    double* ly;
    uint32_t* part = nullptr;
    uint32_t partId = 0;
};

/** scanVisible() for one kind of FOV test: two candidates per step (Vec2; the lane past
 *  the end is masked: rows hold ~2-3 candidates, so a 2-wide step suits them better than
 *  wider vectors), written always, kept (compaction by a counter) if visible. */
template <bool kFrame, typename InFov>
inline size_t scanCandidates(const CSemanticMap::Index& ix, const Geom& g, const VisOut& vo,
                             const detail::VisTable* vt, const detail::ListRange lr, InFov inFov)
{
    using namespace detail;
    size_t cnt = 0;
    // Locals, not members: the stores to `out` could alias them, which made the compiler
    // reload every member and vector pointer at each candidate.
    const double* X = ix.x.data();
    const double* Y = ix.y.data();
    uint32_t* out = vo.hits;
    double* outD2 = vo.d2;
    double* outLx = vo.lx;
    double* outLy = vo.ly;
    uint32_t* outPart = vo.part;
    const uint32_t partId = vo.partId;
    const Vec2 vsx{g.sx, g.sx}, vsy{g.sy, g.sy}, vc{g.c, g.c}, vsn{g.s, g.s};
    const Vec2 vR2{g.R * g.R, g.R * g.R}, zero{0.0, 0.0};
    auto step2 = [&](uint32_t k0, uint32_t k1, unsigned lanes, auto adjacent)
    {
        Vec2 x, y;
        if constexpr (decltype(adjacent)::value)
        {
            x = loadLanes(X + k0);
            y = loadLanes(Y + k0);
        }
        else
        {
            x = Vec2{X[k0], X[k1]};
            y = Vec2{Y[k0], Y[k1]};
        }
        const Vec2 dx = x - vsx;
        const Vec2 dy = y - vsy;
        const Vec2 d2 = dx * dx + dy * dy;
        const Vec2 lx = vc * dx + vsn * dy;
        const auto m =
            static_cast<unsigned>(maskBits(andLanes(lessEqualMask(d2, vR2), inFov(lx, d2)))) &
            lanes;
        const Vec2 ly = kFrame ? vc * dy - vsn * dx : zero;  // (-sn) dx + c dy
        out[cnt] = k0;                                       // written always, kept only if visible
        storeLane0(outD2 + cnt, d2);
        if constexpr (kFrame)
        {
            storeLane0(outLx + cnt, lx);
            storeLane0(outLy + cnt, ly);
            outPart[cnt] = partId;
        }
        cnt += m & 1u;
        out[cnt] = k1;
        storeLane1(outD2 + cnt, d2);
        if constexpr (kFrame)
        {
            storeLane1(outLx + cnt, lx);
            storeLane1(outLy + cnt, ly);
            outPart[cnt] = partId;
        }
        cnt += m >> 1;
    };
    forEachCandidatePair(ix, g, vt, lr, step2);
    return cnt;
}

/** Finds the objects inside range and FOV (z^k) into `out`; returns how many. The
 *  candidates are the visibility table's list of the particle's cell and heading bin (vt,
 *  if any and the particle is inside it: lr = listOf(vt, g)), else the grid cells the FOV
 *  sector overlaps; both in increasing sorted index, so the same z^k in the same order.
 *  The test is branch-free and takes no square root until an object is known to be
 *  visible: most candidates are not, and mispredicted branches and sqrt latency were the
 *  cost of this loop. Two candidates at a time in Vec2 (SSE2 on x86-64; the scalar code
 *  of other targets does the same IEEE operations in the same order: the same decisions). */
template <bool kFrame>
inline size_t scanVisible(const CSemanticMap::Index& ix, const Geom& g, const VisOut& vo,
                          const detail::VisTable* vt, const detail::ListRange& lr)
{
    if (ix.nx <= 0)
    {
        return 0;
    }
    const double ch2 = g.cosHalf * g.cosHalf;
    // One loop per FOV kind (the test inlined, not selected at every candidate).
    if (g.fov >= 2 * M_PI)
    {
        return scanCandidates<kFrame>(ix, g, vo, vt, lr, FullFov{});
    }
    if (g.cosHalf >= 0)  // FOV <= 180 deg
    {
        return scanCandidates<kFrame>(ix, g, vo, vt, lr, NarrowFov{Vec2{ch2, ch2}});
    }
    return scanCandidates<kFrame>(ix, g, vo, vt, lr, WideFov{Vec2{ch2, ch2}});
}
}  // namespace semloc::semantic

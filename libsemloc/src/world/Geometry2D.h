/* semloc — small 2D predicates shared by the ray caster, the world rasterizer, the semantic map
 * and the experiment (private). */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>

#include <cmath>

#include <vector>

namespace semloc::detail
{
/** True if the closed segment [(ax, ay), (bx, by)] touches the closed axis-aligned box
 *  [xmin, xmax] x [ymin, ymax] (Liang & Barsky 1984 parametric clipping). */
inline bool segmentTouchesBox(double ax, double ay, double bx, double by, double xmin, double ymin,
                              double xmax, double ymax) noexcept
{
    double t0 = 0, t1 = 1;
    const double dx = bx - ax, dy = by - ay;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {ax - xmin, xmax - ax, ay - ymin, ymax - ay};
    for (int i = 0; i < 4; i++)
    {
        if (p[i] == 0)
        {
            if (q[i] < 0)
            {
                return false;
            }
            continue;
        }
        const double r = q[i] / p[i];
        if (p[i] < 0)
        {
            if (r > t1)
            {
                return false;
            }
            t0 = r > t0 ? r : t0;
        }
        else
        {
            if (r < t0)
            {
                return false;
            }
            t1 = r < t1 ? r : t1;
        }
    }
    return true;
}

/** True if p is inside the simple polygon `poly` or on its boundary (within `eps` m).
 *  Crossing-number test (O'Rourke, "Computational Geometry in C", §7.4). */
inline bool pointInPolygon(const mrpt::math::TPoint2D& p,
                           const std::vector<mrpt::math::TPoint2D>& poly, double eps = 1e-12)
{
    bool inside = false;
    const size_t n = poly.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++)
    {
        const auto& a = poly[i];
        const auto& b = poly[j];
        // On the edge [a, b]?
        const double ex = b.x - a.x, ey = b.y - a.y;
        const double len2 = ex * ex + ey * ey;
        const double wx = p.x - a.x, wy = p.y - a.y;
        const double u = len2 > 0 ? (wx * ex + wy * ey) / len2 : 0;
        if (u >= 0 && u <= 1)
        {
            const double cx = wx - u * ex, cy = wy - u * ey;
            if (cx * cx + cy * cy <= eps * eps)
            {
                return true;
            }
        }
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * ex / ey)
        {
            inside = !inside;
        }
    }
    return inside;
}

/** True if x, y and phi of `p` are all finite. */
inline bool finitePose(const mrpt::math::TPose2D& p) noexcept
{
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi);
}

}  // namespace semloc::detail

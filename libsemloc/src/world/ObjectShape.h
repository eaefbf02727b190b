/* semloc — the exact shape of a world object: point-in-object and segment-touch tests shared by
 * the world's reader, its geometry and its rasters (private). */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>

#include "world/Geometry2D.h"

namespace semloc::detail
{
/** Twice the signed area of the triangle (o, a, b): > 0 if b is left of o -> a. */
inline double orientation(const mrpt::math::TPoint2D& o, const mrpt::math::TPoint2D& a,
                          const mrpt::math::TPoint2D& b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/** True if p lies in the axis-aligned bounding box of [a, b] (p collinear with a and b). */
inline bool inSegmentBox(const mrpt::math::TPoint2D& p, const mrpt::math::TPoint2D& a,
                         const mrpt::math::TPoint2D& b)
{
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

/** True if closed segments [a,b] and [c,d] share at least one point. */
inline bool segmentsTouch(const mrpt::math::TPoint2D& a, const mrpt::math::TPoint2D& b,
                          const mrpt::math::TPoint2D& c, const mrpt::math::TPoint2D& d)
{
    const double d1 = orientation(c, d, a), d2 = orientation(c, d, b);
    const double d3 = orientation(a, b, c), d4 = orientation(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    {
        return true;
    }
    return (d1 == 0 && inSegmentBox(a, c, d)) || (d2 == 0 && inSegmentBox(b, c, d)) ||
           (d3 == 0 && inSegmentBox(c, a, b)) || (d4 == 0 && inSegmentBox(d, a, b));
}

/** True if p is inside the object's exact shape or on its boundary (a cylinder's exact
 *  circle; never for a point). */
inline bool insideObject(const WorldObject& o, const mrpt::math::TPoint2D& p)
{
    const double dx = p.x - o.center.x, dy = p.y - o.center.y;
    if (dx * dx + dy * dy > o.extent_m * o.extent_m * (1 + 1e-12) + 1e-18)
    {
        return false;
    }
    switch (o.shape)
    {
        case ShapeType::Box:
        {
            // In the box frame (rotate by -yaw).
            const double c = std::cos(o.yaw), s = std::sin(o.yaw);
            const double u = c * dx + s * dy, v = -s * dx + c * dy;
            return std::abs(u) <= 0.5 * o.size_x + 1e-12 && std::abs(v) <= 0.5 * o.size_y + 1e-12;
        }
        case ShapeType::Cylinder:
            return true;  // within extent_m == radius
        case ShapeType::Polygon:
            return pointInPolygon(p, o.points);
        case ShapeType::Point:
            return false;
    }
    return false;
}

}  // namespace semloc::detail

/* semloc — the world's geometry: the outlines the sonar sees, free space, and which object a
 * segment touches (docs/design.md, "World file"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>

#include "world/ObjectShape.h"

namespace semloc
{
using mrpt::math::TPoint2D;

namespace
{
/** Maximum number of rejection-sampling draws in sampleFreePose(). */
constexpr int kMaxFreeDraws = 100000;

/** Distance from p to the closed segment [a, b]. */
double pointSegmentDistance(const TPoint2D& p, const TPoint2D& a, const TPoint2D& b)
{
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    const double u =
        len2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - (a.x + u * ex), p.y - (a.y + u * ey));
}
}  // namespace

int World::cylinderSides(double radius_m, double tolerance_m)
{
    ASSERTMSG_(tolerance_m > 0 && std::isfinite(tolerance_m),
               "World::cylinderSides: the tolerance must be a finite number > 0");
    ASSERTMSG_(radius_m > 0 && std::isfinite(radius_m),
               "World::cylinderSides: the radius must be a finite number > 0");
    constexpr int kMinSides = 6, kMaxSides = 65536;
    const double ratio = tolerance_m / radius_m;
    if (ratio >= 1)
    {
        return kMinSides;  // the sagitta of any n >= 2 is at most r
    }
    // r (1 - cos(pi / n)) <= tol  <=>  n >= pi / acos(1 - tol / r)
    const double nReal = M_PI / std::acos(1 - ratio);
    if (!(nReal <= kMaxSides))
    {
        THROW_EXCEPTION(mrpt::format(
            "World::cylinderSides: tolerance %g m is too small for radius %g m (needs more "
            "than %d sides)",
            tolerance_m, radius_m, kMaxSides));
    }
    int n = std::max(kMinSides, static_cast<int>(std::ceil(nReal)));
    while (n < kMaxSides && radius_m * (1 - std::cos(M_PI / n)) > tolerance_m)
    {
        n++;  // guards the rounding of acos
    }
    return n;
}

std::vector<TPoint2D> World::outlinePolygon(const WorldObject& o, double cylinderTolerance_m)
{
    switch (o.shape)
    {
        case ShapeType::Box:
        case ShapeType::Polygon:
            return o.points;
        case ShapeType::Cylinder:
        {
            const int n = cylinderSides(o.radius, cylinderTolerance_m);
            std::vector<TPoint2D> p;
            p.reserve(static_cast<size_t>(n));
            for (int k = 0; k < n; k++)
            {
                const double a = 2 * M_PI * k / n;
                p.emplace_back(o.center.x + o.radius * std::cos(a),
                               o.center.y + o.radius * std::sin(a));
            }
            return p;
        }
        case ShapeType::Point:
            break;
    }
    return {};
}

std::vector<mrpt::math::TSegment2D> World::outlineSegments(double cylinderTolerance_m) const
{
    std::vector<mrpt::math::TSegment2D> segs;
    for (const auto& o : objects)
    {
        const auto poly = outlinePolygon(o, cylinderTolerance_m);
        for (size_t i = 0; i < poly.size(); i++)
        {
            segs.emplace_back(poly[i], poly[(i + 1) % poly.size()]);
        }
    }
    return segs;
}

bool World::isFree(double x, double y) const
{
    if (!bounds.contains(x, y))
    {
        return false;
    }
    const TPoint2D p(x, y);
    for (const auto& o : objects)
    {
        if (detail::insideObject(o, p))
        {
            return false;
        }
    }
    return true;
}

mrpt::math::TPose2D World::sampleFreePose(mrpt::random::CRandomGenerator& rng) const
{
    for (int i = 0; i < kMaxFreeDraws; i++)
    {
        const double x = rng.drawUniform(bounds.x_min, bounds.x_max);
        const double y = rng.drawUniform(bounds.y_min, bounds.y_max);
        if (isFree(x, y))
        {
            return {x, y, rng.drawUniform(-M_PI, M_PI)};
        }
    }
    THROW_EXCEPTION(mrpt::format(
        "world '%s': no free space: none of %d uniform draws inside bounds fell outside "
        "every object outline",
        (source.empty() ? name : source).c_str(), kMaxFreeDraws));
}

int World::firstObjectOnSegment(const TPoint2D& a, const TPoint2D& b) const
{
    for (size_t k = 0; k < objects.size(); k++)
    {
        const auto& o = objects[k];
        if (o.shape == ShapeType::Point)
        {
            continue;
        }
        // The shape lies in the disc of radius extent_m around the centre (insideObject).
        const double d = pointSegmentDistance(o.center, a, b);
        if (d * d > o.extent_m * o.extent_m * (1 + 1e-12) + 1e-18)
        {
            continue;
        }
        bool touches = o.shape == ShapeType::Cylinder || detail::insideObject(o, a) ||
                       detail::insideObject(o, b);
        for (size_t i = 0; !touches && i < o.points.size(); i++)
        {
            touches = detail::segmentsTouch(a, b, o.points[i], o.points[(i + 1) % o.points.size()]);
        }
        if (touches)
        {
            return static_cast<int>(k);
        }
    }
    return -1;
}

}  // namespace semloc

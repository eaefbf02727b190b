/* semloc tests — World geometry: outlines, free space, rasterization, the shipped worlds. */
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "world/Geometry2D.h"

using mrpt::math::TPoint2D;
using mrpt::math::TSegment2D;
using semloc::World;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kHarbour = SEMLOC_SOURCE_DIR "/maps/harbour_symmetric.yaml";

double pointSegmentDistance(const TPoint2D& p, const TPoint2D& a, const TPoint2D& b)
{
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double l2 = ex * ex + ey * ey;
    const double u = l2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / l2, 0.0, 1.0) : 0;
    return std::hypot(p.x - a.x - u * ex, p.y - a.y - u * ey);
}

double cross(const TPoint2D& o, const TPoint2D& a, const TPoint2D& b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/** Distance between two closed segments (0 if they touch). */
double segmentDistance(const TSegment2D& s, const TSegment2D& t)
{
    const double d1 = cross(t.point1, t.point2, s.point1), d2 = cross(t.point1, t.point2, s.point2);
    const double d3 = cross(s.point1, s.point2, t.point1), d4 = cross(s.point1, s.point2, t.point2);
    if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 &&
        d4 != 0)
    {
        return 0;
    }
    return std::min({pointSegmentDistance(s.point1, t.point1, t.point2),
                     pointSegmentDistance(s.point2, t.point1, t.point2),
                     pointSegmentDistance(t.point1, s.point1, s.point2),
                     pointSegmentDistance(t.point2, s.point1, s.point2)});
}

/** Smallest distance from the trajectory's legs to any outline segment. */
double trajectoryClearance(const World& w)
{
    const auto segs = w.outlineSegments();
    const auto& wp = w.trajectory->waypoints;
    double best = 1e9;
    for (size_t i = 0; i + 1 < wp.size(); i++)
    {
        for (const auto& s : segs)
        {
            best = std::min(best, segmentDistance(TSegment2D(wp[i], wp[i + 1]), s));
        }
    }
    return best;
}

World oneObjectWorld(const std::string& object)
{
    return World::FromText(
        "bounds: {x_min: 0, x_max: 10, y_min: 0, y_max: 10}\nobjects:\n  - " + object + "\n",
        "test");
}
}  // namespace

TEST(WorldGeometry, CylinderSidesHonourTheTolerance)
{
    for (const double r : {0.05, 0.3, 0.6, 1.5, 10.0, 250.0})
    {
        for (const double tol : {1e-4, 0.001, 0.01, 0.05, 0.5})
        {
            const int n = World::cylinderSides(r, tol);
            EXPECT_GE(n, 6);
            EXPECT_LE(r * (1 - std::cos(M_PI / n)), tol) << "r " << r << " tol " << tol;
            if (n > 6)
            {
                EXPECT_GT(r * (1 - std::cos(M_PI / (n - 1))), tol) << "not the smallest n";
            }
        }
    }
    EXPECT_ANY_THROW(World::cylinderSides(1.0, 0.0));
    EXPECT_ANY_THROW(World::cylinderSides(1000.0, 1e-12));
}

TEST(WorldGeometry, CylinderPolygonIsInscribedWithinTolerance)
{
    const World w =
        oneObjectWorld("{id: 1, label: pillar, shape: cylinder, center: [5, 4], radius: 1.3}");
    for (const double tol : {0.001, 0.01, 0.1})
    {
        const auto segs = w.outlineSegments(tol);
        ASSERT_EQ(static_cast<int>(segs.size()), World::cylinderSides(1.3, tol));
        for (const auto& s : segs)
        {
            EXPECT_NEAR(std::hypot(s.point1.x - 5, s.point1.y - 4), 1.3, 1e-12);
            EXPECT_EQ(s.point2, segs[(&s - segs.data() + 1) % segs.size()].point1);  // closed
        }
        // Every point of the circle is within the tolerance of the polygon.
        double worst = 0;
        for (int k = 0; k < 7200; k++)
        {
            const double a = 2 * M_PI * k / 7200;
            const TPoint2D p(5 + 1.3 * std::cos(a), 4 + 1.3 * std::sin(a));
            double d = 1e9;
            for (const auto& s : segs)
            {
                d = std::min(d, pointSegmentDistance(p, s.point1, s.point2));
            }
            worst = std::max(worst, d);
        }
        EXPECT_LE(worst, tol + 1e-12);
        EXPECT_GT(worst, 0.5 * tol);  // and not needlessly fine
    }
}

TEST(WorldGeometry, OutlineSegmentsPerShape)
{
    const World w = World::FromText(R"(
bounds: {x_min: 0, x_max: 20, y_min: 0, y_max: 20}
objects:
  - {id: 1, label: a, shape: box, center: [5, 5], size: [2, 1], yaw_deg: 30}
  - {id: 2, label: b, shape: polygon, points: [[10, 10], [14, 10], [15, 13], [12, 15], [9, 13]]}
  - {id: 3, label: c, shape: point, center: [3, 15]}
)",
                                    "shapes");
    const auto segs = w.outlineSegments();
    ASSERT_EQ(segs.size(), 4u + 5u);
    for (size_t i = 0; i < 4; i++)
    {
        EXPECT_EQ(segs[i].point1, w.objects[0].points[i]);
        EXPECT_EQ(segs[i].point2, w.objects[0].points[(i + 1) % 4]);
        EXPECT_NEAR(segs[i].length(), i % 2 == 0 ? 2.0 : 1.0, 1e-12);
    }
    EXPECT_EQ(segs[8].point1, TPoint2D(9, 13));
    EXPECT_EQ(segs[8].point2, TPoint2D(10, 10));
}

TEST(WorldGeometry, IsFree)
{
    const World w = World::FromFile(kPaper);
    for (const auto& o : w.objects)
    {
        if (o.shape == semloc::ShapeType::Point)
        {
            EXPECT_TRUE(w.isFree(o.center.x, o.center.y)) << "a marker blocks nothing";
        }
        else
        {
            EXPECT_FALSE(w.isFree(o.center.x, o.center.y)) << "object id " << o.id;
            for (const auto& p : World::outlinePolygon(o))
            {
                EXPECT_FALSE(w.isFree(p.x, p.y)) << "vertex of id " << o.id;
            }
        }
    }
    // Manifold id 1: box 4 x 2.5 at (12.5, 10.5).
    EXPECT_FALSE(w.isFree(14.49, 11.74));
    EXPECT_FALSE(w.isFree(14.5, 10.5));  // on the edge
    EXPECT_TRUE(w.isFree(14.51, 10.5));
    EXPECT_TRUE(w.isFree(12.5, 11.76));
    // Pillar id 2: exact circle r 0.5 at (9.5, 8), not its polygon.
    EXPECT_FALSE(w.isFree(9.5 + 0.4999 * std::cos(0.1), 8 + 0.4999 * std::sin(0.1)));
    EXPECT_TRUE(w.isFree(9.5 + 0.5001, 8));
    // Wreck id 12 (polygon): inside, just outside.
    EXPECT_FALSE(w.isFree(33, 25.5));
    EXPECT_TRUE(w.isFree(29.9, 24));
    // Bounds.
    EXPECT_TRUE(w.isFree(0, 0));
    EXPECT_FALSE(w.isFree(-0.01, 5));
    EXPECT_FALSE(w.isFree(5, 50.01));
}

TEST(WorldGeometry, SampleFreePoseIsUniformOverFreeSpace)
{
    const World w = World::FromText(R"(
bounds: {x_min: 0, x_max: 10, y_min: 0, y_max: 10}
objects:
  - {id: 1, label: block, shape: box, center: [2.5, 5], size: [5, 10]}
)",
                                    "half");
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(42);
    const int n = 20000;
    double sx = 0, sy = 0, sphi = 0;
    int upper = 0;
    for (int i = 0; i < n; i++)
    {
        const auto p = w.sampleFreePose(rng);
        ASSERT_TRUE(w.isFree(p.x, p.y));
        ASSERT_GE(p.phi, -M_PI);
        ASSERT_LT(p.phi, M_PI);
        sx += p.x;
        sy += p.y;
        sphi += p.phi;
        upper += p.y > 5 ? 1 : 0;
    }
    // Free space is [5, 10] x [0, 10]: means 7.5 and 5, std. errors ~0.01 and ~0.02.
    EXPECT_NEAR(sx / n, 7.5, 0.05);
    EXPECT_NEAR(sy / n, 5.0, 0.1);
    EXPECT_NEAR(sphi / n, 0.0, 0.05);
    EXPECT_NEAR(upper / double(n), 0.5, 0.02);
}

TEST(WorldGeometry, SampleFreePoseThrowsWithoutFreeSpace)
{
    const World w =
        oneObjectWorld("{id: 1, label: slab, shape: box, center: [5, 5], size: [12, 12]}");
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1);
    try
    {
        w.sampleFreePose(rng);
        FAIL() << "expected an exception";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("no free space"), std::string::npos) << e.what();
    }
}

TEST(WorldGeometry, OccupancyGridAgreesWithOutlines)
{
    const World w = World::FromFile(kPaper);
    const double res = 0.1;
    const auto grid = w.makeOccupancyGrid(res);
    EXPECT_NEAR(grid.getResolution(), res, 1e-6);
    EXPECT_LE(grid.getXMin(), w.bounds.x_min + 1e-4);
    EXPECT_GE(grid.getXMax(), w.bounds.x_max - 1e-4);
    // Every cell an outline crosses is occupied (points every 5 mm along each segment).
    size_t checked = 0;
    for (const auto& s : w.outlineSegments())
    {
        const int steps = static_cast<int>(std::ceil(s.length() / 0.005));
        for (int k = 0; k <= steps; k++)
        {
            const double u = static_cast<double>(k) / steps;
            const double x = s.point1.x + u * (s.point2.x - s.point1.x);
            const double y = s.point1.y + u * (s.point2.y - s.point1.y);
            ASSERT_LT(grid.getPos(x, y), 0.5) << "outline point (" << x << ", " << y << ")";
            checked++;
        }
    }
    EXPECT_GT(checked, 10000u);
    // Cells whose centre is inside an object are occupied; cells farther than a cell
    // diagonal from every outline and outside every object are free.
    const auto segs = w.outlineSegments();
    size_t nFree = 0, nOcc = 0;
    for (unsigned iy = 0; iy < grid.getSizeY(); iy += 3)
    {
        for (unsigned ix = 0; ix < grid.getSizeX(); ix += 3)
        {
            const TPoint2D c(grid.idx2x(ix), grid.idx2y(iy));
            double d = 1e9;
            for (const auto& s : segs)
            {
                d = std::min(d, pointSegmentDistance(c, s.point1, s.point2));
            }
            if (!w.isFree(c.x, c.y) && w.bounds.contains(c.x, c.y))
            {
                EXPECT_LT(grid.getCell(ix, iy), 0.5) << "inside, cell " << ix << "," << iy;
                nOcc++;
            }
            else if (d > res * M_SQRT2)
            {
                EXPECT_GT(grid.getCell(ix, iy), 0.5) << "free, cell " << ix << "," << iy;
                nFree++;
            }
        }
    }
    EXPECT_GT(nOcc, 50u);
    EXPECT_GT(nFree, 10000u);
    // A probe point in open water (the trajectory's start).
    EXPECT_GT(grid.getPos(3.0, 4.0), 0.5);
}

TEST(WorldGeometry, PaperWorldMatchesTheScenario)
{
    const World w = World::FromFile(kPaper);
    EXPECT_EQ(w.bounds.x_min, 0);
    EXPECT_EQ(w.bounds.x_max, 50);
    EXPECT_EQ(w.bounds.y_min, 0);
    EXPECT_EQ(w.bounds.y_max, 50);
    EXPECT_GE(w.objects.size(), 20u);
    std::map<std::string, int> labels;
    std::set<semloc::ShapeType> shapes;
    for (const auto& o : w.objects)
    {
        labels[o.label]++;
        shapes.insert(o.shape);
        if (o.label == "pipeline")
        {
            EXPECT_EQ(o.shape, semloc::ShapeType::Box);
            EXPECT_GE(std::max(o.size_x, o.size_y) / std::min(o.size_x, o.size_y), 10.0);
        }
        if (o.label == "wreck")
        {
            EXPECT_EQ(o.shape, semloc::ShapeType::Polygon);
        }
    }
    for (const char* l : {"wellhead", "manifold", "pillar", "pipeline", "anchor", "wreck"})
    {
        EXPECT_GE(labels[l], 2) << l << " is not repeated";
    }
    EXPECT_GE(labels.size(), 6u);
    EXPECT_EQ(shapes.size(), 4u);  // box, cylinder, polygon, point
    // The two manifold + pillar clusters are the same geometry, shifted.
    const auto& a = w.objects[static_cast<size_t>(w.indexOfId(1))];
    const auto& b = w.objects[static_cast<size_t>(w.indexOfId(14))];
    const double tx = b.center.x - a.center.x, ty = b.center.y - a.center.y;
    for (const auto& [ia, ib] : {std::pair{2, 15}, std::pair{3, 16}})
    {
        const auto& pa = w.objects[static_cast<size_t>(w.indexOfId(ia))];
        const auto& pb = w.objects[static_cast<size_t>(w.indexOfId(ib))];
        EXPECT_EQ(pa.label, pb.label);
        EXPECT_EQ(pa.radius, pb.radius);
        EXPECT_NEAR(pb.center.x - pa.center.x, tx, 1e-12);
        EXPECT_NEAR(pb.center.y - pa.center.y, ty, 1e-12);
    }
    ASSERT_TRUE(w.trajectory);
    EXPECT_EQ(w.trajectory->speed_mps, 0.5);
}

TEST(WorldGeometry, TrajectoriesNeverCrossAnOutline)
{
    for (const auto& file : {kPaper, kHarbour})
    {
        const World w = World::FromFile(file);
        ASSERT_TRUE(w.trajectory) << file;
        for (const auto& p : w.trajectory->waypoints)
        {
            EXPECT_TRUE(w.isFree(p.x, p.y)) << file;
        }
        const double clearance = trajectoryClearance(w);
        EXPECT_GE(clearance, 1.5) << file;  // never crossing, never grazing
        EXPECT_LE(clearance, 4.0) << file;  // but close to the structures
    }
}

TEST(WorldGeometry, HarbourIsMirrorSymmetricButItsLabelsAreNot)
{
    const World w = World::FromFile(kHarbour);
    const double axis = 0.5 * (w.bounds.x_min + w.bounds.x_max);
    // Every outline object has a mirror twin of the same shape and size.
    std::multiset<std::string> west, east;
    for (const auto& o : w.objects)
    {
        if (o.shape == semloc::ShapeType::Point)
        {
            continue;
        }
        bool twin = false;
        for (const auto& m : w.objects)
        {
            if (m.shape != o.shape || std::abs(2 * axis - m.center.x - o.center.x) > 1e-9 ||
                std::abs(m.center.y - o.center.y) > 1e-9)
            {
                continue;
            }
            twin = m.size_x == o.size_x && m.size_y == o.size_y && m.radius == o.radius;
            if (o.shape == semloc::ShapeType::Polygon)
            {
                for (const auto& p : o.points)
                {
                    twin = twin && std::any_of(m.points.begin(), m.points.end(),
                                               [&](auto& q) {
                                                   return std::abs(2 * axis - q.x - p.x) < 1e-9 &&
                                                          std::abs(q.y - p.y) < 1e-9;
                                               });
                }
            }
            if (twin)
            {
                break;
            }
        }
        EXPECT_TRUE(twin) << "object id " << o.id << " has no mirror image";
        if (o.center.x < axis - 1e-9)
        {
            west.insert(o.label);
        }
        else if (o.center.x > axis + 1e-9)
        {
            east.insert(o.label);
        }
    }
    EXPECT_NE(west, east) << "the labels should break the symmetry";
}

namespace
{
/** A world of random boxes (rotated), cylinders, star-shaped (concave) polygons and points,
 *  sizes from centimetres to tens of metres, in bounds far larger than the objects' spread. */
World randomShapesWorld(unsigned seed)
{
    std::mt19937_64 gen(seed);
    auto u = [&gen](double lo, double hi)
    { return std::uniform_real_distribution<double>(lo, hi)(gen); };
    std::ostringstream y;
    y.precision(17);
    y << "bounds: {x_min: -1000, x_max: 1000, y_min: -1000, y_max: 1000}\nobjects:\n";
    for (int id = 1; id <= 60; id++)
    {
        const double cx = u(-60, 60), cy = u(-60, 60),
                     s = std::exp(u(std::log(0.05), std::log(25)));
        y << "  - {id: " << id << ", label: l, ";
        switch (id % 4)
        {
            case 0:
                y << "shape: box, center: [" << cx << ", " << cy << "], size: [" << s << ", "
                  << s * u(0.05, 1) << "], yaw_deg: " << u(-180, 180) << "}\n";
                break;
            case 1:
                y << "shape: cylinder, center: [" << cx << ", " << cy << "], radius: " << s / 2
                  << "}\n";
                break;
            case 2:
            {
                const int n = 3 + static_cast<int>(gen() % 10);
                y << "shape: polygon, points: [";
                for (int k = 0; k < n; k++)
                {
                    const double a = 2 * M_PI * (k + u(0.1, 0.9)) / n, r = s * u(0.2, 1);
                    y << (k ? ", " : "") << "[" << cx + r * std::cos(a) << ", "
                      << cy + r * std::sin(a) << "]";
                }
                y << "]}\n";
                break;
            }
            default:
                y << "shape: point, center: [" << cx << ", " << cy << "]}\n";
                break;
        }
    }
    return World::FromText(y.str(), "random");
}

/** Distance below which a point counts as touching object o's closed shape [m] (tests only:
 *  o's outline polygon, a cylinder's circle). */
bool nearShape(const semloc::WorldObject& o, double xmin, double ymin, double xmax, double ymax,
               double tol)
{
    if (o.shape == semloc::ShapeType::Point)
    {
        return false;
    }
    if (o.shape == semloc::ShapeType::Cylinder)
    {
        const double dx = std::max({xmin - o.center.x, 0.0, o.center.x - xmax});
        const double dy = std::max({ymin - o.center.y, 0.0, o.center.y - ymax});
        return std::hypot(dx, dy) <= o.radius + tol;
    }
    const auto& p = o.points;
    for (size_t i = 0; i < p.size(); i++)
    {
        const auto& a = p[i];
        const auto& b = p[(i + 1) % p.size()];
        if (semloc::detail::segmentTouchesBox(a.x, a.y, b.x, b.y, xmin - tol, ymin - tol,
                                              xmax + tol, ymax + tol))
        {
            return true;
        }
    }
    return semloc::detail::pointInPolygon({0.5 * (xmin + xmax), 0.5 * (ymin + ymax)}, p);
}
}  // namespace

TEST(WorldGeometry, FreeRasterMarksExactlyTheCellsNoObjectTouches)
{
    for (const unsigned seed : {1u, 2u, 3u})
    {
        const World w = randomShapesWorld(seed);
        std::mt19937_64 gen(seed + 100);
        for (const double cell : {0.1, 0.37, 1.0, 6.4, 40.0})
        {
            const double x0 = -80 - cell * 0.5 * static_cast<double>(gen() % 7);
            const double y0 = -75.3;
            // 160 m (the objects' spread) or 500 cells, whichever is less.
            const auto n = std::min(size_t{500}, static_cast<size_t>(std::ceil(160 / cell)));
            const auto free = w.freeRaster(x0, y0, cell, n, n + 1);
            ASSERT_EQ(free.size(), n * (n + 1));
            size_t nFree = 0, nTouched = 0;
            std::uniform_real_distribution<double> f(0, 1);
            for (size_t j = 0; j <= n; j++)
            {
                for (size_t i = 0; i < n; i++)
                {
                    const double xa = x0 + static_cast<double>(i) * cell;
                    const double ya = y0 + static_cast<double>(j) * cell;
                    const double xb = x0 + static_cast<double>(i + 1) * cell;
                    const double yb = y0 + static_cast<double>(j + 1) * cell;
                    if (free[i + j * n])
                    {
                        // The closed cell is free: corners, border midpoints, random points.
                        nFree++;
                        for (const auto& [px, py] : {std::pair{xa, ya},
                                                     {xb, ya},
                                                     {xa, yb},
                                                     {xb, yb},
                                                     {0.5 * (xa + xb), ya},
                                                     {xa, 0.5 * (ya + yb)},
                                                     {xa + f(gen) * cell, ya + f(gen) * cell}})
                        {
                            ASSERT_TRUE(w.isFree(px, py)) << "cell " << cell << " (" << i << ", "
                                                          << j << ") at " << px << ", " << py;
                        }
                    }
                    else
                    {
                        // Marked only where an object's shape comes within a millimetre.
                        nTouched++;
                        bool near = false;
                        for (const auto& o : w.objects)
                        {
                            near = near || nearShape(o, xa, ya, xb, yb, 1e-3);
                        }
                        ASSERT_TRUE(near) << "cell " << cell << " (" << i << ", " << j << ")";
                    }
                }
            }
            EXPECT_GT(nFree, 0u) << cell;
            EXPECT_GT(nTouched, 0u) << cell;
        }
    }
}

TEST(WorldGeometry, OccupancyGridTooLargeForItsResolutionIsAnErrorNamingBoth)
{
    const World w = World::FromText(
        "name: big\nbounds: {x_min: 0, x_max: 20000, y_min: -5, y_max: 19995}\nobjects:\n"
        "  - {id: 1, label: a, shape: cylinder, center: [10000, 10000], radius: 3}\n",
        "big.yaml");
    try
    {
        (void)w.makeOccupancyGrid(0.1);
        FAIL() << "a 20 x 20 km grid of 0.1 m cells was built";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("world 'big.yaml': an occupancy grid over its bounds x [0, 20000], y "
                         "[-5, 19995] at resolution 0.1 m would have 4e+10 cells, more than the "
                         "33554432 allowed: use a resolution of 3.46 m or coarser"),
                  std::string::npos)
            << m;
    }
    EXPECT_THROW((void)w.makeOccupancyGrid(3.45), std::exception);
    const auto grid = w.makeOccupancyGrid(3.46);  // the resolution the message suggests
    EXPECT_LE(static_cast<size_t>(grid.getSizeX()) * grid.getSizeY(),
              semloc::kMaxOccupancyGridCells);
    EXPECT_LT(grid.getPos(10000, 10000), 0.5);
    EXPECT_GT(grid.getPos(10020, 10000), 0.5);
}

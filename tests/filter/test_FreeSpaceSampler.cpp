/* semloc tests — FreeSpaceSampler: contains() against its definition per kind, and the
 * filter's batch excludeOutside() against contains(). */
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/world/World.h>

#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "LargeWorld.h"

using mrpt::math::TPose2D;
using semloc::FreeSpaceSampler;
using semloc::World;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
constexpr double kNegInf = -std::numeric_limits<double>::infinity();

/** Poses over and around the world's bounds (a margin outside), some on cell borders of a
 *  0.1 m raster (multiples of 0.1 as doubles) where a division's rounding decides. */
std::vector<TPose2D> posesAround(const World& w, size_t n, unsigned seed)
{
    std::mt19937_64 gen(seed);
    const auto& b = w.bounds;
    std::uniform_real_distribution<double> x(b.x_min - 3, b.x_max + 3), y(b.y_min - 3, b.y_max + 3);
    std::uniform_int_distribution<int> cell(-30, 530);
    std::vector<TPose2D> out;
    for (size_t i = 0; i < n; i++)
    {
        if (i % 4 == 3)
        {
            out.push_back({b.x_min + cell(gen) * 0.1, b.y_min + cell(gen) * 0.1, 0});
        }
        else
        {
            out.push_back({x(gen), y(gen), 0});
        }
    }
    return out;
}

/** excludeOutside() on `poses` equals contains() pose by pose; -inf entries stay and are
 *  not counted. */
void expectBatchEqualsContains(const FreeSpaceSampler& s, const std::vector<TPose2D>& poses)
{
    std::vector<double> logLik(poses.size());
    for (size_t i = 0; i < poses.size(); i++)
    {
        logLik[i] = i % 7 == 0 ? kNegInf : -static_cast<double>(i % 13);
    }
    const std::vector<double> before = logLik;
    // Two calls over split ranges: any partition gives the same.
    const size_t half = poses.size() / 3;
    const size_t outside =
        s.excludeOutside(poses.data(), half, logLik.data()) +
        s.excludeOutside(poses.data() + half, poses.size() - half, logLik.data() + half);
    size_t expected = 0, in = 0;
    for (size_t i = 0; i < poses.size(); i++)
    {
        const bool c = s.contains(poses[i].x, poses[i].y);
        in += c ? 1 : 0;
        if (before[i] == kNegInf)
        {
            EXPECT_EQ(logLik[i], kNegInf);
        }
        else if (c)
        {
            EXPECT_EQ(logLik[i], before[i]) << i;
        }
        else
        {
            EXPECT_EQ(logLik[i], kNegInf) << i;
            expected++;
        }
    }
    EXPECT_EQ(outside, expected);
    // Both answers occur: the comparison means something.
    EXPECT_GT(expected, poses.size() / 20);
    EXPECT_GT(in, poses.size() / 20);
}
}  // namespace

TEST(FreeSpaceSampler, WorldContainsIsInsideTheBoundsAndFree)
{
    const World w = World::FromFile(kPaper);
    const auto s = FreeSpaceSampler::FromWorld(w);
    const auto poses = posesAround(w, 40000, 3);
    size_t occupiedInBounds = 0;
    for (const auto& p : poses)
    {
        const bool def = w.bounds.contains(p.x, p.y) && w.isFree(p.x, p.y);
        ASSERT_EQ(s.contains(p.x, p.y), def) << p.x << " " << p.y;
        occupiedInBounds += w.bounds.contains(p.x, p.y) && !def ? 1 : 0;
    }
    EXPECT_GT(occupiedInBounds, 0u);  // the outlines are hit
    expectBatchEqualsContains(s, poses);
}

TEST(FreeSpaceSampler, WorldContainsIsExactAtTheCirclesOfCylinders)
{
    // Between a cylinder's circle and its outline polygon (sagitta up to 1 cm): not free.
    const World w = World::FromFile(kPaper);
    const auto s = FreeSpaceSampler::FromWorld(w);
    size_t inSliver = 0, checked = 0;
    for (const auto& o : w.objects)
    {
        if (o.shape != semloc::ShapeType::Cylinder)
        {
            continue;
        }
        const int n = World::cylinderSides(o.radius, semloc::kDefaultCylinderTolerance_m);
        const double chord = o.radius * std::cos(M_PI / n);
        for (int k = 0; k < 8 * n; k++)
        {
            const double a = 2 * M_PI * (k + 0.5) / (8 * n);
            for (const double f : {1 - 1e-3, 1 - 1e-4, 1 - 1e-7, 1 + 1e-7, 1 + 1e-4, 1 + 1e-3})
            {
                const double r = o.radius * f;
                const double x = o.center.x + r * std::cos(a), y = o.center.y + r * std::sin(a);
                ASSERT_EQ(s.contains(x, y), w.isFree(x, y))
                    << "id " << o.id << " at " << x << ", " << y;
                // Beyond the polygon's edge (at angle mid, distance chord from the centre).
                const double mid = (std::floor(a * n / (2 * M_PI)) + 0.5) * 2 * M_PI / n;
                inSliver += f < 1 && r > chord / std::cos(a - mid) ? 1 : 0;
                checked++;
            }
        }
    }
    EXPECT_GT(inSliver, 100u);
    EXPECT_GT(checked, 1000u);
}

TEST(FreeSpaceSampler, A20kmWorldIsExactWithinItsRasterBudget)
{
    const World w = World::FromText(semloc::test::largeWorldYaml(), "large.yaml");
    ASSERT_EQ(w.objects.size(), 300u);
    const auto s = FreeSpaceSampler::FromWorld(w);
    // The raster fits its budget (16 MiB), and uses most of it: 6.4 m cells, 9.8 M of them.
    EXPECT_LE(s.rasterBytes(), FreeSpaceSampler::kMaxWorldRasterCells);
    EXPECT_GE(s.rasterBytes(), FreeSpaceSampler::kMaxWorldRasterCells / 4);
    // contains() is World::isFree: uniform points, and points around every object (the cells
    // an outline crosses, where the exact test decides).
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> u(-10, semloc::test::kLargeWorldSide_m + 10);
    std::uniform_real_distribution<double> near(-1.2, 1.2);
    std::vector<TPose2D> poses;
    poses.reserve(100000 + 300 * w.objects.size());
    for (int i = 0; i < 100000; i++)
    {
        poses.push_back({u(gen), u(gen), 0});
    }
    for (const auto& o : w.objects)
    {
        for (int i = 0; i < 300; i++)
        {
            poses.push_back({o.center.x + near(gen), o.center.y + near(gen), 0});
        }
    }
    size_t occupied = 0;
    for (const auto& p : poses)
    {
        const bool def = w.isFree(p.x, p.y);
        ASSERT_EQ(s.contains(p.x, p.y), def) << p.x << " " << p.y;
        occupied += w.bounds.contains(p.x, p.y) && !def ? 1 : 0;
    }
    EXPECT_GT(occupied, 3000u);
    expectBatchEqualsContains(s, poses);

    // Global initialization: uniform over the free space, exactly (every draw is free), the
    // same draws as World::sampleFreePose; and within a box with a heading interval.
    mrpt::random::CRandomGenerator a(5), b(5);
    size_t quadrant[4] = {0, 0, 0, 0};
    const int kDraws = 20000;
    for (int i = 0; i < kDraws; i++)
    {
        const TPose2D p = s.draw(a);
        const TPose2D q = w.sampleFreePose(b);
        ASSERT_EQ(p.x, q.x);
        ASSERT_EQ(p.y, q.y);
        ASSERT_TRUE(w.isFree(p.x, p.y)) << p.x << " " << p.y;
        quadrant[(p.x < 10000 ? 0 : 1) + (p.y < 10000 ? 0 : 2)]++;
    }
    for (const size_t n : quadrant)
    {
        EXPECT_NEAR(static_cast<double>(n) / kDraws, 0.25, 0.015);
    }
    semloc::TSamplingArea area;
    area.x_min = 9890;  // the survey's objects
    area.x_max = 10110;
    area.y_min = 9985;
    area.y_max = 10055;
    area.yaw_min = 0;
    area.yaw_max = 1;
    const auto boxed = FreeSpaceSampler::FromWorld(w, area);
    for (int i = 0; i < kDraws; i++)
    {
        const TPose2D p = boxed.draw(a);
        ASSERT_TRUE(w.isFree(p.x, p.y) && p.x >= area.x_min && p.x <= area.x_max &&
                    p.y >= area.y_min && p.y <= area.y_max && p.phi >= 0 && p.phi < 1)
            << p.x << " " << p.y << " " << p.phi;
    }
}

TEST(FreeSpaceSampler, GridContainsIsAFreeCell)
{
    const World w = World::FromFile(kPaper);
    const auto grid = w.makeOccupancyGrid(0.25);
    const auto s = FreeSpaceSampler::FromGrid(grid);
    const auto poses = posesAround(w, 40000, 5);
    for (const auto& p : poses)
    {
        // MRPT's cell of (x, y) (x2idx truncates towards 0: x below the origin is outside).
        const int cx = grid.x2idx(p.x), cy = grid.y2idx(p.y);
        const bool def = p.x >= grid.getXMin() && p.y >= grid.getYMin() &&
                         cx < static_cast<int>(grid.getSizeX()) &&
                         cy < static_cast<int>(grid.getSizeY()) &&
                         grid.getCell(cx, cy) >= static_cast<double>(0.7f);
        ASSERT_EQ(s.contains(p.x, p.y), def) << p.x << " " << p.y;
    }
    expectBatchEqualsContains(s, poses);
}

TEST(FreeSpaceSampler, BoxContainsIsInsideTheBoxBordersIncluded)
{
    semloc::TSamplingArea a;
    a.x_min = 10;
    a.x_max = 20.5;
    a.y_min = -4;
    a.y_max = 7;
    const auto s = FreeSpaceSampler::FromBox(a);
    EXPECT_TRUE(s.contains(10, -4));
    EXPECT_TRUE(s.contains(20.5, 7));
    EXPECT_FALSE(s.contains(std::nextafter(10.0, 0.0), 0));
    EXPECT_FALSE(s.contains(15, std::nextafter(7.0, 8.0)));
    EXPECT_FALSE(s.contains(std::numeric_limits<double>::quiet_NaN(), 0));
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> x(5, 25), y(-10, 12);
    std::vector<TPose2D> poses;
    for (int i = 0; i < 10000; i++)
    {
        poses.push_back({x(gen), y(gen), 0});
        const auto& p = poses.back();
        ASSERT_EQ(s.contains(p.x, p.y), p.x >= 10 && p.x <= 20.5 && p.y >= -4 && p.y <= 7);
    }
    expectBatchEqualsContains(s, poses);
}

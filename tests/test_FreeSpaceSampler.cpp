/* semloc tests — FreeSpaceSampler: contains() against its definition per kind, and the
 * filter's batch excludeOutside() against contains(). */
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <semloc/FreeSpaceSampler.h>
#include <semloc/World.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

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

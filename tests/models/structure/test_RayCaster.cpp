/* semloc tests — RayCaster: exact casts, grid walk identical to brute force. */
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/structure/RayCaster.h>
#include <semloc/world/World.h>

#include <cmath>
#include <thread>
#include <vector>

using mrpt::math::TPoint2D;
using mrpt::math::TSegment2D;
using semloc::RayCaster;

namespace
{
constexpr double kTol = 1e-9;

std::vector<TSegment2D> unitSquare(double cx, double cy, double half)
{
    const TPoint2D a(cx - half, cy - half), b(cx + half, cy - half), c(cx + half, cy + half),
        d(cx - half, cy + half);
    return {{a, b}, {b, c}, {c, d}, {d, a}};
}

/** Segments that stress the grid: axis-aligned edges on cell borders (cell 1 m), shared
 *  vertices on grid corners, a long diagonal, a fan of segments from one vertex, tiny and
 *  zero-length segments, plus random ones. */
std::vector<TSegment2D> stressSegments(mrpt::random::CRandomGenerator& rng)
{
    std::vector<TSegment2D> s;
    for (int k = 0; k < 5; k++)
    {
        const auto sq = unitSquare(3 + 4 * k, 3, 1.0);  // corners on integer (grid) points
        s.insert(s.end(), sq.begin(), sq.end());
    }
    s.emplace_back(TPoint2D(0, 10), TPoint2D(20, 10));  // on a row of cell borders
    s.emplace_back(TPoint2D(10, 0), TPoint2D(10, 20));  // on a column of cell borders
    s.emplace_back(TPoint2D(0.5, 0.5), TPoint2D(19.5, 19.5));
    for (int k = 0; k < 12; k++)
    {
        const double a = k * M_PI / 6;
        s.emplace_back(TPoint2D(15, 15), TPoint2D(15 + 2 * std::cos(a), 15 + 2 * std::sin(a)));
    }
    s.emplace_back(TPoint2D(7, 17), TPoint2D(7 + 1e-7, 17));
    s.emplace_back(TPoint2D(8, 18), TPoint2D(8, 18));
    for (int k = 0; k < 150; k++)
    {
        const TPoint2D p(rng.drawUniform(0.0, 20.0), rng.drawUniform(0.0, 20.0));
        const double a = rng.drawUniform(-M_PI, M_PI), l = rng.drawUniform(0.05, 3.0);
        s.emplace_back(p, TPoint2D(p.x + l * std::cos(a), p.y + l * std::sin(a)));
    }
    return s;
}

void expectSame(const RayCaster& rc, double x, double y, double a, double R, int& n)
{
    const double fast = rc.cast(x, y, a, R);
    const double ref = rc.castBruteForce(x, y, a, R);
    ASSERT_NEAR(fast, ref, kTol) << "ray from (" << x << ", " << y << ") angle " << a;
    ASSERT_GE(fast, 0.0);
    ASSERT_LE(fast, R);
    n++;
}

}  // namespace

TEST(RayCaster, KnownAnswers)
{
    const RayCaster rc(unitSquare(0, 0, 0.5));
    EXPECT_NEAR(rc.cast(0, 0, 0, 10), 0.5, 1e-12);
    EXPECT_NEAR(rc.cast(0, 0, M_PI / 2, 10), 0.5, 1e-12);
    EXPECT_NEAR(rc.cast(0, 0, M_PI / 4, 10), std::sqrt(0.5), 1e-12);  // through a corner
    EXPECT_NEAR(rc.cast(-3, 0, 0, 10), 2.5, 1e-12);                   // from outside the grid
    EXPECT_NEAR(rc.cast(-3, 0.5, 0, 10), 2.5, 1e-12);  // along the top edge's line: its end
    EXPECT_NEAR(rc.cast(0, 0.5, 0, 10), 0.0, 1e-12);   // starting on an edge
    EXPECT_EQ(rc.cast(-3, 0, M_PI, 10), 10.0);         // away from everything
    EXPECT_EQ(rc.cast(-3, 0, 0, 2.0), 2.0);            // hit beyond the max range
    EXPECT_EQ(rc.cast(-3, 2, 0, 10), 10.0);            // passes above
    const RayCaster empty;
    EXPECT_TRUE(empty.empty());
    EXPECT_EQ(empty.cast(0, 0, 0, 7.5), 7.5);
}

TEST(RayCaster, RandomRaysEqualBruteForce)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1234);
    const auto segs = stressSegments(rng);
    for (const double cell : {0.0, 1.0, 0.37, 5.0})
    {
        const RayCaster rc(segs, cell);
        int n = 0;
        for (int i = 0; i < 4000; i++)
        {
            // Origins inside and around the grid, any direction, several ranges.
            const double x = rng.drawUniform(-5.0, 25.0), y = rng.drawUniform(-5.0, 25.0);
            const double a = rng.drawUniform(-M_PI, M_PI);
            expectSame(rc, x, y, a, i % 3 == 0 ? 4.0 : 40.0, n);
        }
        EXPECT_EQ(n, 4000);
    }
}

TEST(RayCaster, RaysThroughVerticesAndAlongEdgesEqualBruteForce)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(99);
    const auto segs = stressSegments(rng);
    const RayCaster rc(segs, 1.0);
    int n = 0;
    for (const auto& s : segs)
    {
        for (const auto& v : {s.point1, s.point2})
        {
            // Through the vertex from random origins.
            for (int k = 0; k < 8; k++)
            {
                const double x = rng.drawUniform(-3.0, 23.0), y = rng.drawUniform(-3.0, 23.0);
                expectSame(rc, x, y, std::atan2(v.y - y, v.x - x), 40, n);
            }
        }
        // Along the edge: from beyond either end, and from its middle, both ways.
        const double ex = s.point2.x - s.point1.x, ey = s.point2.y - s.point1.y;
        if (ex == 0 && ey == 0)
        {
            continue;
        }
        const double a = std::atan2(ey, ex);
        expectSame(rc, s.point1.x - 0.7 * ex, s.point1.y - 0.7 * ey, a, 40, n);
        expectSame(rc, s.point2.x + 0.7 * ex, s.point2.y + 0.7 * ey, a + M_PI, 40, n);
        expectSame(rc, s.point1.x + 0.5 * ex, s.point1.y + 0.5 * ey, a, 40, n);
        expectSame(rc, s.point1.x + 0.5 * ex, s.point1.y + 0.5 * ey, a + M_PI, 40, n);
    }
    // Along grid lines and through grid corners (cell borders at integers).
    for (int k = 0; k <= 20; k++)
    {
        for (const double a : {0.0, M_PI / 2, M_PI, -M_PI / 2, M_PI / 4, -3 * M_PI / 4})
        {
            expectSame(rc, -1.0, k, a, 40, n);
            expectSame(rc, k, -1.0, a, 40, n);
            expectSame(rc, k, k, a, 40, n);
        }
    }
    EXPECT_GT(n, 2000);
}

TEST(RayCaster, PaperWorldEqualsBruteForce)
{
    const auto world = semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    const RayCaster rc(world.outlineSegments());
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(7);
    int n = 0;
    for (int i = 0; i < 3000; i++)
    {
        const auto p = world.sampleFreePose(rng);
        expectSame(rc, p.x, p.y, p.phi, 20, n);
    }
    EXPECT_EQ(n, 3000);
}

TEST(RayCaster, ConstCastsAreThreadSafe)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(5);
    const RayCaster rc(stressSegments(rng));
    std::vector<double> xs, ys, as, serial;
    for (int i = 0; i < 20000; i++)
    {
        xs.push_back(rng.drawUniform(0.0, 20.0));
        ys.push_back(rng.drawUniform(0.0, 20.0));
        as.push_back(rng.drawUniform(-M_PI, M_PI));
        serial.push_back(rc.cast(xs.back(), ys.back(), as.back(), 30));
    }
    std::vector<double> out(xs.size());
    auto work = [&](size_t from, size_t to)
    {
        for (size_t i = from; i < to; i++)
        {
            out[i] = rc.cast(xs[i], ys[i], as[i], 30);
        }
    };
    std::thread t1(work, 0, xs.size() / 2), t2(work, xs.size() / 2, xs.size());
    t1.join();
    t2.join();
    EXPECT_EQ(out, serial);
}

// A map with one far vertex (at the world's coordinate bound) spans an elongated bounding box:
// the grid keeps at most 4096 cells along its width plus height, so that the far segment does
// not fill a row of hundreds of thousands of cells (each a copy of it), and the casts stay
// those of brute force.
TEST(RayCaster, FarVertexKeepsTheGridNarrow)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(99);
    auto segs = stressSegments(rng);
    segs.emplace_back(TPoint2D(20, 20), TPoint2D(1e7, 20));
    for (const double cell : {0.0, 0.05})
    {
        const RayCaster rc(segs, cell);
        EXPECT_LE(rc.gridCellsX() + rc.gridCellsY(), 4096) << "cell " << cell;
        int n = 0;
        for (int i = 0; i < 2000; i++)
        {
            const double x = rng.drawUniform(-5.0, 25.0), y = rng.drawUniform(-5.0, 25.0);
            expectSame(rc, x, y, rng.drawUniform(-M_PI, M_PI), i % 2 ? 4.0 : 2e7, n);
        }
        EXPECT_EQ(n, 2000);
    }
}

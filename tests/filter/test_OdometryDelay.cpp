/* semloc tests — an odometry the vehicle follows late: the increments re-cut over the delayed
 * interval, against a vehicle integrated finely from its commands; the history it keeps; the
 * inputs it refuses. */
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <semloc/filter/OdometryDelay.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using mrpt::math::TPose2D;
using semloc::OdometryDelay;

namespace
{
/** Commands that change at whole seconds: (v, w) over (k, k + 1]. */
struct Commands
{
    std::vector<double> v, w;
    /** The pose reached from `from` at time a by the commands over (a, b], integrated in
     *  1e-4 s steps (an oracle independent of the twists). */
    TPose2D move(double a, double b) const
    {
        mrpt::poses::CPose2D p;
        const double h = 1e-4;
        for (double t = a; t < b - 1e-12; t += h)
        {
            const double dt = std::min(h, b - t);
            const auto k = static_cast<long>(std::floor(t + dt / 2));
            const double vk = (k >= 0 && k < static_cast<long>(v.size())) ? v[k] : 0;
            const double wk = (k >= 0 && k < static_cast<long>(w.size())) ? w[k] : 0;
            p = p + mrpt::poses::CPose2D(OdometryDelay::expTwist(vk, 0, wk, dt));
        }
        return p.asTPose();
    }
};

void expectNear(const TPose2D& a, const TPose2D& b, double tol)
{
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(std::remainder(a.phi - b.phi, 2 * M_PI), 0, tol);
}
}  // namespace

TEST(OdometryDelay, ExpAndLogAreInverse)
{
    for (const TPose2D u : {TPose2D{0.3, -0.1, 0.7}, TPose2D{1, 0, 0}, TPose2D{0, 0, -2.5},
                            TPose2D{0.2, 0.05, 1e-7}, TPose2D{-0.4, 0.3, 3.0}})
    {
        double vx = 0, vy = 0, w = 0;
        OdometryDelay::logIncrement(u, vx, vy, w);
        expectNear(OdometryDelay::expTwist(vx, vy, w, 1.0), u, 1e-12);
        // Half the twist twice is the whole increment.
        const mrpt::poses::CPose2D half(OdometryDelay::expTwist(vx, vy, w, 0.5));
        expectNear((half + half).asTPose(), u, 1e-12);
    }
}

TEST(OdometryDelay, NoDelayGivesTheIncrementsAsTheyCome)
{
    OdometryDelay delay(0);
    const std::vector<TPose2D> us = {{0, 0, 0}, {0.1, 0.01, 0.2}, {0.3, -0.2, -1.1}};
    double t = 10;
    for (const auto& u : us)
    {
        const TPose2D out = delay.step(t, u);
        EXPECT_EQ(out.x, u.x);
        EXPECT_EQ(out.y, u.y);
        EXPECT_EQ(out.phi, u.phi);
        t += 0.37;
    }
}

TEST(OdometryDelay, ReCutsTheIncrementsOverTheDelayedInterval)
{
    // Drive straight, turn on the spot, arc, stop: commands change at whole seconds.
    Commands c;
    c.v = {0.5, 0.5, 0.0, 0.3, 0.3, 0.4, 0.0, 0.2};
    c.w = {0.0, 0.1, 1.2, -0.4, -0.4, 0.0, 0.0, 0.3};
    // Steps whose ends are the changes and points between them, of uneven lengths.
    const std::vector<double> times = {0, 0.5, 1, 2, 2.25, 3, 3.1, 4, 5, 5.6, 6, 7, 8};
    for (const double d : {0.25, 0.5, 1.0, 1.7})
    {
        OdometryDelay delay(d);
        mrpt::poses::CPose2D total;
        for (size_t k = 0; k < times.size(); k++)
        {
            const double a = k == 0 ? times[0] : times[k - 1], b = times[k];
            const TPose2D u = c.move(a, b);
            const TPose2D out = delay.step(b, u);
            // What the vehicle did over (a, b]: the commands of (a - d, b - d].
            expectNear(out, c.move(a - d, b - d), 1e-6);
            total = total + mrpt::poses::CPose2D(out);
        }
        // All of it: where the commands had the vehicle d seconds before the end.
        expectNear(total.asTPose(), c.move(0, times.back() - d), 1e-6);
    }
}

TEST(OdometryDelay, AStepOfNoDurationIsAnIncrementAtItsTime)
{
    OdometryDelay delay(0.5);
    delay.step(0, {0, 0, 0});
    expectNear(delay.step(1, {0, 0, 0}), {0, 0, 0}, 1e-15);
    // A jump of the odometry at t = 1 (a repeated timestamp's increment).
    expectNear(delay.step(1, {0.2, 0, 0.1}), {0, 0, 0}, 1e-15);
    expectNear(delay.step(1.4, {0, 0, 0}), {0, 0, 0}, 1e-15);
    expectNear(delay.step(1.6, {0, 0, 0}), {0.2, 0, 0.1}, 1e-15);
    expectNear(delay.step(3, {0, 0, 0}), {0, 0, 0}, 1e-15);
}

TEST(OdometryDelay, KeepsAHistoryOfTheDelayOnlyAndStartsAgainOnReset)
{
    OdometryDelay delay(0.3);
    double t = 0;
    size_t most = 0;
    for (int k = 0; k < 100000; k++)
    {
        delay.step(t, {0.01, 0, 0.001});
        most = std::max(most, delay.history());
        t += 0.1;
    }
    // 0.3 s of 0.1 s steps: the step being cut and the three before it, at most.
    EXPECT_LE(most, 5U);
    delay.reset();
    EXPECT_EQ(delay.history(), 0U);
    // After a reset the first step starts the history again, even at an earlier time.
    const TPose2D first = delay.step(0, {0.5, 0, 0});
    EXPECT_EQ(first.x, 0.5);
    expectNear(delay.step(1, {1, 0, 0}), {0.7, 0, 0}, 1e-12);
}

TEST(OdometryDelay, RefusesWhatItCannotCut)
{
    // (A function, not a statement OdometryDelay(x);, which clang may read as a declaration.)
    const auto make = [](double d) { return OdometryDelay(d); };
    EXPECT_THROW(make(-0.1), std::invalid_argument);
    EXPECT_THROW(make(OdometryDelay::kMaxDelay_s * 2), std::invalid_argument);
    EXPECT_THROW(make(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    OdometryDelay delay(0.2);
    delay.step(5, {0, 0, 0});
    EXPECT_THROW(delay.step(4.9, {0, 0, 0}), std::invalid_argument);
    EXPECT_THROW(delay.step(std::numeric_limits<double>::quiet_NaN(), {0, 0, 0}),
                 std::invalid_argument);
}

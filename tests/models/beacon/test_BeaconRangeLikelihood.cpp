/* semloc — MRPT's CBeaconMap likelihood of beacon ranges with each range's beacon looked up
 * once per frame (detail::BeaconRangeTerm, SensoryFrameLikelihood's path for CBeaconMap):
 * MRPT's value bit for bit, and a cost of the ranges alone, however many beacons the map
 * holds beyond the sensor's range. */
#include <gtest/gtest.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/SensoryFrameLikelihood.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "models/beacon/BeaconRangeLikelihood.h"

namespace
{
using mrpt::maps::CBeacon;
using mrpt::maps::CBeaconMap;
using mrpt::obs::CObservationBeaconRanges;
using mrpt::poses::CPose3D;

/** True when a and b are the same double, bit for bit, where semloc is built by the compiler
 *  that built Debian's MRPT (GCC). Under clang (the sanitized build) MRPT's GCC code and ours
 *  round some steps differently: there the same value within 1e-6 relative. */
bool sameBits(double a, double b)
{
    uint64_t ua = 0, ub = 0;
    std::memcpy(&ua, &a, sizeof a);
    std::memcpy(&ub, &b, sizeof b);
#if defined(__clang__)
    if (ua != ub && std::isfinite(a) && std::isfinite(b))
    {
        return std::abs(a - b) <= 1e-6 * std::max(std::abs(a), std::abs(b));
    }
#endif
    return ua == ub;
}

CBeacon gaussBeacon(int64_t id, double x, double y, double z, double var = 1e-6)
{
    CBeacon b;
    b.m_ID = id;
    b.m_typePDF = CBeacon::pdfGauss;
    b.m_locationGauss.mean = mrpt::poses::CPoint3D(x, y, z);
    b.m_locationGauss.cov.setZero();
    for (int i = 0; i < 3; i++)
    {
        b.m_locationGauss.cov(i, i) = var;
    }
    return b;
}

CObservationBeaconRanges::TMeasurement range(int32_t id, float r, double sx = 0, double sy = 0)
{
    CObservationBeaconRanges::TMeasurement m;
    m.beaconID = id;
    m.sensedDistance = r;
    m.sensorLocationOnRobot = mrpt::poses::CPoint3D(sx, sy, 0);
    return m;
}

/** Beacons 1..3 around the paper area, 10 m below, and (with `far`) `far` more on a grid
 *  kilometres away: none within the 200 m of the sensor. */
CBeaconMap::Ptr paperBeacons(size_t far)
{
    auto map = CBeaconMap::Create();
    map->likelihoodOptions.rangeStd = 0.5;
    map->push_back(gaussBeacon(1, -5, -5, -10));
    map->push_back(gaussBeacon(2, 55, -5, -10));
    map->push_back(gaussBeacon(3, 25, 55, -10));
    for (size_t k = 0; k < far; k++)
    {
        const size_t column = k % 300, row = k / 300;
        map->push_back(gaussBeacon(static_cast<int64_t>(100 + k),
                                   1000.0 + 30.0 * static_cast<double>(column),
                                   1000.0 + 30.0 * static_cast<double>(row), -10));
    }
    return map;
}

CObservationBeaconRanges::Ptr paperRanges()
{
    auto obs = CObservationBeaconRanges::Create();
    obs->maxSensorDistance = 200;
    obs->sensedData.push_back(range(1, 21.5f));
    obs->sensedData.push_back(range(2, 40.25f, 0.3, -0.1));
    obs->sensedData.push_back(range(3, 35.0f));
    return obs;
}

std::vector<CPose3D> somePoses(size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(-10, 60), phi(-M_PI, M_PI);
    std::vector<CPose3D> poses;
    for (size_t i = 0; i < n; i++)
    {
        poses.emplace_back(mrpt::math::TPose3D(mrpt::math::TPose2D(xy(rng), xy(rng), phi(rng))));
    }
    return poses;
}
}  // namespace

TEST(BeaconRangeLikelihood, IsMrptsValueBitForBit)
{
    // Random Gaussian beacons (full covariances), ranges to some of them from transducers
    // off the vehicle's centre, to unknown ids, of 0, negative and NaN: MRPT's value, the
    // same bits, at random 2D and 3D poses.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-50, 50), v(0.0, 0.2);
    auto map = CBeaconMap::Create();
    map->likelihoodOptions.rangeStd = 0.37;
    for (int id = 0; id < 40; id++)
    {
        CBeacon b = gaussBeacon(id, u(rng), u(rng), 0.2 * u(rng));
        mrpt::math::CMatrixDouble33 a;
        for (int i = 0; i < 3; i++)
        {
            for (int j = 0; j < 3; j++)
            {
                a(i, j) = v(rng);
            }
        }
        b.m_locationGauss.cov = mrpt::math::CMatrixDouble33(a.asEigen() * a.asEigen().transpose());
        map->push_back(b);
    }
    map->push_back(gaussBeacon(5, 1e3, 1e3, 0));  // a second id 5: MRPT scores the first
    auto obs = CObservationBeaconRanges::Create();
    obs->minSensorDistance = 0.5f;
    obs->maxSensorDistance = 150;
    std::uniform_int_distribution<int> id(0, 45);
    std::uniform_real_distribution<float> r(0.0f, 90.0f);
    for (int k = 0; k < 30; k++)
    {
        obs->sensedData.push_back(range(id(rng), r(rng), 0.1 * u(rng), 0.1 * u(rng)));
    }
    obs->sensedData.push_back(range(3, 0.0f));
    obs->sensedData.push_back(range(4, -1.0f));
    obs->sensedData.push_back(range(7, std::numeric_limits<float>::quiet_NaN()));

    const semloc::detail::BeaconIdIndex index(*map);
    semloc::detail::BeaconRangeTerm term;
    ASSERT_TRUE(term.plan(*map, index, *obs));
    auto poses = somePoses(500, 11);
    std::uniform_real_distribution<double> tilt(-0.3, 0.3);
    for (size_t i = 0; i < 100; i++)
    {
        poses.emplace_back(u(rng), u(rng), u(rng) * 0.1, tilt(rng) * 10, tilt(rng), tilt(rng));
    }
    for (const auto& p : poses)
    {
        const double mrpt = map->computeObservationLikelihood(*obs, p);
        const double ours = term.logLikelihood(p);
        ASSERT_TRUE(sameBits(ours, mrpt)) << ours << " vs MRPT's " << mrpt << " at " << p;
    }
}

TEST(BeaconRangeLikelihood, BeaconsOutOfRangeAreNotScored)
{
    // 100 000 beacons far away beside the three that answered: the same likelihood, bit for
    // bit, as the map of the three, and three beacons scored per pose, not 100 003.
    const auto near = paperBeacons(0), all = paperBeacons(100000);
    const auto obs = paperRanges();
    const semloc::detail::BeaconIdIndex nearIndex(*near), allIndex(*all);
    semloc::detail::BeaconRangeTerm nearTerm, allTerm;
    ASSERT_TRUE(nearTerm.plan(*near, nearIndex, *obs));
    ASSERT_TRUE(allTerm.plan(*all, allIndex, *obs));
    EXPECT_EQ(nearTerm.beaconsScored(), 3u);
    EXPECT_EQ(allTerm.beaconsScored(), 3u);
    for (const auto& p : somePoses(50, 3))
    {
        const double a = allTerm.logLikelihood(p);
        ASSERT_TRUE(sameBits(a, nearTerm.logLikelihood(p))) << p;
        ASSERT_TRUE(sameBits(a, near->computeObservationLikelihood(*obs, p))) << p;
    }
    for (const auto& p : somePoses(3, 4))  // MRPT's own, looking through every beacon
    {
        ASSERT_TRUE(sameBits(allTerm.logLikelihood(p), all->computeObservationLikelihood(*obs, p)));
    }
}

TEST(BeaconRangeLikelihood, UnknownIdsAndBadRangesScoreNoBeacon)
{
    auto obs = CObservationBeaconRanges::Create();
    obs->maxSensorDistance = 200;
    obs->sensedData.push_back(range(99, 10));  // no such beacon
    obs->sensedData.push_back(range(1, 0));    // not a range
    obs->sensedData.push_back(range(2, 30));
    const auto map = paperBeacons(10);
    const semloc::detail::BeaconIdIndex index(*map);
    semloc::detail::BeaconRangeTerm term;
    ASSERT_TRUE(term.plan(*map, index, *obs));
    EXPECT_EQ(term.beaconsScored(), 1u);
    for (const auto& p : somePoses(20, 5))
    {
        ASSERT_TRUE(sameBits(term.logLikelihood(p), map->computeObservationLikelihood(*obs, p)));
    }
}

TEST(BeaconRangeLikelihood, NonGaussianBeaconsAndNonFiniteValuesAreLeftToMrpt)
{
    auto map = paperBeacons(0);
    (*map)[1].m_typePDF = CBeacon::pdfSOG;
    const auto obs = paperRanges();
    semloc::detail::BeaconRangeTerm term;
    EXPECT_FALSE(term.plan(*map, semloc::detail::BeaconIdIndex(*map), *obs));

    // The vehicle's transducer on a beacon: MRPT throws on the NaN it gets, and so does the
    // term (by MRPT's call).
    const auto at = paperBeacons(0);
    auto on = CObservationBeaconRanges::Create();
    on->maxSensorDistance = 200;
    on->sensedData.push_back(range(1, 3));
    const semloc::detail::BeaconIdIndex index(*at);
    ASSERT_TRUE(term.plan(*at, index, *on));
    const CPose3D pose(-5, -5, -10, 0, 0, 0);
    EXPECT_ANY_THROW((void)at->computeObservationLikelihood(*on, pose));
    EXPECT_ANY_THROW((void)term.logLikelihood(pose));
}

TEST(BeaconRangeLikelihood, IndexFollowsTheMapsBeacons)
{
    auto map = paperBeacons(0);
    const semloc::detail::BeaconIdIndex index(*map);
    EXPECT_TRUE(index.matches(*map));
    ASSERT_NE(index.find(*map, 2), nullptr);
    EXPECT_EQ(index.find(*map, 2)->m_ID, 2);
    EXPECT_EQ(index.find(*map, 4), nullptr);
    map->push_back(gaussBeacon(4, 0, 0, 0));
    EXPECT_FALSE(index.matches(*map));
    EXPECT_NE(semloc::detail::BeaconIdIndex(*map).find(*map, 4), nullptr);
}

TEST(BeaconRangeLikelihood, FrameLikelihoodWithManyBeaconsIsMrpts)
{
    // Through SensoryFrameLikelihood (the filter's sensor model), with the far beacons: MRPT's
    // 1 + term at each pose, on 1 and 2 threads.
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    const auto beacons = paperBeacons(20000);
    multi->maps.push_back(beacons);
    mrpt::obs::CSensoryFrame sf;
    sf.insert(paperRanges());
    std::vector<mrpt::math::TPose2D> poses;
    for (const auto& p : somePoses(600, 9))
    {
        poses.emplace_back(p.x(), p.y(), p.yaw());
    }
    for (size_t threads : {1u, 2u})
    {
        semloc::ParallelExecutor executor(threads);
        semloc::SensoryFrameLikelihood lik(*multi);
        std::vector<double> out(poses.size());
        lik.evaluate(sf, poses.data(), poses.size(), out.data(), executor);
        for (size_t i = 0; i < poses.size(); i += 37)
        {
            const double mrpt =
                1 + beacons->computeObservationLikelihood(*sf.getObservationByIndex(0),
                                                          CPose3D(mrpt::math::TPose3D(poses[i])));
            ASSERT_TRUE(sameBits(out[i], mrpt)) << i;
        }
    }
}

TEST(BeaconRangeLikelihood, OnlyBeaconRangesCountAsUsedByABeaconMap)
{
    // A beacon map scores beacon ranges alone: a sonar scan beside them is skipped (no map
    // scores it), as with a semantic map.
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(paperBeacons(0));
    mrpt::obs::CSensoryFrame sf;
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->resizeScan(3);
    sf.insert(scan);
    sf.insert(paperRanges());
    const std::vector<mrpt::math::TPose2D> poses = {{20, 20, 0}};
    std::vector<double> out(1);
    semloc::ParallelExecutor executor(1);
    semloc::SensoryFrameLikelihood lik(*multi);
    lik.evaluate(sf, poses.data(), poses.size(), out.data(), executor);
    EXPECT_EQ(lik.stats().observations_used, 1u);
    EXPECT_EQ(lik.stats().observations_skipped, 1u);
}

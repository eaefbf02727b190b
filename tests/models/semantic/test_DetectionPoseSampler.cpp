/* semloc tests — DetectionPoseSampler: every drawn pose sees a map object at the detection's
 * range and bearing (sensor pose on the vehicle included), spread around the object, and
 * detections the likelihood skips give nothing to draw from. */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionPoseSampler.h>

#include <cmath>

#include "TestHelpers.h"

using mrpt::math::TPose2D;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;
using semloc::DetectionPoseSampler;
using semloc::TSemanticDetection;
using semloc::test::detection;

namespace
{
CSemanticMap map3()
{
    CSemanticMap m;
    m.addObject({1, "pillar", 5, 0, 0, 0.3, 1});
    m.addObject({2, "pillar", 20, 10, 0, 0.3, 1});
    m.addObject({3, "anchor", -4, 7, 0, 0.3, 1});
    return m;
}

/** An observation with the detector off-centre and turned on the vehicle. */
CObservationSemantic observation()
{
    CObservationSemantic obs;
    obs.sensorPose = mrpt::poses::CPose3D(0.8, -0.3, 0.5, 0.4, 0, 0);
    obs.maxRange_m = 20;
    obs.fov_rad = 2 * M_PI / 3;
    return obs;
}

/** Range and bearing of (ox, oy) from the detector of `obs` on a vehicle at `v`. */
void rangeBearing(const CObservationSemantic& obs, const TPose2D& v, double ox, double oy,
                  double& r, double& b)
{
    const double c = std::cos(v.phi), s = std::sin(v.phi);
    const double sx = v.x + c * obs.sensorPose.x() - s * obs.sensorPose.y();
    const double sy = v.y + s * obs.sensorPose.x() + c * obs.sensorPose.y();
    r = std::hypot(ox - sx, oy - sy);
    b = mrpt::math::wrapToPi(std::atan2(oy - sy, ox - sx) - v.phi - obs.sensorPose.yaw());
}
}  // namespace

TEST(DetectionPoseSampler, NoiselessPosesSeeTheObjectAtTheDetectedRangeAndBearing)
{
    auto map = map3();
    map.likelihoodOptions.detector.sigma_range_m = 0;
    map.likelihoodOptions.detector.sigma_bearing_deg = 0;
    auto obs = observation();
    obs.detections = {detection("pillar", 6.5, 0.3), detection("anchor", 3.0, -0.5)};
    const DetectionPoseSampler sampler(map, obs);
    ASSERT_FALSE(sampler.empty());
    mrpt::random::CRandomGenerator rng(3);
    int pillar1 = 0, pillar2 = 0, anchor = 0;
    double sumCos = 0, sumSin = 0;
    for (int i = 0; i < 3000; i++)
    {
        const TPose2D v = sampler.draw(rng);
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::abs(v.phi) <= M_PI);
        double r = 0, b = 0;
        // Which object it explains: exactly one (the three are far apart).
        int explained = 0;
        for (const auto& o : map.objects())
        {
            rangeBearing(obs, v, o.x, o.y, r, b);
            const double rDet = o.label == "pillar" ? 6.5 : 3.0;
            const double bDet = o.label == "pillar" ? 0.3 : -0.5;
            if (std::abs(r - rDet) < 1e-9 && std::abs(b - bDet) < 1e-9)
            {
                explained++;
                pillar1 += o.id == 1;
                pillar2 += o.id == 2;
                anchor += o.id == 3;
                // Where on the circle around the object: should cover every direction.
                sumCos += (v.x - o.x) / r;
                sumSin += (v.y - o.y) / r;
            }
        }
        ASSERT_EQ(explained, 1) << "pose " << v.x << " " << v.y << " " << v.phi;
    }
    // Detections uniformly, then objects of the label uniformly: 1/4, 1/4, 1/2.
    EXPECT_NEAR(pillar1 / 3000.0, 0.25, 0.03);
    EXPECT_NEAR(pillar2 / 3000.0, 0.25, 0.03);
    EXPECT_NEAR(anchor / 3000.0, 0.5, 0.03);
    EXPECT_LT(std::hypot(sumCos, sumSin) / 3000.0, 0.1) << "not spread around the objects";
}

TEST(DetectionPoseSampler, NoiseFollowsTheMapsLikelihoodSigmas)
{
    auto map = map3();
    map.likelihoodOptions.detector.sigma_range_m = 0.5;
    map.likelihoodOptions.detector.sigma_bearing_deg = 3;
    auto obs = observation();
    obs.detections = {detection("anchor", 8.0, 0.2)};
    const DetectionPoseSampler sampler(map, obs);
    mrpt::random::CRandomGenerator rng(4);
    const int n = 4000;
    double sr = 0, sr2 = 0, sb = 0, sb2 = 0;
    for (int i = 0; i < n; i++)
    {
        double r = 0, b = 0;
        rangeBearing(obs, sampler.draw(rng), -4, 7, r, b);
        sr += r - 8.0;
        sr2 += (r - 8.0) * (r - 8.0);
        sb += b - 0.2;
        sb2 += (b - 0.2) * (b - 0.2);
    }
    EXPECT_NEAR(sr / n, 0, 0.05);
    EXPECT_NEAR(std::sqrt(sr2 / n), 0.5, 0.05);
    EXPECT_NEAR(sb / n, 0, 0.01);
    EXPECT_NEAR(std::sqrt(sb2 / n), 3 * M_PI / 180, 0.005);
}

TEST(DetectionPoseSampler, IdsAreHonouredAndSkippedDetectionsGiveNothing)
{
    auto map = map3();
    map.likelihoodOptions.detector.sigma_range_m = 0;
    map.likelihoodOptions.detector.sigma_bearing_deg = 0;
    auto obs = observation();
    // Unknown label, beyond max range, outside the field of view, NaN: nothing to draw.
    obs.detections = {detection("boulder", 5, 0), detection("pillar", 25, 0),
                      detection("pillar", 5, 2.0), detection("anchor", std::nan(""), 0)};
    EXPECT_TRUE(DetectionPoseSampler(map, obs).empty());
    // A detection that names object 2: only that pillar.
    obs.detections = {detection("pillar", 4, 0.1, 2)};
    const DetectionPoseSampler sampler(map, obs);
    ASSERT_FALSE(sampler.empty());
    mrpt::random::CRandomGenerator rng(5);
    for (int i = 0; i < 200; i++)
    {
        double r = 0, b = 0;
        rangeBearing(obs, sampler.draw(rng), 20, 10, r, b);
        ASSERT_NEAR(r, 4, 1e-9);
        ASSERT_NEAR(b, 0.1, 1e-9);
    }
}

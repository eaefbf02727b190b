/* semloc tests — a sensor model defined here only, plugged into the filter through
 * BatchLikelihood (docs/design.md, "Adding a sensor model"): a position fix (MRPT's
 * CObservationRobotPose, e.g. a surfaced AUV's GPS or a USBL fix) scored by a map of this
 * test's own, with no line of the filter changed. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/SensoryFrameLikelihood.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include "filter/PositionFixModel.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

namespace
{
using mrpt::math::TPose2D;

using semloc::test::fixFrame;
using semloc::test::forward;
using semloc::test::PositionFixModel;

struct FixRun
{
    std::vector<TPose2D> particles;
    double error = 0;
    size_t batchCalls = 0;
};

/** 30 steps east along y = 5 from a start uniform over 20 x 20 m (the heading known within
 *  0.2 rad: a fix tells the position only), a fix (0.5 m) each step. */
FixRun localize(size_t threads)
{
    auto model = std::make_shared<PositionFixModel>();
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(model);
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    pdf.setExecutor(std::make_shared<semloc::ParallelExecutor>(threads));
    mrpt::random::getRandomGenerator().randomize(5);
    pdf.resetUniform(0, 20, 0, 20, -0.2, 0.2, 3000);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    mrpt::random::CRandomGenerator noise(11);
    TPose2D truth(2, 5, 0);
    for (int k = 0; k < 30; k++)
    {
        truth.x += 0.4;
        const auto acts = forward(0.4);
        auto sf = fixFrame(truth.x + 0.5 * noise.drawGaussian1D_normalized(),
                           truth.y + 0.5 * noise.drawGaussian1D_normalized(), 0.5);
        pf.executeOn(pdf, &acts, &sf);
    }
    FixRun r;
    const auto mean = pdf.getMeanVal();
    r.error = std::hypot(mean.x() - truth.x, mean.y() - truth.y);
    for (size_t i = 0; i < pdf.size(); i++)
    {
        r.particles.push_back(pdf.m_particles[i].d);
    }
    r.batchCalls = model->batchCalls.load();
    return r;
}
/** The position fix offering its recovery hook: poses within the fix's spread of its position,
 *  any heading (a fix tells the position only). */
class ProposingFixModel : public PositionFixModel
{
public:
    class FixProposal : public semloc::BatchLikelihood::PoseProposal
    {
    public:
        FixProposal(double x, double y, double sigma) : m_x(x), m_y(y), m_sigma(sigma) {}
        TPose2D draw(mrpt::random::CRandomGenerator& rng) const override
        {
            return {m_x + m_sigma * rng.drawGaussian1D_normalized(),
                    m_y + m_sigma * rng.drawGaussian1D_normalized(), rng.drawUniform(-M_PI, M_PI)};
        }

    private:
        double m_x, m_y, m_sigma;
    };
    bool proposes() const override { return true; }
    std::unique_ptr<PoseProposal> proposal(const mrpt::obs::CSensoryFrame& sf) const override
    {
        const auto fix = sf.getObservationByClass<mrpt::obs::CObservationRobotPose>();
        if (!fix)
        {
            return nullptr;
        }
        return std::make_unique<FixProposal>(fix->pose.mean.x(), fix->pose.mean.y(),
                                             std::sqrt(fix->pose.cov(0, 0)));
    }
};

/** 2000 particles track 20 steps along y = 5 with a fix (0.5 m) each; the vehicle is then
 *  moved 12 m north, the odometry unaware, and drives 40 more steps, with augmented MCL's
 *  trigger on. The error at the end [m]; `fromFixes` the particles drawn from the fixes. */
double kidnapped(const std::shared_ptr<PositionFixModel>& model, size_t& fromFixes)
{
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(model);
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    semloc::TSamplingArea area;
    area.x_max = 40;
    area.y_max = 40;
    pdf.setFreeSpaceSampler(
        std::make_shared<semloc::FreeSpaceSampler>(semloc::FreeSpaceSampler::FromBox(area)));
    semloc::AugmentedMCL::TOptions recovery;
    recovery.alpha_slow = 0.01;
    recovery.alpha_fast = 0.3;
    pdf.setRecoveryOptions(recovery);
    mrpt::random::getRandomGenerator().randomize(9);
    pdf.resetUniform(1, 3, 4, 6, -0.1, 0.1, 2000);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    mrpt::random::CRandomGenerator noise(13);
    TPose2D truth(2, 5, 0);
    for (int k = 0; k < 60; k++)
    {
        truth.x += 0.4;
        truth.y += k == 20 ? 12.0 : 0.0;
        const auto acts = forward(0.4);
        auto sf = fixFrame(truth.x + 0.5 * noise.drawGaussian1D_normalized(),
                           truth.y + 0.5 * noise.drawGaussian1D_normalized(), 0.5);
        pf.executeOn(pdf, &acts, &sf);
    }
    fromFixes = pdf.recoveryStats().injected_from_detections +
                pdf.recoveryStats().reinitialized_from_detections;
    const auto mean = pdf.getMeanVal();
    return std::hypot(mean.x() - truth.x, mean.y() - truth.y);
}
}  // namespace

TEST(PluggedSensorModel, RecoveryDrawsFromTheProposalsOfAnyModel)
{
    // The filter knows no position fix: the model's proposals alone place the injected
    // particles near the fix, and the cloud follows the vehicle after its kidnapping.
    size_t fromFixes = 0;
    EXPECT_LT(kidnapped(std::make_shared<ProposingFixModel>(), fromFixes), 0.5);
    EXPECT_GT(fromFixes, 0u);
    // Without the hook, recovery draws over the free space only.
    size_t none = 0;
    (void)kidnapped(std::make_shared<PositionFixModel>(), none);
    EXPECT_EQ(none, 0u);
}

TEST(PluggedSensorModel, TheFilterLocalizesWithAModelItDoesNotKnow)
{
    const FixRun one = localize(1);
    EXPECT_GT(one.batchCalls, 0u);  // the plugged batch, not MRPT's per-pose call
    EXPECT_LT(one.error, 0.5);
    // Deterministic for any number of threads.
    const FixRun two = localize(2);
    ASSERT_EQ(one.particles.size(), two.particles.size());
    for (size_t i = 0; i < one.particles.size(); i++)
    {
        ASSERT_EQ(one.particles[i], two.particles[i]) << i;
    }
}

TEST(PluggedSensorModel, ItsTermIsMrptsValueAddedToTheOtherMaps)
{
    // The plugged model beside the semantic map: each pose's frame log-likelihood is MRPT's
    // (1 + the maps' computeObservationLikelihood, per observation), bit for bit.
    auto model = std::make_shared<PositionFixModel>();
    auto semantic = semloc::CSemanticMap::Create();
    semantic->loadFromWorldFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(semantic);
    multi->maps.push_back(model);
    auto sf = fixFrame(7, 5, 0.8);
    auto det = semloc::CObservationSemantic::Create();
    det->detections.push_back({semantic->objects().at(0).label, 3.0, 0.1, 1.0, -1});
    sf.insert(det);

    std::vector<TPose2D> poses;
    poses.reserve(600);
    for (int i = 0; i < 600; i++)
    {
        poses.emplace_back(0.08 * i, 5 + 0.05 * i, -1 + 0.004 * i);
    }
    semloc::ParallelExecutor executor(2);
    semloc::SensoryFrameLikelihood lik(*multi);
    std::vector<double> out(poses.size());
    model->batchCalls = 0;
    lik.evaluate(sf, poses.data(), poses.size(), out.data(), executor);
    EXPECT_GT(model->batchCalls.load(), 0u);
    for (size_t i = 0; i < poses.size(); i++)
    {
        const auto p = mrpt::poses::CPose3D(mrpt::math::TPose3D(poses[i]));
        double expected = 1;
        for (const auto& obs : sf)
        {
            double sum = 0;
            for (const auto& m : multi->maps)
            {
                sum += m->computeObservationLikelihood(*obs, p);
            }
            expected += sum;
        }
        ASSERT_EQ(out[i], expected) << i;
    }
    EXPECT_EQ(lik.stats().observations_used, 2u);
}

TEST(PluggedSensorModel, MrptsBeaconMapAddsItsTermOnEveryThread)
{
    // MRPT's own range-only beacon map (LBL), beside the semantic map, through the generic
    // call: MRPT's value at each pose, the same for 1 and 3 threads.
    auto beacons = mrpt::maps::CBeaconMap::Create();
    beacons->likelihoodOptions.rangeStd = 0.5;
    const double xy[4][2] = {{0, 0}, {50, 0}, {50, 50}, {0, 50}};
    for (int i = 0; i < 4; i++)
    {
        mrpt::maps::CBeacon b;
        b.m_ID = i + 1;
        b.m_locationGauss.mean = mrpt::poses::CPoint3D(xy[i][0], xy[i][1], -10);
        beacons->push_back(b);
    }
    auto semantic = semloc::CSemanticMap::Create();
    semantic->loadFromWorldFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(semantic);
    multi->maps.push_back(beacons);
    auto ranges = mrpt::obs::CObservationBeaconRanges::Create();
    ranges->maxSensorDistance = 200;
    for (int i = 0; i < 4; i++)
    {
        mrpt::obs::CObservationBeaconRanges::TMeasurement m;
        m.beaconID = i + 1;
        m.sensedDistance = static_cast<float>(
            std::sqrt(std::pow(20 - xy[i][0], 2) + std::pow(15 - xy[i][1], 2) + 100.0));
        ranges->sensedData.push_back(m);
    }
    mrpt::obs::CSensoryFrame sf;
    sf.insert(ranges);
    auto det = semloc::CObservationSemantic::Create();
    det->detections.push_back({semantic->objects().at(0).label, 3.0, 0.1, 1.0, -1});
    sf.insert(det);

    std::vector<TPose2D> poses;
    poses.reserve(2000);
    for (int i = 0; i < 2000; i++)
    {
        poses.emplace_back(10 + 0.01 * i, 15, 0.003 * i);  // through (20, 15)
    }
    std::vector<std::vector<double>> outs;
    for (size_t threads : {1, 3})
    {
        semloc::ParallelExecutor executor(threads);
        semloc::SensoryFrameLikelihood lik(*multi);
        outs.emplace_back(poses.size());
        lik.evaluate(sf, poses.data(), poses.size(), outs.back().data(), executor);
    }
    EXPECT_EQ(outs[0], outs[1]);
    double best = -1e300;
    for (size_t i = 0; i < poses.size(); i++)
    {
        const auto p = mrpt::poses::CPose3D(mrpt::math::TPose3D(poses[i]));
        const double expected = 1 + beacons->computeObservationLikelihood(*ranges, p) +
                                semantic->computeObservationLikelihood(*det, p);
        ASSERT_EQ(outs[0][i], expected) << i;
        best = std::max(best, beacons->computeObservationLikelihood(*ranges, p));
    }
    EXPECT_GT(best, -1.0);  // the path passes near (20, 15), where the ranges were taken
}

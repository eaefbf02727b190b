/* semloc tests — the recovery's sensor resetting while lost ([Recovery] lost_var_xy_m2): a
 * spread cloud re-seeded from the detections at a resampled particle's weight, nothing while
 * tracking or without a detection, the same bits on any thread count. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/AugmentedMCL.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>
#include <vector>

#include "KidnapRun.h"
#include "TestHelpers.h"

using mrpt::math::TPose2D;
using semloc::CParallelMonteCarloLocalization2D;

namespace
{
/** The trace of the particles' x-y covariance [m^2]. */
double varXY(const CParallelMonteCarloLocalization2D& pdf)
{
    const auto cov = std::get<0>(pdf.getCovarianceAndMean());
    return cov(0, 0) + cov(1, 1);
}

/** What globalStart() saw. */
struct LostRun
{
    std::unique_ptr<CParallelMonteCarloLocalization2D> pdf;
    std::vector<int> reseededAt;  ///< steps with a sensor resetting while lost
    bool equalWeights = true;     ///< after each of them, every particle of the same weight
    double error = 0;             ///< of the estimate at the end [m]
};

/** Evidence recovery (injected_weight 3e-6) re-seeding while the x-y variance is above
 *  `lostVar`. */
semloc::AugmentedMCL::TOptions evidenceRecovery(double lostVar)
{
    semloc::AugmentedMCL::TOptions ro;
    ro.trigger = semloc::RecoveryTrigger::Evidence;
    ro.injected_weight = 3e-6;
    ro.lost_var_xy_m2 = lostVar;
    return ro;
}

/** 2000 particles uniform over the paper world (every heading) of a semantic-only filter
 *  on `threads` threads with recovery `ro`, seeded with 5; the vehicle drives `steps` steps of 0.5
 * m east from (5, 4) along the first leg, seen by an ideal detector of 12 m and 120 degrees (or
 * none with `blind`). */
LostRun globalStart(size_t threads, const semloc::AugmentedMCL::TOptions& ro, int steps,
                    bool blind = false)
{
    const auto world = semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    LostRun r;
    r.pdf = semloc::test::semanticOnlyFilter(world, threads, ro);
    auto& pdf = *r.pdf;
    mrpt::random::getRandomGenerator().randomize(5);
    pdf.resetUniform(0, 50, 0, 50, -M_PI, M_PI, 2000);
    const semloc::test::DetectorSim detector;
    TPose2D truth(5, 4, 0);
    for (int k = 0; k < steps; k++)
    {
        truth.x += 0.5;
        const auto acts = semloc::test::gaussianOdometry(mrpt::poses::CPose2D(0.5, 0, 0));
        auto z = semloc::test::observe(world, truth, detector);
        if (blind)
        {
            z.detections.clear();
        }
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<semloc::CObservationSemantic>(z));
        const size_t before = pdf.recoveryStats().lost_injection_steps;
        pf.executeOn(pdf, &acts, &sf);
        if (pdf.recoveryStats().lost_injection_steps > before)
        {
            r.reseededAt.push_back(k);
            const auto [lo, hi] =
                std::minmax_element(pdf.m_particles.begin(), pdf.m_particles.end(),
                                    [](const auto& a, const auto& b) { return a.log_w < b.log_w; });
            r.equalWeights = r.equalWeights && lo->log_w == hi->log_w;
        }
    }
    r.error = std::hypot(pdf.getMeanVal().x() - truth.x, pdf.getMeanVal().y() - truth.y);
    return r;
}
}  // namespace

TEST(LostReseeding, ASpreadCloudIsReseededFromTheDetectionsUntilItConverges)
{
    const auto lost = globalStart(1, evidenceRecovery(10), 90);
    ASSERT_FALSE(lost.reseededAt.empty());
    EXPECT_EQ(lost.reseededAt.front(), 0) << "spread from the start, with a detection at once";
    // The re-seeded particles weigh as much as the resampled ones (injected_weight is for the
    // trigger's injections), so right after each one every weight is the same.
    EXPECT_TRUE(lost.equalWeights);
    const auto& st = lost.pdf->recoveryStats();
    EXPECT_EQ(st.lost_injection_steps, lost.reseededAt.size());
    EXPECT_LE(st.lost_injection_steps, st.injection_steps);
    EXPECT_GT(st.injected_from_detections, 0u);
    // Converged on the true pose, and no longer re-seeded once the cloud was concentrated.
    EXPECT_LT(lost.error, 1.0);
    EXPECT_LT(varXY(*lost.pdf), 10.0);
    EXPECT_LT(lost.reseededAt.back(), 70);

    const auto off = globalStart(1, evidenceRecovery(0), 90);
    EXPECT_EQ(off.pdf->recoveryStats().lost_injection_steps, 0u);
}

TEST(LostReseeding, NothingWhileTrackingNorWithoutADetection)
{
    size_t lostWhileTracking = 1;
    const auto r = semloc::test::kidnapOnPaperWorld(
        1, evidenceRecovery(10),
        [&](CParallelMonteCarloLocalization2D& pdf, int k)
        {
            if (k == 59)
            {
                lostWhileTracking = pdf.recoveryStats().lost_injection_steps;
            }
        });
    EXPECT_EQ(lostWhileTracking, 0u);
    EXPECT_EQ(r.injectionsTracking, 0u);
    EXPECT_LT(r.errorTracking, 1.0);

    // Spread over the world but never a detection: nothing to re-seed from (augmented MCL
    // watches frames that measure nothing but misses).
    semloc::AugmentedMCL::TOptions amcl{0.001, 0.1};
    amcl.lost_var_xy_m2 = 10;
    const auto blind = globalStart(1, amcl, 20, true);
    EXPECT_EQ(blind.pdf->recoveryStats().lost_injection_steps, 0u);
    EXPECT_GT(varXY(*blind.pdf), 10.0);
}

TEST(LostReseeding, TheSameBitsOnOneAndTwoThreads)
{
    const auto a = globalStart(1, evidenceRecovery(10), 40),
               b = globalStart(2, evidenceRecovery(10), 40);
    ASSERT_FALSE(a.reseededAt.empty());
    EXPECT_EQ(a.reseededAt, b.reseededAt);
    ASSERT_EQ(a.pdf->m_particles.size(), b.pdf->m_particles.size());
    for (size_t i = 0; i < a.pdf->m_particles.size(); i++)
    {
        const auto &p = a.pdf->m_particles[i], &q = b.pdf->m_particles[i];
        ASSERT_EQ(p.d.x, q.d.x) << i;
        ASSERT_EQ(p.d.y, q.d.y) << i;
        ASSERT_EQ(p.d.phi, q.d.phi) << i;
        ASSERT_EQ(p.log_w, q.log_w) << i;
    }
}

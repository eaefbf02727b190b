/* semloc tests — the challenger set of augmented MCL: the odds of "elsewhere" against the
 * cloud, merged or dropped on the evidence, and a kidnapping recovered through it. */
#include <gtest/gtest.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>

#include <cmath>
#include <functional>
#include <limits>

#include "KidnapRun.h"
#include "filter/ChallengerSet.h"

using mrpt::math::TPose2D;
using semloc::CParallelMonteCarloLocalization2D;
using semloc::ParallelExecutor;
using semloc::detail::ChallengerSet;
using Verdict = semloc::detail::ChallengerSet::Verdict;

namespace
{
/** A set of `n` challengers at x = 0 .. n - 1 (log-weights 0). */
ChallengerSet challengers(size_t n)
{
    ChallengerSet set;
    auto& store = set.start();
    store.particles.resize(n);
    for (size_t i = 0; i < n; i++)
    {
        store.particles[i].d = TPose2D(static_cast<double>(i), 0, 0);
        store.particles[i].log_w = 0;
    }
    return set;
}

/** One frame: the set appended to a cloud of `cloudSize` particles, each challenger's
 *  log-weight raised by `lik(i)`, the set taken back and weighed against the cloud's
 *  log w_avg `cloudLogWAvg`. */
template <typename Lik>
Verdict frame(ChallengerSet& set, size_t cloudSize, Lik&& lik, double cloudLogWAvg,
              size_t maxFrames, ParallelExecutor& ex)
{
    semloc::detail::ParticleStore store;
    store.particles.resize(cloudSize);
    set.attach(store, ex);
    for (size_t i = cloudSize; i < store.particles.size(); i++)
    {
        store.particles[i].log_w += lik(i - cloudSize);
    }
    set.detach(store);
    EXPECT_EQ(store.particles.size(), cloudSize) << "the cloud is left as it was";
    return set.weigh(cloudLogWAvg, std::log(1e-4), maxFrames, 0.5, ex);
}
}  // namespace

TEST(ChallengerSet, OddsArePriorTimesTheRatioOfTheFramesEvidence)
{
    ParallelExecutor ex(1);
    auto set = challengers(4);
    // Every challenger explains the frame e^3 better than the cloud: the odds gain e^3 per
    // frame from the prior 1e-4 (log -9.21), reaching 1 at the fourth frame.
    const auto even = [](size_t) { return -1.0; };
    for (int k = 1; k <= 3; k++)
    {
        ASSERT_EQ(frame(set, 10, even, -4.0, 100, ex), Verdict::Keep) << k;
        EXPECT_NEAR(set.logOdds(), std::log(1e-4) + 3.0 * k, 1e-12);
        EXPECT_EQ(set.size(), 4u);
    }
    EXPECT_EQ(frame(set, 10, even, -4.0, 100, ex), Verdict::Merge);
    EXPECT_NEAR(set.logOdds(), std::log(1e-4) + 12.0, 1e-12);

    // The set's evidence is its prior-weighted mean: one challenger of four explaining the
    // frame (the others not at all) gives log(1/4) + its likelihood.
    auto one = challengers(4);
    const auto first = [](size_t i) { return i == 0 ? 0.0 : -1e9; };
    ASSERT_EQ(frame(one, 10, first, 0.0, 100, ex), Verdict::Keep);
    EXPECT_NEAR(one.logOdds(), std::log(1e-4) + std::log(0.25), 1e-9);
    // ... and the set, degenerate, was resampled onto it: equal weights, every pose its.
    for (const auto& p : one.particles().particles)
    {
        EXPECT_EQ(p.log_w, 0.0);
        EXPECT_EQ(p.d.x, 0.0);
    }
}

TEST(ChallengerSet, DroppedWhenTheOddsFallToThePriorSquaredOrAfterItsFrames)
{
    ParallelExecutor ex(1);
    auto behind = challengers(3);
    // e^-4 per frame behind the cloud: log odds -9.21 - 4k, at or below 2 log 1e-4 = -18.4
    // from the third frame.
    const auto worse = [](size_t) { return -6.0; };
    EXPECT_EQ(frame(behind, 5, worse, -2.0, 100, ex), Verdict::Keep);
    EXPECT_EQ(frame(behind, 5, worse, -2.0, 100, ex), Verdict::Keep);
    EXPECT_EQ(frame(behind, 5, worse, -2.0, 100, ex), Verdict::Drop);

    auto level = challengers(3);  // as good as the cloud: undecided until its frames run out
    const auto same = [](size_t) { return -2.0; };
    for (int k = 1; k < 7; k++)
    {
        ASSERT_EQ(frame(level, 5, same, -2.0, 7, ex), Verdict::Keep) << k;
    }
    EXPECT_EQ(frame(level, 5, same, -2.0, 7, ex), Verdict::Drop);

    auto dead = challengers(3);  // every challenger's weight vanished
    EXPECT_EQ(frame(
                  dead, 5, [](size_t) { return -std::numeric_limits<double>::infinity(); }, -2.0,
                  100, ex),
              Verdict::Drop);
}

namespace
{
/** The paper world's kidnapping (KidnapRun.h) with the evidence trigger and challenger sets
 *  of `frames` frames, on `threads` threads. */
semloc::test::KidnapRun kidnapped(
    size_t threads, size_t frames,
    const std::function<void(CParallelMonteCarloLocalization2D&, int)>& afterStep = {})
{
    semloc::AugmentedMCL::TOptions ro;
    ro.trigger = semloc::RecoveryTrigger::Evidence;
    ro.injected_weight = 3e-6;
    ro.challenger_frames = frames;
    return semloc::test::kidnapOnPaperWorld(threads, ro, afterStep);
}
}  // namespace

TEST(ChallengerSet, KidnappedFilterRecoversThroughAChallengerSet)
{
    const auto r = kidnapped(2, 20);
    const auto& st = r.pdf->recoveryStats();
    EXPECT_EQ(r.injectionsTracking, 0u) << "tracking: the trigger never fired";
    EXPECT_GT(st.injection_steps, 0u);
    EXPECT_GE(st.challenger_merges, 1u);
    EXPECT_EQ(st.reinitializations, 0u);
    EXPECT_TRUE(r.cloudSizeKept) << "the challengers live beside the cloud, not in it";
    EXPECT_LT(r.error, 1.0);
}

TEST(ChallengerSet, SameBitsOnOneAndTwoThreads)
{
    const auto a = kidnapped(1, 20);
    const auto b = kidnapped(2, 20);
    ASSERT_EQ(a.pdf->size(), b.pdf->size());
    for (size_t i = 0; i < a.pdf->size(); i++)
    {
        ASSERT_EQ(a.pdf->m_particles[i].d.x, b.pdf->m_particles[i].d.x) << i;
        ASSERT_EQ(a.pdf->m_particles[i].d.phi, b.pdf->m_particles[i].d.phi) << i;
        ASSERT_EQ(a.pdf->m_particles[i].log_w, b.pdf->m_particles[i].log_w) << i;
    }
    EXPECT_EQ(a.pdf->recoveryStats().challenger_merges, b.pdf->recoveryStats().challenger_merges);
    EXPECT_GT(a.pdf->recoveryStats().challenger_merges, 0u);
}

TEST(ChallengerSet, ANewMotionModelDropsALiveSet)
{
    // Right after the first set is drawn, the heading drift turns on: every particle gets a
    // state of the new model, and the set (with the old model's states) is dropped instead of
    // entering the next step's pass with states of the wrong size.
    bool switched = false;
    const auto r = kidnapped(1, 20,
                             [&](CParallelMonteCarloLocalization2D& pdf, int)
                             {
                                 if (!switched && pdf.recoveryStats().injection_steps == 1)
                                 {
                                     pdf.setHeadingDrift(1e-4, 1e-4);
                                     switched = true;
                                 }
                             });
    EXPECT_TRUE(switched);
    EXPECT_EQ(r.pdf->motionStates().size(), r.pdf->size());
    EXPECT_GT(r.pdf->recoveryStats().injection_steps, 1u) << "the trigger drew again";
    EXPECT_LT(r.error, 1.0);
}

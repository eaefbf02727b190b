/* semloc tests — AugmentedMCL: w_slow / w_fast in the log domain (Probabilistic Robotics
 * §8.3.5). */
#include <gtest/gtest.h>
#include <semloc/filter/AugmentedMCL.h>

TEST(AugmentedMCL, InjectsOnlyAfterALikelihoodDrop)
{
    semloc::AugmentedMCL off;
    EXPECT_EQ(off.update(-5), 0.0);

    semloc::AugmentedMCL aug({0.01, 0.2});
    for (int k = 0; k < 200; k++)
    {
        EXPECT_EQ(aug.update(-700), 0.0) << "steady likelihood e^-700, step " << k;
    }
    double p = 0;
    for (int k = 0; k < 5; k++)
    {
        p = aug.update(-720);  // the likelihood falls by e^-20: lost
    }
    EXPECT_GT(p, 0.5);
    EXPECT_LE(p, 1.0);
    aug.reset();
    EXPECT_EQ(aug.update(-720), 0.0);
}

TEST(AugmentedMCL, EvidenceTriggerNeedsASustainedShortfall)
{
    semloc::AugmentedMCL::TOptions o;
    o.trigger = semloc::RecoveryTrigger::Evidence;
    o.evidence_margin = 2;
    o.evidence_threshold = 20;
    o.inject_share = 0.25;
    ASSERT_TRUE(o.enabled());
    semloc::AugmentedMCL ev(o);
    EXPECT_EQ(ev.update(-5), 0.0);  // the averages are the amcl trigger's
    for (int k = 0; k < 50; k++)
    {
        EXPECT_EQ(ev.updateEvidence(12), 0.0) << "frames explained e^12 better than by clutter";
    }
    EXPECT_EQ(ev.shortfall(), 0.0);
    // One frame alone, however bad, adds at most half the threshold.
    EXPECT_EQ(ev.updateEvidence(-1e6), 0.0);
    EXPECT_DOUBLE_EQ(ev.shortfall(), 10.0);
    // A good frame pays part of it back: 10 + 2 - 5.
    EXPECT_EQ(ev.updateEvidence(5), 0.0);
    EXPECT_DOUBLE_EQ(ev.shortfall(), 7.0);
    // Frames at the reference (b = 0, as after a kidnapping) add the margin each: 7 + 2k.
    double share = 0;
    int frames = 0;
    while (share == 0 && frames < 100)
    {
        share = ev.updateEvidence(0);
        frames++;
    }
    EXPECT_EQ(frames, 7);  // 7 + 2 * 7 = 21 >= 20
    EXPECT_EQ(share, 0.25);
    EXPECT_EQ(ev.updateEvidence(-1), 0.25) << "still short";
    // Explained again: the shortfall drains and the injections stop.
    EXPECT_EQ(ev.updateEvidence(10), 0.0);
    EXPECT_DOUBLE_EQ(ev.shortfall(), 24.0 + 2 - 10);
    ev.reset();
    EXPECT_EQ(ev.shortfall(), 0.0);

    semloc::AugmentedMCL amcl({0.01, 0.2});
    EXPECT_EQ(amcl.updateEvidence(-100), 0.0);  // not its trigger
    o.trigger = semloc::RecoveryTrigger::Off;
    EXPECT_FALSE(o.enabled());
}

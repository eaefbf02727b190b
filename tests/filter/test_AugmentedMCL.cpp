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

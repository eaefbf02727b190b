/* semloc tests — GroundTruth: the nearest row in time, within a tolerance. */
#include <gtest/gtest.h>
#include <semloc/experiment/GroundTruth.h>

#include <cmath>

TEST(GroundTruth, NearestRowWithinTolerance)
{
    semloc::GroundTruth gt({{1.0, 1, 0, 0}, {2.0, 2, 0, 0}, {3.0, 3, 0, 0}});
    EXPECT_EQ(gt.rows().front().t, 1.0);
    EXPECT_DOUBLE_EQ(gt.medianPeriod(), 1.0);
    ASSERT_NE(gt.nearest(2.3, 0.5), nullptr);
    EXPECT_EQ(gt.nearest(2.3, 0.5)->x, 2);
    EXPECT_EQ(gt.nearest(2.7, 0.5)->x, 3);
    EXPECT_EQ(gt.nearest(0.4, 0.5), nullptr);
    EXPECT_EQ(gt.nearest(3.6, 0.5), nullptr);
    EXPECT_EQ(gt.nearest(std::nan(""), 0.5), nullptr);
}

TEST(GroundTruth, RowsOutOfOrderOrNotFiniteAreErrors)
{
    using Row = semloc::GroundTruthRow;
    EXPECT_THROW(semloc::GroundTruth({Row{2.0, 2, 0, 0}, Row{1.0, 1, 0, 0}}), std::exception);
    EXPECT_THROW(semloc::GroundTruth({Row{1.0, 2, 0, 0}, Row{1.0, 1, 0, 0}}), std::exception);
    EXPECT_THROW(semloc::GroundTruth({Row{1.0, std::nan(""), 0, 0}}), std::exception);
}

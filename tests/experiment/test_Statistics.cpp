/* semloc tests — the experiment's small statistics: median, mean, percentiles, standard error. */
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "experiment/Statistics.h"

using semloc::detail::mean;
using semloc::detail::median;
using semloc::detail::percentile;
using semloc::detail::standardError;

TEST(Statistics, MedianMeanAndEmptyInputs)
{
    EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
    EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 3.0);  // the upper one of an even count
    EXPECT_EQ(median({}), 0.0);
    EXPECT_EQ(mean({1.0, 2.0, 6.0}), 3.0);
    EXPECT_TRUE(std::isnan(mean({})));
    EXPECT_TRUE(std::isnan(percentile({}, 0.5)));
}

TEST(Statistics, PercentilesInterpolateBetweenClosestRanks)
{
    const std::vector<double> v = {10.0, 20.0, 30.0, 40.0, 50.0};  // sorted
    EXPECT_EQ(percentile(v, 0.0), 10.0);
    EXPECT_EQ(percentile(v, 1.0), 50.0);
    EXPECT_EQ(percentile(v, 0.5), 30.0);
    EXPECT_DOUBLE_EQ(percentile(v, 0.1), 14.0);  // rank 0.4: 10 + 0.4 * (20 - 10)
    EXPECT_DOUBLE_EQ(percentile(v, 0.9), 46.0);
    EXPECT_EQ(percentile({7.0}, 0.9), 7.0);
}

TEST(Statistics, StandardErrorOfTheMean)
{
    // Sample standard deviation of {1, 2, 3, 4} is sqrt(5/3); over sqrt(4).
    EXPECT_DOUBLE_EQ(standardError({1.0, 2.0, 3.0, 4.0}), std::sqrt(5.0 / 3.0) / 2.0);
    EXPECT_EQ(standardError({2.0, 2.0, 2.0}), 0.0);
    EXPECT_TRUE(std::isnan(standardError({5.0})));
    EXPECT_TRUE(std::isnan(standardError({})));
}

/* semloc — small statistics shared by the experiment's readers and reports (private). */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace semloc::detail
{
/** The median of `v` (the upper one of an even count); 0 if `v` is empty. */
inline double median(std::vector<double> v)
{
    if (v.empty())
    {
        return 0;
    }
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

/** The mean of `v`; NaN if `v` is empty. */
inline double mean(const std::vector<double>& v)
{
    if (v.empty())
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    double s = 0;
    for (double x : v)
    {
        s += x;
    }
    return s / static_cast<double>(v.size());
}

/** The standard error of the mean of `v`: the sample standard deviation (n - 1) over
 *  sqrt(n); NaN with fewer than two values. */
inline double standardError(const std::vector<double>& v)
{
    if (v.size() < 2)
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const double m = mean(v);
    double ss = 0;
    for (double x : v)
    {
        ss += (x - m) * (x - m);
    }
    const auto n = static_cast<double>(v.size());
    return std::sqrt(ss / (n - 1) / n);
}

/** The `p` quantile (0..1) of `v`, sorted: linear interpolation between closest ranks; NaN if
 *  `v` is empty. */
inline double percentile(const std::vector<double>& v, double p)
{
    if (v.empty())
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const double r = p * static_cast<double>(v.size() - 1);
    const auto i = static_cast<size_t>(std::floor(r));
    const size_t j = std::min(i + 1, v.size() - 1);
    return v[i] + (r - static_cast<double>(i)) * (v[j] - v[i]);
}

}  // namespace semloc::detail

/* semloc — small statistics shared by the experiment's readers and reports (private). */
#pragma once

#include <algorithm>
#include <cstddef>
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

}  // namespace semloc::detail

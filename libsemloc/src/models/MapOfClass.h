/* semloc — the map of a class among a filter's maps (private). */
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/maps/CMultiMetricMap.h>

namespace semloc::detail
{
/** `map` itself when it is a T, else the first T of a CMultiMetricMap, else nullptr. By
 *  dynamic_cast, not MRPT's mapByClass(): T may be an abstract base without a class id of its
 *  own (CObjectDetectorMap), which mapByClass() would take for CMetricMap's. */
template <typename T>
const T* mapOfClass(const mrpt::maps::CMetricMap& map)
{
    if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(&map))
    {
        for (const auto& m : multi->maps)
        {
            if (const auto* t = dynamic_cast<const T*>(m.get()))
            {
                return t;
            }
        }
        return nullptr;
    }
    return dynamic_cast<const T*>(&map);
}
}  // namespace semloc::detail

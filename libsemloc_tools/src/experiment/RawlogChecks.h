/* semloc — what a localization run needs of a rawlog, checked before the run (private). */
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/filter/Localizer.h>

#include <cstddef>
#include <functional>
#include <string>

namespace semloc::detail
{
/** Refuses rawlog `path` when its odometry is not finite (mean or covariance), when an action
 *  cannot be re-derived by the filter's [MotionModel] (MotionModelConfig::problem, naming the
 *  entry), when it holds no odometry at all (unless the filter's allow_no_odometry), or when
 *  no observation can be scored by `maps` (Localizer::invalidObservation,
 *  canComputeObservationLikelihood). */
void checkRawlog(const mrpt::obs::CRawlog& rawlog, const std::string& path,
                 const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter);

/** checkRawlog() over the entries `next()` returns in order until it returns null (a rawlog
 *  streamed: nothing is kept), each also handed to `visit(entry, index)`; the number of
 *  entries. */
size_t checkRawlog(
    const std::function<mrpt::serialization::CSerializable::Ptr()>& next,
    const std::function<void(const mrpt::serialization::CSerializable::Ptr&, size_t)>& visit,
    const std::string& path, const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter);

}  // namespace semloc::detail

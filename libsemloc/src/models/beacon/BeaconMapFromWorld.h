/* semloc — MRPT's range-only beacon maps of a [MetricMap] filled from the world (private). */
#pragma once

#include <semloc/maps/LocalizationMap.h>

#include <string>
#include <utility>
#include <vector>

namespace semloc::detail
{
/** Standard deviation of a beacon's position in its CBeacon [m]: the beacons are where the
 *  world says, to a millimetre (MRPT adds the position's variance along the line of sight
 *  to rangeStd^2). */
constexpr double kBeaconPositionStd_m = 1e-3;

/** Fills every beaconMap of `lm` (the k-th map defined as `aliases[k]` in `[section]`) with
 *  the beacons of `lm.world` (World::beacons): a Gaussian CBeacon each (m_ID the beacon's id,
 *  mean (x, y, z), covariance kBeaconPositionStd_m^2 I). Throws "ini [<prefix>_likelihoodOpts]
 *  rangeStd: ..." for a rangeStd that is not > 0, "ini [section] beaconMap_count: ..." naming
 *  the world file for a world without beacons, or the map file for a beacon map left
 *  empty without a world. */
void fillBeaconMaps(LocalizationMap& lm,
                    const std::vector<std::pair<std::string, unsigned>>& aliases,
                    const std::string& mapFile, const std::string& section);
}  // namespace semloc::detail

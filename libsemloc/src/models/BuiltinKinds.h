/* semloc — semloc's own kinds of map, each defined in its room (private). */
#pragma once

#include <semloc/models/SensorModelRegistry.h>

#include <memory>

namespace semloc::detail
{
/** semanticMap (models/semantic/SemanticMapKind.cpp). */
std::shared_ptr<const SensorModelKind> semanticMapKind();
/** structureMap (models/structure/StructureMapKind.cpp). */
std::shared_ptr<const SensorModelKind> structureMapKind();
/** MRPT's occupancyGrid (models/grid/OccupancyGridKind.cpp). */
std::shared_ptr<const SensorModelKind> occupancyGridKind();
/** MRPT's beaconMap (models/beacon/BeaconMapKind.cpp). */
std::shared_ptr<const SensorModelKind> beaconMapKind();
/** sideScanMap (models/sidescan/CSideScanMap.cpp). */
std::shared_ptr<const SensorModelKind> sideScanMapKind();
/** forwardSonarMap (models/forwardsonar/CForwardSonarMap.cpp). */
std::shared_ptr<const SensorModelKind> forwardSonarMapKind();
/** bearingCameraMap (models/camera/CBearingCameraMap.cpp). */
std::shared_ptr<const SensorModelKind> bearingCameraMapKind();
/** compassMap (models/compass/CCompassMap.cpp). */
std::shared_ptr<const SensorModelKind> compassMapKind();
/** poseFixMap (models/fix/CPoseFixMap.cpp). */
std::shared_ptr<const SensorModelKind> poseFixMapKind();
}  // namespace semloc::detail

/* semloc — the sensor models among a filter's maps, and what their hooks give it (private). */
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/models/BatchLikelihood.h>

#include <memory>
#include <vector>

namespace semloc::detail
{
/** The maps of `map` (itself, or those of a CMultiMetricMap, in order) that are sensor models
 *  (BatchLikelihood). */
std::vector<const BatchLikelihood*> sensorModels(const mrpt::maps::CMetricMap& map);

/** The first proposal of `sf` among the sensor models of `map` (nullptr: `map` is null, or no
 *  model places the frame). */
std::unique_ptr<BatchLikelihood::PoseProposal> poseProposal(const mrpt::obs::CSensoryFrame& sf,
                                                            const mrpt::maps::CMetricMap* map);
}  // namespace semloc::detail

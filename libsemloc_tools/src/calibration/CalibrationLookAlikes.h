/* semloc — semloc-calibrate's fit of the look-alike persistence (private). */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/models/semantic/LookAlikeMemory.h>
#include <semloc/observation/CObservationSemantic.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** The look-alike samples of one scan (TCalibrationSamples::lookAlike*): the memory's
 *  detections within the coverage of the sensor at `sensor` (map frame), and for each of the
 *  scan's detections of a label in `labels` left unmatched (detTo < 0) the memory's density
 *  there; then the scan's detections of those labels are remembered. Nothing with a sigma of
 *  0 (the first matching pass) or a scan without a timestamp. */
void addLookAlikeScan(const CObservationSemantic& obs, const mrpt::poses::CPose2D& sensor,
                      const std::vector<int>& detTo, const std::vector<std::string>& labels,
                      double sigmaRange_m, double sigmaBearing_rad,
                      const SensorCalibration::TOptions& o, LookAlikeMemory& memory,
                      TCalibrationSamples& s);

/** r.lookalike_persistence and r.lookAlikeResightings from the samples, and
 *  r.clutter_per_scan made the uniform part (TCalibrationResult::lookalike_persistence). */
void fitLookAlikes(TCalibrationResult& r);
}  // namespace semloc::detail

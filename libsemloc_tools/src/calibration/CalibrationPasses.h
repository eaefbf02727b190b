/* semloc — semloc-calibrate's walks through the rawlog: the entries read in order once per
 * pass, from memory or streamed from the file (private). */
#pragma once

#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CSerializable.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/experiment/GroundTruth.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "calibration/CalibrationFits.h"

namespace semloc::detail
{
/** Called with each entry of a rawlog and its index (as RawlogReader counts them). */
using EntryVisitor = std::function<void(size_t, const mrpt::serialization::CSerializable::Ptr&)>;
/** Walks every entry of a rawlog, in order, each time it is called. */
using RawlogWalk = std::function<void(const EntryVisitor&)>;

/** The entries of `rawlog`, held in memory. */
RawlogWalk walkInMemory(const mrpt::obs::CRawlog& rawlog);
/** The entries of the rawlog file `path`, read again at each walk (RawlogReader::next: one
 *  entry in memory at a time); a walk throws RawlogReader::Load()'s errors (a truncated or
 *  corrupted entry, once the entries before it are visited; a file without entries). */
RawlogWalk walkFile(const std::string& path);

/** The odometry actions of the walk with their ground-truth rows (an error naming the entry
 *  when one has none within options.gtTolerance_s). */
std::vector<TimedIncrement> timedIncrements(const RawlogWalk& walk, const std::string& rawlogName,
                                            const GroundTruth& gt,
                                            const SensorCalibration::TOptions& o);

/** The matching gate: a disc of radius `radius_m` around the object's centre, or (with
 *  sigmas > 0) the ellipse (d_range / sigma_range)^2 + (d_bearing / sigma_bearing)^2 <= k^2. */
struct Gate
{
    double radius_m = 3.0;
    double sigmaRange_m = 0, sigmaBearing_rad = 0, k = 4.0;
    bool normalized() const { return sigmaRange_m > 0 && sigmaBearing_rad > 0; }
};

/** One matching pass: every semantic scan and every odometry action of the walk against the
 *  ground truth, the scans placed by `toMap` and gated by `gate`, the increments re-cut by
 *  `delay_s`; the samples and counts into `r`. */
void collect(const RawlogWalk& walk, const std::string& rawlogName, const World& world,
             const GroundTruth& gt, const SensorCalibration::TOptions& o, const Gate& gate,
             const RigidTransform2D& toMap, double delay_s, TCalibrationResult& r);
}  // namespace semloc::detail

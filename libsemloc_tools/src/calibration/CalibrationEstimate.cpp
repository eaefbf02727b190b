/* semloc — semloc-calibrate's estimate: the odometry's delay, then the matching passes and
 * their fits, over a rawlog held in memory or streamed from its file. */
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/io/RawlogReader.h>

#include <stdexcept>
#include <utility>

#include "calibration/CalibrationFits.h"
#include "calibration/CalibrationLookAlikes.h"
#include "calibration/CalibrationPasses.h"

namespace semloc
{
namespace detail
{
RawlogWalk walkInMemory(const mrpt::obs::CRawlog& rawlog)
{
    return [&rawlog](const EntryVisitor& visit)
    {
        for (size_t i = 0; i < rawlog.size(); i++)
        {
            visit(i, rawlog.getAsGeneric(i));
        }
    };
}

RawlogWalk walkFile(const std::string& path)
{
    return [path](const EntryVisitor& visit)
    {
        RawlogReader reader(path);
        size_t n = 0;
        while (const auto entry = reader.next())
        {
            visit(n++, entry);
        }
        if (reader.defect())
        {
            RawlogReader::TResult bad;
            bad.path = path;
            bad.defect = reader.defect();
            THROW_EXCEPTION(bad.defectMessage());
        }
        if (n == 0)
        {
            THROW_EXCEPTION("rawlog '" + path + "' holds no entries");
        }
    };
}
}  // namespace detail

namespace
{
using detail::RawlogWalk;

/** `walk` telling `progress` of each entry under `stage` (of `total`, 0: not known); the
 *  number of entries in `entries`. */
RawlogWalk counted(const RawlogWalk& walk, const std::string& stage, size_t total,
                   const CalibrationProgress& progress, size_t& entries)
{
    return [=, &entries](const detail::EntryVisitor& visit)
    {
        entries = 0;
        walk(
            [&](size_t i, const mrpt::serialization::CSerializable::Ptr& entry)
            {
                visit(i, entry);
                entries = i + 1;
                if (progress)
                {
                    progress({stage, entries, total, "entries"});
                }
            });
    };
}

std::string passName(int pass, int passes)
{
    return "pass " + std::to_string(pass + 1) + " of " + std::to_string(passes + 1);
}

/** The fits of one pass's samples in `r`, and the gate and map offset of the next pass. */
void fitPass(TCalibrationResult& r, const std::string& name, const CalibrationProgress& progress,
             detail::Gate& gate, detail::RigidTransform2D& toMap)
{
    detail::fitDetector(
        r,
        [&](int round, size_t step, size_t steps)
        {
            if (progress)
            {
                progress({name + ": detection model, round " + std::to_string(round), step, steps,
                          "search steps"});
            }
        });
    detail::fitLookAlikes(r);
    detail::fitBias(r);
    gate.sigmaRange_m = r.sigma_range_m.value;
    gate.sigmaBearing_rad = mrpt::DEG2RAD(r.sigma_bearing_deg.value);
    // An offset that moves the objects by more than kBiasSigmas sigma_range is removed
    // from the next pass's poses (a smaller one is noise, or changes little).
    r.mapOffset.removed = toMap.theta != 0 || toMap.tx != 0 || toMap.ty != 0;
    const auto total = detail::fitMapOffset(r, toMap).after(toMap);
    const bool large = r.mapOffset.fitted && r.mapOffset.rms_m > TCalibrationResult::kBiasSigmas *
                                                                     r.bias.sigmaRangeAround_m;
    toMap = large ? total : detail::RigidTransform2D();
}

/** The passes of Estimate() over `walk` (SensorCalibration.h). */
TCalibrationResult estimate(const RawlogWalk& walk, const std::string& rawlogName,
                            const World& world, std::vector<GroundTruthRow> groundTruth,
                            const SensorCalibration::TOptions& options,
                            const CalibrationProgress& progress)
{
    if (!(options.gate_m > 0) || !(options.gateSigmas > 0) || options.gatePasses < 0 ||
        !(options.gtTolerance_s >= 0))
    {
        throw std::invalid_argument("calibration: the gate must be > 0 and the tolerance >= 0");
    }
    const GroundTruth gt(std::move(groundTruth));
    // The first pass gates by distance; the next ones by the sigmas the previous one fitted.
    detail::Gate gate;
    gate.radius_m = options.gate_m;
    gate.k = options.gateSigmas;
    // Each pass places the scans by the ground truth moved by the map offset the passes
    // before it fitted (none in the first).
    detail::RigidTransform2D toMap;
    TCalibrationResult delayFit;
    size_t entries = 0;
    detail::fitOdometryDelay(
        detail::timedIncrements(counted(walk, "reading the rawlog", 0, progress, entries),
                                rawlogName, gt, options),
        delayFit);
    TCalibrationResult r;
    std::vector<double> rangeBias, rangeBiasCi95;
    double sigmaUncorrected = 0;
    for (int pass = 0; pass <= options.gatePasses; pass++)
    {
        const std::string name = passName(pass, options.gatePasses);
        r = TCalibrationResult();
        r.rangeBias_m = rangeBias;
        r.rangeBiasCi95_m = rangeBiasCi95;
        size_t seen = 0;
        detail::collect(counted(walk, name + ": matching", entries, progress, seen), rawlogName,
                        world, gt, options, gate, toMap, delayFit.odometry_delay_s.value, r);
        if (seen != entries)
        {
            throw std::runtime_error("rawlog '" + rawlogName + "': " + std::to_string(seen) +
                                     " entries at its " + name + ", " + std::to_string(entries) +
                                     " at its first reading: the file changed while it was "
                                     "calibrated");
        }
        if (r.scans == 0)
        {
            throw std::runtime_error("rawlog '" + rawlogName +
                                     "': no semantic observation (CObservationSemantic) to "
                                     "calibrate");
        }
        if (pass < options.gatePasses)
        {
            // The next pass reads the ranges less the bias so far and what this one adds.
            if (pass == 0)
            {
                sigmaUncorrected = detail::madSigma(r.samples.rangeResiduals_m);
            }
            detail::addRangeBias(r.samples, rangeBias, rangeBiasCi95);
        }
        r.sigmaRangeUncorrected_m = sigmaUncorrected;
        fitPass(r, name, progress, gate, toMap);
    }
    r.odometry_delay_s = delayFit.odometry_delay_s;
    r.odomHeadingRms_deg = delayFit.odomHeadingRms_deg;
    r.odomHeadingRmsDelayed_deg = delayFit.odomHeadingRmsDelayed_deg;
    detail::fitOdometry(r);
    detail::applyLimits(r);
    return r;
}
}  // namespace

TCalibrationResult SensorCalibration::Estimate(const mrpt::obs::CRawlog& rawlog,
                                               const std::string& rawlogName, const World& world,
                                               const std::vector<GroundTruthRow>& groundTruth,
                                               const TOptions& options)
{
    return estimate(detail::walkInMemory(rawlog), rawlogName, world, groundTruth, options, {});
}

TCalibrationResult SensorCalibration::EstimateFromFile(const std::string& rawlogPath,
                                                       const World& world,
                                                       std::vector<GroundTruthRow> groundTruth,
                                                       const TOptions& options,
                                                       const CalibrationProgress& progress)
{
    return estimate(detail::walkFile(rawlogPath), rawlogPath, world, std::move(groundTruth),
                    options, progress);
}

}  // namespace semloc

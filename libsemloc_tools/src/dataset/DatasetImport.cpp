/* semloc — DatasetImport: the steps, rawlog, ground truth and world of an imported dataset
 * (the CSV readers are in DatasetImportReaders.cpp, DatasetImportDetections.cpp and
 * DatasetImportReadings.cpp; the ground truth at the steps and the counts of the summary line
 * in DatasetImportChecks.cpp). */
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/observation/CObservationDepth.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "dataset/ImportCells.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
/** A time as the import's messages write it (detail::timeText). */
std::string num(double v)
{
    return detail::timeText(v);
}

/** Number of odometry-only steps between two steps `gap` seconds apart (a double: a gap of
 *  1e18 s must not overflow before it is refused). */
double stepsBetween(double gap, double maxStep_s)
{
    return std::max(0.0, std::ceil(gap / maxStep_s - 1e-9) - 1);
}

/** Throws if the scans within the odometry's span would make more than kMaxImportSteps steps
 *  (counted, not made). */
void checkStepCount(const std::vector<DetectionScan>& scans, const OdometryTrack& odometry,
                    double maxStep_s, const std::string& detectionsName)
{
    double count = 0, first = 0, last = 0;
    for (const auto& s : scans)
    {
        if (s.t < odometry.t.front() || s.t > odometry.t.back())
        {
            continue;
        }
        count += count == 0 ? 1 : 1 + stepsBetween(s.t - last, maxStep_s);
        first = count == 1 ? s.t : first;
        last = s.t;
    }
    if (count > static_cast<double>(kMaxImportSteps))
    {
        THROW_EXCEPTION(mrpt::format(
            "detections '%s': times span %s s (from %s to %s): %s steps at --max-step-s %s, more "
            "than the %zu allowed; is --max-step-s too short, or are the times not in seconds? "
            "semloc-import takes seconds",
            detectionsName.c_str(), num(last - first).c_str(), num(first).c_str(),
            num(last).c_str(), detail::shortestText(count).c_str(),
            detail::shortestText(maxStep_s).c_str(), kMaxImportSteps));
    }
}

/** The scan's observation: its sensor's label, pose, coverage and detections at time `t`. */
CObservationSemantic::Ptr semanticObservation(const DetectionScan& scan,
                                              const TDatasetImportOptions& o,
                                              TDatasetImportStats& stats)
{
    const TImportSensor sensor = o.sensor(scan.sensor);
    auto obs = CObservationSemantic::Create();
    obs->sensorLabel = scan.sensor;
    obs->timestamp = mrpt::Clock::fromDouble(scan.t);
    obs->sensorPose =
        mrpt::poses::CPose3D(sensor.pose.x, sensor.pose.y, sensor.z_m, sensor.pose.phi, 0, 0);
    obs->maxRange_m = sensor.maxRange_m;
    obs->fov_rad = mrpt::DEG2RAD(sensor.fov_deg);
    obs->detections = scan.detections;
    for (const auto& d : scan.detections)
    {
        // A bearing-only detection (no range) of a camera, a sonar... is in coverage when its
        // bearing is in the field of view: isValid() wants a range, as the semantic models
        // of sensor SEMANTIC do.
        const bool bearingOnly = std::isnan(d.range_m);
        const bool semantic = scan.sensor == kDefaultImportSensor;
        TSemanticDetection inView = d;
        inView.range_m = bearingOnly && !semantic ? 0.0 : d.range_m;
        stats.detectionsOutsideCoverage += obs->isValid(inView) ? 0 : 1;
        stats.detectionsWithoutRange += bearingOnly ? 1 : 0;
        stats.semanticWithoutRange += bearingOnly && semantic ? 1 : 0;
    }
    stats.detections += scan.detections.size();
    stats.scanObservations++;
    stats.sensorScans[scan.sensor]++;
    return obs;
}

/** A depth file's reading as semloc's observation (label `depth`). */
mrpt::obs::CObservation::Ptr depthObservation(const DepthReading& r)
{
    auto obs = CObservationDepth::Create();
    obs->sensorLabel = "depth";
    obs->timestamp = mrpt::Clock::fromDouble(r.t);
    obs->depth_m = r.depth_m;
    obs->altitude_m = r.altitude_m;
    return obs;
}

/** A heading file's reading as MRPT's IMU observation of a yaw (label `compass`). */
mrpt::obs::CObservation::Ptr headingObservation(const HeadingReading& r)
{
    auto obs = mrpt::obs::CObservationIMU::Create();
    obs->sensorLabel = "compass";
    obs->timestamp = mrpt::Clock::fromDouble(r.t);
    obs->set(mrpt::obs::IMU_YAW, r.heading_rad);
    return obs;
}

/** A fixes file's reading as MRPT's pose observation (label `usbl`): the position and its
 *  variances (1 m^2 without standard deviations), 1 m^2 on z and 100 on the attitude (a fix
 *  has none). */
mrpt::obs::CObservation::Ptr fixObservation(const FixReading& r)
{
    auto obs = mrpt::obs::CObservationRobotPose::Create();
    obs->sensorLabel = "usbl";
    obs->timestamp = mrpt::Clock::fromDouble(r.t);
    obs->pose.mean = mrpt::poses::CPose3D(r.x, r.y, r.z, 0, 0, 0);
    obs->pose.cov.setZero();
    obs->pose.cov(0, 0) = std::isnan(r.sigma_x_m) ? 1.0 : r.sigma_x_m * r.sigma_x_m;
    obs->pose.cov(1, 1) = std::isnan(r.sigma_y_m) ? 1.0 : r.sigma_y_m * r.sigma_y_m;
    obs->pose.cov(2, 2) = 1;
    for (int i = 3; i < 6; i++)
    {
        obs->pose.cov(i, i) = 100;  // no attitude in a fix
    }
    return obs;
}

/** The readings of one file (times increasing) handed to the steps in order: each in the frame
 *  of the first step at or after its time, the last of those before one step only. */
template <typename Reading>
class ReadingPlacer
{
public:
    ReadingPlacer(const std::vector<Reading>& readings, TImportReadingCounts& counts)
        : m_readings(readings), m_counts(counts)
    {
    }
    /** The reading of the step at `t` (nullptr: none since the previous step); the earlier
     *  ones since then counted as superseded. */
    const Reading* at(double t)
    {
        const Reading* last = nullptr;
        for (; m_next < m_readings.size() && m_readings[m_next].t <= t; m_next++)
        {
            m_counts.superseded += last != nullptr ? 1 : 0;
            last = &m_readings[m_next];
        }
        m_counts.written += last != nullptr ? 1 : 0;
        return last;
    }
    /** Counts the readings after the last step as dropped. */
    void finish() { m_counts.dropped += m_readings.size() - m_next; }

private:
    const std::vector<Reading>& m_readings;
    TImportReadingCounts& m_counts;
    size_t m_next = 0;
};

/** The odometry action of the step from `from` to `to` (poses of the odometry track). */
mrpt::obs::CActionCollection::Ptr odometryAction(const mrpt::math::TPose2D& from,
                                                 const mrpt::math::TPose2D& to, double t)
{
    // MRPT's default Gaussian model (a1 0.01 m/m, a2 0.057 m/rad, a3 1 deg/m, a4 0.05 rad/rad,
    // minimum std 0.01 m and 0.2 deg per step).
    const mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;
    mrpt::obs::CActionRobotMovement2D action;
    action.computeFromOdometry(mrpt::poses::CPose2D(to) - mrpt::poses::CPose2D(from), model);
    action.timestamp = mrpt::Clock::fromDouble(t);
    auto actions = mrpt::obs::CActionCollection::Create();
    actions->insert(action);
    return actions;
}
/** Whether scan `k` shares the last step of `out`: the scan that follows its scans, of a sensor
 *  none of them is of, within `window_s` of its time. */
bool joinsStep(const std::vector<ImportStep>& out, const std::vector<DetectionScan>& scans,
               size_t k, double window_s)
{
    if (out.empty() || out.back().scan < 0)
    {
        return false;
    }
    const ImportStep& s = out.back();
    const auto first = static_cast<size_t>(s.scan);
    if (first + s.scanCount != k || !detail::inScan(s.t, scans[k].t, window_s))
    {
        return false;
    }
    for (size_t j = first; j < k; j++)
    {
        if (scans[j].sensor == scans[k].sensor)
        {
            return false;
        }
    }
    return true;
}
}  // namespace

const char* DatasetImport::likelyTimeUnit(double ratio)
{
    return ratio < 3e4 ? "milliseconds" : ratio < 3e7 ? "microseconds" : "nanoseconds";
}

void DatasetImport::checkTimeUnit(const std::vector<DetectionScan>& scans,
                                  const OdometryTrack& odometry, const std::string& odometryName,
                                  const std::string& detectionsName)
{
    std::vector<double> t(odometry.t);
    t.reserve(t.size() + scans.size());
    for (const auto& s : scans)
    {
        t.push_back(s.t);
    }
    std::sort(t.begin(), t.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
    if (t.size() < 2)
    {
        return;
    }
    std::vector<double> dt(t.size() - 1);
    for (size_t i = 0; i + 1 < t.size(); i++)
    {
        dt[i] = t[i + 1] - t[i];
    }
    std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
    const double median = dt[dt.size() / 2];
    if (median > kMaxImportMedianInterval_s)
    {
        THROW_EXCEPTION(mrpt::format(
            "times of '%s' and '%s' (%s to %s): the median time between consecutive rows is %s "
            "s, more than %s s: are the times in %s? semloc-import takes seconds",
            odometryName.c_str(), detectionsName.c_str(), num(t.front()).c_str(),
            num(t.back()).c_str(), num(median).c_str(),
            detail::shortestText(kMaxImportMedianInterval_s).c_str(), likelyTimeUnit(median)));
    }
}

std::vector<ImportStep> DatasetImport::steps(const std::vector<DetectionScan>& scans,
                                             const OdometryTrack& odometry, double maxStep_s,
                                             TDatasetImportStats& stats,
                                             const std::string& odometryName,
                                             const std::string& detectionsName, double scanWindow_s)
{
    ASSERT_(!odometry.t.empty());
    checkTimeUnit(scans, odometry, odometryName, detectionsName);
    checkStepCount(scans, odometry, maxStep_s, detectionsName);
    std::vector<ImportStep> out;
    for (size_t k = 0; k < scans.size(); k++)
    {
        const double t = scans[k].t;
        if (t < odometry.t.front() || t > odometry.t.back())
        {
            stats.scansOutsideOdometry++;
            continue;
        }
        if (joinsStep(out, scans, k, scanWindow_s))
        {
            out.back().scanCount++;  // another sensor's scan within the window: one step
            continue;
        }
        if (!out.empty())
        {
            // Evenly spaced odometry-only steps, none of the gaps longer than maxStep_s.
            const double t0 = out.back().t, gap = t - t0;
            const auto n = static_cast<size_t>(stepsBetween(gap, maxStep_s)) + 1;
            for (size_t i = 1; i < n; i++)
            {
                const double ti = t0 + gap * static_cast<double>(i) / static_cast<double>(n);
                if (ti != 0 && ti > out.back().t && ti < t)  // 0: MRPT's "no timestamp"
                {
                    out.push_back({ti, -1, 0});
                }
            }
        }
        out.push_back({t, static_cast<long>(k), 1});
    }
    if (out.empty())
    {
        THROW_EXCEPTION(
            mrpt::format("no scan lies within the odometry's time span [%s, %s] s: "
                         "nothing to import (the %zu scans are at %s to %s s)",
                         num(odometry.t.front()).c_str(), num(odometry.t.back()).c_str(),
                         scans.size(), num(scans.front().t).c_str(), num(scans.back().t).c_str()));
    }
    return out;
}

namespace
{
/** Hands each entry of the steps' rawlog (makeRawlog) to `out`, in order. */
void forEachEntry(const std::vector<ImportStep>& steps, const std::vector<DetectionScan>& scans,
                  const OdometryTrack& odometry, const VehicleReadings& readings,
                  const TDatasetImportOptions& options, TDatasetImportStats& stats,
                  const std::function<void(const mrpt::serialization::CSerializable::Ptr&)>& out)
{
    ReadingPlacer<DepthReading> depth(readings.depth, stats.depth);
    ReadingPlacer<HeadingReading> heading(readings.heading, stats.heading);
    ReadingPlacer<FixReading> fixes(readings.fixes, stats.fixes);
    mrpt::math::TPose2D previous = odometry.at(steps.front().t);
    for (const auto& s : steps)
    {
        const mrpt::math::TPose2D pose = odometry.at(s.t);
        out(odometryAction(previous, pose, s.t));
        previous = pose;
        // The depth first: the detector models take the frame's last depth reading before
        // they score its scans. An odometry-only step's frame holds no scan: the detectors
        // did not report then.
        auto frame = mrpt::obs::CSensoryFrame::Create();
        if (const auto* r = depth.at(s.t))
        {
            frame->insert(depthObservation(*r));
        }
        if (const auto* r = heading.at(s.t))
        {
            frame->insert(headingObservation(*r));
        }
        if (const auto* r = fixes.at(s.t))
        {
            frame->insert(fixObservation(*r));
        }
        if (s.scan >= 0)
        {
            for (size_t k = 0; k < s.scanCount; k++)
            {
                const auto& scan = scans[static_cast<size_t>(s.scan) + k];
                frame->insert(semanticObservation(scan, options, stats));
            }
            stats.scans++;
            stats.stepsOfSeveralScans += s.scanCount > 1 ? 1 : 0;
        }
        else
        {
            stats.odometryOnlySteps++;
        }
        out(frame);
        stats.steps++;
    }
    depth.finish();
    heading.finish();
    fixes.finish();
}
}  // namespace

mrpt::obs::CRawlog DatasetImport::makeRawlog(const std::vector<ImportStep>& steps,
                                             const std::vector<DetectionScan>& scans,
                                             const OdometryTrack& odometry,
                                             const VehicleReadings& readings,
                                             const TDatasetImportOptions& options,
                                             TDatasetImportStats& stats)
{
    mrpt::obs::CRawlog log;
    forEachEntry(steps, scans, odometry, readings, options, stats,
                 [&](const mrpt::serialization::CSerializable::Ptr& e) { log.insert(e); });
    return log;
}

mrpt::obs::CRawlog DatasetImport::makeRawlog(const std::vector<ImportStep>& steps,
                                             const std::vector<DetectionScan>& scans,
                                             const OdometryTrack& odometry,
                                             const TDatasetImportOptions& options,
                                             TDatasetImportStats& stats)
{
    return makeRawlog(steps, scans, odometry, VehicleReadings{}, options, stats);
}

void DatasetImport::writeRawlog(const std::vector<ImportStep>& steps,
                                const std::vector<DetectionScan>& scans,
                                const OdometryTrack& odometry, const VehicleReadings& readings,
                                const TDatasetImportOptions& options, TDatasetImportStats& stats,
                                const std::string& path)
{
    // As saveRawlog() writes makeRawlog()'s CRawlog: the signature, then each entry in order.
    GzOutputFile f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    writeRawlogSignature(a, "semloc-import");
    forEachEntry(steps, scans, odometry, readings, options, stats,
                 [&](const mrpt::serialization::CSerializable::Ptr& e) { a << *e; });
    f.close();
}

void DatasetImport::writeRawlog(const std::vector<ImportStep>& steps,
                                const std::vector<DetectionScan>& scans,
                                const OdometryTrack& odometry, const TDatasetImportOptions& options,
                                TDatasetImportStats& stats, const std::string& path)
{
    writeRawlog(steps, scans, odometry, VehicleReadings{}, options, stats, path);
}

World DatasetImport::makeWorld(const std::vector<ImportedLandmark>& landmarks,
                               const std::vector<GroundTruthRow>& groundTruth, double margin_m,
                               const std::string& name)
{
    std::vector<WorldObject> objects;
    objects.reserve(landmarks.size());
    for (const auto& l : landmarks)
    {
        objects.push_back(l.object);
    }
    return LandmarkImport::makeWorld(objects, posesOf(groundTruth), margin_m, name);
}

}  // namespace semloc

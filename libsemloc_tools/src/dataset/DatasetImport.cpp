/* semloc — DatasetImport: the steps, rawlog, ground truth and world of an imported dataset
 * (the CSV readers are in DatasetImportReaders.cpp; the ground truth at the steps and the
 * counts of the summary line in DatasetImportChecks.cpp). */
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/io/RawlogWriter.h>

#include <algorithm>
#include <cmath>
#include <functional>

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

/** The scan's observation: the detector's pose, coverage and detections at time `t`. */
CObservationSemantic::Ptr semanticObservation(const DetectionScan& scan,
                                              const TDatasetImportOptions& o,
                                              TDatasetImportStats& stats)
{
    auto obs = CObservationSemantic::Create();
    obs->sensorLabel = "SEMANTIC";
    obs->timestamp = mrpt::Clock::fromDouble(scan.t);
    obs->sensorPose =
        mrpt::poses::CPose3D(o.sensorPose.x, o.sensorPose.y, 0, o.sensorPose.phi, 0, 0);
    obs->maxRange_m = o.maxRange_m;
    obs->fov_rad = mrpt::DEG2RAD(o.fov_deg);
    obs->detections = scan.detections;
    for (const auto& d : scan.detections)
    {
        stats.detectionsOutsideCoverage += obs->isValid(d) ? 0 : 1;
    }
    stats.detections += scan.detections.size();
    return obs;
}

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
                                             const std::string& detectionsName)
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
                    out.push_back({ti, -1});
                }
            }
        }
        out.push_back({t, static_cast<long>(k)});
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
                  const OdometryTrack& odometry, const TDatasetImportOptions& options,
                  TDatasetImportStats& stats,
                  const std::function<void(const mrpt::serialization::CSerializable::Ptr&)>& out)
{
    mrpt::math::TPose2D previous = odometry.at(steps.front().t);
    for (const auto& s : steps)
    {
        const mrpt::math::TPose2D pose = odometry.at(s.t);
        out(odometryAction(previous, pose, s.t));
        previous = pose;
        // An odometry-only step's frame is empty: the detector did not report then.
        auto frame = mrpt::obs::CSensoryFrame::Create();
        if (s.scan >= 0)
        {
            frame->insert(semanticObservation(scans[static_cast<size_t>(s.scan)], options, stats));
            stats.scans++;
        }
        else
        {
            stats.odometryOnlySteps++;
        }
        out(frame);
        stats.steps++;
    }
}
}  // namespace

mrpt::obs::CRawlog DatasetImport::makeRawlog(const std::vector<ImportStep>& steps,
                                             const std::vector<DetectionScan>& scans,
                                             const OdometryTrack& odometry,
                                             const TDatasetImportOptions& options,
                                             TDatasetImportStats& stats)
{
    mrpt::obs::CRawlog log;
    forEachEntry(steps, scans, odometry, options, stats,
                 [&](const mrpt::serialization::CSerializable::Ptr& e) { log.insert(e); });
    return log;
}

void DatasetImport::writeRawlog(const std::vector<ImportStep>& steps,
                                const std::vector<DetectionScan>& scans,
                                const OdometryTrack& odometry, const TDatasetImportOptions& options,
                                TDatasetImportStats& stats, const std::string& path)
{
    // As saveRawlog() writes makeRawlog()'s CRawlog: the signature, then each entry in order.
    GzOutputFile f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    writeRawlogSignature(a, "semloc-import");
    forEachEntry(steps, scans, odometry, options, stats,
                 [&](const mrpt::serialization::CSerializable::Ptr& e) { a << *e; });
    f.close();
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

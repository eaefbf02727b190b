/* semloc — the detector's and the odometry's noise estimated against ground truth. */
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/system/datetime.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/experiment/GroundTruth.h>
#include <semloc/filter/OdometryDelay.h>
#include <semloc/models/semantic/DetectionProbability.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/SemanticDetectorModel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "calibration/CalibrationFits.h"
#include "calibration/CalibrationLookAlikes.h"
#include "calibration/CalibrationPasses.h"

namespace semloc
{
namespace
{
constexpr double kInfinity = std::numeric_limits<double>::infinity();
using detail::Gate;
using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CSensoryFrame;

/** The detector options that reproduce an observation's coverage (visibility only). */
SemanticDetectorModel::TOptions coverageOf(const CObservationSemantic& obs)
{
    SemanticDetectorModel::TOptions o;
    o.max_range_m = obs.maxRange_m;
    o.fov_deg = mrpt::RAD2DEG(obs.fov_rad);
    o.sensor_x_m = obs.sensorPose.x();
    o.sensor_y_m = obs.sensorPose.y();
    o.sensor_yaw_deg = mrpt::RAD2DEG(obs.sensorPose.yaw());
    return o;
}

/** Squared distance between a detection and an object in the sensor frame. */
double distance2(const TSemanticDetection& d, const SemanticDetectorModel::TVisibleObject& v)
{
    const double dx = d.range_m * std::cos(d.bearing_rad) - v.range_m * std::cos(v.bearing_rad);
    const double dy = d.range_m * std::sin(d.bearing_rad) - v.range_m * std::sin(v.bearing_rad);
    return dx * dx + dy * dy;
}

/** A candidate (detection j, object v) of a matching and what it costs. */
struct MatchPair
{
    double cost;
    size_t j, v;
};

/** Takes the `pairs` one to one, cheapest first (ties by j, then v), each unless its detection
 *  or its object is taken; returns how many it took. */
size_t takeGreedy(std::vector<MatchPair>& pairs, std::vector<int>& detTo, std::vector<int>& visTo)
{
    std::sort(pairs.begin(), pairs.end(),
              [](const MatchPair& a, const MatchPair& b) {
                  return a.cost < b.cost ||
                         (a.cost == b.cost && (a.j < b.j || (a.j == b.j && a.v < b.v)));
              });
    size_t n = 0;
    for (const auto& p : pairs)
    {
        if (detTo[p.j] < 0 && visTo[p.v] < 0)
        {
            detTo[p.j] = static_cast<int>(p.v);
            visTo[p.v] = static_cast<int>(p.j);
            n++;
        }
    }
    return n;
}

/** One-to-one greedy matching, nearest pair first, of the detections and objects not yet used
 *  within the gate; `sameLabel` selects same- or other-label pairs. */
void matchGreedy(const std::vector<TSemanticDetection>& dets,
                 const std::vector<SemanticDetectorModel::TVisibleObject>& vis, const World& world,
                 const Gate& gate, bool sameLabel, std::vector<int>& detTo, std::vector<int>& visTo)
{
    std::vector<MatchPair> pairs;
    for (size_t j = 0; j < dets.size(); j++)
    {
        for (size_t v = 0; v < vis.size(); v++)
        {
            const bool same = dets[j].label == world.objects[vis[v].index].label;
            double d2 = distance2(dets[j], vis[v]) / (gate.radius_m * gate.radius_m);
            if (gate.normalized())
            {
                const double dr = (dets[j].range_m - vis[v].range_m) / gate.sigmaRange_m;
                const double db = mrpt::math::wrapToPi(dets[j].bearing_rad - vis[v].bearing_rad) /
                                  gate.sigmaBearing_rad;
                d2 = (dr * dr + db * db) / (gate.k * gate.k);
            }
            if (detTo[j] < 0 && visTo[v] < 0 && same == sameLabel && d2 <= 1.0)
            {
                pairs.push_back({d2, j, v});
            }
        }
    }
    takeGreedy(pairs, detTo, visTo);
}

/** The share of one scan's clutter expected within the gate of object `v`: the clutter is
 *  uniform in range and bearing over the coverage, so this is the area of the gate in the
 *  (range, bearing) plane, clipped to the coverage, over R fov (a 32 x 32 grid over the
 *  gate's bounding box). */
double clutterInGate(const SemanticDetectorModel::TVisibleObject& v,
                     const CObservationSemantic& obs, const Gate& gate)
{
    constexpr int kCells = 32;
    // Half-extents of the bounding box in range and bearing.
    const double hr = gate.normalized() ? gate.k * gate.sigmaRange_m : gate.radius_m;
    const double hb = gate.normalized() ? gate.k * gate.sigmaBearing_rad
                                        : std::asin(std::min(1.0, gate.radius_m / v.range_m));
    double area = 0;
    for (int i = 0; i < kCells; i++)
    {
        for (int j = 0; j < kCells; j++)
        {
            const double dr = hr * (2 * (i + 0.5) / kCells - 1);
            const double db = hb * (2 * (j + 0.5) / kCells - 1);
            const double r = v.range_m + dr, b = v.bearing_rad + db;
            if (r < 0 || r > obs.maxRange_m || std::abs(b) > 0.5 * obs.fov_rad)
            {
                continue;
            }
            TSemanticDetection d;
            d.range_m = r;
            d.bearing_rad = b;
            const bool inside = gate.normalized()
                                    ? (dr * dr / (hr * hr) + db * db / (hb * hb) <= 1)
                                    : distance2(d, v) <= gate.radius_m * gate.radius_m;
            area += inside ? 4 * hr * hb / (kCells * kCells) : 0.0;
        }
    }
    return area / (obs.maxRange_m * obs.fov_rad);
}

/** The bearing interval of the misread strip of object `v` (within gateSigmas sigma_bearing
 *  of its bearing), clipped to the field of view; empty when lo >= hi. */
std::pair<double, double> misreadStrip(const SemanticDetectorModel::TVisibleObject& v,
                                       const CObservationSemantic& obs, const Gate& gate)
{
    const double half = 0.5 * obs.fov_rad, hb = gate.k * gate.sigmaBearing_rad;
    return {std::max(v.bearing_rad - hb, -half), std::min(v.bearing_rad + hb, half)};
}

/** Per in-view object, the share of one scan's clutter of its label expected in its misread
 *  strip (its bearing gate at any range, outside its gate) when `open[v]` (no detection
 *  matched it in a gate), else 0. A clutter detection is taken once: where strips of
 *  one label overlap, their shares are scaled down to the union's. */
std::vector<double> clutterInMisreadStrips(
    const std::vector<SemanticDetectorModel::TVisibleObject>& vis, const std::vector<bool>& open,
    const World& world, const CObservationSemantic& obs, const Gate& gate)
{
    std::vector<double> share(vis.size(), 0.0);
    std::vector<bool> done(vis.size(), false);
    for (size_t a = 0; a < vis.size(); a++)
    {
        if (!open[a] || done[a])
        {
            continue;
        }
        // The open objects of a's label: their strips' summed width and union.
        const std::string& label = world.objects[vis[a].index].label;
        std::vector<std::pair<double, double>> strips;
        std::vector<size_t> members;
        double sum = 0;
        for (size_t v = a; v < vis.size(); v++)
        {
            if (open[v] && world.objects[vis[v].index].label == label)
            {
                const auto st = misreadStrip(vis[v], obs, gate);
                sum += std::max(0.0, st.second - st.first);
                strips.push_back(st);
                members.push_back(v);
                done[v] = true;
            }
        }
        std::sort(strips.begin(), strips.end());
        double uni = 0, end = -kInfinity;
        for (const auto& [lo, hi] : strips)
        {
            uni += std::max(0.0, hi - std::max(lo, end));
            end = std::max(end, hi);
        }
        const double scale = sum > 0 ? uni / sum : 0.0;
        for (const size_t v : members)
        {
            const auto st = misreadStrip(vis[v], obs, gate);
            share[v] = std::max(0.0, std::max(0.0, st.second - st.first) * scale / obs.fov_rad -
                                         clutterInGate(vis[v], obs, gate));
        }
    }
    return share;
}

/** One-to-one greedy matching, nearest bearing first, of the detections and objects left of
 *  the same label whose bearings are within the gate's bearing half-width: misread ranges. */
size_t matchMisread(const std::vector<TSemanticDetection>& dets,
                    const std::vector<SemanticDetectorModel::TVisibleObject>& vis,
                    const World& world, const Gate& gate, std::vector<int>& detTo,
                    std::vector<int>& visTo)
{
    std::vector<MatchPair> pairs;
    for (size_t j = 0; j < dets.size(); j++)
    {
        for (size_t v = 0; v < vis.size(); v++)
        {
            const double db =
                std::abs(mrpt::math::wrapToPi(dets[j].bearing_rad - vis[v].bearing_rad));
            if (detTo[j] < 0 && visTo[v] < 0 &&
                dets[j].label == world.objects[vis[v].index].label &&
                db <= gate.k * gate.sigmaBearing_rad)
            {
                pairs.push_back({db, j, v});
            }
        }
    }
    return takeGreedy(pairs, detTo, visTo);
}

/** The sensor's pose in the world at vehicle pose `pose`. */
mrpt::poses::CPose2D sensorAt(const mrpt::math::TPose2D& pose, const CObservationSemantic& obs)
{
    return mrpt::poses::CPose2D(pose) +
           mrpt::poses::CPose2D(obs.sensorPose.x(), obs.sensorPose.y(), obs.sensorPose.yaw());
}

/** The samples of detection `d` matched to object `v`: its residuals (at `pose` and at the
 *  ground truth `truth`), unless the object is near the coverage's edge, and where it puts the
 *  object in the map's frame. */
void addMatch(const CObservationSemantic& obs, const TSemanticDetection& d,
              const SemanticDetectorModel::TVisibleObject& v, const mrpt::math::TPose2D& pose,
              const mrpt::math::TPose2D& truth, const World& world, const Gate& gate,
              TCalibrationSamples& s)
{
    const auto& centre = world.objects[v.index].center;
    const auto sensorTruth = sensorAt(truth, obs);
    const auto local = sensorTruth.inverseComposePoint(centre);
    // The detector clamps its readings to its coverage: residuals of objects within
    // 3 sigma of its edge are truncated and left out of the sigmas.
    if (v.range_m + 3 * gate.sigmaRange_m <= obs.maxRange_m && v.range_m >= 3 * gate.sigmaRange_m)
    {
        s.rangeResiduals_m.push_back(d.range_m - v.range_m);
        s.rangeResidualBearing.push_back(bearingOverHalfView(d.bearing_rad, obs.fov_rad));
        s.rangeResidualsAtTruth_m.push_back(d.range_m - local.norm());
    }
    if (std::abs(v.bearing_rad) + 3 * gate.sigmaBearing_rad <= 0.5 * obs.fov_rad)
    {
        s.bearingResiduals_deg.push_back(
            mrpt::RAD2DEG(mrpt::math::wrapToPi(d.bearing_rad - v.bearing_rad)));
        s.bearingResidualsAtTruth_deg.push_back(
            mrpt::RAD2DEG(mrpt::math::wrapToPi(d.bearing_rad - std::atan2(local.y, local.x))));
    }
    const auto at = sensorAt(pose, obs).composePoint(mrpt::math::TPoint2D(
        d.range_m * std::cos(d.bearing_rad), d.range_m * std::sin(d.bearing_rad)));
    s.detectedX_m.push_back(at.x);
    s.detectedY_m.push_back(at.y);
    s.objectX_m.push_back(centre.x);
    s.objectY_m.push_back(centre.y);
}

/** The detector's side of one scan at true pose `truth`, placed in the map's frame by
 *  `toMap`, seen by `model`. */
void addScan(const CObservationSemantic& obs, const mrpt::math::TPose2D& truth,
             const detail::RigidTransform2D& toMap, const World& world,
             const SemanticDetectorModel& model, const Gate& gate,
             const SensorCalibration::TOptions& o, LookAlikeMemory& memory, TCalibrationResult& r)
{
    const auto pose = toMap.apply(truth);
    const auto vis = model.visibleObjects(pose);
    std::vector<int> detTo(obs.detections.size(), -1), visTo(vis.size(), -1);
    matchGreedy(obs.detections, vis, world, gate, true, detTo, visTo);
    size_t same = 0;
    for (size_t j = 0; j < detTo.size(); j++)
    {
        if (detTo[j] >= 0)
        {
            addMatch(obs, obs.detections[j], vis[static_cast<size_t>(detTo[j])], pose, truth, world,
                     gate, r.samples);
            same++;
        }
    }
    const double otherLabels = model.labels().size() > 1
                                   ? static_cast<double>(model.labels().size() - 1) /
                                         static_cast<double>(model.labels().size())
                                   : 0.0;
    for (size_t v = 0; v < vis.size(); v++)
    {
        r.samples.visibleSpurious.push_back(
            visTo[v] < 0 ? otherLabels * clutterInGate(vis[v], obs, gate) : 0.0);
    }
    matchGreedy(obs.detections, vis, world, gate, false, detTo, visTo);
    const double ownLabel = 1.0 / static_cast<double>(std::max<size_t>(1, model.labels().size()));
    std::vector<bool> open(vis.size());
    for (size_t v = 0; v < vis.size(); v++)
    {
        r.samples.visibleRanges_m.push_back(vis[v].range_m);
        r.samples.visibleDetected.push_back(visTo[v] >= 0 ? 1 : 0);
        r.samples.visibleOffAxis.push_back(
            obs.fov_rad < 2 * M_PI
                ? std::min(std::abs(vis[v].bearing_rad) / (0.5 * obs.fov_rad), 1.0)
                : 0.0);
        open[v] = visTo[v] < 0 && gate.normalized();
    }
    for (const double share : clutterInMisreadStrips(vis, open, world, obs, gate))
    {
        r.samples.visibleMisreadSpurious.push_back(ownLabel * share);
    }
    // Misread ranges, once the sigmas are known (the first pass's disc has no bearing width),
    // among what the gates left: they leave the other fits as they were.
    const size_t misread =
        gate.normalized() ? matchMisread(obs.detections, vis, world, gate, detTo, visTo) : 0;
    detail::addLookAlikeScan(obs, sensorAt(pose, obs), detTo, model.labels(), gate.sigmaRange_m,
                             gate.sigmaBearing_rad, o, memory, r.samples);
    const auto used = static_cast<size_t>(
        std::count_if(detTo.begin(), detTo.end(), [](int v) { return v >= 0; }));
    r.matched += same;
    r.misread += misread;
    r.confused += used - same - misread;
    r.clutter += obs.detections.size() - used;
    if (r.scans == 0)
    {
        r.maxRange_m = obs.maxRange_m;
        r.misreadInGate = gate.normalized()
                              ? std::min(1.0, 2 * gate.k * gate.sigmaRange_m / obs.maxRange_m)
                              : 0.0;
    }
    r.scans++;
}

std::string secondsText(double s)
{
    std::ostringstream t;
    t << s;
    return t.str();
}

/** The ground-truth row at `t`, or an error naming the rawlog entry. */
const GroundTruthRow& rowAt(const GroundTruth& gt, mrpt::Clock::time_point t, double tol,
                            const std::string& rawlogName, size_t entry)
{
    const GroundTruthRow* row = gt.nearest(mrpt::Clock::toDouble(t), tol);
    if (t == INVALID_TIMESTAMP || row == nullptr)
    {
        throw std::runtime_error("rawlog '" + rawlogName + "': entry " + std::to_string(entry) +
                                 ": no ground-truth row within " + secondsText(tol) +
                                 " s of its timestamp");
    }
    return *row;
}

/** The odometry increment `odo` of one action against the ground truth between `prev` and
 *  `cur`. */
void addIncrement(const mrpt::poses::CPose2D& odo, const GroundTruthRow& prev,
                  const GroundTruthRow& cur, TCalibrationResult& r)
{
    const mrpt::poses::CPose2D truth =
        mrpt::poses::CPose2D(cur.pose()) - mrpt::poses::CPose2D(prev.pose());
    r.samples.odomDist_m.push_back(truth.norm());
    r.samples.odomTurn_rad.push_back(std::abs(truth.phi()));
    r.samples.odomErrXY_m.push_back(std::hypot(odo.x() - truth.x(), odo.y() - truth.y()));
    const double errPhi = mrpt::math::wrapToPi(odo.phi() - truth.phi());
    r.samples.odomErrPhi_rad.push_back(std::abs(errPhi));
    r.samples.odomErrPhiSigned_rad.push_back(errPhi);
    r.samples.odomDt_s.push_back(cur.t - prev.t);
    r.increments++;
}

/** A detector model of `obs`'s coverage: `model` kept while the coverage is the same. */
const SemanticDetectorModel& modelFor(const CObservationSemantic& obs, const World& world,
                                      std::unique_ptr<SemanticDetectorModel>& model)
{
    const auto c = coverageOf(obs);
    if (!model || model->options().max_range_m != c.max_range_m ||
        model->options().fov_deg != c.fov_deg || model->options().sensor_x_m != c.sensor_x_m ||
        model->options().sensor_y_m != c.sensor_y_m ||
        model->options().sensor_yaw_deg != c.sensor_yaw_deg)
    {
        model = std::make_unique<SemanticDetectorModel>(world, c);
    }
    return *model;
}

/** The odometry and the truth composed since the last scan with a detection. */
struct Span
{
    mrpt::poses::CPose2D odometry, truth;
    size_t begin = 0;
    double dt_s = 0;
    /** A scan with a detection: the span up to it is recorded and a new one begins. */
    void close(TCalibrationResult& r)
    {
        auto& s = r.samples;
        if (s.odomDist_m.size() > begin)
        {
            s.spanBegin.push_back(begin);
            s.spanEnd.push_back(s.odomDist_m.size());
            s.spanErrXY_m.push_back(std::hypot(odometry.x() - truth.x(), odometry.y() - truth.y()));
            s.spanErrPhi_rad.push_back(mrpt::math::wrapToPi(odometry.phi() - truth.phi()));
            s.spanDt_s.push_back(dt_s);
        }
        *this = Span();
        begin = s.odomDist_m.size();
    }
    void add(const mrpt::poses::CPose2D& odo, const GroundTruthRow& prev, const GroundTruthRow& cur)
    {
        odometry = odometry + odo;
        truth = truth + (mrpt::poses::CPose2D(cur.pose()) - mrpt::poses::CPose2D(prev.pose()));
        dt_s += cur.t - prev.t;
    }
};

/** The semantic observations of a sensory frame or observation entry. */
std::vector<std::shared_ptr<CObservationSemantic>> semanticScans(
    const mrpt::serialization::CSerializable::Ptr& entry)
{
    std::vector<std::shared_ptr<CObservationSemantic>> out;
    const auto add = [&](const mrpt::obs::CObservation::Ptr& o)
    {
        if (auto obs = std::dynamic_pointer_cast<CObservationSemantic>(o))
        {
            out.push_back(std::move(obs));
        }
    };
    if (const auto sf = std::dynamic_pointer_cast<CSensoryFrame>(entry))
    {
        for (size_t k = 0; k < sf->size(); k++)
        {
            add(sf->getObservationByIndex(k));
        }
    }
    else
    {
        add(std::dynamic_pointer_cast<mrpt::obs::CObservation>(entry));
    }
    return out;
}

/** The odometry of an action-collection entry (null for another entry, or an action
 *  collection without a movement). */
std::shared_ptr<CActionRobotMovement2D> odometryOf(
    const mrpt::serialization::CSerializable::Ptr& entry)
{
    const auto acts = std::dynamic_pointer_cast<CActionCollection>(entry);
    return acts ? acts->getBestMovementEstimation() : nullptr;
}
}  // namespace

namespace detail
{
std::vector<TimedIncrement> timedIncrements(const RawlogWalk& walk, const std::string& rawlogName,
                                            const GroundTruth& gt,
                                            const SensorCalibration::TOptions& o)
{
    std::vector<TimedIncrement> out;
    walk(
        [&](size_t i, const mrpt::serialization::CSerializable::Ptr& entry)
        {
            if (const auto act = odometryOf(entry))
            {
                out.push_back({mrpt::Clock::toDouble(act->timestamp),
                               act->rawOdometryIncrementReading.asTPose(),
                               &rowAt(gt, act->timestamp, o.gtTolerance_s, rawlogName, i)});
            }
        });
    return out;
}

void collect(const RawlogWalk& walk, const std::string& rawlogName, const World& world,
             const GroundTruth& gt, const SensorCalibration::TOptions& o, const Gate& gate,
             const RigidTransform2D& toMap, double delay_s, TCalibrationResult& r)
{
    const GroundTruthRow* prevAction = nullptr;
    std::unique_ptr<SemanticDetectorModel> model;
    OdometryDelay delay(delay_s);
    LookAlikeMemory memory;
    Span span;
    walk(
        [&](size_t i, const mrpt::serialization::CSerializable::Ptr& entry)
        {
            if (std::dynamic_pointer_cast<CActionCollection>(entry))
            {
                const auto act = odometryOf(entry);
                if (!act)
                {
                    return;
                }
                const GroundTruthRow& row =
                    rowAt(gt, act->timestamp, o.gtTolerance_s, rawlogName, i);
                // The increment the filter moves by: the odometry's, re-cut by the delay.
                const mrpt::poses::CPose2D odo(
                    delay.step(mrpt::Clock::toDouble(act->timestamp),
                               act->rawOdometryIncrementReading.asTPose()));
                if (prevAction != nullptr)
                {
                    addIncrement(odo, *prevAction, row, r);
                    span.add(odo, *prevAction, row);
                }
                prevAction = &row;
                return;
            }
            for (const auto& obs : semanticScans(entry))
            {
                const GroundTruthRow& row =
                    rowAt(gt, obs->timestamp, o.gtTolerance_s, rawlogName, i);
                // The ranges as the filter reads them: less the bias found so far.
                CObservationSemantic corrected;
                addScan(lessRangeBias(*obs, r.rangeBias_m, corrected), row.pose(), toMap, world,
                        modelFor(*obs, world, model), gate, o, memory, r);
                if (!obs->detections.empty())
                {
                    span.close(r);
                }
            }
        });
    span.close(r);
}
}  // namespace detail

}  // namespace semloc

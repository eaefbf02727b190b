/* semloc — CSemanticMap's mapping: observations taken from a known pose become objects, or
 * refine the objects they name or lie near; the objects a detector's coverage holds. */
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionProbability.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace semloc
{
namespace
{
/** A detection placed in the world. */
struct NewDetection
{
    std::string label;
    int32_t id;
    double wx, wy;
    /** P_D at its range and bearing (1 for MRPT landmarks, which carry no coverage). */
    double expected = 1;
};

/** The world position of range r and bearing b of a sensor at sensorOnVehicle. */
std::pair<double, double> toWorld(const mrpt::poses::CPose3D& vehicle,
                                  const mrpt::poses::CPose3D& sensorOnVehicle, double r, double b)
{
    const mrpt::poses::CPose3D s = vehicle + sensorOnVehicle;
    const double a = s.yaw() + b;
    return std::make_pair(s.x() + r * std::cos(a), s.y() + r * std::sin(a));
}

/** The valid detections of `o` with at least `minConfidence`, in the world. */
std::vector<NewDetection> inWorld(const CObservationSemantic& o,
                                  const mrpt::poses::CPose3D& vehicle,
                                  const CSemanticMap::TLikelihoodOptions& opt)
{
    const double minConfidence = opt.detector.min_confidence;
    const double R = opt.maxRange(o);
    const double fov = opt.fieldOfView(o);
    std::vector<NewDetection> news;
    for (const auto& d : o.detections)
    {
        if (!o.isValid(d) || d.confidence < minConfidence)
        {
            continue;
        }
        const double range = opt.correctedRange(d.range_m, d.bearing_rad, R, fov);
        const auto [wx, wy] = toWorld(vehicle, o.sensorPose, range, d.bearing_rad);
        news.push_back({d.label, d.object_id, wx, wy,
                        R > 0 && std::isfinite(R)
                            ? opt.detectionProbability(range, R, d.bearing_rad, fov)
                            : 1.0});
    }
    return news;
}

/** The landmarks of `br` with a finite, non-negative range and a finite bearing, in the
 *  world, labelled `label`. */
std::vector<NewDetection> inWorld(const mrpt::obs::CObservationBearingRange& br,
                                  const mrpt::poses::CPose3D& vehicle, const std::string& label)
{
    std::vector<NewDetection> news;
    for (const auto& m : br.sensedData)
    {
        if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || m.range < 0)
        {
            continue;
        }
        const auto [wx, wy] = toWorld(vehicle, br.sensorLocationOnRobot, m.range, m.yaw);
        news.push_back({label, m.landmarkID, wx, wy, 1.0});
    }
    return news;
}

/** The object detection n merges into: the object it names, else (without an id) the
 *  nearest object of its label within mergeDistance; null: none. */
CSemanticMap::TObject* mergeTarget(std::vector<CSemanticMap::TObject>& objects,
                                   const NewDetection& n, double mergeDistance)
{
    CSemanticMap::TObject* target = nullptr;
    if (n.id >= 0)
    {
        for (auto& ob : objects)
        {
            if (ob.id == n.id)
            {
                target = &ob;
            }
        }
        return target;
    }
    double best = mergeDistance;
    for (auto& ob : objects)
    {
        const double dd = std::hypot(ob.x - n.wx, ob.y - n.wy);
        if (ob.label == n.label && dd <= best)
        {
            best = dd;
            target = &ob;
        }
    }
    return target;
}

/** Running mean of the merged detections, and the sum of their squared distances to it
 *  (Welford's update, both axes). */
void mergeInto(CSemanticMap::TObject& target, const NewDetection& n)
{
    const double k = 1.0 / (target.n_observations + 1.0);
    const double dx = n.wx - target.x, dy = n.wy - target.y;
    target.x += dx * k;
    target.y += dy * k;
    target.scatter_m2 += dx * (n.wx - target.x) + dy * (n.wy - target.y);
    target.n_observations++;
    target.n_detected++;
}

/** Counts every object of `map` inside the coverage of `o` (taken at `vehicle`) as in view,
 *  with the detection it was expected to give (P_D at its range), into `objects` (the map's). */
void countInView(const CSemanticMap& map, std::vector<CSemanticMap::TObject>& objects,
                 const CObservationSemantic& o, const mrpt::poses::CPose3D& vehicle)
{
    const auto& opt = map.likelihoodOptions;
    const double R = opt.maxRange(o), fov = opt.fieldOfView(o);
    for (const auto& v : map.objectsInView(o, vehicle))
    {
        objects[v.index].n_in_view++;
        objects[v.index].expected_detections +=
            opt.detectionProbability(v.range_m, R, v.bearing_rad, fov);
    }
}

/** How sure the map now is of an object the insertions saw: the position sigma of its mean
 *  (the detections' spread per axis over sqrt(n) from 3 detections on, else sigma_rho /
 *  sqrt(n)) and p_exist = (detections + 1) / (expected detections + 1), at most 1. */
void updateSurety(CSemanticMap::TObject& ob, double sigmaRange)
{
    const double n = ob.n_observations;
    if (ob.n_detected > 0)
    {
        const double var =
            n >= 3 ? ob.scatter_m2 / (2 * (n - 1)) : sigmaRange * sigmaRange;  // per axis
        ob.sigma_m = std::sqrt(var / n);
    }
    if (ob.n_in_view > 0)
    {
        ob.p_exist = std::clamp((ob.n_detected + 1.0) / (ob.expected_detections + 1.0), 1e-3, 1.0);
    }
}
}  // namespace

double CSemanticMap::TLikelihoodOptions::detectionProbability(double rho, double R, double theta,
                                                              double fov) const
{
    return std::clamp(
        semloc::detectionProbability(probabilistic.p_detect_near, probabilistic.p_detect_far,
                                     probabilistic.p_detect_edge_ratio, rho, R, theta, fov),
        1e-6, 1.0);
}

std::vector<CSemanticMap::TObjectInView> CSemanticMap::objectsInView(
    const CObservationSemantic& obs, const mrpt::poses::CPose3D& vehicle) const
{
    const double R = likelihoodOptions.maxRange(obs);
    const double fov = likelihoodOptions.fieldOfView(obs);
    std::vector<TObjectInView> out;
    if (!(R > 0 && std::isfinite(R) && fov > 0 && std::isfinite(fov)))
    {
        return out;
    }
    const mrpt::poses::CPose3D s = vehicle + obs.sensorPose;
    for (size_t i = 0; i < m_objects.size(); i++)
    {
        const double dx = m_objects[i].x - s.x(), dy = m_objects[i].y - s.y();
        const double rho = std::hypot(dx, dy);
        const double b = mrpt::math::wrapToPi(std::atan2(dy, dx) - s.yaw());
        if (rho <= R && (fov >= 2 * M_PI || std::abs(b) <= 0.5 * fov))
        {
            out.push_back({i, rho, b});
        }
    }
    return out;
}

bool CSemanticMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const mrpt::poses::CPose3D vehicle = robotPose ? *robotPose : mrpt::poses::CPose3D();
    std::vector<NewDetection> news;
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        news = inWorld(*o, vehicle, likelihoodOptions);
        countInView(*this, m_objects, *o, vehicle);
    }
    else if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        news = inWorld(*br, vehicle, insertionOptions.landmark_label);
    }
    else
    {
        return false;
    }
    for (const auto& n : news)
    {
        if (TObject* target = mergeTarget(m_objects, n, insertionOptions.merge_distance_m))
        {
            mergeInto(*target, n);
            continue;
        }
        TObject ob;
        ob.id = n.id > 0 ? n.id : nextFreeId();
        ob.label = n.label;
        ob.x = n.wx;
        ob.y = n.wy;
        ob.z = 0;
        ob.n_detected = 1;
        ob.n_in_view = 1;  // in view where it was detected, with its detection expected
        ob.expected_detections = n.expected;
        m_objects.push_back(std::move(ob));
    }
    for (auto& ob : m_objects)
    {
        updateSurety(ob, likelihoodOptions.detector.sigma_range_m);
    }
    rebuildIndex();
    return !news.empty();
}
}  // namespace semloc

/* semloc — CSemanticMap's mapping: observations taken from a known pose become objects, or
 * refine the objects they name or lie near. */
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/maps/CSemanticMap.h>

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
    /** P_D at its range (1 for MRPT landmarks, which carry no coverage). */
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

/** P_D(rho) of the probabilistic model (linear between p_detect_near and p_detect_far). */
double detectionProbability(const CSemanticMap::TLikelihoodOptions& opt, double rho, double R)
{
    const double p = opt.p_detect_near + (opt.p_detect_far - opt.p_detect_near) * rho / R;
    return std::clamp(p, 1e-6, 1.0);
}

/** The valid detections of `o` with at least `minConfidence`, in the world. */
std::vector<NewDetection> inWorld(const CObservationSemantic& o,
                                  const mrpt::poses::CPose3D& vehicle,
                                  const CSemanticMap::TLikelihoodOptions& opt)
{
    const double minConfidence = opt.min_confidence;
    const double R = opt.max_range_m > 0 ? opt.max_range_m : o.maxRange_m;
    std::vector<NewDetection> news;
    for (const auto& d : o.detections)
    {
        if (!o.isValid(d) || d.confidence < minConfidence)
        {
            continue;
        }
        const auto [wx, wy] = toWorld(vehicle, o.sensorPose, d.range_m, d.bearing_rad);
        news.push_back({d.label, d.object_id, wx, wy,
                        R > 0 && std::isfinite(R) ? detectionProbability(opt, d.range_m, R) : 1.0});
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

/** Counts every object inside the coverage of `o` (taken at `vehicle`) as in view, with the
 *  detection it was expected to give (P_D at its range). */
void countInView(std::vector<CSemanticMap::TObject>& objects, const CObservationSemantic& o,
                 const mrpt::poses::CPose3D& vehicle, const CSemanticMap::TLikelihoodOptions& opt)
{
    const double R = opt.max_range_m > 0 ? opt.max_range_m : o.maxRange_m;
    const double fov = opt.fov_deg > 0 ? opt.fov_deg * M_PI / 180 : o.fov_rad;
    if (!(R > 0 && std::isfinite(R) && fov > 0 && std::isfinite(fov)))
    {
        return;
    }
    const mrpt::poses::CPose3D s = vehicle + o.sensorPose;
    for (auto& ob : objects)
    {
        const double dx = ob.x - s.x(), dy = ob.y - s.y();
        const double rho = std::hypot(dx, dy);
        const double b = mrpt::math::wrapToPi(std::atan2(dy, dx) - s.yaw());
        if (rho <= R && (fov >= 2 * M_PI || std::abs(b) <= 0.5 * fov))
        {
            ob.n_in_view++;
            ob.expected_detections += detectionProbability(opt, rho, R);
        }
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

bool CSemanticMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const mrpt::poses::CPose3D vehicle = robotPose ? *robotPose : mrpt::poses::CPose3D();
    std::vector<NewDetection> news;
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        news = inWorld(*o, vehicle, likelihoodOptions);
        countInView(m_objects, *o, vehicle, likelihoodOptions);
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
        updateSurety(ob, likelihoodOptions.sigma_range_m);
    }
    rebuildIndex();
    return !news.empty();
}
}  // namespace semloc

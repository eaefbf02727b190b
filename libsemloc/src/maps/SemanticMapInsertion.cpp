/* semloc — CSemanticMap's mapping: observations taken from a known pose become objects, or
 * refine the objects they name or lie near. */
#include <mrpt/poses/CPose3D.h>
#include <semloc/maps/CSemanticMap.h>

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
                                  const mrpt::poses::CPose3D& vehicle, double minConfidence)
{
    std::vector<NewDetection> news;
    for (const auto& d : o.detections)
    {
        if (!o.isValid(d) || d.confidence < minConfidence)
        {
            continue;
        }
        const auto [wx, wy] = toWorld(vehicle, o.sensorPose, d.range_m, d.bearing_rad);
        news.push_back({d.label, d.object_id, wx, wy});
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
        news.push_back({label, m.landmarkID, wx, wy});
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

/** Running mean of the merged detections. */
void mergeInto(CSemanticMap::TObject& target, const NewDetection& n)
{
    const double k = 1.0 / (target.n_observations + 1.0);
    target.x += (n.wx - target.x) * k;
    target.y += (n.wy - target.y) * k;
    target.n_observations++;
}
}  // namespace

bool CSemanticMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const mrpt::poses::CPose3D vehicle = robotPose ? *robotPose : mrpt::poses::CPose3D();
    std::vector<NewDetection> news;
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        news = inWorld(*o, vehicle, likelihoodOptions.min_confidence);
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
        m_objects.push_back(std::move(ob));
    }
    rebuildIndex();
    return !news.empty();
}
}  // namespace semloc

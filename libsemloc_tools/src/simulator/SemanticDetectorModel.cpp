/* semloc — SemanticDetectorModel: visibility by ray casting, detector error model. */
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/semantic/DetectionProbability.h>
#include <semloc/simulator/SemanticDetectorModel.h>

#include <algorithm>
#include <cmath>

#include "io/ExactConfigWrite.h"
#include "simulator/SensorMount.h"
#include "simulator/SimRandom.h"

namespace semloc
{
void SemanticDetectorModel::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                         const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    config::readDouble(c, s, "max_range_m", max_range_m, 1e-3, 1e5);
    config::readDouble(c, s, "fov_deg", fov_deg, 1e-6, 360);
    config::readDouble(c, s, "range_noise_std_m", range_noise_std_m, 0, 1e3);
    config::readDouble(c, s, "bearing_noise_std_deg", bearing_noise_std_deg, 0, 360);
    config::readDoubles(c, s, "range_bias_m", range_bias_m, kRangeBiasTerms, -1e3, 1e3);
    if (std::all_of(range_bias_m.begin(), range_bias_m.end(), [](double b) { return b == 0; }))
    {
        range_bias_m.clear();  // none
    }
    config::readDouble(c, s, "p_detect_near", p_detect_near, 0, 1);
    config::readDouble(c, s, "p_detect_far", p_detect_far, 0, 1);
    config::readDouble(c, s, "p_detect_edge_ratio", p_detect_edge_ratio, 0, 1);
    config::readDouble(c, s, "false_positives_per_scan", false_positives_per_scan, 0, 100);
    config::readDouble(c, s, "p_confusion", p_confusion, 0, 1);
    config::readDouble(c, s, "p_range_outlier", p_range_outlier, 0, 1);
    config::readBool(c, s, "report_ids", report_ids);
    config::readDouble(c, s, "gap_every_s", gap_every_s, 0, 1e9);
    config::readDouble(c, s, "gap_min_s", gap_min_s, 0, 1e9);
    config::readDouble(c, s, "gap_max_s", gap_max_s, 0, 1e9);
    if (gap_min_s > gap_max_s)
    {
        THROW_EXCEPTION(
            mrpt::format("ini [%s] gap_min_s, gap_max_s: the shortest silence (%g s) "
                         "is longer than the longest (%g s)",
                         s.c_str(), gap_min_s, gap_max_s));
    }
    config::readInt(c, s, "distractors", distractors, 0, 100000);
    config::readDouble(c, s, "distractor_speed_mps", distractor_speed_mps, 0, 1e3);
    detail::readSensorMount(c, s, sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

void SemanticDetectorModel::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const
{
    using detail::writeExact;
    c.write(s, "enabled", enabled, 24, 24, "false: no CObservationSemantic in the frames");
    writeExact(c, s, "max_range_m", max_range_m, "maximum detection range [m]");
    writeExact(c, s, "fov_deg", fov_deg, "field of view, centred ahead [deg]");
    writeExact(c, s, "range_noise_std_m", range_noise_std_m, "range noise [m]");
    writeExact(c, s, "bearing_noise_std_deg", bearing_noise_std_deg, "bearing noise [deg]");
    detail::writeExactList(c, s, "range_bias_m", range_bias_m,
                           "range bias c0, c1, c2, c3 [m] in bearing / half the view");
    writeExact(c, s, "p_detect_near", p_detect_near, "P(detect) of a visible object at 0 m");
    writeExact(c, s, "p_detect_far", p_detect_far, "P(detect) at max range (linear between)");
    writeExact(c, s, "p_detect_edge_ratio", p_detect_edge_ratio,
               "P(detect) at the edge of the view / on its axis (linear in |bearing|)");
    writeExact(c, s, "false_positives_per_scan", false_positives_per_scan,
               "Poisson mean of false positives per scan");
    writeExact(c, s, "p_confusion", p_confusion, "P(label swapped to another world label)");
    writeExact(c, s, "p_range_outlier", p_range_outlier,
               "P(range misread: uniform over [0, max_range_m])");
    c.write(s, "report_ids", report_ids, 24, 24, "report map object ids (else -1)");
    writeExact(c, s, "gap_every_s", gap_every_s,
               "mean time between silences (nothing reported) [s]; 0: none");
    writeExact(c, s, "gap_min_s", gap_min_s, "shortest silence [s]");
    writeExact(c, s, "gap_max_s", gap_max_s, "longest silence [s]");
    c.write(s, "distractors", distractors, 24, 24,
            "unmapped moving objects under the world's labels");
    writeExact(c, s, "distractor_speed_mps", distractor_speed_mps, "their speed [m/s]");
    detail::writeSensorMount(c, s, "detector", sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

mrpt::poses::CPose3D SemanticDetectorModel::TOptions::sensorPose() const
{
    return detail::sensorMountPose(sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

SemanticDetectorModel::SemanticDetectorModel(const World& world, const TOptions& options)
    : m_options(options), m_objects(world.objects), m_all(world.outlineSegments())
{
    for (const auto& o : m_objects)
    {
        m_labels.push_back(o.label);
        for (const auto& c : o.classes)
        {
            m_labels.push_back(c.first);
        }
    }
    std::sort(m_labels.begin(), m_labels.end());
    m_labels.erase(std::unique(m_labels.begin(), m_labels.end()), m_labels.end());
    for (const auto& o : m_objects)
    {
        m_labelOf.push_back(labelIndex(o.label));
        // The class it is seen as: label index and cumulative probability.
        std::vector<std::pair<size_t, double>> classes;
        double cumulative = 0;
        for (const auto& [label, p] : o.classes)
        {
            cumulative += p;
            classes.emplace_back(labelIndex(label), cumulative);
        }
        m_classesOf.push_back(std::move(classes));
        // The same segments World::outlineSegments() makes for this object.
        const auto poly = World::outlinePolygon(o);
        std::vector<mrpt::math::TSegment2D> own;
        for (size_t i = 0; i < poly.size(); i++)
        {
            own.emplace_back(poly[i], poly[(i + 1) % poly.size()]);
        }
        m_own.emplace_back(own);
    }
}

double SemanticDetectorModel::detectionProbability(double range_m, double bearing_rad) const
{
    const TOptions& o = m_options;
    const double fov = o.fov_deg < 360 ? mrpt::DEG2RAD(o.fov_deg) : 2 * M_PI;
    return semloc::detectionProbability(o.p_detect_near, o.p_detect_far, o.p_detect_edge_ratio,
                                        range_m, o.max_range_m, bearing_rad, fov);
}

mrpt::math::TPoint2D SemanticDetectorModel::sensorPosition(const mrpt::math::TPose2D& vehicle) const
{
    const TOptions& o = m_options;
    const double c = std::cos(vehicle.phi), s = std::sin(vehicle.phi);
    return {vehicle.x + c * o.sensor_x_m - s * o.sensor_y_m,
            vehicle.y + s * o.sensor_x_m + c * o.sensor_y_m};
}

std::vector<SemanticDetectorModel::TVisibleObject> SemanticDetectorModel::visibleObjects(
    const mrpt::math::TPose2D& vehicle) const
{
    const TOptions& o = m_options;
    const auto [sx, sy] = sensorPosition(vehicle);
    const double sphi = vehicle.phi + mrpt::DEG2RAD(o.sensor_yaw_deg);
    const double halfFov = 0.5 * mrpt::DEG2RAD(o.fov_deg);

    std::vector<TVisibleObject> out;
    for (size_t i = 0; i < m_objects.size(); i++)
    {
        const double dx = m_objects[i].center.x - sx, dy = m_objects[i].center.y - sy;
        const double r = std::hypot(dx, dy);
        if (r > o.max_range_m)
        {
            continue;
        }
        const double angle = std::atan2(dy, dx);
        const double b = mrpt::math::wrapToPi(angle - sphi);
        if (std::abs(b) > halfFov)
        {
            continue;
        }
        if (occluded(sx, sy, angle, r, i))
        {
            continue;
        }
        out.push_back({i, r, b});
    }
    return out;
}

bool SemanticDetectorModel::occluded(double sx, double sy, double angle, double range,
                                     size_t index) const
{
    // Occluded if the sight line first crosses an outline that is not the object's own.
    const double hit = m_all.cast(sx, sy, angle, range);
    return hit < range && m_own[index].cast(sx, sy, angle, range) != hit;
}

bool SemanticDetectorModel::inLineOfSight(const mrpt::math::TPoint2D& sensor, size_t index) const
{
    const auto& c = m_objects.at(index).center;
    const double dx = c.x - sensor.x, dy = c.y - sensor.y;
    return !occluded(sensor.x, sensor.y, std::atan2(dy, dx), std::hypot(dx, dy), index);
}

size_t SemanticDetectorModel::labelIndex(const std::string& label) const
{
    return static_cast<size_t>(std::lower_bound(m_labels.begin(), m_labels.end(), label) -
                               m_labels.begin());
}

void SemanticDetectorModel::detect(double range, double bearing, size_t label, int32_t id,
                                   mrpt::random::CRandomGenerator& rng, CObservationSemantic& obs,
                                   const std::vector<std::pair<size_t, double>>* classes) const
{
    const TOptions& o = m_options;
    if (!detail::bernoulli(rng, detectionProbability(range, bearing)))
    {
        return;
    }
    const double halfFov = 0.5 * obs.fov_rad;
    TSemanticDetection d;
    const double bias =
        o.range_bias_m.empty() ? 0.0 : rangeBias(o.range_bias_m, bearing, obs.fov_rad);
    d.range_m = std::clamp(range + bias + o.range_noise_std_m * rng.drawGaussian1D_normalized(),
                           0.0, o.max_range_m);
    d.bearing_rad =
        std::clamp(mrpt::math::wrapToPi(bearing + mrpt::DEG2RAD(o.bearing_noise_std_deg) *
                                                      rng.drawGaussian1D_normalized()),
                   -halfFov, halfFov);
    // Drawn only when enabled: datasets without misreads keep their random streams.
    if (o.p_range_outlier > 0 && detail::bernoulli(rng, o.p_range_outlier))
    {
        d.range_m = o.max_range_m * detail::uniform01(rng);
    }
    if (classes != nullptr && !classes->empty())
    {
        // An object of uncertain class is seen as each of its classes with its probability
        // (drawn only for such objects: other datasets keep their random streams).
        const double u = detail::uniform01(rng) * classes->back().second;
        label = classes->back().first;
        for (const auto& [index, cumulative] : *classes)
        {
            if (u < cumulative)
            {
                label = index;
                break;
            }
        }
    }
    const size_t nLabels = m_labels.size();
    if (nLabels > 1 && detail::bernoulli(rng, o.p_confusion))
    {
        // Uniform over the K - 1 other labels.
        const size_t k = detail::uniformIndex(rng, nLabels - 1);
        label = k >= label ? k + 1 : k;
    }
    d.label = m_labels[label];
    d.object_id = id;
    obs.detections.push_back(std::move(d));
}

bool SemanticDetectorModel::distractorVisible(const mrpt::math::TPose2D& vehicle,
                                              const TDistractor& d, double& range,
                                              double& bearing) const
{
    const TOptions& o = m_options;
    const auto [sx, sy] = sensorPosition(vehicle);
    range = std::hypot(d.x - sx, d.y - sy);
    const double angle = std::atan2(d.y - sy, d.x - sx);
    bearing = mrpt::math::wrapToPi(angle - vehicle.phi - mrpt::DEG2RAD(o.sensor_yaw_deg));
    return range <= o.max_range_m && std::abs(bearing) <= 0.5 * mrpt::DEG2RAD(o.fov_deg) &&
           !(m_all.cast(sx, sy, angle, range) < range);
}

CObservationSemantic::Ptr SemanticDetectorModel::measure(
    const mrpt::math::TPose2D& vehicle, mrpt::random::CRandomGenerator& rng,
    const std::vector<TDistractor>& distractors) const
{
    const TOptions& o = m_options;
    auto obs = CObservationSemantic::Create();
    obs->sensorLabel = "SEMANTIC";
    obs->sensorPose = o.sensorPose();
    obs->maxRange_m = o.max_range_m;
    obs->fov_rad = mrpt::DEG2RAD(o.fov_deg);
    const double halfFov = 0.5 * obs->fov_rad;
    const size_t nLabels = m_labels.size();

    for (const auto& v : visibleObjects(vehicle))
    {
        detect(v.range_m, v.bearing_rad, m_labelOf[v.index],
               o.report_ids ? m_objects[v.index].id : -1, rng, *obs, &m_classesOf[v.index]);
    }
    for (const auto& d : distractors)
    {
        double range = 0, bearing = 0;
        if (distractorVisible(vehicle, d, range, bearing))
        {
            detect(range, bearing, d.label, -1, rng, *obs);
        }
    }

    const unsigned nFalse = nLabels > 0 ? detail::poisson(rng, o.false_positives_per_scan) : 0;
    for (unsigned j = 0; j < nFalse; j++)
    {
        TSemanticDetection d;
        d.label = m_labels[detail::uniformIndex(rng, nLabels)];
        d.range_m = detail::uniform01(rng) * o.max_range_m;
        d.bearing_rad = -halfFov + detail::uniform01(rng) * 2 * halfFov;
        obs->detections.push_back(std::move(d));
    }
    return obs;
}

}  // namespace semloc

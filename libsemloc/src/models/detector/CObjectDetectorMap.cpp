/* semloc — CObjectDetectorMap: the objects, their grid, the water column and a scan's shared
 * part; the kinds' geometries are in their rooms. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/detector/CObjectDetectorMap.h>
#include <semloc/models/detector/FanOptions.h>
#include <semloc/observation/CObservationDepth.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "io/BoundedRead.h"
#include "models/detector/DetectorKind.h"

namespace semloc
{
namespace
{
/** The grid's largest cell count (a world of far-apart objects gets coarser cells). */
constexpr size_t kMaxCells = size_t{1} << 20;
/** The most objects a map file may hold (a corrupted count must not allocate gigabytes). */
constexpr uint32_t kMaxSerializedObjects = 1u << 24;

void writeDouble(mrpt::config::CConfigFileBase& c, const std::string& s, const char* key, double v,
                 const char* comment)
{
    c.write(s, key, mrpt::format("%.17g", v), 24, 24, comment);
}
}  // namespace

void CObjectDetectorMap::TDetectorParam::load(const mrpt::config::CConfigFileBase& source,
                                              const std::string& section,
                                              const std::vector<std::string>& kindKeys,
                                              bool measuresRange)
{
    std::vector<std::string> keys = {"sensor_label",    "range_kind",    "min_range_m",
                                     "max_range_m",     "p_detect_near", "p_detect_far",
                                     "clutter_per_scan"};
    if (measuresRange)
    {
        keys.insert(keys.end(), {"sigma_range_m", "p_range_outlier"});
    }
    keys.insert(keys.end(), kindKeys.begin(), kindKeys.end());
    config::rejectUnknownKeys(source, section, keys);
    sensor_label = source.read_string(section, "sensor_label", sensor_label);
    std::string kind = slant ? "slant" : "horizontal";
    config::readChoice(source, section, "range_kind", kind, {"slant", "horizontal"});
    slant = kind == "slant";
    config::readDouble(source, section, "max_range_m", max_range_m, 1e-3, 1e6);
    config::readDouble(source, section, "min_range_m", min_range_m, 0, 1e6);
    if (!(min_range_m < max_range_m))
    {
        THROW_EXCEPTION_FMT("ini [%s] min_range_m: %g is not below max_range_m %g", section.c_str(),
                            min_range_m, max_range_m);
    }
    config::readDouble(source, section, "p_detect_near", p_detect_near, 0, 0.999);
    config::readDouble(source, section, "p_detect_far", p_detect_far, 0, 0.999);
    config::readDouble(source, section, "clutter_per_scan", clutter_per_scan, 1e-9, 1e6);
    if (measuresRange)
    {
        config::readDouble(source, section, "sigma_range_m", sigma_range_m, 1e-6, 1e6);
        config::readDouble(source, section, "p_range_outlier", p_range_outlier, 0, 0.999999);
    }
}

void CObjectDetectorMap::TDetectorParam::save(mrpt::config::CConfigFileBase& c,
                                              const std::string& s, bool measuresRange) const
{
    c.write(s, "sensor_label", sensor_label, 24, 24,
            "the scans scored: CObservationSemantic of this sensorLabel (empty: every one)");
    c.write(s, "range_kind", std::string(slant ? "slant" : "horizontal"), 24, 24,
            "slant (from the 3D offset of sensor and object) | horizontal");
    writeDouble(c, s, "min_range_m", min_range_m, "nearest range seen [m]");
    writeDouble(c, s, "max_range_m", max_range_m, "farthest range seen [m]");
    writeDouble(c, s, "p_detect_near", p_detect_near, "P_D at range 0, in [0, 0.999]");
    writeDouble(c, s, "p_detect_far", p_detect_far, "P_D at max_range_m (linear between)");
    writeDouble(c, s, "clutter_per_scan", clutter_per_scan, "mean false alarms per scan (> 0)");
    if (measuresRange)
    {
        writeDouble(c, s, "sigma_range_m", sigma_range_m, "range noise [m]");
        writeDouble(c, s, "p_range_outlier", p_range_outlier,
                    "probability that a range is misread (uniform over the window)");
    }
}

void CObjectDetectorMap::loadFromWorld(const World& world)
{
    m_objects.clear();
    m_labels.clear();
    std::map<std::string, uint32_t> ids;
    for (const auto& wo : world.objects)
    {
        const auto it = ids.emplace(wo.label, static_cast<uint32_t>(ids.size())).first;
        if (it->second == m_labels.size())
        {
            m_labels.push_back(wo.label);
        }
        TObject o;
        o.x = wo.center.x;
        o.y = wo.center.y;
        o.z = wo.z;
        o.label = it->second;
        o.id = wo.id;
        m_objects.push_back(o);
    }
    buildIndex();
}

void CObjectDetectorMap::internal_clear()
{
    m_objects.clear();
    m_labels.clear();
    buildIndex();
}

void CObjectDetectorMap::buildIndex()
{
    m_cellBegin.clear();
    m_cellObjects.clear();
    m_nx = m_ny = 0;
    if (m_objects.empty())
    {
        return;
    }
    double x0 = m_objects[0].x, x1 = x0, y0 = m_objects[0].y, y1 = y0;
    for (const auto& o : m_objects)
    {
        x0 = std::min(x0, o.x), x1 = std::max(x1, o.x);
        y0 = std::min(y0, o.y), y1 = std::max(y1, o.y);
    }
    // Cells of half the detector's range: a pose visits about 5 x 5 of them.
    m_cell = std::max(0.5 * detectorParam().max_range_m, 1e-3);
    const auto cellsFor = [](double span, double cell)
    { return static_cast<size_t>(std::floor(span / cell)) + 1; };
    while (cellsFor(x1 - x0, m_cell) * cellsFor(y1 - y0, m_cell) > kMaxCells)
    {
        m_cell *= 2;
    }
    m_x0 = x0, m_y0 = y0;
    m_nx = static_cast<int>(cellsFor(x1 - x0, m_cell));
    m_ny = static_cast<int>(cellsFor(y1 - y0, m_cell));
    const size_t nCells = static_cast<size_t>(m_nx) * static_cast<size_t>(m_ny);
    std::vector<uint32_t> cellOf(m_objects.size());
    m_cellBegin.assign(nCells + 1, 0);
    for (size_t k = 0; k < m_objects.size(); k++)
    {
        const auto cx = std::min<size_t>(static_cast<size_t>((m_objects[k].x - x0) / m_cell),
                                         static_cast<size_t>(m_nx - 1));
        const auto cy = std::min<size_t>(static_cast<size_t>((m_objects[k].y - y0) / m_cell),
                                         static_cast<size_t>(m_ny - 1));
        cellOf[k] = static_cast<uint32_t>(cy * static_cast<size_t>(m_nx) + cx);
        m_cellBegin[cellOf[k] + 1]++;
    }
    for (size_t c = 0; c < nCells; c++)
    {
        m_cellBegin[c + 1] += m_cellBegin[c];
    }
    m_cellObjects.resize(m_objects.size());
    std::vector<uint32_t> next(m_cellBegin.begin(), m_cellBegin.end() - 1);
    for (size_t k = 0; k < m_objects.size(); k++)
    {
        m_cellObjects[next[cellOf[k]]++] = static_cast<uint32_t>(k);
    }
}

std::string CObjectDetectorMap::asString() const
{
    return mrpt::format("%zu objects of %zu labels", m_objects.size(), m_labels.size());
}

bool CObjectDetectorMap::uses(const mrpt::obs::CObservation& obs) const
{
    if (dynamic_cast<const CObservationDepth*>(&obs))
    {
        return true;
    }
    const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs);
    const auto& label = detectorParam().sensor_label;
    return sem && (label.empty() || sem->sensorLabel == label);
}

void CObjectDetectorMap::takeDepth(const mrpt::obs::CObservation& obs) const
{
    const auto* depth = dynamic_cast<const CObservationDepth*>(&obs);
    if (depth && depth->problem().empty())
    {
        m_depth_m = depth->depth_m;
    }
}

CObjectDetectorMap::TScan CObjectDetectorMap::scan(const CObservationSemantic& obs) const
{
    TScan s;
    s.mountX = obs.sensorPose.x();
    s.mountY = obs.sensorPose.y();
    s.mountYaw = obs.sensorPose.yaw();
    s.sensorZ = -m_depth_m + obs.sensorPose.z();
    const auto nLabels = static_cast<uint32_t>(m_labels.size());
    for (const auto& d : obs.detections)
    {
        if (!validDetection(d))
        {
            s.invalid++;
            continue;
        }
        const auto it = std::find(m_labels.begin(), m_labels.end(), d.label);
        const auto label = static_cast<uint32_t>(it - m_labels.begin());
        s.unknown += label == nLabels ? 1 : 0;
        s.detections.push_back({label, d.range_m, d.bearing_rad});
    }
    std::stable_sort(s.detections.begin(), s.detections.end(),
                     [](const auto& a, const auto& b) { return a.label < b.label; });
    // labelBegin[k]: the detections of labels below k (the unknown label, nLabels, last).
    s.labelBegin.assign(nLabels + 1, 0);
    for (const auto& d : s.detections)
    {
        if (d.label < nLabels)
        {
            s.labelBegin[d.label + 1]++;
        }
    }
    for (uint32_t k = 1; k <= nLabels; k++)
    {
        s.labelBegin[k] += s.labelBegin[k - 1];
    }
    const auto& p = detectorParam();
    s.minusLambda = -p.clutter_per_scan;
    s.logKappa =
        std::log(p.clutter_per_scan) - std::log(measurementVolume() * std::max<double>(nLabels, 1));
    return s;
}

BatchLikelihood::TObservationPlan CObjectDetectorMap::plan(const mrpt::obs::CObservation& obs) const
{
    TObservationPlan plan;
    const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs);
    if (!sem)
    {
        return plan;  // a depth reading: 0 at every pose
    }
    const TScan s = scan(*sem);
    plan.checked = true;
    plan.invalid = s.invalid;
    plan.unknown = s.unknown;
    plan.readingsWithoutMap = s.detections.size();
    plan.logLikWithoutMap = s.minusLambda + static_cast<double>(s.detections.size()) * s.logKappa;
    return plan;
}

namespace
{
/** A scan prepared once per frame. */
class PreparedScan final : public BatchLikelihood::Prepared
{
public:
    PreparedScan(const CObjectDetectorMap& map, CObjectDetectorMap::TScan scan)
        : m_map(map), m_scan(std::move(scan))
    {
    }
    void logLikelihoods(const mrpt::math::TPose2D* poses, size_t n, double* out) const override
    {
        m_map.scoreScan(m_scan, poses, n, out);
    }

private:
    const CObjectDetectorMap& m_map;
    CObjectDetectorMap::TScan m_scan;
};
/** A depth reading: 0 at every pose. */
class PreparedZero final : public BatchLikelihood::Prepared
{
public:
    void logLikelihoods(const mrpt::math::TPose2D*, size_t n, double* out) const override
    {
        std::fill_n(out, n, 0.0);
    }
};
}  // namespace

std::unique_ptr<BatchLikelihood::Prepared> CObjectDetectorMap::prepareObservation(
    const mrpt::obs::CObservation& obs) const
{
    if (const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        return std::make_unique<PreparedScan>(*this, scan(*sem));
    }
    takeDepth(obs);
    return std::make_unique<PreparedZero>();
}

void CObjectDetectorMap::logLikelihoods(const mrpt::obs::CObservation& obs,
                                        const mrpt::math::TPose2D* poses, size_t n,
                                        double* out) const
{
    if (const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        scoreScan(scan(*sem), poses, n, out);
        return;
    }
    std::fill_n(out, n, 0.0);
}

double CObjectDetectorMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    const auto* sem = dynamic_cast<const CObservationSemantic*>(&obs);
    if (!sem)
    {
        takeDepth(obs);
        return 0;
    }
    if (!uses(obs))
    {
        return 0;
    }
    const mrpt::math::TPose2D pose(takenFrom.x(), takenFrom.y(), takenFrom.yaw());
    double out = 0;
    scoreScan(scan(*sem), &pose, 1, &out);
    return out;
}

void CObjectDetectorMap::writeObjects(mrpt::serialization::CArchive& out) const
{
    out.WriteAs<uint32_t>(m_labels.size());
    for (const auto& l : m_labels)
    {
        out << l;
    }
    out.WriteAs<uint32_t>(m_objects.size());
    for (const auto& o : m_objects)
    {
        out << o.x << o.y << o.z << o.label << o.id;
    }
    out << m_depth_m;
}

void CObjectDetectorMap::readObjects(mrpt::serialization::CArchive& in)
{
    const auto nLabels = in.ReadAs<uint32_t>();
    if (nLabels > kMaxSerializedObjects)
    {
        THROW_EXCEPTION_FMT("detector map: %u labels is more than a map holds", nLabels);
    }
    m_labels.assign(nLabels, {});
    for (auto& l : m_labels)
    {
        detail::readString(in, l, "detector map label");
    }
    const auto nObjects = in.ReadAs<uint32_t>();
    if (nObjects > kMaxSerializedObjects)
    {
        THROW_EXCEPTION_FMT("detector map: %u objects is more than a map holds", nObjects);
    }
    m_objects.assign(nObjects, {});
    for (auto& o : m_objects)
    {
        in >> o.x >> o.y >> o.z >> o.label >> o.id;
        if (o.label >= nLabels || !std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.z))
        {
            THROW_EXCEPTION_FMT("detector map: object id %d is not a finite point of a label",
                                o.id);
        }
    }
    in >> m_depth_m;
    buildIndex();
}

}  // namespace semloc

namespace semloc
{
void TFanParam::load(const mrpt::config::CConfigFileBase& source, const std::string& section)
{
    config::readDouble(source, section, "fov_deg", fov_deg, 1e-3, 360);
    config::readDouble(source, section, "sigma_bearing_deg", sigma_bearing_deg, 1e-6, 360);
    config::readDouble(source, section, "tilt_deg", tilt_deg, -90, 90);
    config::readDouble(source, section, "vertical_fov_deg", vertical_fov_deg, 1e-3, 180);
}

void TFanParam::save(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    writeDouble(c, s, "fov_deg", fov_deg, "horizontal field of view [deg]");
    writeDouble(c, s, "sigma_bearing_deg", sigma_bearing_deg, "bearing noise [deg]");
    writeDouble(c, s, "tilt_deg", tilt_deg, "the fan's depression below the horizontal [deg]");
    writeDouble(c, s, "vertical_fov_deg", vertical_fov_deg,
                "vertical field of view [deg] (180: no limit)");
}

void TFanDetectorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                             const std::string& section)
{
    detector.load(source, section, TFanParam::keys(), m_measuresRange);
    fan.load(source, section);
}

void TFanDetectorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                           const std::string& section) const
{
    detector.save(target, section, m_measuresRange);
    fan.save(target, section);
}
}  // namespace semloc

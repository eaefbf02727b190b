/* semloc — CCompassMap: the heading's likelihood, its options and its kind. */
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/compass/CCompassMap.h>

#include <cmath>

#include "models/BuiltinKinds.h"

MAP_DEFINITION_REGISTER("compassMap,semloc::CCompassMap", semloc::CCompassMap)
IMPLEMENTS_SERIALIZABLE(CCompassMap, CMetricMap, semloc)

namespace semloc
{
namespace
{
constexpr double kDeg = M_PI / 180;

const mrpt::obs::CObservationIMU* headingOf(const mrpt::obs::CObservation& obs)
{
    const auto* imu = dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs);
    return imu && imu->has(mrpt::obs::IMU_YAW) ? imu : nullptr;
}
}  // namespace

void CCompassMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section)
{
    config::rejectUnknownKeys(source, section, {"sensor_label", "sigma_deg", "p_outlier"});
    sensor_label = source.read_string(section, "sensor_label", sensor_label);
    config::readDouble(source, section, "sigma_deg", sigma_deg, 1e-6, 180);
    config::readDouble(source, section, "p_outlier", p_outlier, 0, 0.999999);
}

void CCompassMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const
{
    c.write(s, "sensor_label", sensor_label, 24, 24,
            "the readings scored: CObservationIMU of this sensorLabel (empty: every one)");
    c.write(s, "sigma_deg", mrpt::format("%.17g", sigma_deg), 24, 24, "heading noise [deg]");
    c.write(s, "p_outlier", mrpt::format("%.17g", p_outlier), 24, 24,
            "probability that a reading is disturbed (uniform)");
}

double CCompassMap::logLik(double yaw, double mountYaw, double phi) const
{
    const double s = likelihoodOptions.sigma_deg * kDeg, eps = likelihoodOptions.p_outlier;
    const double u = std::remainder(yaw - phi - mountYaw, 2 * M_PI) / s;
    const double g = std::exp(-0.5 * u * u) / (std::sqrt(2 * M_PI) * s);
    return std::log((1 - eps) * g + eps / (2 * M_PI));
}

bool CCompassMap::uses(const mrpt::obs::CObservation& obs) const
{
    const auto* imu = headingOf(obs);
    return imu && (likelihoodOptions.sensor_label.empty() ||
                   imu->sensorLabel == likelihoodOptions.sensor_label);
}

void CCompassMap::logLikelihoods(const mrpt::obs::CObservation& obs,
                                 const mrpt::math::TPose2D* poses, size_t n, double* out) const
{
    const auto& imu = *headingOf(obs);
    const double yaw = imu.get(mrpt::obs::IMU_YAW), mount = imu.sensorPose.yaw();
    for (size_t i = 0; i < n; i++)
    {
        out[i] = logLik(yaw, mount, poses[i].phi);
    }
}

double CCompassMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    if (!uses(obs))
    {
        return 0;
    }
    const auto& imu = *headingOf(obs);
    return logLik(imu.get(mrpt::obs::IMU_YAW), imu.sensorPose.yaw(), takenFrom.yaw());
}

CCompassMap::TMapDefinition::TMapDefinition() = default;

void CCompassMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
}

void CCompassMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "sigma_deg = " << likelihoodOpts.sigma_deg << "\n";
}

mrpt::maps::CMetricMap* CCompassMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CCompassMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CCompassMap::serializeGetVersion() const
{
    return 0;
}
void CCompassMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << likelihoodOptions.sensor_label << likelihoodOptions.sigma_deg
        << likelihoodOptions.p_outlier;
}
void CCompassMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
    {
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
    in >> likelihoodOptions.sensor_label >> likelihoodOptions.sigma_deg >>
        likelihoodOptions.p_outlier;
}

namespace detail
{
namespace
{
class CompassKind final : public SensorModelKind
{
public:
    std::string name() const override { return "compassMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override { return CLASS_ID(CCompassMap); }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return "compass"; }
    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string&) const override
    {
        dynamic_cast<const CCompassMap::TMapDefinition&>(definition)
            .likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
    void writeReference(mrpt::config::CConfigFileBase& out,
                        const std::string& prefix) const override
    {
        CCompassMap::TLikelihoodOptions().saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap&) const override
    {
        const auto* imu = headingOf(obs);
        if (imu && !std::isfinite(imu->get(mrpt::obs::IMU_YAW)))
        {
            return "its yaw is not finite";
        }
        return {};
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> compassMapKind()
{
    return std::make_shared<CompassKind>();
}
}  // namespace detail

}  // namespace semloc

/* semloc tests — CPositionFixMap, registered with MRPT's map registry and semloc's. */
#include "models/registry/CPositionFixMap.h"

#include <mrpt/core/format.h>
#include <mrpt/core/initializer.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/SensorModelRegistry.h>

#include <cmath>

MAP_DEFINITION_REGISTER("positionFixMap,semloc::test::CPositionFixMap",
                        semloc::test::CPositionFixMap)
IMPLEMENTS_SERIALIZABLE(CPositionFixMap, CMetricMap, semloc::test)

namespace semloc::test
{
void CPositionFixMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section)
{
    config::rejectUnknownKeys(source, section, {"sigma_m"});
    config::readDouble(source, section, "sigma_m", sigma_m, 1e-6, 1e6);
}

void CPositionFixMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                                           const std::string& section) const
{
    target.write(section, "sigma_m", mrpt::format("%.17g", sigma_m), 24, 24,
                 "the fixes' standard deviation [m]");
}

double CPositionFixMap::logLik(const mrpt::obs::CObservationRobotPose& fix, double x,
                               double y) const
{
    const double s = likelihoodOptions.sigma_m;
    const double dx = x - fix.pose.mean.x(), dy = y - fix.pose.mean.y();
    return -0.5 * (dx * dx + dy * dy) / (s * s);
}

bool CPositionFixMap::uses(const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs) != nullptr;
}

void CPositionFixMap::logLikelihoods(const mrpt::obs::CObservation& obs,
                                     const mrpt::math::TPose2D* poses, size_t n, double* out) const
{
    const auto& fix = dynamic_cast<const mrpt::obs::CObservationRobotPose&>(obs);
    for (size_t i = 0; i < n; i++)
    {
        out[i] = logLik(fix, poses[i].x, poses[i].y);
    }
}

double CPositionFixMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
    return fix ? logLik(*fix, takenFrom.x(), takenFrom.y()) : 0.0;
}

CPositionFixMap::TMapDefinition::TMapDefinition() = default;

void CPositionFixMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
}

void CPositionFixMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "sigma_m = " << likelihoodOpts.sigma_m << "\n";
}

mrpt::maps::CMetricMap* CPositionFixMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CPositionFixMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CPositionFixMap::serializeGetVersion() const
{
    return 0;
}
void CPositionFixMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << likelihoodOptions.sigma_m;
}
void CPositionFixMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t)
{
    in >> likelihoodOptions.sigma_m;
}

namespace
{
/** What semloc does with it beside MRPT: its variant name, its effective options, and a fix
 *  that is not finite refused. */
class PositionFixKind final : public SensorModelKind
{
public:
    std::string name() const override { return "positionFixMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override
    {
        return CLASS_ID(CPositionFixMap);
    }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return "position_fix"; }
    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string&) const override
    {
        dynamic_cast<const CPositionFixMap::TMapDefinition&>(definition)
            .likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap&) const override
    {
        const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
        if (fix && !(std::isfinite(fix->pose.mean.x()) && std::isfinite(fix->pose.mean.y())))
        {
            return "its fix is not finite";
        }
        return {};
    }
};
}  // namespace
}  // namespace semloc::test

MRPT_INITIALIZER(semloc_test_registerPositionFixMap)
{
    mrpt::rtti::registerClass(CLASS_ID(semloc::test::CPositionFixMap));
    semloc::SensorModelRegistry::add(std::make_shared<semloc::test::PositionFixKind>());
}

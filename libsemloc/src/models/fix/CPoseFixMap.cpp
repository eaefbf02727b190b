/* semloc — CPoseFixMap: a fix's likelihood, its options and its kind. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/fix/CPoseFixMap.h>

#include <cmath>

#include "models/BuiltinKinds.h"
#include "models/MapOfClass.h"

MAP_DEFINITION_REGISTER("poseFixMap,semloc::CPoseFixMap", semloc::CPoseFixMap)
IMPLEMENTS_SERIALIZABLE(CPoseFixMap, CMetricMap, semloc)

namespace semloc
{
void CPoseFixMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section)
{
    config::rejectUnknownKeys(source, section,
                              {"sensor_label", "sigma_m", "p_outlier", "outlier_sigma_m"});
    sensor_label = source.read_string(section, "sensor_label", sensor_label);
    config::readDouble(source, section, "sigma_m", sigma_m, 0, 1e6);
    config::readDouble(source, section, "p_outlier", p_outlier, 0, 0.999999);
    config::readDouble(source, section, "outlier_sigma_m", outlier_sigma_m, 1e-3, 1e7);
}

void CPoseFixMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const
{
    c.write(s, "sensor_label", sensor_label, 24, 24,
            "the fixes scored: CObservationRobotPose of this sensorLabel (empty: every one)");
    c.write(s, "sigma_m", mrpt::format("%.17g", sigma_m), 24, 24,
            "> 0: the fixes' std in x and y [m]; 0: each fix's covariance");
    c.write(s, "p_outlier", mrpt::format("%.17g", p_outlier), 24, 24,
            "probability that a fix is an outlier");
    c.write(s, "outlier_sigma_m", mrpt::format("%.17g", outlier_sigma_m), 24, 24,
            "the outliers' spread [m]");
}

bool CPoseFixMap::covariance(const mrpt::obs::CObservationRobotPose& fix, double& sxx, double& sxy,
                             double& syy) const
{
    if (likelihoodOptions.sigma_m > 0)
    {
        sxx = syy = likelihoodOptions.sigma_m * likelihoodOptions.sigma_m;
        sxy = 0;
        return true;
    }
    sxx = fix.pose.cov(0, 0), sxy = fix.pose.cov(0, 1), syy = fix.pose.cov(1, 1);
    return std::isfinite(sxx) && std::isfinite(sxy) && std::isfinite(syy) && sxx > 0 &&
           sxx * syy - sxy * sxy > 0;
}

double CPoseFixMap::logLik(const mrpt::obs::CObservationRobotPose& fix, double x, double y) const
{
    double sxx = 0, sxy = 0, syy = 0;
    if (!covariance(fix, sxx, sxy, syy))
    {
        return 0;  // refused by the kind before the filter sees it
    }
    const double dx = fix.pose.mean.x() - x, dy = fix.pose.mean.y() - y;
    const double det = sxx * syy - sxy * sxy;
    const double m2 = (syy * dx * dx - 2 * sxy * dx * dy + sxx * dy * dy) / det;
    const double g = std::exp(-0.5 * m2) / (2 * M_PI * std::sqrt(det));
    const double eps = likelihoodOptions.p_outlier;
    if (eps <= 0)
    {
        return -0.5 * m2 - std::log(2 * M_PI * std::sqrt(det));
    }
    const double so2 = likelihoodOptions.outlier_sigma_m * likelihoodOptions.outlier_sigma_m;
    const double go = std::exp(-0.5 * (dx * dx + dy * dy) / so2) / (2 * M_PI * so2);
    return std::log((1 - eps) * g + eps * go);
}

bool CPoseFixMap::uses(const mrpt::obs::CObservation& obs) const
{
    const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
    return fix && (likelihoodOptions.sensor_label.empty() ||
                   fix->sensorLabel == likelihoodOptions.sensor_label);
}

void CPoseFixMap::logLikelihoods(const mrpt::obs::CObservation& obs,
                                 const mrpt::math::TPose2D* poses, size_t n, double* out) const
{
    const auto& fix = dynamic_cast<const mrpt::obs::CObservationRobotPose&>(obs);
    for (size_t i = 0; i < n; i++)
    {
        out[i] = logLik(fix, poses[i].x, poses[i].y);
    }
}

double CPoseFixMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    if (!uses(obs))
    {
        return 0;
    }
    return logLik(dynamic_cast<const mrpt::obs::CObservationRobotPose&>(obs), takenFrom.x(),
                  takenFrom.y());
}

CPoseFixMap::TMapDefinition::TMapDefinition() = default;

void CPoseFixMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
}

void CPoseFixMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "sigma_m = " << likelihoodOpts.sigma_m << "\n";
}

mrpt::maps::CMetricMap* CPoseFixMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CPoseFixMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CPoseFixMap::serializeGetVersion() const
{
    return 0;
}
void CPoseFixMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    const auto& o = likelihoodOptions;
    out << o.sensor_label << o.sigma_m << o.p_outlier << o.outlier_sigma_m;
}
void CPoseFixMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
    {
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
    auto& o = likelihoodOptions;
    in >> o.sensor_label >> o.sigma_m >> o.p_outlier >> o.outlier_sigma_m;
}

namespace detail
{
namespace
{
/** Where the filter holds a fix map, a fix it scores whose position is not finite, or whose
 *  covariance it would use is not positive definite, is refused. */
class PoseFixKind final : public SensorModelKind
{
public:
    std::string name() const override { return "poseFixMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override { return CLASS_ID(CPoseFixMap); }
    std::string variant(const mrpt::maps::CMetricMap&) const override { return "fix"; }
    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string&) const override
    {
        dynamic_cast<const CPoseFixMap::TMapDefinition&>(definition)
            .likelihoodOpts.saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
    void writeReference(mrpt::config::CConfigFileBase& out,
                        const std::string& prefix) const override
    {
        CPoseFixMap::TLikelihoodOptions().saveToConfigFile(out, prefix + "_likelihoodOpts");
    }
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap& map) const override
    {
        const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
        const CPoseFixMap* model = fix ? mapOfClass<CPoseFixMap>(map) : nullptr;
        if (!model || !model->uses(obs))
        {
            return {};
        }
        if (!(std::isfinite(fix->pose.mean.x()) && std::isfinite(fix->pose.mean.y())))
        {
            return "its fix is not finite";
        }
        double sxx = 0, sxy = 0, syy = 0;
        if (!model->covariance(*fix, sxx, sxy, syy))
        {
            return "its x-y covariance is not positive definite (set sigma_m to score it)";
        }
        return {};
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> poseFixMapKind()
{
    return std::make_shared<PoseFixKind>();
}
}  // namespace detail

}  // namespace semloc

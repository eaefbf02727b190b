/* semloc — CForwardSonarMap: the forward-looking sonar's geometry, its options and its kind. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/forwardsonar/CForwardSonarMap.h>

#include <cmath>

#include "models/BuiltinKinds.h"
#include "models/detector/DetectorKind.h"
#include "models/detector/DetectorLikelihood.h"

MAP_DEFINITION_REGISTER("forwardSonarMap,semloc::CForwardSonarMap", semloc::CForwardSonarMap)
IMPLEMENTS_SERIALIZABLE(CForwardSonarMap, CMetricMap, semloc)

namespace semloc
{
namespace
{
constexpr double kDeg = M_PI / 180;

/** The fan; range and bearing measured. */
struct ForwardSonarGeometry
{
    detail::FanView view;
    double sigmaBearing;

    bool see(double u, double w, double dz, detail::TSeen& seen) const
    {
        return view.see(u, w, dz, seen);
    }
    double density(const CObjectDetectorMap::TScan::TDetection& d, const detail::TSeen& seen) const
    {
        return detail::rangeDensity(view.p, d.range_m - seen.range) *
               detail::gaussianDensity(detail::angleDifference(d.bearing_rad, seen.bearing),
                                       sigmaBearing);
    }
};
}  // namespace

CForwardSonarMap::TLikelihoodOptions::TLikelihoodOptions() : TFanDetectorOptions(true)
{
    detector.max_range_m = 60;
    detector.p_detect_near = 0.8;
    detector.p_detect_far = 0.4;
    detector.sigma_range_m = 0.3;
    fan.fov_deg = 130;
    fan.sigma_bearing_deg = 1;
}

bool CForwardSonarMap::validDetection(const TSemanticDetection& d) const
{
    const auto& p = likelihoodOptions.detector;
    const bool bearing =
        std::isfinite(d.bearing_rad) && std::abs(detail::angleDifference(d.bearing_rad, 0)) <=
                                            0.5 * likelihoodOptions.fan.fov_deg * kDeg + 1e-9;
    return !d.label.empty() && bearing && d.confidence >= 0 && d.confidence <= 1 &&
           d.range_m >= p.min_range_m && d.range_m <= p.max_range_m;
}

double CForwardSonarMap::measurementVolume() const
{
    const auto& p = likelihoodOptions.detector;
    return (p.max_range_m - p.min_range_m) * likelihoodOptions.fan.fov_deg * kDeg;
}

namespace
{
ForwardSonarGeometry geometryOf(const CForwardSonarMap::TLikelihoodOptions& likelihoodOptions)
{
    const auto& f = likelihoodOptions.fan;
    return ForwardSonarGeometry{{likelihoodOptions.detector, 0.5 * f.fov_deg * kDeg,
                                 f.tilt_deg * kDeg, 0.5 * f.vertical_fov_deg * kDeg},
                                f.sigma_bearing_deg * kDeg};
}
}  // namespace

void CForwardSonarMap::scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                                 double* out) const
{
    detail::detectorLogLikelihoods(*this, geometryOf(likelihoodOptions), scan, poses, n, out);
}

std::vector<CObjectDetectorMap::TInView> CForwardSonarMap::inView(
    const TScan& scan, const mrpt::math::TPose2D& pose) const
{
    return detail::detectorInView(*this, geometryOf(likelihoodOptions), scan, pose);
}

CForwardSonarMap::TMapDefinition::TMapDefinition() = default;

void CForwardSonarMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    detail::loadDetectorDefinition(*this, source, sectionNamePrefix);
}

void CForwardSonarMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "world_file = " << world_file << "\n";
}

mrpt::maps::CMetricMap* CForwardSonarMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CForwardSonarMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CForwardSonarMap::serializeGetVersion() const
{
    return 0;
}
void CForwardSonarMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    writeObjects(out);
}
void CForwardSonarMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
    {
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
    readObjects(in);
}

namespace detail
{
std::shared_ptr<const SensorModelKind> forwardSonarMapKind()
{
    return std::make_shared<DetectorKind<CForwardSonarMap>>("forwardSonarMap", "fls",
                                                            "forward-looking sonar");
}
}  // namespace detail

}  // namespace semloc

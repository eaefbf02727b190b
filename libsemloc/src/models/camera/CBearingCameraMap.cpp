/* semloc — CBearingCameraMap: the bearing-only camera's geometry, its options and its kind. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/camera/CBearingCameraMap.h>

#include <cmath>

#include "models/BuiltinKinds.h"
#include "models/detector/DetectorKind.h"
#include "models/detector/DetectorLikelihood.h"

MAP_DEFINITION_REGISTER("bearingCameraMap,semloc::CBearingCameraMap", semloc::CBearingCameraMap)
IMPLEMENTS_SERIALIZABLE(CBearingCameraMap, CMetricMap, semloc)

namespace semloc
{
namespace
{
constexpr double kDeg = M_PI / 180;

/** The field of view; the bearing measured. */
struct CameraGeometry
{
    detail::FanView view;
    double sigmaBearing;

    bool see(double u, double w, double dz, detail::TSeen& seen) const
    {
        return view.see(u, w, dz, seen);
    }
    double density(const CObjectDetectorMap::TScan::TDetection& d, const detail::TSeen& seen) const
    {
        return detail::gaussianDensity(detail::angleDifference(d.bearing_rad, seen.bearing),
                                       sigmaBearing);
    }
};
}  // namespace

CBearingCameraMap::TLikelihoodOptions::TLikelihoodOptions() : TFanDetectorOptions(false)
{
    detector.max_range_m = 8;
    detector.p_detect_near = 0.9;
    detector.p_detect_far = 0.5;
    fan.fov_deg = 60;
    fan.sigma_bearing_deg = 1;
}

bool CBearingCameraMap::validDetection(const TSemanticDetection& d) const
{
    const bool bearing =
        std::isfinite(d.bearing_rad) && std::abs(detail::angleDifference(d.bearing_rad, 0)) <=
                                            0.5 * likelihoodOptions.fan.fov_deg * kDeg + 1e-9;
    return !d.label.empty() && bearing && d.confidence >= 0 && d.confidence <= 1;
}

double CBearingCameraMap::measurementVolume() const
{
    return likelihoodOptions.fan.fov_deg * kDeg;
}

namespace
{
CameraGeometry geometryOf(const CBearingCameraMap::TLikelihoodOptions& likelihoodOptions)
{
    const auto& f = likelihoodOptions.fan;
    return CameraGeometry{{likelihoodOptions.detector, 0.5 * f.fov_deg * kDeg, f.tilt_deg * kDeg,
                           0.5 * f.vertical_fov_deg * kDeg},
                          f.sigma_bearing_deg * kDeg};
}
}  // namespace

void CBearingCameraMap::scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                                  double* out) const
{
    detail::detectorLogLikelihoods(*this, geometryOf(likelihoodOptions), scan, poses, n, out);
}

std::vector<CObjectDetectorMap::TInView> CBearingCameraMap::inView(
    const TScan& scan, const mrpt::math::TPose2D& pose) const
{
    return detail::detectorInView(*this, geometryOf(likelihoodOptions), scan, pose);
}

CBearingCameraMap::TMapDefinition::TMapDefinition() = default;

void CBearingCameraMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    detail::loadDetectorDefinition(*this, source, sectionNamePrefix);
}

void CBearingCameraMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "world_file = " << world_file << "\n";
}

mrpt::maps::CMetricMap* CBearingCameraMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CBearingCameraMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CBearingCameraMap::serializeGetVersion() const
{
    return 0;
}
void CBearingCameraMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    writeObjects(out);
}
void CBearingCameraMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
    {
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
    readObjects(in);
}

namespace detail
{
std::shared_ptr<const SensorModelKind> bearingCameraMapKind()
{
    return std::make_shared<DetectorKind<CBearingCameraMap>>("bearingCameraMap", "camera",
                                                             "camera");
}
}  // namespace detail

}  // namespace semloc

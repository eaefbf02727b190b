/* semloc — CSideScanMap: the side-scan's geometry, its options and its kind. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/sidescan/CSideScanMap.h>

#include <cmath>

#include "models/BuiltinKinds.h"
#include "models/detector/DetectorKind.h"
#include "models/detector/DetectorLikelihood.h"

MAP_DEFINITION_REGISTER("sideScanMap,semloc::CSideScanMap", semloc::CSideScanMap)
IMPLEMENTS_SERIALIZABLE(CSideScanMap, CMetricMap, semloc)

namespace semloc
{
namespace
{
constexpr double kDeg = M_PI / 180;

/** What the side-scan sees of an object: abeam, beyond the nadir gap, in the window. */
struct SideScanGeometry
{
    const CObjectDetectorMap::TDetectorParam& p;
    double sin2HalfBeam, nadirGap;

    bool see(double u, double w, double dz, detail::TSeen& seen) const
    {
        const double ground2 = u * u + w * w, slant2 = ground2 + dz * dz;
        if (std::abs(w) < nadirGap || u * u > slant2 * sin2HalfBeam)
        {
            return false;
        }
        seen.range = std::sqrt(p.slant ? slant2 : ground2);
        seen.side = w >= 0 ? 1 : -1;
        return seen.range >= p.min_range_m && seen.range <= p.max_range_m;
    }
    double density(const CObjectDetectorMap::TScan::TDetection& d, const detail::TSeen& seen) const
    {
        if ((d.bearing_rad > 0) != (seen.side > 0))
        {
            return 0;
        }
        return detail::rangeDensity(p, d.range_m - seen.range);
    }
};
}  // namespace

CSideScanMap::TLikelihoodOptions::TLikelihoodOptions()
{
    detector.max_range_m = 50;
    detector.p_detect_near = 0.8;
    detector.p_detect_far = 0.4;
    detector.sigma_range_m = 0.5;
}

void CSideScanMap::TLikelihoodOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section)
{
    detector.load(source, section, {"beam_width_deg", "nadir_gap_m"}, true);
    config::readDouble(source, section, "beam_width_deg", beam_width_deg, 1e-3, 90);
    config::readDouble(source, section, "nadir_gap_m", nadir_gap_m, 0, 1e6);
}

void CSideScanMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                                        const std::string& section) const
{
    detector.save(target, section, true);
    target.write(section, "beam_width_deg", mrpt::format("%.17g", beam_width_deg), 24, 24,
                 "the fan's along-track width [deg]");
    target.write(section, "nadir_gap_m", mrpt::format("%.17g", nadir_gap_m), 24, 24,
                 "across-track seabed distance below which nothing is seen [m]");
}

bool CSideScanMap::validDetection(const TSemanticDetection& d) const
{
    const auto& p = likelihoodOptions.detector;
    return !d.label.empty() && d.range_m >= p.min_range_m && d.range_m <= p.max_range_m &&
           std::isfinite(d.bearing_rad) && d.bearing_rad != 0 && d.confidence >= 0 &&
           d.confidence <= 1;
}

double CSideScanMap::measurementVolume() const
{
    const auto& p = likelihoodOptions.detector;
    return 2 * (p.max_range_m - p.min_range_m);
}

namespace
{
SideScanGeometry geometryOf(const CSideScanMap::TLikelihoodOptions& o)
{
    const double s = std::sin(0.5 * o.beam_width_deg * kDeg);
    return {o.detector, s * s, o.nadir_gap_m};
}
}  // namespace

void CSideScanMap::scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                             double* out) const
{
    detail::detectorLogLikelihoods(*this, geometryOf(likelihoodOptions), scan, poses, n, out);
}

std::vector<CObjectDetectorMap::TInView> CSideScanMap::inView(const TScan& scan,
                                                              const mrpt::math::TPose2D& pose) const
{
    return detail::detectorInView(*this, geometryOf(likelihoodOptions), scan, pose);
}

CSideScanMap::TMapDefinition::TMapDefinition() = default;

void CSideScanMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    detail::loadDetectorDefinition(*this, source, sectionNamePrefix);
}

void CSideScanMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "world_file = " << world_file << "\n";
}

mrpt::maps::CMetricMap* CSideScanMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    auto* m = new CSideScanMap();
    m->likelihoodOptions = dynamic_cast<const TMapDefinition&>(def).likelihoodOpts;
    return m;
}

uint8_t CSideScanMap::serializeGetVersion() const
{
    return 0;
}
void CSideScanMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    writeObjects(out);
}
void CSideScanMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
    {
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
    readObjects(in);
}

namespace detail
{
std::shared_ptr<const SensorModelKind> sideScanMapKind()
{
    return std::make_shared<DetectorKind<CSideScanMap>>("sideScanMap", "sidescan", "side-scan");
}
}  // namespace detail

}  // namespace semloc

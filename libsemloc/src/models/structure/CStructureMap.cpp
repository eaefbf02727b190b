/* semloc — CStructureMap: outline segments and the sonar beam-model likelihood. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/structure/CStructureMap.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <memory>

#include "io/BoundedRead.h"
#include "io/ExactConfigWrite.h"

using mrpt::math::TPose2D;

//  =========== Map definition (CMultiMetricMap factory) ============
MAP_DEFINITION_REGISTER("structureMap,semloc::CStructureMap", semloc::CStructureMap)

namespace semloc
{
CStructureMap::TMapDefinition::TMapDefinition() = default;

void CStructureMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    const std::string sc = sectionNamePrefix + "_creationOpts";
    // MRPT reads genericMapParams (enableObservationLikelihood, ...) from this section too.
    auto known = config::keysOf(genericMapParams);
    known.insert(known.end(), {"world_file", "cylinder_tolerance_m", "raycast_cell_m"});
    config::rejectUnknownKeys(source, sc, known);
    world_file = config::resolveNextToIni(source, source.read_string(sc, "world_file", world_file));
    config::readDouble(source, sc, "cylinder_tolerance_m", cylinder_tolerance_m, 1e-6, 1e3);
    config::readDouble(source, sc, "raycast_cell_m", raycast_cell_m, 0, 1e3);
    likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
}

void CStructureMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "world_file = " << world_file << "\n";
    out << "cylinder_tolerance_m = " << cylinder_tolerance_m << "\n";
    out << "raycast_cell_m = " << raycast_cell_m << "\n";
    likelihoodOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CStructureMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& _def)
{
    const auto& def = dynamic_cast<const CStructureMap::TMapDefinition&>(_def);
    auto m = std::make_unique<CStructureMap>();
    m->likelihoodOptions = def.likelihoodOpts;
    if (!def.world_file.empty())
    {
        m->loadFromWorldFile(def.world_file, def.cylinder_tolerance_m, def.raycast_cell_m);
    }
    return m.release();
}
}  // namespace semloc
//  =========== End of map definition ============

IMPLEMENTS_SERIALIZABLE(CStructureMap, CMetricMap, semloc)

namespace semloc
{
// ------------------------------------------------------------------ options

namespace
{
using LikOptions = CStructureMap::TLikelihoodOptions;

/** The real-valued likelihood options and their valid ranges: one table for the ini reader
 *  and for the check of deserialized maps. */
struct DoubleOption
{
    const char* key;
    double LikOptions::*field;
    double lo, hi;
};
const DoubleOption kDoubleOptions[] = {
    {"sigma_hit_m", &LikOptions::sigma_hit_m, 1e-6, 1e6},
    {"z_hit", &LikOptions::z_hit, 0, 1},
    {"z_short", &LikOptions::z_short, 0, 1},
    {"lambda_short", &LikOptions::lambda_short, 1e-9, 1e6},
    {"z_max", &LikOptions::z_max, 0, 1},
    {"z_rand", &LikOptions::z_rand, 0, 1},
    {"max_range_m", &LikOptions::max_range_m, 0, 1e6},
    {"min_beam_likelihood", &LikOptions::min_beam_likelihood, 1e-300, 1}};
constexpr int kMaxDecimation = 1000000;

/** The check both readers share once every value is in range; `where` prefixes the error. */
void checkWeights(const LikOptions& o, const std::string& where)
{
    if (!(o.z_hit + o.z_short + o.z_max + o.z_rand > 0))
    {
        THROW_EXCEPTION(where + " z_hit, z_short, z_max, z_rand: all zero");
    }
}

/** The options of a deserialized map, checked as the ini reader checks them (a crafted or
 *  corrupted .simplemap must not give NaN likelihoods). */
void checkDeserialized(const LikOptions& o)
{
    const std::string where = "CStructureMap: corrupted data: likelihood option";
    for (const auto& d : kDoubleOptions)
    {
        const double v = o.*d.field;
        if (!(v >= d.lo && v <= d.hi))
        {
            THROW_EXCEPTION(mrpt::format("%s %s = %g is out of range [%g, %g]", where.c_str(),
                                         d.key, v, d.lo, d.hi));
        }
    }
    if (o.decimation < 1 || o.decimation > kMaxDecimation)
    {
        THROW_EXCEPTION(mrpt::format("%s decimation = %d is out of range [1, %d]", where.c_str(),
                                     o.decimation, kMaxDecimation));
    }
    checkWeights(o, where + "s");
}
}  // namespace

void CStructureMap::TLikelihoodOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                           const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    for (const auto& d : kDoubleOptions)
    {
        config::readDouble(c, s, d.key, this->*d.field, d.lo, d.hi);
    }
    config::readInt(c, s, "decimation", decimation, 1, kMaxDecimation);
    checkWeights(*this, "ini [" + s + "]");
}

void CStructureMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                         const std::string& s) const
{
    detail::writeExact(c, s, "sigma_hit_m", sigma_hit_m, "range noise of a hit, sigma_hit [m]");
    detail::writeExact(c, s, "z_hit", z_hit, "weight of the Gaussian hit term (weights sum to 1)");
    detail::writeExact(c, s, "z_short", z_short, "weight of the exponential short term");
    detail::writeExact(c, s, "lambda_short", lambda_short, "rate of the short term [1/m]");
    detail::writeExact(c, s, "z_max", z_max, "weight of the max-range point mass");
    detail::writeExact(c, s, "z_rand", z_rand, "weight of the uniform random term");
    c.write(s, "decimation", decimation, 24, 24, "use one beam out of this many");
    detail::writeExact(c, s, "max_range_m", max_range_m, ">0 overrides the scan's max range [m]");
    detail::writeExact(c, s, "min_beam_likelihood", min_beam_likelihood,
                       "floor of each beam's probability");
}

// ------------------------------------------------------------------ contents

CStructureMap::CStructureMap() = default;

void CStructureMap::loadFromWorld(const World& world, double cylinderTolerance_m,
                                  double raycastCell_m)
{
    setSegments(world.outlineSegments(cylinderTolerance_m), raycastCell_m);
    m_name = world.name;
}

void CStructureMap::loadFromWorldFile(const std::string& path, double cylinderTolerance_m,
                                      double raycastCell_m)
{
    loadFromWorld(World::FromFile(path), cylinderTolerance_m, raycastCell_m);
}

void CStructureMap::setSegments(const std::vector<mrpt::math::TSegment2D>& segments,
                                double raycastCell_m)
{
    m_requestedCell_m = raycastCell_m > 0 ? raycastCell_m : 0;
    m_caster.setSegments(segments, m_requestedCell_m);
    m_name.clear();
}

void CStructureMap::internal_clear()
{
    m_caster.setSegments({});
    m_name.clear();
}

bool CStructureMap::internal_insertObservation(const mrpt::obs::CObservation&,
                                               const std::optional<const mrpt::poses::CPose3D>&)
{
    return false;  // a static map of known structures
}

// ------------------------------------------------------------------ likelihood

namespace
{
/** Lowest value returned, for a non-finite pose. */
constexpr double kMinLogLik = -1e300;
/** Standard normal CDF beyond this many sigmas is 0 or 1 to double precision. */
constexpr double kTailSigmas = 8.3;

/** Phi(u) - Phi(l), the standard normal mass on [l, u], skipping erfc in the tails. */
inline double normalMass(double l, double u)
{
    const double hi = u > kTailSigmas ? 1.0 : 0.5 * std::erfc(-u * M_SQRT1_2);
    const double lo = l < -kTailSigmas ? 0.0 : 0.5 * std::erfc(-l * M_SQRT1_2);
    return hi - lo;
}
}  // namespace

double CStructureMap::computeLogLikelihood(const mrpt::obs::CObservation2DRangeScan& scan,
                                           const TPose2D& pose) const
{
    const TLikelihoodOptions& o = likelihoodOptions;
    const size_t n = scan.getScanSize();
    const double zmax = o.max_range_m > 0 ? o.max_range_m : static_cast<double>(scan.maxRange);
    const double wsum = o.z_hit + o.z_short + o.z_max + o.z_rand;
    if (n == 0 || !(zmax > 0) || !std::isfinite(zmax) || !(wsum > 0))
    {
        return 0;  // nothing usable: uninformative, identical for every particle
    }
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.phi))
    {
        return kMinLogLik;
    }
    const double wHit = o.z_hit / wsum, wShort = o.z_short / wsum;
    const double wMax = o.z_max / wsum, wRand = o.z_rand / wsum;
    const double sigma = o.sigma_hit_m, invSigma = 1.0 / sigma;
    const double gaussNorm = 1.0 / (sigma * std::sqrt(2 * M_PI));
    const double lambda = o.lambda_short, pRand = wRand / zmax;
    const double floorP = o.min_beam_likelihood;
    const size_t step = static_cast<size_t>(std::max(1, o.decimation));

    // Sensor pose: vehicle pose (+) scan.sensorPose, projected to 2D.
    const double c = std::cos(pose.phi), s = std::sin(pose.phi);
    const double spx = scan.sensorPose.x(), spy = scan.sensorPose.y();
    const double sx = pose.x + c * spx - s * spy;
    const double sy = pose.y + s * spx + c * spy;
    const double sphi = pose.phi + scan.sensorPose.yaw();

    // Beam k at angle a0 + k da in the sensor frame (MRPT's getScanAngle), negated when
    // the scan runs left to right; directions are stepped by a rotation (no trig per beam).
    const double aperture = scan.aperture;
    const double a0 = n > 1 ? -0.5 * aperture : 0.0;
    const double da = n > 1 ? aperture / static_cast<double>(n - 1) : 0.0;
    const double sign = scan.rightToLeft ? 1.0 : -1.0;
    double dx = std::cos(sphi + sign * a0), dy = std::sin(sphi + sign * a0);
    const double rc = std::cos(sign * da * static_cast<double>(step));
    const double rs = std::sin(sign * da * static_cast<double>(step));

    // p(z | z*) of (6.12); z is clamped to z_max and isMax tells a max-range reading.
    auto beamProbability = [&](double z, double zexp, bool isMax)
    {
        // (6.4): Gaussian around the expected range, normalized on [0, z_max].
        const double u = (z - zexp) * invSigma;
        const double mass = normalMass(-zexp * invSigma, (zmax - zexp) * invSigma);
        double p = wHit * gaussNorm * std::exp(-0.5 * u * u) / std::max(mass, 1e-300);
        // (6.7): exponential for readings short of the expected range.
        if (wShort > 0 && z <= zexp && zexp > 0)
        {
            p += wShort * lambda * std::exp(-lambda * z) / -std::expm1(-lambda * zexp);
        }
        // (6.10), (6.11): max-range point mass, uniform below z_max.
        return p + (isMax ? wMax : pRand);
    };
    // The usual beam in open water: nothing expected, nothing seen; one log per scan.
    const double logBothMax = std::log(std::max(beamProbability(zmax, zmax, true), floorP));

    double logLik = 0;
    for (size_t k = 0; k < n; k += step)
    {
        const double z = scan.getScanRange(k);
        if (scan.getScanRangeValidity(k) && std::isfinite(z) && z >= 0)
        {
            const double zexp = m_caster.castDir(sx, sy, dx, dy, zmax);
            const bool isMax = z >= zmax;
            if (isMax && zexp >= zmax)
            {
                logLik += logBothMax;
            }
            else
            {
                const double p = beamProbability(isMax ? zmax : z, zexp, isMax);
                logLik += std::log(p > floorP ? p : floorP);
            }
        }
        const double ndx = dx * rc - dy * rs;
        dy = dx * rs + dy * rc;
        dx = ndx;
    }
    return logLik;
}

bool CStructureMap::uses(const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs) != nullptr;
}

void CStructureMap::logLikelihoods(const mrpt::obs::CObservation& obs, const TPose2D* poses,
                                   size_t n, double* out) const
{
    const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs);
    for (size_t i = 0; i < n; i++)
    {
        out[i] = scan ? computeLogLikelihood(*scan, poses[i]) : 0.0;
    }
}

bool CStructureMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs) != nullptr;
}

double CStructureMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs))
    {
        return computeLogLikelihood(*scan, TPose2D(takenFrom.x(), takenFrom.y(), takenFrom.yaw()));
    }
    return 0;
}

// ------------------------------------------------------------------ I/O

uint8_t CStructureMap::serializeGetVersion() const
{
    return 0;
}

void CStructureMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    const auto& o = likelihoodOptions;
    out << genericMapParams;
    out << o.sigma_hit_m << o.z_hit << o.z_short << o.lambda_short << o.z_max << o.z_rand
        << static_cast<int32_t>(o.decimation) << o.max_range_m << o.min_beam_likelihood;
    out << m_name << m_requestedCell_m;
    const auto& segs = m_caster.segments();
    out.WriteAs<uint32_t>(segs.size());
    for (const auto& sg : segs)
    {
        out << sg.point1.x << sg.point1.y << sg.point2.x << sg.point2.y;
    }
}

void CStructureMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            // Read into locals and check: a throw leaves the map as it was.
            const auto params = detail::readGenericMapParams(in, "CStructureMap");
            TLikelihoodOptions o;
            int32_t decimation = 1;
            in >> o.sigma_hit_m >> o.z_hit >> o.z_short >> o.lambda_short >> o.z_max >> o.z_rand >>
                decimation >> o.max_range_m >> o.min_beam_likelihood;
            o.decimation = decimation;
            checkDeserialized(o);
            std::string name;
            double cell = 0;
            detail::readString(in, name, "CStructureMap name");
            in >> cell;
            if (!std::isfinite(cell))
            {
                THROW_EXCEPTION("CStructureMap: corrupted data: non-finite ray-casting cell");
            }
            const uint32_t n = detail::readCount(in, 1u << 26, "CStructureMap segments");
            std::vector<mrpt::math::TSegment2D> segs;
            for (uint32_t i = 0; i < n; i++)
            {
                mrpt::math::TSegment2D sg;
                in >> sg.point1.x >> sg.point1.y >> sg.point2.x >> sg.point2.y;
                if (!(std::isfinite(sg.point1.x) && std::isfinite(sg.point1.y) &&
                      std::isfinite(sg.point2.x) && std::isfinite(sg.point2.y)))
                {
                    THROW_EXCEPTION_FMT(
                        "CStructureMap: corrupted data: segment %u has a non-finite coordinate", i);
                }
                segs.push_back(sg);
            }
            setSegments(segs, cell);
            genericMapParams = params;
            likelihoodOptions = o;
            m_name = name;
            break;
        }
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

void CStructureMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    const std::string file = prefix + "_outlines.txt";
    std::ofstream f(file);
    if (!f)
    {
        THROW_EXCEPTION("CStructureMap: cannot write '" + file + "'");
    }
    f << "# CStructureMap outlines" << (m_name.empty() ? "" : " of world " + m_name)
      << ": one segment per line, x1 y1 x2 y2 [m]\n";
    f.precision(17);
    for (const auto& sg : m_caster.segments())
    {
        f << sg.point1.x << ' ' << sg.point1.y << ' ' << sg.point2.x << ' ' << sg.point2.y << '\n';
    }
    if (!f)
    {
        THROW_EXCEPTION("CStructureMap: write error on '" + file + "'");
    }
}

std::string CStructureMap::asString() const
{
    return mrpt::format("CStructureMap: world '%s', %u segments, ray-cast grid %dx%d of %.3g m",
                        m_name.c_str(), static_cast<unsigned>(m_caster.segments().size()),
                        m_caster.gridCellsX(), m_caster.gridCellsY(), m_caster.cellSize());
}

void CStructureMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const
{
    if (!genericMapParams.enableSaveAs3DObject)
    {
        return;
    }
    auto lines = mrpt::opengl::CSetOfLines::Create();
    for (const auto& sg : m_caster.segments())
    {
        lines->appendLine(sg.point1.x, sg.point1.y, 0, sg.point2.x, sg.point2.y, 0);
    }
    lines->setColor(0.9f, 0.5f, 0.1f);
    lines->setLineWidth(2.0f);
    outObj.insert(lines);
}

}  // namespace semloc

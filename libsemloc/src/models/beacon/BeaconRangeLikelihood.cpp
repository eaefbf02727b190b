/* semloc — MRPT's CBeaconMap likelihood of beacon ranges, the beacons looked up once per frame
 * (see BeaconRangeLikelihood.h). */
#include "models/beacon/BeaconRangeLikelihood.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/ops_matrices.h>

#include <Eigen/Dense>

#include <cmath>
#include <typeinfo>

namespace semloc::detail
{
using mrpt::maps::CBeacon;
using mrpt::maps::CBeaconMap;

BeaconIdIndex::BeaconIdIndex(const CBeaconMap& map)
    : m_size(map.size()), m_storage(map.size() ? &map[0] : nullptr)
{
    m_first.reserve(map.size());
    for (size_t i = 0; i < map.size(); i++)
    {
        m_first.emplace(map[i].m_ID, i);  // keeps the first of an id, as getBeaconByID
    }
}

bool BeaconIdIndex::matches(const CBeaconMap& map) const
{
    return map.size() == m_size && (m_size == 0 || &map[0] == m_storage);
}

const CBeacon* BeaconIdIndex::find(const CBeaconMap& map, CBeacon::TBeaconID id) const
{
    const auto it = m_first.find(id);
    return it == m_first.end() ? nullptr : &map[it->second];
}

bool BeaconRangeTerm::plan(const CBeaconMap& map, const BeaconIdIndex& index,
                           const mrpt::obs::CObservationBeaconRanges& obs)
{
    m_map = &map;
    m_obs = &obs;
    m_ranges.clear();
    m_beaconsScored = 0;
    for (const auto& m : obs.sensedData)
    {
        Range r;
        r.beacon = index.find(map, m.beaconID);
        if (r.beacon != nullptr && m.sensedDistance > 0 && !std::isnan(m.sensedDistance))
        {
            if (r.beacon->m_typePDF != CBeacon::pdfGauss)
            {
                return false;
            }
            r.sensedRange = m.sensedDistance;
            r.sensorOnRobot = m.sensorLocationOnRobot;
            m_beaconsScored++;
        }
        else if (obs.maxSensorDistance != obs.minSensorDistance)
        {
            // What CBeaconMap adds for a range it cannot score: a uniform density.
            r.beacon = nullptr;
            r.constant = std::log(1.0 / (obs.maxSensorDistance - obs.minSensorDistance));
        }
        else
        {
            continue;  // it adds nothing
        }
        m_ranges.push_back(r);
    }
    return true;
}

double BeaconRangeTerm::logLikelihood(const mrpt::poses::CPose3D& robotPose3D) const
{
    // CBeaconMap::internal_computeObservationLikelihood (MRPT 2.5) for Gaussian beacons, its
    // float and double steps as they are (MRPT converts to float where the casts are).
    using mrpt::square;
    double ret = 0;
    for (const Range& r : m_ranges)
    {
        if (r.beacon == nullptr)
        {
            ret += r.constant;
            continue;
        }
        const mrpt::poses::CPoint3D sensor3D = robotPose3D + r.sensorOnRobot;
        const auto& g = r.beacon->m_locationGauss;
        mrpt::math::CMatrixFixed<double, 1, 3> H;
        const auto varR = static_cast<float>(square(m_map->likelihoodOptions.rangeStd));
        const auto Ax = static_cast<float>(g.mean.x() - sensor3D.x());
        const auto Ay = static_cast<float>(g.mean.y() - sensor3D.y());
        const auto Az = static_cast<float>(g.mean.z() - sensor3D.z());
        H(0, 0) = Ax;
        H(0, 1) = Ay;
        H(0, 2) = Az;
        const auto expectedRange = static_cast<float>(sensor3D.distanceTo(g.mean));
        H.asEigen() *= 1.0 / expectedRange;
        auto varZ = static_cast<float>(mrpt::math::multiply_HCHt_scalar(H, g.cov));
        varZ += varR;
        ret += -0.5 * square(r.sensedRange - expectedRange) / varZ;
    }
    if (!std::isfinite(ret))
    {
        return m_map->computeObservationLikelihood(*m_obs, robotPose3D);  // throws as it did
    }
    return ret;
}

namespace
{
/** The pose MRPT hands to CMetricMap::computeObservationLikelihood for a 2D particle. */
mrpt::poses::CPose3D mrptPose(const mrpt::math::TPose2D& p)
{
    return mrpt::poses::CPose3D(mrpt::math::TPose3D(p));
}

/** A frame's beacon ranges, their beacons found. */
class PreparedRanges final : public BatchLikelihood::Prepared
{
public:
    BeaconRangeTerm term;
    void logLikelihoods(const mrpt::math::TPose2D* poses, size_t n, double* out) const override
    {
        for (size_t i = 0; i < n; i++)
        {
            out[i] = term.logLikelihood(mrptPose(poses[i]));
        }
    }
};
}  // namespace

BeaconMapBatch::BeaconMapBatch(const CBeaconMap& map) : m_map(map) {}

BeaconMapBatch::~BeaconMapBatch() = default;

bool BeaconMapBatch::uses(const mrpt::obs::CObservation& obs) const
{
    return typeid(obs) == typeid(mrpt::obs::CObservationBeaconRanges);
}

void BeaconMapBatch::logLikelihoods(const mrpt::obs::CObservation& obs,
                                    const mrpt::math::TPose2D* poses, size_t n, double* out) const
{
    for (size_t i = 0; i < n; i++)
    {
        out[i] = m_map.computeObservationLikelihood(obs, mrptPose(poses[i]));
    }
}

std::unique_ptr<BatchLikelihood::Prepared> BeaconMapBatch::prepareObservation(
    const mrpt::obs::CObservation& obs) const
{
    if (!m_index || !m_index->matches(m_map))
    {
        m_index = std::make_unique<BeaconIdIndex>(m_map);  // built, or rebuilt
    }
    auto prepared = std::make_unique<PreparedRanges>();
    if (!prepared->term.plan(m_map, *m_index,
                             static_cast<const mrpt::obs::CObservationBeaconRanges&>(obs)))
    {
        return nullptr;  // a beacon that is not a Gaussian: MRPT's call
    }
    return prepared;
}
}  // namespace semloc::detail

/* semloc — MRPT's CBeaconMap likelihood of beacon ranges, each range's beacon looked up once
 * per frame through an index of the map's ids (private). */
#pragma once

#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/models/BatchLikelihood.h>

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace semloc::detail
{
/** The beacons of a CBeaconMap by id: the first beacon of each id, the one
 *  CBeaconMap::getBeaconByID finds (by looking through every beacon of the map, once per
 *  range and pose in MRPT's likelihood). */
class BeaconIdIndex
{
public:
    explicit BeaconIdIndex(const mrpt::maps::CBeaconMap& map);

    /** True while `map` holds the beacons the index was built from: as many, in the same
     *  storage (a beacon added or removed reallocates or resizes it). */
    bool matches(const mrpt::maps::CBeaconMap& map) const;

    /** The first beacon of `map` with id `id`, or nullptr (what getBeaconByID returns);
     *  `map` is the indexed one (matches()). */
    const mrpt::maps::CBeacon* find(const mrpt::maps::CBeaconMap& map,
                                    mrpt::maps::CBeacon::TBeaconID id) const;

private:
    size_t m_size = 0;
    const mrpt::maps::CBeacon* m_storage = nullptr;
    std::unordered_map<mrpt::maps::CBeacon::TBeaconID, size_t> m_first;
};

/** One CObservationBeaconRanges against one CBeaconMap whose ranges were resolved to their
 *  beacons once (plan()): logLikelihood(pose) is map.computeObservationLikelihood(obs, pose)
 *  bit for bit (MRPT's terms, types and order of summation), at the cost of the
 *  observation's ranges alone. The map's beacons that did not answer (beyond the sensor's
 *  range: they are not in the observation) are never visited. */
class BeaconRangeTerm
{
public:
    /** Resolves the ranges of `obs` to the beacons of `map` through `index` (which must
     *  match the map). False, leaving the term unusable, when an answering beacon's
     *  position is not a Gaussian (a Monte Carlo or sum-of-Gaussians beacon, as MRPT's
     *  range-only SLAM leaves them): the caller keeps MRPT's call for that observation. */
    bool plan(const mrpt::maps::CBeaconMap& map, const BeaconIdIndex& index,
              const mrpt::obs::CObservationBeaconRanges& obs);

    /** log p(obs | pose), as CBeaconMap computes it. A value that is not finite is left to
     *  MRPT's call, which throws as it always did. Safe from several threads. */
    double logLikelihood(const mrpt::poses::CPose3D& pose) const;

    /** Beacons scored at each pose: the planned ranges whose beacon the map holds. */
    size_t beaconsScored() const { return m_beaconsScored; }

private:
    /** One range, in the observation's order: a beacon's term, or (beacon == nullptr) the
     *  constant of a range the map cannot score (unknown id, range <= 0 or NaN). */
    struct Range
    {
        const mrpt::maps::CBeacon* beacon = nullptr;
        float sensedRange = 0;
        mrpt::poses::CPoint3D sensorOnRobot;
        double constant = 0;
    };

    const mrpt::maps::CBeaconMap* m_map = nullptr;
    const mrpt::obs::CObservationBeaconRanges* m_obs = nullptr;
    std::vector<Range> m_ranges;
    size_t m_beaconsScored = 0;
};
/** MRPT's CBeaconMap evaluated in blocks (its kind's SensorModelKind::batchOf(), for the map
 *  of that exact class: a subclass may keep state of its own): beacon ranges only (CBeaconMap
 *  adds 0 for any other observation), each range's beacon found once per frame through an
 *  index of the map's ids (rebuilt when its beacons change), then BeaconRangeTerm's terms, bit
 *  for bit MRPT's value; MRPT's call, pose by pose, for an observation with a beacon whose
 *  position is not a Gaussian. */
class BeaconMapBatch final : public BatchLikelihood
{
public:
    explicit BeaconMapBatch(const mrpt::maps::CBeaconMap& map);
    ~BeaconMapBatch() override;
    bool uses(const mrpt::obs::CObservation& obs) const override;
    /** MRPT's call at every pose (the observations prepareObservation() cannot plan). */
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;
    /** The ranges' beacons found (BeaconRangeTerm::plan), or nullptr when one is not a
     *  Gaussian. */
    std::unique_ptr<Prepared> prepareObservation(const mrpt::obs::CObservation& obs) const override;

private:
    const mrpt::maps::CBeaconMap& m_map;
    /** The map's id index (built, or rebuilt, by prepareObservation(), on one thread). */
    mutable std::unique_ptr<BeaconIdIndex> m_index;
};
}  // namespace semloc::detail

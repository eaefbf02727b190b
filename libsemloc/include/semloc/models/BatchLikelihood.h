/* semloc — the interface of a sensor model the filter evaluates on blocks of poses
 * (docs/design.md, "Adding a sensor model"). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>

namespace semloc
{
/** A sensor model as the filter evaluates it: log p(obs | pose) for a block of vehicle poses.
 *
 *  An MRPT metric map that also derives from this class is evaluated through it by the filter
 *  (SensoryFrameLikelihood), on each thread's block of particles; any other map through its
 *  generic CMetricMap::computeObservationLikelihood (MRPT's occupancy grids in parallel, other
 *  maps on one thread). CSemanticMap and CStructureMap implement it; so can a map of a
 *  program's own, without a line of the filter changed.
 *
 *  The contract:
 *  - uses(obs) says whether the model scores `obs`; false: its term is 0 and is not evaluated.
 *    It is called on one thread, once per frame and observation, before any logLikelihoods()
 *    of that frame.
 *  - logLikelihoods(obs, poses, n, out) sets out[i] = log p(obs | poses[i]) for i in [0, n).
 *    It is called from several threads at once, each with its own block of the particles and
 *    the same `obs`: it must not change state that the calls share (or must synchronize), and
 *    a pose's value must not depend on the block it is in (the filter's results are then the
 *    same for any number of threads).
 *  - Its values equal the map's CMetricMap::computeObservationLikelihood at the same pose (the
 *    value MRPT's own CMonteCarloLocalization2D uses), so that the filter's results are MRPT's.
 *    A subclass that overrides one overrides the other.
 *  - A value may be -inf (the pose is impossible); NaN and +inf are counted and made -inf by
 *    the filter (SensoryFrameLikelihood::TStats::nonfinite_likelihoods). */
class BatchLikelihood
{
public:
    virtual ~BatchLikelihood() = default;

    /** True when the model scores `obs` (see the class documentation). */
    virtual bool uses(const mrpt::obs::CObservation& obs) const = 0;

    /** out[i] = log p(obs | poses[i]) for i in [0, n); safe from several threads at once. */
    virtual void logLikelihoods(const mrpt::obs::CObservation& obs,
                                const mrpt::math::TPose2D* poses, size_t n, double* out) const = 0;

protected:
    BatchLikelihood() = default;
    BatchLikelihood(const BatchLikelihood&) = default;
    BatchLikelihood(BatchLikelihood&&) = default;
    BatchLikelihood& operator=(const BatchLikelihood&) = default;
    BatchLikelihood& operator=(BatchLikelihood&&) = default;
};

}  // namespace semloc

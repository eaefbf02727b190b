/* semloc — the interface of a sensor model the filter evaluates on blocks of poses
 * (docs/design.md, "Adding a sensor model"). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::obs
{
class CSensoryFrame;
}  // namespace mrpt::obs
namespace mrpt::random
{
class CRandomGenerator;
}  // namespace mrpt::random

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
 *    the filter (SensoryFrameLikelihood::TStats::nonfinite_likelihoods).
 *
 *  The hooks below are optional (their defaults say and do nothing): through them a model asks
 *  the filter for what it cannot do from inside one evaluation, and the filter names no
 *  model. The semantic model (models/semantic/) uses plan() for its detection counts, its
 *  detector's outages and its likelihood with no object in view (the evidence recovery
 *  trigger's reference), newMemory() for its look-alike memory, proposal() for the poses
 *  recovery and start-up draw from a detection, approximations() for its marginal
 *  association's count; MRPT's beacon map's batch (models/beacon/) prepareObservation() for
 *  each frame's ranges matched to their beacons. */
class BatchLikelihood
{
public:
    virtual ~BatchLikelihood() = default;

    /** What the model tells the filter of one observation it uses (plan()). */
    struct TObservationPlan
    {
        /** The model checked the observation's readings: `invalid` and `unknown` count
         *  (SensoryFrameLikelihood::TStats, from the first model of an observation that
         *  checks it). */
        bool checked = false;
        /** Readings refused (not finite, out of range...) and readings of what the model
         *  does not know. */
        size_t invalid = 0, unknown = 0;
        /** The readings the likelihood with nothing of the map in view uses (0: the
         *  observation tells nothing of the map) and that log-likelihood, the same at every
         *  pose: the evidence recovery trigger's reference. */
        size_t readingsWithoutMap = 0;
        double logLikWithoutMap = 0;
        /** The detector that took it may be out for a while (> 0: its outage model's mean
         *  time between outages and mean outage [s]): a frame whose outage terms are all
         *  `silent` is scored as the mixture of "out" and the model's likelihood, the
         *  outage probability carried from frame to frame by the filter (one detector for
         *  the filter: the first such observation's rates). */
        double outage_every_s = 0, outage_mean_s = 0;
        /** It reports nothing of the map (only what an outage would let through). */
        bool silent = false;
        /** The model's Memory remembers it: a filter that weighs particles by the frame
         *  calls Memory::remember() on it, then logLikelihoodsRemembering() instead of
         *  logLikelihoods(). */
        bool remembered = false;
    };
    /** Called on one thread once per frame and used observation, before any evaluation. */
    virtual TObservationPlan plan(const mrpt::obs::CObservation& obs) const
    {
        (void)obs;
        return {};
    }

    /** An observation prepared once per frame for its evaluations (what every pose shares). */
    class Prepared
    {
    public:
        virtual ~Prepared() = default;
        /** out[i] = log p(obs | poses[i]) for i in [0, n); safe from several threads at
         *  once, as logLikelihoods(). */
        virtual void logLikelihoods(const mrpt::math::TPose2D* poses, size_t n,
                                    double* out) const = 0;

    protected:
        Prepared() = default;
        Prepared(const Prepared&) = default;
        Prepared& operator=(const Prepared&) = default;
    };
    /** `obs` prepared for this frame's evaluations, or nullptr (the default): the filter then
     *  calls logLikelihoods(obs, ...). Called on one thread, once per frame and used
     *  observation, after plan(); the model may keep caches across frames there (it is the
     *  one call that may change them). Not with a remembered observation. */
    virtual std::unique_ptr<Prepared> prepareObservation(const mrpt::obs::CObservation& obs) const
    {
        (void)obs;
        return nullptr;
    }

    /** The model's state from frame to frame, kept by the filter (one per model and filter,
     *  made by newMemory(), dropped with a new run). */
    class Memory
    {
    public:
        virtual ~Memory() = default;
        /** Remembers `obs` (plan() said `remembered`), taken at `odometry` (the vehicle's pose
         *  by its odometry, any fixed origin); `context` gets what the observation's
         *  evaluations need of the memory, and what the memory changes of the likelihood
         *  with nothing of the map in view is added to `logLikWithoutMap`. */
        virtual void remember(const mrpt::obs::CObservation& obs,
                              const mrpt::math::TPose2D& odometry, std::vector<double>& context,
                              double& logLikWithoutMap) = 0;

    protected:
        Memory() = default;
        Memory(const Memory&) = default;
        Memory& operator=(const Memory&) = default;
    };
    /** A new, empty memory; nullptr (the default): the model keeps none. */
    virtual std::unique_ptr<Memory> newMemory() const { return nullptr; }
    /** logLikelihoods() of an observation its memory remembered, with the `context` of
     *  Memory::remember(); safe from several threads at once, as logLikelihoods(). */
    virtual void logLikelihoodsRemembering(const mrpt::obs::CObservation& obs,
                                           const std::vector<double>& context,
                                           const mrpt::math::TPose2D* poses, size_t n,
                                           double* out) const
    {
        (void)context;
        logLikelihoods(obs, poses, n, out);
    }

    /** Vehicle poses from which a frame's observation could have been taken. */
    class PoseProposal
    {
    public:
        virtual ~PoseProposal() = default;
        /** One vehicle pose. */
        virtual mrpt::math::TPose2D draw(mrpt::random::CRandomGenerator& rng) const = 0;

    protected:
        PoseProposal() = default;
        PoseProposal(const PoseProposal&) = default;
        PoseProposal& operator=(const PoseProposal&) = default;
    };
    /** True when the model can propose poses from some frames (proposal()). */
    virtual bool proposes() const { return false; }
    /** The poses `sf` places (recovery's injected particles, `init_PDF_mode = 3`), or nullptr
     *  when it places none (the default). */
    virtual std::unique_ptr<PoseProposal> proposal(const mrpt::obs::CSensoryFrame& sf) const
    {
        (void)sf;
        return nullptr;
    }

    /** True when plan() gives the likelihood with nothing of the map in view of every
     *  observation the model uses: the evidence recovery trigger needs it of every map. */
    virtual bool weighsWithoutMap() const { return false; }
    /** Why the model needs MRPT's standard proposal ([PF_options] PF_algorithm = 0: a
     *  state the filter carries from frame to frame that the other algorithms do not
     *  update), or empty (the default). */
    virtual std::string needsStandardProposal() const { return {}; }
    /** Evaluations approximated since the model was made (counted, not an error; 0 by
     *  default): SensoryFrameLikelihood::TStats::associations_approximated. */
    virtual size_t approximations() const { return 0; }

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

/* semloc — the observation log-likelihood of a sensory frame at many vehicle poses, computed
 * in parallel and equal to what MRPT's CMonteCarloLocalization2D computes one by one. */
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/system/datetime.h>
#include <semloc/models/BatchLikelihood.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace semloc
{
namespace detail
{
class DetectorOutage;
}  // namespace detail
class ParallelExecutor;

/** log p(sf | pose) for every particle pose, the sensor model of the filter.
 *
 *  The value is MRPT's (CMonteCarloLocalization2D::PF_SLAM_computeObservationLikelihoodForParticle
 *  over a CMultiMetricMap): 1 + sum over the frame's observations of the sum over the maps of
 *  CMetricMap::computeObservationLikelihood (0 for a map or multimap whose
 *  `enableObservationLikelihood` is off), added in the same order. Each (observation, map)
 *  term takes the fastest path that gives the same value:
 *  - a map that is a BatchLikelihood (semloc's sensor models, a program's own), or that its
 *    kind evaluates by one (SensorModelKind::batchOf(): MRPT's CBeaconMap, each range's
 *    beacon found once per frame through an index of the map's ids, so a pose costs the
 *    observation's ranges alone, however many beacons the map holds):
 *    BatchLikelihood::logLikelihoods() (or its prepareObservation()s) on each thread's
 *    contiguous chunk of poses; 0, not evaluated, for an observation it does not use; its
 *    plan() and prepareObservation() (BatchLikelihood's hooks) called once per frame;
 *  - COccupancyGridMap2D with the ray-tracing or Thrun likelihood-field method: the generic
 *    call on every thread (the first pose is evaluated alone first, so the lazy caches of
 *    the observation are built before threads share it; the grid's likelihood-field cache
 *    is filled completely before the first multi-threaded use);
 *  - any other map: the generic call, for every pose on the calling thread (MRPT's other
 *    maps keep mutable caches that are not safe to share).
 *
 *  A non-finite value (NaN, +-inf) makes that pose's value -inf (weight zero) and is
 *  counted in TStats::nonfinite_likelihoods. */
class SensoryFrameLikelihood
{
public:
    /** What the evaluated frames contained (cumulative). */
    struct TStats
    {
        /** Observations at least one map can score (canComputeObservationLikelihood; for
         *  a map its kind evaluates in blocks, what the batch uses: a CBeaconMap's beacon
         *  ranges only, as it adds 0 for any other observation). */
        size_t observations_used = 0;
        /** Observations no map can score (ignored, as MRPT does). */
        size_t observations_skipped = 0;
        /** Readings a sensor model rejected as invalid (NaN, out of range...: the semantic
         *  map's detections; BatchLikelihood::TObservationPlan::invalid). */
        size_t detections_invalid = 0;
        /** Valid readings of what the model does not know (a semantic detection's label or
         *  id; TObservationPlan::unknown). */
        size_t detections_unknown = 0;
        /** Particle evaluations that were not finite (set to -inf). */
        size_t nonfinite_likelihoods = 0;
        /** Particle evaluations a sensor model approximated (BatchLikelihood::approximations():
         *  the semantic map's `association = marginal` sums over associations) since the
         *  Localizer last drew its particles (counted by Localizer, 0 here). */
        size_t associations_approximated = 0;
        /** Range-scan beams flagged valid whose range is NaN, +-inf, negative or beyond the
         *  scan's maxRange: marked invalid before any map sees the scan (counted by
         *  Localizer, which does that; 0 here). */
        size_t beams_invalid = 0;
        /** Observations left out whole because they cannot be scored (a non-finite sensor
         *  pose, aperture or range limit, a scan without beams...:
         *  Localizer::invalidObservation(); counted by Localizer, 0 here). Not counted in
         *  observations_used or observations_skipped. */
        size_t observations_invalid = 0;
    };

    /** The terms of the planned frame that a detector outage silences: those whose model's
     *  plan gives outage rates (TObservationPlan::outage_every_s > 0: the semantic map's
     *  outage model), one detector for the filter. */
    struct TOutageTerms
    {
        /** The frame has at least one such term. */
        bool present = false;
        /** Every one of their observations is silent (TObservationPlan::silent: for the
         *  semantic map, no detection it knows, an invalid reading counting as one). */
        bool silent = true;
        /** The first such observation's timestamp. */
        mrpt::Clock::time_point t{};
        /** The model's rates (the first such term's) [s]. */
        double every_s = 0, mean_s = 0;
    };

    /** The frame's likelihood with nothing of the maps in view (TObservationPlan's
     *  logLikWithoutMap summed over the frame's model terms, with what their memories add):
     *  the reference of the evidence recovery trigger. */
    struct TWithoutObjects
    {
        /** Readings the terms use for it; 0: the frame tells nothing of the maps. */
        size_t detections = 0;
        /** log p(z | no object in view) of those terms. */
        double logLik = 0;
    };

    /** `map` is the filter's map (usually a CMultiMetricMap); it must outlive this object. */
    explicit SensoryFrameLikelihood(const mrpt::maps::CMetricMap& map);
    ~SensoryFrameLikelihood();

    /** Does the one-off work of the first multi-threaded evaluate() now (fills the
     *  likelihood-field caches of the occupancy grids), e.g. before timing starts. Throws
     *  semloc::Interrupted at an interrupt request (semloc/io/Interrupt.h); a later call goes on
     *  filling the caches. */
    void prepare(const ParallelExecutor& executor);

    /** out[i] = log p(sf | poses[i]) for i in [0, n), on the executor's threads. */
    void evaluate(const mrpt::obs::CSensoryFrame& sf, const mrpt::math::TPose2D* poses, size_t n,
                  double* out, ParallelExecutor& executor);

    /** @name evaluate() in steps, for a caller that computes the poses in its own parallel
     *  section: plan(sf), preEvaluate(all poses) unless plan() returned true, then
     *  evaluateChunk() on any partition of the poses, from any threads, and addNonfinite()
     *  with the sum of what the chunks returned.
     *  @{ */
    /** Plans the frame's terms and counts its statistics. True when every term is evaluated
     *  chunk by chunk (no generic MRPT map): preEvaluate() is then not needed. */
    bool plan(const mrpt::obs::CSensoryFrame& sf, ParallelExecutor& executor);
    /** The terms that need every pose before any chunk (generic maps). */
    void preEvaluate(const mrpt::math::TPose2D* poses, size_t n);
    /** out[i] = log p(sf | poses[i]) for i in [b, e) (a non-finite value becomes -inf); the
     *  number of non-finite values. Between beginUpdate() and endUpdate(), the frame's
     *  outage terms enter as the outage mixture. Safe from several threads on disjoint
     *  chunks. */
    size_t evaluateChunk(const mrpt::math::TPose2D* poses, size_t b, size_t e, double* out) const;
    /** Counts non-finite evaluations (TStats::nonfinite_likelihoods). */
    void addNonfinite(size_t count) { m_stats.nonfinite_likelihoods += count; }
    /** @} */

    /** True when the frame of the last plan() holds an observation some map scores: a frame
     *  without (odometry only, or only observations no map understands) measures nothing. */
    bool measures() const { return !m_terms.empty(); }

    /** The outage terms of the frame of the last plan(). */
    const TOutageTerms& outageTerms() const { return m_outage; }

    /** @name The sensor models' state from frame to frame: the detector's outages, the
     *  models' memories
     *  A filter that weighs its particles by the planned frame calls beginUpdate() before
     *  the chunks and endUpdate() with the particles' updated log-weights after: the
     *  probability that the detector is out (outageTerms(); one detector for the filter) is
     *  carried to the frame's time, a silent frame is scored as the mixture
     *  pi + (1 - pi) p(z | x) (detail::DetectorOutage), and the probability's posterior is
     *  taken from the weights. evaluate() leaves the state alone.
     *  @{ */
    /** Starts weighing `particles` particles by the planned frame. Throws for a frame with
     *  outage terms and no timestamp. With `odometry` (the vehicle's pose by its odometry at
     *  the frame, any fixed origin), each term its model's plan says `remembered` is
     *  remembered by the model's Memory (one per model, made at its first such term) and
     *  scored by BatchLikelihood::logLikelihoodsRemembering() (the semantic map's look-alike
     *  persistence); withoutObjects() then includes what the memories add. */
    void beginUpdate(size_t particles, const mrpt::math::TPose2D* odometry = nullptr);
    /** True when endUpdate() needs the weights (the frame was scored with the outage
     *  mixture). */
    bool updatesState() const { return m_outageMixed; }
    /** Ends the weighing: the outage probability's posterior from the first n particles'
     *  updated log-weights (only read when updatesState(); particles weighed beyond them, a
     *  filter's challengers, do not inform it). */
    void endUpdate(const double* logWeights, size_t n);
    /** The probability that the detector is out after the last frame (0 before any frame
     *  with outage terms). */
    double detectorOutageProbability() const;
    /** Forgets the state (a new run): the outage probability and the models' memories. */
    void resetState();
    /** @} */

    /** The model terms of the frame of the last plan() with nothing of the maps in view. */
    const TWithoutObjects& withoutObjects() const { return m_withoutObjects; }

    /** Counters accumulated over every evaluate() call. */
    const TStats& stats() const { return m_stats; }

private:
    enum class Path
    {
        Zero,
        /** A BatchLikelihood map, or a map its kind evaluates by one. */
        Model,
        GenericParallel,
        GenericSerial
    };
    struct Term
    {
        const mrpt::obs::CObservation* obs = nullptr;
        const mrpt::maps::CMetricMap* map = nullptr;
        /** The map's BatchLikelihood (Path::Model): itself, or its kind's batch. */
        const BatchLikelihood* model = nullptr;
        Path path = Path::Zero;
        /** The model's prepareObservation() (Path::Model), or nullptr. */
        std::shared_ptr<const BatchLikelihood::Prepared> prepared;
        /** Index into m_serial for GenericSerial. */
        size_t serialIndex = 0;
        /** First term of a new observation (the per-observation sum restarts). */
        bool firstOfObservation = false;
        /** One of outageTerms(). */
        bool outage = false;
        /** Its model's Memory remembers it (TObservationPlan::remembered). */
        bool remembered = false;
        /** Index into m_contexts of its Memory's context (remembered by beginUpdate()), or
         *  -1. */
        int context = -1;
    };

    /** The path of `obs` against `map`, whose BatchLikelihood is `model` (or nullptr). */
    Path choosePath(const mrpt::obs::CObservation& obs, const mrpt::maps::CMetricMap& map,
                    const BatchLikelihood* model) const;
    /** term[0..m) = term `t` at poses[b..b+m). */
    void evaluateTerm(const Term& t, const mrpt::math::TPose2D* poses, size_t b, size_t m,
                      double* term) const;
    /** Adds a model term of `obs` planned as `plan` to m_outage if it is an outage term;
     *  true if so. */
    bool planOutage(const BatchLikelihood::TObservationPlan& plan,
                    const mrpt::obs::CObservation& obs);
    void prepareGridCaches();
    /** beginUpdate(): the remembered terms noted by their models' memories, their
     *  contexts set. */
    void remember(const mrpt::math::TPose2D& odometry);

    std::vector<const mrpt::maps::CMetricMap*> m_maps;
    /** Each map's BatchLikelihood (itself, its kind's batch, or nullptr), and whether it is
     *  its kind's batch (owned in m_adapters). */
    std::vector<const BatchLikelihood*> m_models;
    std::vector<bool> m_adapted;
    std::vector<std::unique_ptr<BatchLikelihood>> m_adapters;
    bool m_enabled = true;
    bool m_gridCachesReady = false;
    std::vector<Term> m_terms;
    /** Terms of the GenericSerial path in m_terms. */
    size_t m_nSerial = 0;
    TOutageTerms m_outage;
    /** The detector's outage state, and whether this frame is scored with its mixture (the
     *  outage terms per particle, then log P(out | z, x_i), in m_outageLik). */
    std::unique_ptr<detail::DetectorOutage> m_detectorOutage;
    bool m_outageMixed = false;
    std::vector<double> m_outageLik;
    double* m_outageOut = nullptr;  ///< m_outageLik's values, written by evaluateChunk()
    TWithoutObjects m_withoutObjects;
    /** The memory of each model that remembers (nullptr: it keeps none). */
    std::vector<std::pair<const BatchLikelihood*, std::unique_ptr<BatchLikelihood::Memory>>>
        m_memories;
    /** The planned frame's memory contexts, one per remembered term. */
    std::vector<std::vector<double>> m_contexts;
    std::vector<std::vector<double>> m_serial;
    TStats m_stats;
};

}  // namespace semloc

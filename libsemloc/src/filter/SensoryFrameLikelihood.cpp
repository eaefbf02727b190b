/* semloc — SensoryFrameLikelihood: MRPT's per-particle observation likelihood, per chunk. */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/SensoryFrameLikelihood.h>
#include <semloc/io/Interrupt.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/models/SensorModelRegistry.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <typeinfo>

#include "filter/DetectorOutage.h"

namespace semloc
{
using mrpt::maps::COccupancyGridMap2D;
using mrpt::math::TPose2D;

namespace
{
/** Cells of the likelihood-field cache filled between two looks at interruptRequested(). */
constexpr unsigned kGridCacheBandCells = 1u << 18;

/** The pose MRPT hands to CMetricMap::computeObservationLikelihood for a 2D particle. */
mrpt::poses::CPose3D mrptPose(const TPose2D& p)
{
    return mrpt::poses::CPose3D(mrpt::math::TPose3D(p));
}

/** out[i] += v[i] for one observation's log-likelihoods; the first observation's sum starts
 *  from 1 as MRPT's CMonteCarloLocalization2D does (1 + v is 1, then += v, bit for bit), the
 *  last one's maps non-finite sums to -inf and counts them. */
template <bool First, bool Last>
size_t addObservationAs(double* out, const double* v, size_t m)
{
    size_t nonfinite = 0;
    for (size_t i = 0; i < m; i++)
    {
        double o = (First ? 1.0 : out[i]) + v[i];
        if constexpr (Last)
        {
            if (!std::isfinite(o))
            {
                o = -std::numeric_limits<double>::infinity();
                nonfinite++;
            }
        }
        out[i] = o;
    }
    return nonfinite;
}

size_t addObservation(double* out, const double* v, size_t m, bool first, bool last)
{
    if (first)
    {
        return last ? addObservationAs<true, true>(out, v, m)
                    : addObservationAs<true, false>(out, v, m);
    }
    return last ? addObservationAs<false, true>(out, v, m)
                : addObservationAs<false, false>(out, v, m);
}

bool isThreadSafeGrid(const COccupancyGridMap2D& g)
{
    // These two methods only read the grid (the likelihood field through its cache, filled
    // in advance by prepareGridCaches); the others write mutable members on every call.
    const auto m = g.likelihoodOptions.likelihoodMethod;
    return m == COccupancyGridMap2D::lmRayTracing ||
           m == COccupancyGridMap2D::lmLikelihoodField_Thrun;
}
}  // namespace

SensoryFrameLikelihood::SensoryFrameLikelihood(const mrpt::maps::CMetricMap& map)
    : m_detectorOutage(std::make_unique<detail::DetectorOutage>())
{
    if (const auto* mm = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(&map))
    {
        m_enabled = mm->genericMapParams.enableObservationLikelihood;
        for (const auto& m : mm->maps)
        {
            m_maps.push_back(m.get());
        }
    }
    else
    {
        m_maps.push_back(&map);
    }
    // Each map's sensor model: the map itself, or what its kind evaluates it by in blocks
    // (MRPT's CBeaconMap), else none (MRPT's generic call).
    for (const auto* m : m_maps)
    {
        const auto* model = dynamic_cast<const BatchLikelihood*>(m);
        if (!model)
        {
            if (const auto* kind = SensorModelRegistry::of(*m))
            {
                if (auto batch = kind->batchOf(*m))
                {
                    model = batch.get();
                    m_adapters.push_back(std::move(batch));
                }
            }
            m_adapted.push_back(model != nullptr);
        }
        else
        {
            m_adapted.push_back(false);
        }
        m_models.push_back(model);
    }
}

SensoryFrameLikelihood::~SensoryFrameLikelihood() = default;

SensoryFrameLikelihood::Path SensoryFrameLikelihood::choosePath(const mrpt::obs::CObservation& obs,
                                                                const mrpt::maps::CMetricMap& map,
                                                                const BatchLikelihood* model) const
{
    if (!map.genericMapParams.enableObservationLikelihood)
    {
        return Path::Zero;  // CMetricMap::computeObservationLikelihood returns 0
    }
    // A sensor model (semloc's, a program's, or the batch of an MRPT map's kind): its batch.
    if (model)
    {
        return model->uses(obs) ? Path::Model : Path::Zero;
    }
    // MRPT's other maps: the generic call, in parallel where it only reads the map and the
    // observation.
    if (const auto* grid = dynamic_cast<const COccupancyGridMap2D*>(&map);
        grid && isThreadSafeGrid(*grid))
    {
        return Path::GenericParallel;
    }
    return Path::GenericSerial;
}

void SensoryFrameLikelihood::prepareGridCaches()
{
    for (const auto* m : m_maps)
    {
        const auto* g = dynamic_cast<const COccupancyGridMap2D*>(m);
        if (!g ||
            g->likelihoodOptions.likelihoodMethod != COccupancyGridMap2D::lmLikelihoodField_Thrun ||
            !g->likelihoodOptions.enableLikelihoodCache || g->getSizeX() < 2 || g->getSizeY() < 2)
        {
            continue;
        }
        // The likelihood-field cache is filled lazily, cell by cell, by const calls: fill it
        // all now (one point per cell centre, every point used) so that threads only read it.
        // A cell's value depends only on the cell, so the results are those of lazy filling,
        // and filling it in bands of rows is filling it at once: between bands, an interrupt
        // request (Ctrl-C) stops it (a large grid takes many seconds).
        const unsigned rows = g->getSizeY() - 1, cols = g->getSizeX() - 1;
        const unsigned band = std::max(1u, kGridCacheBandCells / cols);
        auto& grid = const_cast<COccupancyGridMap2D&>(*g);  // restored below; same thread
        const auto decimation = grid.likelihoodOptions.LF_decimation;
        grid.likelihoodOptions.LF_decimation = 1;
        mrpt::maps::CSimplePointsMap centres;
        centres.reserve(static_cast<size_t>(std::min(band, rows)) * cols);
        for (unsigned y0 = 0; y0 < rows; y0 += band)
        {
            if (interruptRequested())
            {
                grid.likelihoodOptions.LF_decimation = decimation;
                throw Interrupted();
            }
            centres.clear();
            for (unsigned cy = y0; cy < std::min(rows, y0 + band); cy++)
            {
                for (unsigned cx = 0; cx < cols; cx++)
                {
                    centres.insertPointFast(g->idx2x(cx), g->idx2y(cy), 0);
                }
            }
            grid.computeLikelihoodField_Thrun(&centres, nullptr);
        }
        grid.likelihoodOptions.LF_decimation = decimation;
    }
}

void SensoryFrameLikelihood::prepare(const ParallelExecutor& executor)
{
    if (executor.threads() > 1 && !m_gridCachesReady)
    {
        prepareGridCaches();
        m_gridCachesReady = true;
    }
}

bool SensoryFrameLikelihood::plan(const mrpt::obs::CSensoryFrame& sf, ParallelExecutor& executor)
{
    // One term per (observation, map) pair that can contribute, in MRPT's order.
    m_terms.clear();
    m_nSerial = 0;
    m_outage = TOutageTerms();
    m_outageMixed = false;
    m_withoutObjects = TWithoutObjects();
    bool anyParallelGeneric = false;
    for (const auto& o : sf)
    {
        if (!o)
        {
            continue;
        }
        bool usable = false, first = true, checked = false;
        for (size_t k = 0; k < m_maps.size(); k++)
        {
            const auto* map = m_maps[k];
            const auto* model = m_models[k];
            // An MRPT map evaluated by its kind's batch scores what the batch uses (CBeaconMap
            // says it can score any observation, and adds 0 for any but beacon ranges).
            usable = usable ||
                     (m_adapted[k] ? model->uses(*o) : map->canComputeObservationLikelihood(*o));
            const Path path = m_enabled ? choosePath(*o, *map, model) : Path::Zero;
            if (path == Path::Zero)
            {
                continue;
            }
            Term t;
            t.obs = o.get();
            t.map = map;
            t.model = model;
            t.path = path;
            t.firstOfObservation = first;
            first = false;
            if (path == Path::GenericSerial)
            {
                t.serialIndex = m_nSerial++;
            }
            anyParallelGeneric = anyParallelGeneric || path == Path::GenericParallel;
            if (path == Path::Model)
            {
                const auto plan = t.model->plan(*o);
                if (plan.checked && !checked)
                {
                    checked = true;
                    m_stats.detections_invalid += plan.invalid;
                    m_stats.detections_unknown += plan.unknown;
                }
                t.remembered = plan.remembered;
                t.outage = planOutage(plan, *o);
                m_withoutObjects.logLik += plan.logLikWithoutMap;
                m_withoutObjects.detections += plan.readingsWithoutMap;
                if (!t.remembered)
                {
                    t.prepared = t.model->prepareObservation(*o);
                }
            }
            m_terms.push_back(t);
        }
        (usable ? m_stats.observations_used : m_stats.observations_skipped)++;
    }

    if (anyParallelGeneric)
    {
        prepare(executor);
    }
    return m_nSerial == 0 && !anyParallelGeneric;
}

bool SensoryFrameLikelihood::planOutage(const BatchLikelihood::TObservationPlan& plan,
                                        const mrpt::obs::CObservation& obs)
{
    if (!(plan.outage_every_s > 0))
    {
        return false;
    }
    m_outage.silent = m_outage.silent && plan.silent;
    if (!m_outage.present)
    {
        m_outage.present = true;
        m_outage.t = obs.timestamp;
        m_outage.every_s = plan.outage_every_s;
        m_outage.mean_s = plan.outage_mean_s;
    }
    return true;
}

void SensoryFrameLikelihood::preEvaluate(const TPose2D* poses, size_t n)
{
    // Terms no thread may share: every pose, here, before the parallel section.
    m_serial.resize(std::max(m_serial.size(), m_nSerial));
    for (const auto& t : m_terms)
    {
        if (t.path == Path::GenericSerial)
        {
            auto& v = m_serial[t.serialIndex];
            v.resize(n);
            for (size_t i = 0; i < n; i++)
            {
                v[i] = t.map->computeObservationLikelihood(*t.obs, mrptPose(poses[i]));
            }
        }
        else if (t.path == Path::GenericParallel && n > 0)
        {
            // Builds the observation's lazy caches (e.g. the scan's points map) on this thread.
            (void)t.map->computeObservationLikelihood(*t.obs, mrptPose(poses[0]));
        }
    }
}

void SensoryFrameLikelihood::evaluateTerm(const Term& t, const TPose2D* poses, size_t b, size_t m,
                                          double* term) const
{
    switch (t.path)
    {
        case Path::Model:
            if (t.prepared)
            {
                t.prepared->logLikelihoods(poses + b, m, term);
                break;
            }
            if (t.context >= 0)
            {
                t.model->logLikelihoodsRemembering(
                    *t.obs, m_contexts[static_cast<size_t>(t.context)], poses + b, m, term);
                break;
            }
            t.model->logLikelihoods(*t.obs, poses + b, m, term);
            break;
        case Path::GenericParallel:
            for (size_t i = 0; i < m; i++)
            {
                term[i] = t.map->computeObservationLikelihood(*t.obs, mrptPose(poses[b + i]));
            }
            break;
        case Path::GenericSerial:
            std::copy_n(m_serial[t.serialIndex].begin() + static_cast<ptrdiff_t>(b), m, term);
            break;
        case Path::Zero:
            std::fill_n(term, m, 0.0);
            break;
    }
}

size_t SensoryFrameLikelihood::evaluateChunk(const TPose2D* poses, size_t b, size_t e,
                                             double* out) const
{
    // The outage terms' sum per particle (written on disjoint chunks by the threads).
    double* outageOut = m_outageMixed ? m_outageOut : nullptr;
    const size_t m = e - b;
    // Per-thread scratch, grown only (no allocation or clearing per chunk).
    thread_local std::vector<double> obsScratch, termScratch;
    if (termScratch.size() < m)
    {
        obsScratch.resize(m);
        termScratch.resize(m);
    }
    double* obsSum = obsScratch.data();
    double* term = termScratch.data();
    if (m_terms.empty())
    {
        std::fill_n(out + b, m, 1.0);  // MRPT's CMonteCarloLocalization2D starts the sum at 1
        return 0;
    }
    bool firstSum = true;
    size_t nonfinite = 0;
    if (outageOut)
    {
        std::fill_n(outageOut + b, m, 0.0);
    }
    for (size_t k = 0; k < m_terms.size(); k++)
    {
        const Term& t = m_terms[k];
        const bool lastOfObservation = k + 1 == m_terms.size() || m_terms[k + 1].firstOfObservation;
        evaluateTerm(t, poses, b, m, term);
        if (outageOut && t.outage)
        {
            for (size_t i = 0; i < m; i++)
            {
                outageOut[b + i] += term[i];
            }
        }
        if (t.firstOfObservation && lastOfObservation)
        {
            // The observation's only term: out + (0 + term) is out + term, bit for bit (0 + term
            // only turns -0 into +0, which adds the same to out, never -0 as a sum from 1).
            nonfinite += addObservation(out + b, term, m, firstSum, k + 1 == m_terms.size());
            firstSum = false;
            continue;
        }
        for (size_t i = 0; i < m; i++)
        {
            obsSum[i] = (t.firstOfObservation ? 0.0 : obsSum[i]) + term[i];
        }
        if (lastOfObservation)
        {
            nonfinite += addObservation(out + b, obsSum, m, firstSum, k + 1 == m_terms.size());
            firstSum = false;
        }
    }
    if (outageOut)
    {
        detail::DetectorOutage::apply(*m_detectorOutage->mix(), out + b, outageOut + b, m);
    }
    return nonfinite;
}

void SensoryFrameLikelihood::remember(const TPose2D& odometry)
{
    size_t used = 0;
    for (Term& t : m_terms)
    {
        if (!t.remembered)
        {
            continue;
        }
        auto it = std::find_if(m_memories.begin(), m_memories.end(),
                               [&](const auto& m) { return m.first == t.model; });
        if (it == m_memories.end())
        {
            it = m_memories.emplace(m_memories.end(), t.model, t.model->newMemory());
        }
        if (!it->second)
        {
            continue;  // the model said it remembers, and keeps no memory
        }
        if (m_contexts.size() <= used)
        {
            m_contexts.resize(used + 1);
        }
        it->second->remember(*t.obs, odometry, m_contexts[used], m_withoutObjects.logLik);
        t.context = static_cast<int>(used++);
    }
}

void SensoryFrameLikelihood::beginUpdate(size_t particles, const TPose2D* odometry)
{
    if (odometry)
    {
        remember(*odometry);
    }
    m_outageMixed = false;
    if (!m_outage.present)
    {
        return;
    }
    m_outageMixed = m_detectorOutage->predict(m_outage);
    m_outageLik.resize(m_outageMixed ? particles : 0);
    m_outageOut = m_outageLik.data();
}

void SensoryFrameLikelihood::endUpdate(const double* logWeights, size_t n)
{
    if (m_outageMixed)
    {
        ASSERT_LE_(n, m_outageLik.size());
        m_detectorOutage->update(logWeights, m_outageLik.data(), n);
    }
    m_outageMixed = false;
}

double SensoryFrameLikelihood::detectorOutageProbability() const
{
    return m_detectorOutage->probability();
}

void SensoryFrameLikelihood::resetState()
{
    m_detectorOutage->reset();
    m_outageMixed = false;
    m_memories.clear();
}

void SensoryFrameLikelihood::evaluate(const mrpt::obs::CSensoryFrame& sf, const TPose2D* poses,
                                      size_t n, double* out, ParallelExecutor& executor)
{
    plan(sf, executor);
    preEvaluate(poses, n);
    std::atomic<size_t> nonfinite{0};
    executor.forEachRange(
        n,
        [&](size_t b, size_t e, size_t)
        { nonfinite.fetch_add(evaluateChunk(poses, b, e, out), std::memory_order_relaxed); },
        256);  // below a few hundred poses one thread is faster than waking another
    addNonfinite(nonfinite.load());
}

}  // namespace semloc

/* semloc — LocalizationExperiment's run: the rawlog fed to the Localizer step by step, the
 * ground truth matched to the steps, the outputs written. The configuration and the checks
 * before the run are in LocalizationConfig.cpp. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/StagedDirectory.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <utility>

#include "experiment/DetectionsCsv.h"
#include "experiment/LocalizationConfig.h"
#include "experiment/LocalizationOutputs.h"
#include "experiment/RunDetectorBound.h"
#include "experiment/StepTimes.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
using detail::writeFile;

/** Feeds a rawlog's entries to a Localizer step by step, as pf-localization groups them:
 *  action / sensory-frame pairs, or (observations-only rawlogs) CObservationOdometry readings
 *  for the motion and consecutive observations with one timestamp as one frame. */
class RawlogPlayback
{
public:
    /** What is called after each step run: its record (which the callee may complete: its
     *  ground truth) and the frame it weighed. */
    using OnStep = std::function<void(TStepRecord&, const mrpt::obs::CSensoryFrame&)>;
    /** `skip` steps skipped first (rawlog_offset); `onStep` is called after each step run. */
    RawlogPlayback(Localizer& loc, size_t skip, OnStep onStep)
        : m_loc(loc), m_skip(skip), m_onStep(std::move(onStep))
    {
    }

    /** The rawlog's next entry. */
    void entry(const mrpt::serialization::CSerializable::Ptr& obj);
    /** After the last entry: the frame still grouped. */
    void finish() { flush(); }
    /** "action/sensory-frame", "observations-only" or "mixed". */
    std::string format() const
    {
        return m_sawPairs && m_sawObservations ? "mixed"
               : m_sawObservations             ? "observations-only"
                                               : "action/sensory-frame";
    }

private:
    /** The record of the step just run on `sf`, timed by its first observation, else by the
     *  step's `action` (a frame without observations: an odometry-only step). */
    void record(const mrpt::obs::CSensoryFrame& sf,
                const mrpt::obs::CActionCollection* action = nullptr)
    {
        TStepRecord r = m_loc.lastStepRecord(sf);
        r.step = m_steps++;
        if (std::isnan(r.t) && action)
        {
            r.t = detail::actionTime(*action);
        }
        m_onStep(r, sf);
    }
    /** The observations grouped so far as one step (or one skipped). */
    void flush();
    void sensoryFrame(const mrpt::obs::CSensoryFrame& sf);
    void observation(const mrpt::obs::CObservation::Ptr& obs);

    Localizer& m_loc;
    size_t m_steps = 0;
    // pf-localization's rawlog_offset skips steps (pairs, or observations), not entries. An
    // odometry reading met while skipping is handed over when the first step runs, so that
    // step moves by zero and the next by the increment since it.
    size_t m_skip;
    std::optional<mrpt::obs::CObservationOdometry> m_heldOdometry;
    // Observations-only rawlogs: consecutive observations with one timestamp are one frame.
    mrpt::obs::CSensoryFrame m_group;
    bool m_sawPairs = false, m_sawObservations = false;
    mrpt::obs::CActionCollection::Ptr m_action;
    OnStep m_onStep;
};

void RawlogPlayback::flush()
{
    if (m_group.size() == 0)
    {
        return;
    }
    if (m_skip > 0)
    {
        m_skip--;
    }
    else
    {
        if (m_heldOdometry)
        {
            m_loc.setOdometry(*m_heldOdometry);
            m_heldOdometry.reset();
        }
        m_loc.step(m_group);
        record(m_group);
    }
    m_group.clear();
}

void RawlogPlayback::entry(const mrpt::serialization::CSerializable::Ptr& obj)
{
    if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
    {
        flush();
        m_action = std::move(acts);
    }
    else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
    {
        flush();
        sensoryFrame(*sf);
    }
    else if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
    {
        m_sawObservations = true;
        observation(obs);
    }
}

void RawlogPlayback::sensoryFrame(const mrpt::obs::CSensoryFrame& sf)
{
    if (m_skip > 0)
    {
        m_skip--;
    }
    else
    {
        if (m_action)
        {
            m_loc.step(*m_action, sf);
            m_sawPairs = true;
        }
        else
        {
            m_loc.step(sf);  // a frame without its action: the odometry since the last
        }
        record(sf, m_action.get());
    }
    m_action.reset();
}

void RawlogPlayback::observation(const mrpt::obs::CObservation::Ptr& obs)
{
    if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
    {
        flush();
        if (m_skip > 0)
        {
            m_heldOdometry = *odo;
        }
        else
        {
            m_heldOdometry.reset();
            m_loc.setOdometry(*odo);
        }
    }
    else if (obs)
    {
        if (m_group.size() > 0 && m_group.getObservationByIndex(0)->timestamp != obs->timestamp)
        {
            flush();
        }
        m_group.insert(obs);
    }
}

/** Where each step's record goes as it is run: its ground truth matched, then steps.csv, the
 *  metrics, the detector's bound, particles.csv and (Records::Keep) the kept records. */
struct StepSinks
{
    StepSinks(const StagedDirectory& out, const LocalizationExperiment::TOptions& o,
              const LocalizationMap& maps, const GroundTruth& gt, double gtTolerance,
              LocalizationExperiment::Records keep, std::vector<TStepRecord>& kept)
        : steps(out.path("steps.csv")),
          metrics(o.convergence),
          bound(maps, o.filter),
          m_gt(gt),
          m_gtTolerance(gtTolerance),
          m_keep(keep == LocalizationExperiment::Records::Keep),
          m_kept(kept)
    {
        if (o.particles_save_every > 0)
        {
            particles.emplace(out.path("particles.csv"), o.particles_save_every);
        }
        if (o.detections_trace)
        {
            // A semantic map is there: FromConfigFile refuses the trace without one.
            detections.emplace(out.path("detections.csv"), *maps.map->mapByClass<CSemanticMap>());
        }
    }
    void add(TStepRecord& r, const Localizer& loc, const mrpt::obs::CSensoryFrame& sf)
    {
        if (const auto* row = m_gt.nearest(r.t, m_gtTolerance))
        {
            r.gt = row->pose();
        }
        steps.add(r);
        metrics.add(r);
        if (bound.active())
        {
            bound.add(r, sf, loc.lastMovement(), metrics.result());
        }
        if (particles)
        {
            particles->step(r, loc.pdf());
        }
        if (detections)
        {
            detections->add(r, sf);
        }
        if (m_keep)
        {
            m_kept.push_back(r);
        }
        last = r;
    }
    /** After the last step: the files closed (the last cloud written). */
    void finish(const Localizer& loc)
    {
        if (particles && last)
        {
            particles->finish(*last, loc.pdf());
        }
        steps.finish();
        if (detections)
        {
            detections->finish();
        }
    }

    detail::StepsCsv steps;
    RunMetricsAccumulator metrics;
    detail::RunDetectorBound bound;
    std::optional<detail::ParticlesCsv> particles;
    std::optional<detail::DetectionsCsv> detections;
    std::optional<TStepRecord> last;

private:
    const GroundTruth& m_gt;
    double m_gtTolerance;
    bool m_keep;
    std::vector<TStepRecord>& m_kept;
};

/** Reads the `entries` intact entries of the rawlog at `path` again, one at a time, into
 *  `playback`; throws Interrupted at a request, and when the file changed since it was
 *  checked. */
void replay(const std::string& path, size_t entries, RawlogPlayback& playback,
            const std::function<void(size_t, size_t)>& progress)
{
    RawlogReader reader(path);
    for (size_t i = 0; i < entries; i++)
    {
        if (interruptRequested())
        {
            throw Interrupted();  // Ctrl-C (installInterruptHandlers): no output directory
        }
        const auto obj = reader.next();
        if (!obj)
        {
            THROW_EXCEPTION(
                mrpt::format("rawlog '%s' changed during the run: entry %zu of the "
                             "%zu read before it is missing now",
                             path.c_str(), i, entries));
        }
        playback.entry(obj);
        if (progress)
        {
            progress(i + 1, entries);
        }
    }
}
}  // namespace

LocalizationExperiment::TResult LocalizationExperiment::run(
    const std::function<void(size_t, size_t)>& progress, Records records) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;
    // Created first: an output location that cannot be written fails before the run.
    StagedDirectory out(o.logOutput_dir, inputFiles());

    Localizer loc(o.filter, m_maps.map, m_maps.world ? &*m_maps.world : nullptr);
    TResult res;
    res.variant = o.variant;
    res.threads = loc.threads();

    // Each step's record goes to steps.csv, the metrics and particles.csv as it comes: memory
    // does not grow with the rawlog's length (unless the records are kept).
    StepSinks sinks(out, o, m_maps, m_groundTruth, m_gtTolerance, records, res.records);
    RawlogPlayback playback(loc, static_cast<size_t>(o.rawlog_offset),
                            [&](TStepRecord& r, const mrpt::obs::CSensoryFrame& sf)
                            { sinks.add(r, loc, sf); });
    replay(o.rawlog_file, m_entries, playback, progress);
    playback.finish();
    sinks.finish(loc);
    res.rawlogTruncatedAtEntry = m_truncatedAt;
    res.rawlogFormat = playback.format();
    res.final_particles = sinks.last ? sinks.last->n_particles : 0;

    res.metrics = sinks.metrics.result();
    res.detector_bound_mean_m = sinks.bound.mean();
    res.detector_bound_after_conv_m = sinks.bound.meanAfterConvergence(res.metrics);
    res.likelihood = loc.likelihoodStats();
    res.recovery = loc.recoveryStats();
    res.initialized_from_detections = loc.initializedFromDetections();
    res.heading_drift_deg_per_min = loc.headingDriftDegPerMin();

    res.outputDir = out.target();
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    writeFile(out.path("summary.yaml"), detail::summaryYaml(res, o));
    writeFile(out.path("config.ini"), detail::effectiveConfigText(o, m_carried, m_maps, *m_ini));
    if (interruptRequested())
    {
        throw Interrupted();  // the staging directory goes, a previous output stays
    }
    out.commit();
    return res;
}

std::string LocalizationExperiment::TResult::summaryParagraph() const
{
    const auto& m = metrics;
    std::string s = mrpt::format(
        "%s: %zu steps with %zu particles on %zu thread%s, %.2f s of "
        "filter updates (%.3f us per particle).",
        variant.c_str(), m.steps, final_particles, threads, threads == 1 ? "" : "s",
        m.total_update_s, m.mean_update_us_per_particle);
    if (m.steps_with_ground_truth == 0)
    {
        s += " No ground truth: errors unknown.";
    }
    else if (m.converged)
    {
        s += mrpt::format(
            " Converged at step %ld (%.1f s); mean error after convergence %.3f m, RMSE %.3f m, "
            "final error %.3f m.",
            m.convergence_step, m.convergence_time_s, m.mean_err_after_conv_m, m.rmse_m,
            m.final_err_m);
    }
    else
    {
        s += mrpt::format(" Did not converge; RMSE %.3f m, final error %.3f m.", m.rmse_m,
                          m.final_err_m);
    }
    if (recovery.reinitializations > 0)
    {
        s += mrpt::format(" Re-initialized %zu time(s) after every weight vanished.",
                          recovery.reinitializations);
    }
    if (recovery.injected_particles > 0)
    {
        s += mrpt::format(" Recovery injected %zu particles (%zu from detections) in %zu steps.",
                          recovery.injected_particles, recovery.injected_from_detections,
                          recovery.injection_steps);
    }
    if (likelihood.observations_skipped > 0)
    {
        s += mrpt::format(" %zu observations were ignored: no map in [MetricMap] uses them.",
                          likelihood.observations_skipped);
    }
    return s + " Outputs in " + outputDir + ".";
}

}  // namespace semloc

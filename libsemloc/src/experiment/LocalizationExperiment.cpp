/* semloc — LocalizationExperiment's run: the rawlog fed to the Localizer step by step, the
 * ground truth matched to the steps, the outputs written. The configuration and the checks
 * before the run are in LocalizationConfig.cpp. */
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/StagedDirectory.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <utility>

#include "experiment/LocalizationConfig.h"
#include "experiment/LocalizationOutputs.h"
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
    /** `skip` steps skipped first (rawlog_offset); each step run appends its record. */
    RawlogPlayback(Localizer& loc, size_t skip, std::vector<TStepRecord>& records)
        : m_loc(loc), m_records(records), m_skip(skip)
    {
    }

    /** Entry `i` of `rawlog`. */
    void entry(const mrpt::obs::CRawlog& rawlog, size_t i);
    /** Called after each step run with its record. */
    void onStep(std::function<void(const TStepRecord&)> f) { m_onStep = std::move(f); }
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
        r.step = m_records.size();
        if (std::isnan(r.t) && action)
        {
            r.t = detail::actionTime(*action);
        }
        m_records.push_back(r);
        if (m_onStep)
        {
            m_onStep(m_records.back());
        }
    }
    /** The observations grouped so far as one step (or one skipped). */
    void flush();
    void sensoryFrame(const mrpt::obs::CSensoryFrame& sf);
    void observation(const mrpt::obs::CObservation::Ptr& obs);

    Localizer& m_loc;
    std::vector<TStepRecord>& m_records;
    // pf-localization's rawlog_offset skips steps (pairs, or observations), not entries. An
    // odometry reading met while skipping is handed over when the first step runs, so that
    // step moves by zero and the next by the increment since it.
    size_t m_skip;
    std::optional<mrpt::obs::CObservationOdometry> m_heldOdometry;
    // Observations-only rawlogs: consecutive observations with one timestamp are one frame.
    mrpt::obs::CSensoryFrame m_group;
    bool m_sawPairs = false, m_sawObservations = false;
    mrpt::obs::CActionCollection::Ptr m_action;
    std::function<void(const TStepRecord&)> m_onStep;
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

void RawlogPlayback::entry(const mrpt::obs::CRawlog& rawlog, size_t i)
{
    switch (rawlog.getType(i))
    {
        case mrpt::obs::CRawlog::etActionCollection:
            flush();
            m_action = rawlog.getAsAction(i);
            break;
        case mrpt::obs::CRawlog::etSensoryFrame:
            flush();
            sensoryFrame(*rawlog.getAsObservations(i));
            break;
        case mrpt::obs::CRawlog::etObservation:
            m_sawObservations = true;
            observation(rawlog.getAsObservation(i));
            break;
        default:
            break;
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

/** Ground truth by timestamp: each record gets the nearest row within half a step. */
void matchRecords(std::vector<TStepRecord>& records, const GroundTruth& gt)
{
    if (gt.empty())
    {
        return;
    }
    std::vector<double> times;
    times.reserve(records.size());
    for (const auto& r : records)
    {
        times.push_back(r.t);
    }
    const auto rows = detail::matchGroundTruth(gt, times);
    for (size_t k = 0; k < rows.size(); k++)
    {
        if (rows[k])
        {
            records[k].gt = rows[k]->pose();
        }
    }
}
}  // namespace

LocalizationExperiment::TResult LocalizationExperiment::run(
    const std::function<void(size_t, size_t)>& progress) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;
    // Created first: an output location that cannot be written fails before the run.
    StagedDirectory out(o.logOutput_dir, inputFiles());

    Localizer loc(o.filter, m_maps.map, m_maps.world ? &*m_maps.world : nullptr);
    TResult res;
    res.variant = o.variant;
    res.threads = loc.threads();

    RawlogPlayback playback(loc, static_cast<size_t>(o.rawlog_offset), res.records);
    std::optional<detail::ParticlesCsv> particles;
    if (o.particles_save_every > 0)
    {
        particles.emplace(out.path("particles.csv"), o.particles_save_every);
        playback.onStep([&](const TStepRecord& r) { particles->step(r, loc.pdf()); });
    }
    const size_t n = m_rawlog.size();
    for (size_t i = 0; i < n; i++)
    {
        if (interruptRequested())
        {
            throw Interrupted();  // Ctrl-C (installInterruptHandlers): no output directory
        }
        playback.entry(m_rawlog, i);
        if (progress)
        {
            progress(i + 1, n);
        }
    }
    playback.finish();
    if (particles && !res.records.empty())
    {
        particles->finish(res.records.back(), loc.pdf());
    }
    res.rawlogTruncatedAtEntry = m_truncatedAt;
    res.rawlogFormat = playback.format();
    matchRecords(res.records, m_groundTruth);

    res.metrics = RunMetrics::compute(res.records, o.convergence);
    res.likelihood = loc.likelihoodStats();
    res.recovery = loc.recoveryStats();
    res.initialized_from_detections = loc.initializedFromDetections();
    res.heading_drift_deg_per_min = loc.headingDriftDegPerMin();

    res.outputDir = out.target();
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    writeFile(out.path("steps.csv"), detail::stepsCsv(res.records));
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
        variant.c_str(), m.steps, records.empty() ? size_t(0) : records.front().n_particles,
        threads, threads == 1 ? "" : "s", m.total_update_s, m.mean_update_us_per_particle);
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

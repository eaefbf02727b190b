/* semloc — Benchmark: R seeds × variants of simulate + localize, aggregated (paper §IV). The
 * configuration is in BenchmarkConfig.cpp, the child processes in BenchmarkRunPool.cpp, the
 * tables in BenchmarkTables.cpp and the report in BenchmarkReport.cpp. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/GroundTruth.h>
#include <semloc/filter/Localizer.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <sstream>

#include "experiment/BenchmarkReport.h"
#include "experiment/BenchmarkRunPool.h"
#include "experiment/BenchmarkTables.h"
#include "experiment/ClosedLoop.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
using detail::writeFile;

/** Benchmark::SetStageReporter()'s. */
std::function<void(const std::string&)>& stageReporter()
{
    static std::function<void(const std::string&)> reporter;
    return reporter;
}

/** Benchmark::SetWarningReporter()'s. */
std::function<void(const std::string&)>& warningReporter()
{
    static std::function<void(const std::string&)> reporter;
    return reporter;
}

/** The results of runs 1..runs read back from their run files (`pathOf(run)`; detail::
 *  readRunFile(), `inputs` the benchmark's digest), in run-major order, each with its scenario
 *  name, its metrics (its variant's convergence criterion, `kidnapStep`) and its distance to
 *  convergence; each run holds every variant with each of `controls`. */
std::vector<Benchmark::TRunResult> collectRuns(const std::function<std::string(int)>& pathOf,
                                               int runs, const std::string& inputs,
                                               const std::vector<Benchmark::TVariant>& variants,
                                               const std::vector<std::string>& controls,
                                               const std::string& scenario, long kidnapStep)
{
    detail::RunSeries series;
    for (const auto& v : variants)
    {
        for (const auto& c : controls)
        {
            series.emplace_back(v.name(), c);
        }
    }
    std::vector<Benchmark::TRunResult> out;
    for (int run = 1; run <= runs; run++)
    {
        auto rs = detail::readRunFile(pathOf(run), run, inputs, series);
        for (size_t k = 0; k < rs.size(); k++)
        {
            auto& r = rs[k];
            r.scenario = scenario;
            r.metrics = RunMetrics::compute(
                r.records, variants[k / controls.size()].options.convergence, kidnapStep);
            r.distance_to_convergence_m =
                r.metrics.converged ? detail::distanceDriven(r.records, r.metrics.convergence_step)
                                    : std::numeric_limits<double>::quiet_NaN();
            out.push_back(std::move(r));
        }
    }
    return out;
}
}  // namespace

// ------------------------------------------------------------------ one run

namespace
{
/** True when every map of `maps` is a CSemanticMap: a filter of the detections alone, which
 *  the detector's Cramér–Rao bound bounds. */
bool detectionsOnly(const LocalizationMap& maps)
{
    return maps.map && weighsWithoutMaps(*maps.map);
}
}  // namespace

namespace
{
/** The filter's records over the rawlog of a simulated run. */
std::vector<TStepRecord> localizeRoute(Localizer& loc, const SimulationResult& data,
                                       double tolerance)
{
    const GroundTruth gt(data.groundTruth);
    std::vector<TStepRecord> records;
    mrpt::obs::CActionCollection::Ptr action;
    for (size_t i = 0; i < data.rawlog.size(); i++)
    {
        if (data.rawlog.getType(i) == mrpt::obs::CRawlog::etActionCollection)
        {
            action = data.rawlog.getAsAction(i);
            continue;
        }
        if (data.rawlog.getType(i) != mrpt::obs::CRawlog::etSensoryFrame || !action)
        {
            continue;
        }
        const auto sf = data.rawlog.getAsObservations(i);
        loc.step(*action, *sf);
        action.reset();
        TStepRecord s = loc.lastStepRecord(*sf);
        s.step = records.size();
        if (const auto* row = gt.nearest(s.t, tolerance))
        {
            s.gt = row->pose();
        }
        records.push_back(s);
    }
    return records;
}
}  // namespace

std::vector<Benchmark::TRunResult> Benchmark::runOne(int run) const
{
    auto simOptions = m_simulation;
    simOptions.simulation.seed = static_cast<uint32_t>(run);
    const Simulator simulator =
        m_changedWorld ? Simulator(*m_changedWorld, simOptions) : Simulator(simOptions);
    const bool byRoute = std::find(m_options.controls.begin(), m_options.controls.end(), "route") !=
                         m_options.controls.end();
    const SimulationResult data = byRoute ? simulator.run() : SimulationResult();
    // The detector's bound, for the variants of the detections alone (if any).
    const bool anyDetectionsOnly = std::any_of(
        m_variants.begin(), m_variants.end(), [](const auto& v) { return detectionsOnly(v.maps); });
    const auto bound = anyDetectionsOnly && byRoute ? detectorCramerRaoBound(simulator, data)
                                                    : std::vector<TDetectorBoundStep>();
    const double tolerance = 0.5 * simOptions.simulation.time_step_s;

    std::vector<TRunResult> out;
    for (const auto& v : m_variants)
    {
        for (const auto& control : m_options.controls)
        {
            const auto wall0 = std::chrono::steady_clock::now();
            auto filter = v.options.filter;
            filter.seed = static_cast<uint32_t>(run);  // keySetByBenchmark(): never swept
            Localizer loc(filter, v.maps.map, v.maps.world ? &*v.maps.world : nullptr);
            TRunResult r;
            r.scenario = m_scenario.name;
            r.run = run;
            r.seed = filter.seed;
            r.variant = v.name();
            r.control = control;
            r.particles = static_cast<size_t>(filter.particles_count);
            r.threads = loc.threads();
            if (control == "route")
            {
                r.records = localizeRoute(loc, data, tolerance);
                if (detectionsOnly(v.maps))
                {
                    r.detectorBound = bound;  // of the detections: not of the sonar's filters
                }
            }
            else
            {
                auto policy = m_options.active;
                policy.threads = m_options.filter_threads;
                const std::string who =
                    (m_scenario.name.empty() ? "" : "scenario '" + m_scenario.name + "', ") +
                    "run " + std::to_string(run) + ", " + r.series() + ": ";
                auto loop = detail::runClosedLoop(
                    simulator, loc, *v.maps.map->mapByClass<CSemanticMap>(),
                    detail::controlFromName(control), policy, static_cast<uint32_t>(run),
                    [&who](const std::string& kind, const std::string& text)
                    { detail::runNote(kind, who + text); });
                r.records = std::move(loop.records);
                r.decisions = loop.decisions;
                r.decisionWall_s = loop.decisionWall_s;
                r.decisionFilterSteps = loop.decisionFilterSteps;
                r.maxDecisionFilterSteps = loop.maxDecisionFilterSteps;
                r.stuckDecisions = loop.stuckDecisions;
                if (detectionsOnly(v.maps))
                {
                    r.detectorBound = detectorCramerRaoBound(simulator, loop.data);
                }
            }
            r.wallTime_s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
            r.metrics = RunMetrics::compute(r.records, v.options.convergence, kidnapStep());
            r.reinitializations = loc.recoveryStats().reinitializations;
            out.push_back(std::move(r));
        }
    }
    return out;
}

// ------------------------------------------------------------------ the benchmark

void Benchmark::SetStageReporter(std::function<void(const std::string&)> reporter)
{
    stageReporter() = std::move(reporter);
}

void detail::reportStage(const std::string& what)
{
    if (stageReporter())
    {
        stageReporter()(what);
    }
}

void Benchmark::SetWarningReporter(std::function<void(const std::string&)> reporter)
{
    warningReporter() = std::move(reporter);
}

void detail::reportWarning(const std::string& text)
{
    if (warningReporter())
    {
        warningReporter()(text);
    }
}

Benchmark::TResult Benchmark::run(const std::function<void(size_t, size_t)>& progress) const
{
    checkOutputKind();
    return m_scenarios.empty() ? runAll(progress) : runScenarios(progress);
}

Benchmark::TResult Benchmark::runAll(const std::function<void(size_t, size_t)>& progress,
                                     const std::vector<TShard>& shards,
                                     const std::string& inputsDigest) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;
    const std::string inputs = inputsDigest.empty() ? digest() : inputsDigest;
    auto inputPaths = inputFiles();
    for (const auto& s : shards)
    {
        inputPaths.push_back(s.dir);
    }
    StagedDirectory out(o.output_dir, inputPaths);
    const size_t jobs = effectiveJobs();
    const std::string scenario =
        m_scenario.name.empty() ? std::string() : "scenario '" + m_scenario.name + "': ";
    const auto stage = [&](const std::string& what) { detail::reportStage(scenario + what); };
    TResult res;
    const auto collect = [&](const std::function<std::string(int)>& pathOf)
    {
        return collectRuns(pathOf, o.runs, inputs, m_variants, o.controls, m_scenario.name,
                           kidnapStep());
    };
    if (shards.empty())
    {
        // One child process per run (see the class documentation: MRPT's global generator).
        const detail::RunFiles files(out.path("runs"), inputs);
        std::filesystem::create_directories(files.dir());
        detail::runInChildProcesses(
            files, 1, o.runs, jobs, m_scenario.name, [this](int run) { return runOne(run); },
            progress);
        stage(mrpt::format("reading the results of %d runs x %zu series", o.runs,
                           seriesNames().size()));
        res.runs = collect([&](int run) { return files.path(run, "txt"); });
        std::filesystem::remove_all(files.dir());
    }
    else
    {
        // Each run's file as the user named its shard (Merge() checked that one holds it).
        stage(mrpt::format("reading the results of %d runs x %zu series of %zu shards", o.runs,
                           seriesNames().size(), shards.size()));
        res.runs = collect(
            [&](int run)
            {
                const auto s =
                    std::find_if(shards.begin(), shards.end(),
                                 [run](const auto& x) { return x.first <= run && run <= x.last; });
                return detail::RunFiles(shardRunsDir(s->dir), inputs).path(run, "txt");
            });
    }

    const auto names = seriesNames();
    stage("writing results.csv and curves.csv");
    writeFile(out.path("results.csv"), detail::resultsCsv(res.runs));
    writeFile(out.path("curves.csv"), detail::curvesCsv(res.runs, names));
    res.figureWarnings = detail::writeFigures(out, names, m_simulation, res.runs, scenario);

    stage("writing report.md");
    for (const auto& c : detail::costlySeries(res.runs, m_options.active))
    {
        res.warnings.push_back((c.scenario.empty() ? "" : "scenario '" + c.scenario + "', ") +
                               c.series + ": " + c.text);
    }
    res.table = reportTable(res.runs, names);
    res.summaries = summarize(res.runs);
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    writeFile(out.path("report.md"), detail::reportMarkdown(*this, res, jobs, kidnapStep()));
    res.outputDir = out.target();
    out.commit();
    return res;
}

Benchmark::TResult Benchmark::runScenarios(const std::function<void(size_t, size_t)>& progress,
                                           const std::vector<TShard>& shards) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const std::string inputs = digest();  // the whole benchmark's, in every scenario's run files
    auto inputPaths = inputFiles();
    for (const auto& s : shards)
    {
        inputPaths.push_back(s.dir);
    }
    StagedDirectory out(m_options.output_dir, inputPaths);
    const size_t total = m_scenarios.size() * static_cast<size_t>(m_options.runs);
    TResult res;
    for (size_t i = 0; i < m_scenarios.size(); i++)
    {
        Benchmark sc = m_scenarios[i];
        sc.m_options.output_dir = out.path(sc.m_scenario.name);
        const size_t offset = i * static_cast<size_t>(m_options.runs);
        const auto r = sc.runAll(
            [&](size_t done, size_t)
            {
                if (progress && (done > 0 || i == 0))
                {
                    progress(offset + done, total);
                }
            },
            shards, inputs);
        res.runs.insert(res.runs.end(), r.runs.begin(), r.runs.end());
        res.summaries.insert(res.summaries.end(), r.summaries.begin(), r.summaries.end());
        res.warnings.insert(res.warnings.end(), r.warnings.begin(), r.warnings.end());
        for (auto w : r.figureWarnings)
        {
            w.figure = sc.m_scenario.name + "/" + w.figure;
            w.script = sc.m_scenario.name + "/" + w.script;
            res.figureWarnings.push_back(std::move(w));
        }
    }
    detail::reportStage("writing scenarios.csv and report.md");
    res.table = scenariosTable(res.summaries);
    writeFile(out.path("scenarios.csv"), detail::scenariosCsv(res.summaries));

    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    writeFile(out.path("report.md"), detail::scenariosReportMarkdown(*this, res));
    res.outputDir = out.target();
    out.commit();
    return res;
}

}  // namespace semloc

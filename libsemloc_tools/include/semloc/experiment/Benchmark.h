/* semloc — semloc-benchmark's engine: the paper's experiment (§IV, Fig. 3, Table I), R
 * simulated runs localized by every variant, aggregated into tables and figures. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/experiment/RunMetrics.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/plot/FigureWarning.h>
#include <semloc/simulator/DetectorBound.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/simulator/WorldChanges.h>

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace semloc
{
/** The paper's benchmark: run i (i = 1..runs) simulates the scenario of `simulate_ini` with
 *  seed i once, in memory, and localizes that same dataset with every variant, each filter
 *  seeded with i.
 *
 *  ## Parallel runs and MRPT's random generator
 *  Localizer seeds and draws from mrpt::random::getRandomGenerator(), one generator per
 *  process, so two filters in one process would interleave their draws. Each run therefore
 *  executes in a child process (fork(), no exec: the parent runs no filter, and its only
 *  other thread, the interrupt watchdog, waits in read() holding no lock); at most `jobs`
 *  children run at once. A run's results depend only on its seed,
 *  never on `jobs`.
 *
 *  ## Outputs (in `output_dir`, written to a staging directory and renamed at the end)
 *  `results.csv` (one row per run and variant: run, seed, variant and summary.yaml's fields
 *  of docs/design.md, plus wall_time_s), `curves.csv` (per variant and step: mean and 10/50/90 %
 *  percentiles of err_xy and var_xy over the runs), `report.md` (reportTable() and the
 *  paper's Table I beside ours), `figures.gp` + `fig_variance.png`, `fig_error.png` (Fig. 3)
 *  and `world_paths.png` (the world, run 1's true path and estimates; WorldPlot).
 *
 *  ## Scenarios (the robustness experiment)
 *  With `scenarios`, each scenario file is an overlay of `simulate_ini` (its [Simulation],
 *  [Odometry], [Sonar], [SemanticDetector], [Kidnapping], [BeaconRanging] keys replace the
 *  base's) plus a [Scenario] section (TScenario: name, variants, recovery). Each scenario is
 *  a benchmark of its own written to `output_dir/<name>/` (all the outputs above);
 *  `output_dir` also gets `scenarios.csv` and `report.md`: per scenario and variant the
 *  success rate (converged; with a kidnapping: recovered within `recovery_max_steps`),
 *  convergence and recovery. */
class Benchmark
{
public:
    /** Section [Benchmark] of benchmark.ini. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Largest `runs` (the ini key and the tool's -r alike). */
        static constexpr int kMaxRuns = 1000000;
        /** Number of runs (seeds 1..runs), 1..kMaxRuns. */
        int runs = 100;
        /** Variant names (`<name>.ini` in variants_dir) or ini paths (resolved next to
         *  benchmark.ini). */
        std::vector<std::string> variants{"semantic", "geometric", "grid_lf", "grid_rt", "fused"};
        /** The folder of the variants named without `.ini` (relative: next to benchmark.ini,
         *  else from the working directory); empty: benchmark.ini's own folder. */
        std::string variants_dir;
        /** The simulation (semloc-simulate's ini; resolved next to benchmark.ini). */
        std::string simulate_ini = "simulate.ini";
        /** Output directory (relative: from the working directory). */
        std::string output_dir = "results/benchmark";
        /** Runs in parallel (child processes); 0 = every hardware thread. */
        int jobs = 0;
        /** Threads of each filter ([PF_options] threads). */
        int filter_threads = 1;
        /** Steps simulated per run; 0 = the whole trajectory. */
        int max_steps = 0;
        /** Particles of every variant; 0 = the reference filter's particles_count. */
        int particles = 0;
        /** true: every variant runs the first variant's filter (particles, PF_options,
         *  KLD_options, initial distribution, convergence criterion), so that only the
         *  likelihood (the maps) differs; false: each variant's own. A variant whose maps
         *  cannot take the first one's start from the detections starts uniform, and one
         *  that is not semantic maps only runs without the evidence recovery trigger. */
        bool same_filter = true;
        /** Who drives the simulated vehicle, each for every run and variant: `route` (the
         *  world's trajectory), `active` (ActivePolicy, then back to the route), `random` (a
         *  random walk over the policy's candidate motions, then back to the route); the
         *  closed loops need a semantic map in every variant. */
        std::vector<std::string> controls{"route"};
        /** A parameter sweep (`sweep = SECTION.KEY: v1, v2, ...`): every variant runs once
         *  per value, with SECTION's KEY set to it, as the variant `<name>@KEY=<value>`;
         *  empty `key`: none. No value twice (values that read as numbers are compared as
         *  numbers), and the key must change the runs: see Benchmark::FromConfigFile(). */
        struct TSweep
        {
            std::string section, key;
            std::vector<std::string> values;
            /** "SECTION.KEY: v1, v2, ..." (the [Benchmark] sweep line as read). */
            std::string text() const;
            /** An error of the sweep line: "ini [Benchmark] sweep: 'text()': `why`". */
            std::string error(const std::string& why) const;
        } sweep;
        /** [ActiveLocalization] of benchmark.ini: the policy of `active` and the candidates
         *  and stop rule of `random` (its seed replaced by each run's). */
        ActivePolicy::TOptions active;
        /** Scenario files (overlays of simulate_ini with a [Scenario] section; resolved next
         *  to benchmark.ini); empty: the one scenario of simulate_ini. */
        std::vector<std::string> scenarios;
        /** true: every variant localizes against the simulated world (the [Simulation]
         *  world_file of simulate_ini, or of a scenario that sets its own), its map_file
         *  replaced; false: each variant against its own map_file. A scenario's
         *  map_from_world replaces this one. A map that differs from the simulated world is
         *  a warning (stderr, report.md) either way. */
        bool map_from_world = true;

        /** Reads the [Benchmark] section strictly: an unknown key or a bad value is an error
         *  naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the [Benchmark] section (the effective configuration). */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** Section [Scenario] of a scenario file. */
    struct TScenario : public mrpt::config::CLoadableOptions
    {
        /** Name (output subdirectory); empty: the file's stem. */
        std::string name;
        /** One line saying what the scenario changes. */
        std::string description;
        /** Variants of this scenario (as [Benchmark] variants); empty: [Benchmark]'s. */
        std::vector<std::string> variants;
        /** Particles of every variant of this scenario; 0: [Benchmark] particles. */
        int particles = 0;
        /** true: every variant runs with augmented MCL recovery ([Recovery] trigger = amcl,
         *  the two rates below), whatever its own trigger. */
        bool recovery = false;
        /** [Recovery] alpha_slow when `recovery`. */
        double recovery_alpha_slow = 0.001;
        /** [Recovery] alpha_fast when `recovery`. */
        double recovery_alpha_fast = 0.1;
        /** With a kidnapping: a run succeeds if it recovers (RunMetrics::recovery_steps)
         *  within this many steps of the kidnapping. */
        int recovery_max_steps = 100;
        /** [Benchmark] map_from_world for this scenario; unset (the key empty or absent):
         *  [Benchmark]'s. */
        std::optional<bool> map_from_world;
        /** Every variant's init_PDF_mode (0..3, Localizer::InitMode); -1: their own. */
        int init_PDF_mode = -1;
        /** The world the runs are simulated in, changed from the world file (the maps the
         *  variants carry stay the file's): world_shift_sigma_m, world_removed_share,
         *  world_added, world_changes_seed (TWorldChanges). */
        TWorldChanges world_changes;

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** One variant as it runs: its resolved options (overrides applied) and its maps. */
    struct TVariant
    {
        /** Path of the variant's ini file. */
        std::string iniPath;
        /** The variant's options, benchmark overrides applied. */
        LocalizationExperiment::TOptions options;
        /** The maps the variant localizes in. */
        LocalizationMap maps;
        /** The maps' effective configuration (LocalizationMap::effectiveConfig() of the
         *  variant's ini as read, the scenario's and the sweep's keys on it). */
        std::string mapsConfig;
        /** The variant's name (options.variant). */
        const std::string& name() const { return options.variant; }
    };

    /** One run of one variant. */
    struct TRunResult
    {
        /** Scenario name (empty without scenarios). */
        std::string scenario;
        /** Index of the run. */
        int run = 0;
        /** Seed of the run (simulation and filter). */
        uint32_t seed = 0;
        /** Name of the variant. */
        std::string variant;
        /** Who drove the vehicle ([Benchmark] controls). */
        std::string control = "route";
        /** Distance driven until the convergence step [m] (the true path's length); NaN when
         *  not converged. */
        double distance_to_convergence_m = std::numeric_limits<double>::quiet_NaN();
        /** Decisions of the control (active, random; 0 for the route). */
        size_t decisions = 0;
        /** Wall time of those decisions [s]. */
        double decisionWall_s = 0;
        /** The active policy's decisions in filter steps of the run's particles
         *  (ActivePolicy::filterSteps): their sum and the largest (0 for the other controls). */
        double decisionFilterSteps = 0, maxDecisionFilterSteps = 0;
        /** Decisions at which no candidate motion that goes somewhere was free from the true
         *  pose: the vehicle turned on the spot or stood. */
        size_t stuckDecisions = 0;
        /** Where the tables list it: the variant, and with another control than the route
         *  "variant/control". */
        std::string series() const { return seriesName(variant, control); }
        /** Number of particles of the filter (the initial number with KLD). */
        size_t particles = 0;
        /** Threads of the filter's per-particle work. */
        size_t threads = 1;
        /** Summary metrics of the run. */
        RunMetrics metrics;
        /** Times every particle weight was zero and the cloud was drawn again. */
        size_t reinitializations = 0;
        /** Filter construction and every step [s] (the paper's execution time). */
        double wallTime_s = 0;
        /** One record per filter step (rows of steps.csv). */
        std::vector<TStepRecord> records;
        /** The detector's Cramér–Rao bound at each step of the simulated run
         *  (detectorCramerRaoBound): what no filter of the detections alone can beat; for the
         *  variants whose maps are all semantic maps (the same for each of a run), empty for
         *  the others (the sonar's and the grids' filters have other information). */
        std::vector<TDetectorBoundStep> detectorBound;

        /** The mean of detectorBound's mean_err_xy_m over the steps from the convergence step
         *  on (those of metrics.mean_err_after_conv_m); NaN if not converged or without it. */
        double detectorBoundAfterConvergence() const;
    };

    /** Success of one variant in one scenario over the runs. */
    struct TScenarioSummary
    {
        /** Scenario name (empty without scenarios). */
        std::string scenario;
        /** TScenario::description. */
        std::string description;
        /** Variant name (TRunResult::series(): with its control unless the route). */
        std::string variant;
        /** Runs. */
        size_t runs = 0;
        /** Successful runs: converged, or with a kidnapping recovered within the bound. */
        size_t successes = 0;
        /** Converged runs (RunMetrics::converged). */
        size_t converged = 0;
        /** Mean time to convergence of the converged runs [s]; NaN if none. */
        double mean_convergence_time_s = 0;
        /** Mean error after convergence of the converged runs [m]; NaN if none. */
        double mean_err_after_conv_m = 0;
        /** Kidnap step of the scenario, -1 without a kidnapping. */
        long kidnap_step = -1;
        /** TScenario::recovery_max_steps. */
        int recovery_max_steps = 0;
        /** Mean and maximum recovery steps of the runs that recovered; NaN if none. */
        double mean_recovery_steps = 0, max_recovery_steps = 0;
        /** Over the runs with ground truth: the median of their RunMetrics::nees_median, the
         *  means of their nees_inside_share and nees_well_conditioned_share, and the mean of
         *  nees_mean_well_conditioned over the runs that have one; NaN if none. */
        double nees_median = 0, nees_inside_share = 0, nees_mean_well_conditioned = 0,
               nees_well_conditioned_share = 0;

        /** successes / runs. */
        double successRate() const;
    };

    /** Everything the benchmark produced. */
    struct TResult
    {
        /** Run-major, variants in configuration order. */
        std::vector<TRunResult> runs;
        /** Directory the outputs were written to. */
        std::string outputDir;
        /** Per scenario and variant (configuration order). */
        std::vector<TScenarioSummary> summaries;
        /** reportTable() of the runs (with scenarios: scenariosTable()). */
        std::string table;
        /** Wall time of the whole benchmark [s]. */
        double wallTime_s = 0;
        /** The figures gnuplot could not draw (left out; the other outputs are written);
         *  with scenarios, each figure's path starts with its scenario's directory. */
        std::vector<TFigureWarning> figureWarnings;
        /** The series whose active-policy decisions cost more than their budget on average
         *  over all their runs (report.md lists them too): "scenario 'S', series: text" (the
         *  scenario's part with scenarios only), the text naming the [ActiveLocalization]
         *  keys that set the cost. */
        std::vector<std::string> warnings;
    };

    /** Reads [Benchmark], the simulation ini and every variant ini (strictly) before any
     *  output is written. Throws naming the file, [section] and key of any error.
     *  A non-empty `outputDir` replaces [Benchmark] output_dir, `runs` > 0 its runs.
     *
     *  A sweep is refused, naming the [Benchmark] sweep line and why, when its key is not one
     *  the variants' runs read and that changes them: a key of [Benchmark] (the benchmark's
     *  own), of a section semloc-localize does not read, or one the benchmark sets itself
     *  (keySetByBenchmark()); a bad value, or a key a variant does not have, is an error of
     *  the sweep line, not of the variant's file; and two values of which a variant runs the
     *  same (runConfiguration()) are refused. */
    static Benchmark FromConfigFile(const std::string& iniPath, const std::string& outputDir = {},
                                    int runs = 0);

    /** Runs everything and writes the outputs; `progress(runsDone, runs)` is called from the
     *  calling thread at the start (0) and after each run. On error nothing is left in output_dir.
     */
    TResult run(const std::function<void(size_t, size_t)>& progress = {}) const;
    /** What run() and Merge() do once the runs are done, as a line each as it starts (reading
     *  the runs' results, the tables, each figure, the report; with scenarios, each starting
     *  with "scenario 'NAME': "): the work after the last run, which a wide sweep makes
     *  long. Process-wide, for every benchmark from then on (Merge() builds its own); none by
     *  default; semloc-benchmark shows them on a terminal. */
    static void SetStageReporter(std::function<void(const std::string&)> reporter);
    /** What a run tells while the runs go on, once per benchmark (per scenario) and kind, as
     *  soon as the first run tells it: a decision of the active policy over its budget of
     *  ActivePolicy::kBudgetFilterSteps filter steps (before it is made), a vehicle that could
     *  not move; each text names the scenario, the run, the series and the [ActiveLocalization]
     *  keys. Process-wide as SetStageReporter(); semloc-benchmark prints them on stderr as
     *  warnings. report.md's "Controls" counts the runs of each. */
    static void SetWarningReporter(std::function<void(const std::string&)> reporter);

    /** A shard: runs first..last of a benchmark, as its `shard.txt` describes them. */
    struct TShard
    {
        /** The shard's directory. */
        std::string dir;
        /** The benchmark's ini (absolute path). */
        std::string ini;
        /** digest() of the benchmark. */
        std::string digest;
        /** The benchmark's runs, and the shard's first and last. */
        int runs = 0, first = 0, last = 0;
    };
    /** Runs first..last (1 <= first <= last <= runs; each with its seed, as in the whole
     *  benchmark) and writes them to output_dir as a shard: `shard.txt` (the benchmark's ini,
     *  digest(), runs, first, last) and the runs' results (`runs/`, with scenarios
     *  `<scenario>/runs/`), staged and renamed at the end. `progress` as run()'s. */
    TShard runShard(int first, int last,
                    const std::function<void(size_t, size_t)>& progress = {}) const;
    /** Throws unless 1 <= first <= last <= runs (the runs of a shard), naming them: what
     *  runShard() checks first, for a caller to check before it prints anything. */
    void checkShardRuns(int first, int last) const;
    /** Throws, before any work, when output_dir holds the other kind of outputs than those to
     *  be written (first = 0: the whole benchmark's, of run() or Merge(); else the shard of runs
     *  first..last): a shard never replaces a whole benchmark's outputs, nor a whole benchmark
     *  a shard. The error names the directory and what it holds ("a whole benchmark of N
     *  runs", "a shard of runs A:B"); the user removes it to replace it. run(), runShard() and
     *  Merge() check it first, a caller may before it prints anything. */
    void checkOutputKind(int first = 0, int last = 0) const;
    /** Reads the `shard.txt` of `dir`; throws naming the file and line of anything wrong. */
    static TShard ReadShard(const std::string& dir);
    /** Merges shards into `outputDir`: they must be of one benchmark (the same digest and
     *  runs; its ini, read again, must still have that digest) and cover its runs 1..runs
     *  exactly once, else the merge is refused naming the shards and the runs that overlap or
     *  are missing. Each run file is read where its shard is (detail::readRunFile: refused,
     *  naming it and its line, unless it is a regular file of that run and of this benchmark's
     *  digest whose content matches its own digest). The outputs are those run() writes (the
     *  same bytes but for the timings). */
    static TResult Merge(const std::vector<std::string>& shardDirs, const std::string& outputDir,
                         const std::function<void(size_t, size_t)>& progress = {});
    /** What identifies the benchmark across machines: 16 hex digits of a 64-bit FNV-1a hash
     *  of its effective configuration (runs, every variant's filter and maps as they run, the
     *  simulation, the scenarios: effectiveConfiguration()) and the contents of every file it
     *  reads (its ini and bases, the simulation's, the variants' inis and maps, the
     *  scenarios', the worlds), in order. Every run file carries it. */
    std::string digest() const;

    /** Runs one (run, seed) in this process: simulation and every variant, each with every
     *  control (variant-major). */
    std::vector<TRunResult> runOne(int run) const;

    /** The markdown table of report.md: per variant success rate, convergence time, error,
     *  the detector's bound, consistency (over the runs, as TScenarioSummary's: the median
     *  NEES, the share inside its bound, the mean NEES of the well-conditioned steps and
     *  their share), variance, filter time per run and per particle-step, wall
     *  time, ratio to the first variant (or to "semantic" if present). */
    static std::string reportTable(const std::vector<TRunResult>& runs,
                                   const std::vector<std::string>& variants);

    /** report.md's paired comparison: each variant against the reference of reportTable()
     *  on the same runs (same simulation, same filter seed). Per variant: the runs both
     *  converged, the mean over them of (the variant's mean error after convergence - the
     *  reference's) with its standard error, the runs where the variant's error is lower,
     *  and the runs only one of the two converged. Empty with fewer than two variants. */
    static std::string pairedTable(const std::vector<TRunResult>& runs,
                                   const std::vector<std::string>& variants);

    /** The table of scenarios.csv / report.md with scenarios: per scenario and variant the
     *  success rate, convergence, consistency (NEES) and recovery. */
    static std::string scenariosTable(const std::vector<TScenarioSummary>& summaries);

    /** report.md's table of the controls: per scenario and series (TRunResult::series(), in
     *  the order of their first run) the runs, the converged ones, the median and 90th
     *  percentile of the distance driven to convergence (a run that did not converge counts
     *  as infinitely far: "-" when the percentile falls on one), the decisions per run, the
     *  mean wall time of a decision, the active policy's mean decision in filter steps
     *  (ActivePolicy::filterSteps) and the share of the decisions at which the vehicle could
     *  not move. */
    static std::string controlsTable(const std::vector<TRunResult>& runs);
    /** The benchmark options. */
    const TOptions& options() const { return m_options; }
    /** A series' name: `variant`, and with another control than the route
     *  "variant/control". */
    static std::string seriesName(const std::string& variant, const std::string& control)
    {
        return control == "route" ? variant : variant + "/" + control;
    }
    /** The series of the tables (TRunResult::series()): every variant with every control,
     *  variant-major. */
    std::vector<std::string> seriesNames() const;
    /** The variants, in configuration order (empty with scenarios). */
    const std::vector<TVariant>& variants() const { return m_variants; }
    /** One benchmark per scenario file (empty without scenarios). */
    const std::vector<Benchmark>& scenarios() const { return m_scenarios; }
    /** The scenario of a benchmark from `scenarios()`. */
    const TScenario& scenario() const { return m_scenario; }
    /** The simulation options (scenario overlay applied). */
    const TSimulatorOptions& simulation() const { return m_simulation; }
    /** Jobs actually used. */
    size_t effectiveJobs() const;
    /** True when the variants localize against the simulated world (map_from_world). */
    bool mapFromWorld() const;
    /** One line per variant whose map differs from the world it is simulated in (another
     *  file whose objects or bounds differ, a map that is not a world file, or a world the
     *  scenario changes), naming both; with scenarios, every scenario's, each starting with
     *  `scenario 'NAME': `. To be shown on stderr; report.md lists them too. */
    std::vector<std::string> mapWarnings() const;

private:
    Benchmark() = default;
    /** Reads the variants of m_options (names resolved next to `ini`; with a sweep, each
     *  once per value) into m_variants; per variant, the index of the first one of its sweep
     *  value (the reference of same_filter). */
    std::vector<size_t> readVariants(const mrpt::config::CConfigFileBase& ini);
    /** Reads the variants of m_options (names resolved next to `ini`) and applies the
     *  benchmark's and the scenario's filter overrides. */
    void loadVariants(const mrpt::config::CConfigFileBase& ini);
    /** Why the runs do not take the variants' [section] key (empty: they do): the keys the
     *  benchmark sets itself, in loadVariants() and runOne(): the filter's seed (each run's),
     *  its threads ([Benchmark] filter_threads: results do not depend on them), the variant's
     *  name, and, when this benchmark or its scenario sets them, particles_count, map_file
     *  (map_from_world), init_PDF_mode and the [Recovery] trigger and rates. */
    std::string keySetByBenchmark(const std::string& section, const std::string& key) const;
    /** Throws, naming the sweep line, unless the variants' runs read the sweep's key and the
     *  benchmark does not set it itself (keySetByBenchmark()). */
    void checkSweepKey() const;
    /** Throws, naming the sweep line, when two values of the sweep give one variant the same
     *  runConfiguration(). */
    void checkSweepValuesDiffer() const;
    /** What the runs of `v` depend on, as ini text: its filter (but the seed, each run's, and
     *  the threads), its convergence criterion, its map_file and mapsConfig. */
    static std::string runConfiguration(const TVariant& v);
    /** The kidnap step of the simulation, -1 if none. */
    long kidnapStep() const;
    /** Summaries of `runs` (this benchmark's) per variant. */
    std::vector<TScenarioSummary> summarize(const std::vector<TRunResult>& runs) const;
    /** run() with scenarios; with `shards`, the runs are those shards' (Merge()). */
    TResult runScenarios(const std::function<void(size_t, size_t)>& progress,
                         const std::vector<TShard>& shards = {}) const;
    /** run() without scenarios; with `shards`, the runs are those shards' (Merge(): each run
     *  in one). The run files carry `inputs` (empty: digest()), the whole benchmark's digest. */
    TResult runAll(const std::function<void(size_t, size_t)>& progress,
                   const std::vector<TShard>& shards = {}, const std::string& inputs = {}) const;
    /** What digest() hashes besides the input files' bytes: the effective configuration of the
     *  whole benchmark as ini text ([Benchmark] but output_dir, the simulation, each scenario
     *  and its overlay, each variant's name, ini and runConfiguration()). */
    std::string effectiveConfiguration() const;
    /** Where the run files of this benchmark are in a shard directory. */
    std::string shardRunsDir(const std::string& shardDir) const;
    /** Fills m_mapWarnings: the variants' maps compared with the simulated world. */
    void checkMaps();
    /** The files the benchmark reads (its ini, the simulation's ini and world, the
     *  variants' inis and maps, the scenarios' too): the output directory holds none. */
    std::vector<std::string> inputFiles() const;

    std::string m_iniPath;
    TOptions m_options;
    TSimulatorOptions m_simulation;
    /** The scenario file's sections other than [Scenario] and the simulation's: (section,
     *  key, value) replacing the variants' own. */
    std::vector<std::array<std::string, 3>> m_variantOverlay;
    /** The changed world the runs are simulated in (TScenario::world_changes), if any. */
    std::shared_ptr<const World> m_changedWorld;
    std::vector<TVariant> m_variants;
    /** checkMaps()'s lines (this benchmark's variants only). */
    std::vector<std::string> m_mapWarnings;
    TScenario m_scenario;
    std::vector<Benchmark> m_scenarios;
};

}  // namespace semloc

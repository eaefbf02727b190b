/* semloc-benchmark: the paper's experiment, R seeds × variants (results.csv, curves.csv,
 * report.md, figures).
 *   semloc-benchmark config/benchmark/benchmark.ini [-o results/benchmark]
 *   semloc-benchmark config/benchmark/robustness.ini   (scenarios: sensor faults, kidnapping)
 *   semloc-benchmark INI --runs A:B -o SHARD           (runs A..B only, a shard)
 *   semloc-benchmark --merge SHARD... -o OUT            (the shards' outputs as one run's) */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ProcessControl.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <set>

#include "common/AppMain.h"
#include "common/ProgressBar.h"

namespace
{
TCLAP::CmdLine cmd("semloc-benchmark", ' ', "0.1");
TCLAP::UnlabeledMultiArg<std::string> argInputs(
    "config",
    "Benchmark ini (see config/benchmark/benchmark.ini); with --merge, the shard directories", true,
    "benchmark.ini | SHARD...", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output-dir", "Overrides output_dir", false, "", "DIR",
                                    cmd);
TCLAP::ValueArg<std::string> argRuns(
    "r", "runs",
    "N: overrides [Benchmark] runs (seeds 1..N); A:B: runs A..B of the benchmark only, written "
    "as a shard to -o (semloc-benchmark --merge)",
    false, "", "N | A:B", cmd);
TCLAP::SwitchArg argMerge("", "merge",
                          "Merges the shard directories given (semloc-benchmark INI --runs A:B) "
                          "into -o: the outputs of the whole benchmark",
                          cmd);

/** --runs: N (first = 0) or A:B. */
struct RunsArg
{
    int first = 0, last = 0;
};

/** One run number of --runs: decimal digits only (no blank, no sign), 1..kMaxRuns. */
int parseRunNumber(const std::string& text)
{
    constexpr int kMaxRuns = semloc::Benchmark::TOptions::kMaxRuns;  // as [Benchmark] runs
    unsigned long v = 0;  // from_chars takes no blank and no sign for an unsigned type
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || v < 1 ||
        v > static_cast<unsigned long>(kMaxRuns))
    {
        THROW_EXCEPTION("--runs: '" + argRuns.getValue() +
                        "' is not N or A:B (decimal digits, no blank or sign) with runs in [1, " +
                        std::to_string(kMaxRuns) + "]");
    }
    return static_cast<int>(v);
}

/** --runs: N, or A:B (one colon); nothing else. */
RunsArg runsArg()
{
    RunsArg r;
    if (!argRuns.isSet())
    {
        return r;
    }
    const std::string& v = argRuns.getValue();
    const auto colon = v.find(':');
    if (colon == std::string::npos)
    {
        r.last = parseRunNumber(v);
        return r;
    }
    r.first = parseRunNumber(v.substr(0, colon));
    r.last = parseRunNumber(v.substr(colon + 1));  // a second colon is not a digit
    if (r.first > r.last)
    {
        THROW_EXCEPTION("--runs " + v + ": the first run is after the last");
    }
    return r;
}

/** SEMLOC_BENCHMARK_RUNS (docs/testing.md): the most runs of any benchmark, whatever the ini
 *  or --runs say (the doc-commands test runs the documented benchmarks reduced); 0: unset. */
int runsCap()
{
    const char* env = std::getenv("SEMLOC_BENCHMARK_RUNS");
    if (env == nullptr || *env == '\0')
    {
        return 0;
    }
    char* end = nullptr;
    const long v = std::strtol(env, &end, 10);
    if (*end != '\0' || v < 1 || v > semloc::Benchmark::TOptions::kMaxRuns)
    {
        THROW_EXCEPTION("environment SEMLOC_BENCHMARK_RUNS: '" + std::string(env) +
                        "' is not a number of runs in [1, " +
                        std::to_string(semloc::Benchmark::TOptions::kMaxRuns) + "]");
    }
    return static_cast<int>(v);
}

/** The benchmark of the command line; a shard's (A:B) is the whole benchmark's, uncapped. */
semloc::Benchmark load(const std::string& ini, const RunsArg& runs)
{
    const bool shard = runs.first > 0;
    auto bench = semloc::Benchmark::FromConfigFile(ini, argOut.getValue(), shard ? 0 : runs.last);
    const int cap = shard ? 0 : runsCap();  // a shard runs the runs it names
    if (cap > 0 && bench.options().runs > cap)
    {
        std::cerr << "semloc-benchmark: SEMLOC_BENCHMARK_RUNS=" << cap << ": " << cap
                  << " run(s) instead of " << bench.options().runs
                  << " (a reduced benchmark: its figures are not the documented ones)\n";
        bench = semloc::Benchmark::FromConfigFile(ini, argOut.getValue(), cap);
    }
    return bench;
}

/** The variants' deprecated keys, once per variant file. */
void warnAboutVariants(const semloc::Benchmark& bench)
{
    std::set<std::string> said;
    auto warn = [&](const semloc::Benchmark& b)
    {
        for (const auto& v : b.variants())
        {
            for (const auto& w : v.options.filter.warnings)
            {
                if (said.insert(v.iniPath + ": " + w).second)
                {
                    std::cerr << "semloc-benchmark: warning: " << v.iniPath << ": " << w << "\n";
                }
            }
        }
    };
    warn(bench);
    for (const auto& sc : bench.scenarios())
    {
        warn(sc);
    }
}

/** When semloc-benchmark started: the progress's clock. */
const auto kStart = std::chrono::steady_clock::now();

/** What the runs tell as they go (Benchmark::SetWarningReporter), on stderr as warnings (on
 *  a terminal, where the progress bar is), and the stages after the runs
 *  (Benchmark::SetStageReporter) on a terminal's stderr. */
void showStages()
{
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    semloc::Benchmark::SetWarningReporter(
        [tty](const std::string& text)
        {
            std::cerr << (tty ? "\r" + std::string(79, ' ') + "\r" : std::string())
                      << "semloc-benchmark: warning: " << text << "\n"
                      << std::flush;
        });
    if (!tty)
    {
        return;
    }
    semloc::Benchmark::SetStageReporter(
        [](const std::string& what)
        {
            const double el =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - kStart).count();
            std::cerr << "\r" << std::string(79, ' ') << "\rsemloc-benchmark: " << what
                      << " (elapsed " << semloc::apps::clockText(el) << ")\n"
                      << std::flush;
        });
}

/** The progress bar on a terminal's stderr. */
const auto progressBar = semloc::apps::runsProgressBar;

void printResult(const semloc::Benchmark::TResult& res, bool scenarios)
{
    for (const auto& w : res.figureWarnings)
    {
        std::cerr << "semloc-benchmark: warning: " << w.text() << "\n";
    }
    for (const auto& w : res.warnings)
    {
        std::cerr << "semloc-benchmark: warning: " << w << "\n";
    }
    std::cout << "\n"
              << res.table << "\nsemloc-benchmark: " << res.runs.size() << " results in "
              << res.outputDir
              << (scenarios ? " (report.md, scenarios.csv, one directory per scenario), "
                            : " (report.md, results.csv, curves.csv, fig_*.png), ")
              << mrpt::format("%.1f", res.wallTime_s) << " s\n";
}

/** --merge SHARD... -o OUT. */
void merge()
{
    if (!argOut.isSet() || argRuns.isSet())
    {
        THROW_EXCEPTION(
            "--merge SHARD... -o OUT: the output directory (-o) is required and "
            "--runs is not taken (the shards say which runs they hold)");
    }
    semloc::installInterruptHandlers();
    const auto res =
        semloc::Benchmark::Merge(argInputs.getValue(), argOut.getValue(), progressBar());
    std::cout << "semloc-benchmark: " << argInputs.getValue().size() << " shard(s) merged\n";
    printResult(res, res.summaries.size() > 0 && !res.summaries.front().scenario.empty());
}

void run()
{
    showStages();
    if (argMerge.getValue())
    {
        merge();
        return;
    }
    if (argInputs.getValue().size() != 1)
    {
        THROW_EXCEPTION("one benchmark ini expected, got " +
                        std::to_string(argInputs.getValue().size()) +
                        " arguments (several shard directories go with --merge)");
    }
    const RunsArg runs = runsArg();
    const auto bench = load(argInputs.getValue().front(), runs);
    if (runs.first > 0)
    {
        bench.checkShardRuns(runs.first, runs.last);  // before anything is printed
    }
    bench.checkOutputKind(runs.first, runs.last);
    warnAboutVariants(bench);
    for (const auto& w : bench.mapWarnings())
    {
        std::cerr << "semloc-benchmark: warning: the map differs from the simulated world: " << w
                  << "\n";
    }
    // Ctrl-C: the running runs end, nothing is written (the staging directory is removed).
    semloc::installInterruptHandlers();
    const auto& o = bench.options();
    const int n = runs.first > 0 ? runs.last - runs.first + 1 : o.runs;
    std::cout << "semloc-benchmark: " << n << " runs x ";
    if (bench.scenarios().empty())
    {
        std::cout << bench.variants().size() << " variants";
    }
    else
    {
        std::cout << bench.scenarios().size() << " scenarios";
    }
    std::cout << ", " << bench.effectiveJobs() << " parallel runs, " << o.filter_threads
              << " filter thread(s) each\n";
    if (runs.first > 0)
    {
        const auto s = bench.runShard(runs.first, runs.last, progressBar());
        std::cout << "semloc-benchmark: runs " << s.first << ".." << s.last << " of " << s.runs
                  << " in the shard " << s.dir << " (digest " << s.digest
                  << "; merge the shards with semloc-benchmark --merge SHARD... -o OUT)\n";
        return;
    }
    printResult(bench.run(progressBar()), !bench.scenarios().empty());
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-benchmark", run);
}

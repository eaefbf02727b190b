/* semloc-benchmark: the paper's experiment, R seeds × variants (results.csv, curves.csv,
 * report.md, figures).
 *   semloc-benchmark config/benchmark/benchmark.ini [-o results/benchmark]
 *   semloc-benchmark config/benchmark/robustness.ini   (scenarios: sensor faults, kidnapping) */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/Interrupt.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <set>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-benchmark", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argIni("config",
                                             "Benchmark ini (see config/benchmark/benchmark.ini)",
                                             true, "", "benchmark.ini", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output-dir", "Overrides output_dir", false, "", "DIR",
                                    cmd);
TCLAP::ValueArg<int> argRuns("r", "runs", "Overrides [Benchmark] runs (seeds 1..N)", false, 0, "N",
                             cmd);

std::string clock(double s)
{
    const long t = std::lround(s);
    return mrpt::format("%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
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

semloc::Benchmark load()
{
    constexpr int kMaxRuns = semloc::Benchmark::TOptions::kMaxRuns;  // as [Benchmark] runs
    if (argRuns.isSet() && (argRuns.getValue() < 1 || argRuns.getValue() > kMaxRuns))
    {
        THROW_EXCEPTION("--runs: must be in [1, " + std::to_string(kMaxRuns) + "]");
    }
    const int cap = runsCap();
    auto bench =
        semloc::Benchmark::FromConfigFile(argIni.getValue(), argOut.getValue(), argRuns.getValue());
    if (cap > 0 && bench.options().runs > cap)
    {
        std::cerr << "semloc-benchmark: SEMLOC_BENCHMARK_RUNS=" << cap << ": " << cap
                  << " run(s) instead of " << bench.options().runs
                  << " (a reduced benchmark: its figures are not the documented ones)\n";
        bench = semloc::Benchmark::FromConfigFile(argIni.getValue(), argOut.getValue(), cap);
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

void run()
{
    const auto bench = load();
    warnAboutVariants(bench);
    for (const auto& w : bench.mapWarnings())
    {
        std::cerr << "semloc-benchmark: warning: the map differs from the simulated world: " << w
                  << "\n";
    }
    // Ctrl-C: the running runs end, nothing is written (the staging directory is removed).
    semloc::installInterruptHandlers();
    const auto& o = bench.options();
    std::cout << "semloc-benchmark: " << o.runs << " runs x ";
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
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    const auto t0 = std::chrono::steady_clock::now();
    const auto res = bench.run(
        [&](size_t done, size_t total)
        {
            if (!tty)
            {
                return;
            }
            const double el =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const int width = 30;
            const int fill = static_cast<int>(width * done / total);
            std::cerr << "\r[" << std::string(fill, '#') << std::string(width - fill, ' ') << "] "
                      << done << "/" << total << " runs, elapsed " << clock(el) << ", left "
                      << (done ? clock(el / static_cast<double>(done) *
                                       static_cast<double>(total - done))
                               : std::string("?"))
                      << "  " << std::flush;
            if (done == total)
            {
                std::cerr << "\n";
            }
        });
    for (const auto& w : res.figureWarnings)
    {
        std::cerr << "semloc-benchmark: warning: " << w.text() << "\n";
    }
    std::cout << "\n"
              << res.table << "\nsemloc-benchmark: " << res.runs.size() << " results in "
              << res.outputDir
              << (bench.scenarios().empty() ? " (report.md, results.csv, curves.csv, fig_*.png), "
                                            : " (report.md, scenarios.csv, one directory per "
                                              "scenario), ")
              << mrpt::format("%.1f", res.wallTime_s) << " s\n";
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-benchmark", run);
}

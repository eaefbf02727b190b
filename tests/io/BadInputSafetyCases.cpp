/* semloc tests — the bad inputs of docs/bad-input.md's table that a hostile user tries: special
 * files where a file is read, benchmark shards and merges, calibration, large maps. Each case
 * writes its input in a fresh directory and returns the tool's command line (test_BadInput.cpp
 * runs it and checks the row). */
#include <filesystem>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{

/** Special files (devices, FIFOs) where a tool reads a file. */
Cases specialFileCases()
{
    return {};
}

namespace
{
/** dir/bench.ini: 2 runs of 5 steps of config/localize/semantic.ini (the variant `semantic`,
 *  100 particles, into `out`), then the [Benchmark] lines of `extra`. */
fs::path writeBenchIni(const fs::path& dir, const std::string& extra)
{
    writeText(dir / "bench.ini", "[Benchmark]\nruns = 2\nvariants = semantic\nvariants_dir = " +
                                     kSrc + "/config/localize\nsimulate_ini = " + kSrc +
                                     "/config/simulate/simulate.ini\nmax_steps = 5\n"
                                     "particles = 100\njobs = 1\noutput_dir = out\n" +
                                     extra);
    return dir / "bench.ini";
}

/** semloc-benchmark on writeBenchIni(`extra`) with `args`. */
std::vector<std::string> benchmark(const fs::path& dir, const std::string& extra,
                                   const std::vector<std::string>& args = {})
{
    std::vector<std::string> a{"semloc-benchmark", writeBenchIni(dir, extra).string()};
    a.insert(a.end(), args.begin(), args.end());
    return a;
}

/** The benchmark of writeBenchIni() with `sweep = <line>`. */
Builder sweep(const std::string& line)
{
    return [line](const fs::path& d) { return benchmark(d, "sweep = " + line + "\n"); };
}

/** `--runs <runs>` of the benchmark of writeBenchIni(), a shard into `shard`. */
Builder shardRuns(const std::string& runs)
{
    return [runs](const fs::path& d) { return benchmark(d, "", {"--runs", runs, "-o", "shard"}); };
}
}  // namespace

/** Benchmark sweeps, shards and merges. */
Cases benchmarkSafetyCases()
{
    return {
        {"benchmark-sweep-unknown-section", sweep("NoSuchSection.foo: 1, 2")},
        {"benchmark-sweep-benchmark-key", sweep("Benchmark.particles: 100, 300")},
        {"benchmark-sweep-particles-set-by-benchmark",
         sweep("LocalizationExperiment.particles_count: 100, 300")},
        {"benchmark-sweep-threads", sweep("PF_options.threads: 1, 2")},
        {"benchmark-sweep-seed", sweep("LocalizationExperiment.seed: 1, 2")},
        {"benchmark-sweep-map-from-world",
         sweep("LocalizationExperiment.map_file: paper_50x50.yaml, paper_50x50_surveyed.yaml")},
        {"benchmark-sweep-one-number", sweep("PF_options.powFactor: 0.5, 0.50, 5e-1")},
        {"benchmark-sweep-changes-nothing", sweep("LocalizationExperiment.rawlog_offset: 1, 2")},
        {"benchmark-sweep-bad-value", sweep("PF_options.powFactor: 0.5, abc")},
        {"benchmark-runs-blank", shardRuns(" 1:2")},
        {"benchmark-runs-sign", shardRuns("+1:+2")},
    };
}

/** semloc-calibrate. */
Cases calibrateSafetyCases()
{
    return {};
}

/** Large maps and landmark imports. */
Cases largeMapCases()
{
    return {};
}

}  // namespace semloc::test::bad_input

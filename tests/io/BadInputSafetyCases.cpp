/* semloc tests — the bad inputs of docs/bad-input.md's table that a hostile user tries: special
 * files where a file is read, benchmark shards and merges, calibration, large maps, the active
 * control's cost and a vehicle that cannot move. Each case
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

/** Benchmark sweeps, shards and merges. */
Cases benchmarkSafetyCases()
{
    return {};
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

/** semloc-benchmark's active control told of what it costs and cannot do. */
Cases reportSafetyCases()
{
    const auto activeBenchmark = [](const fs::path& d, const std::string& policy)
    {
        writeText(d / "bench.ini",
                  "[Benchmark]\nruns = 1\nmax_steps = 20\nparticles = 300\ncontrols = active\n"
                  "variants = " +
                      kSrc + "/config/localize/semantic.ini\nsimulate_ini = " + kSrc +
                      "/config/simulate/simulate.ini\noutput_dir = out\n[ActiveLocalization]\n" +
                      policy);
        return std::vector<std::string>{"semloc-benchmark", (d / "bench.ini").string()};
    };
    return {
        {"benchmark-active-decision-costly", [=](const fs::path& d)
         { return activeBenchmark(d, "look_around = true\noutcomes = 64\n"); }},
        {"benchmark-active-vehicle-stuck",
         [=](const fs::path& d) { return activeBenchmark(d, "distances_m = 1000\n"); }},
    };
}

}  // namespace semloc::test::bad_input

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

/** Benchmark sweeps, shards and merges. */
Cases benchmarkSafetyCases()
{
    return {};
}

/** semloc-calibrate. */
Cases calibrateSafetyCases()
{
    // The rawlog is streamed through the passes, not loaded: its defects are still refused
    // on the first reading, before anything is written.
    return {
        {"calibrate-rawlog-truncated",
         [](const fs::path& d)
         {
             auto args = calibrate(d, 100, "semantic", "out.ini");
             const std::string b = plainBytes(d);
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return args;
         }},
        {"calibrate-rawlog-corrupted-entry",
         [](const fs::path& d)
         {
             auto args = calibrate(d, 100, "semantic", "out.ini");
             // The serialization version byte after the 2nd sensory frame's class name.
             std::string b = plainBytes(d);
             const std::string name = "mrpt::obs::CSensoryFrame";
             const auto p = b.find(name, b.find(name) + 1);
             b[p + name.size()] = 99;
             writeText(d / "data.rawlog", b);
             return args;
         }},
        {"calibrate-rawlog-empty",
         [](const fs::path& d)
         {
             auto args = calibrate(d, 100, "semantic", "out.ini");
             writeText(d / "data.rawlog", "");
             return args;
         }},
    };
}

/** Large maps and landmark imports. */
Cases largeMapCases()
{
    return {};
}

}  // namespace semloc::test::bad_input

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
    return {};
}

/** Large maps and landmark imports. */
Cases largeMapCases()
{
    return {};
}

}  // namespace semloc::test::bad_input

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

namespace
{
/** semloc-import-landmarks' small dataset with landmark 2's id written as `id`. */
std::vector<std::string> importLandmarkId(const fs::path& d, const std::string& id)
{
    auto a = importLandmarks(d, {});
    writeText(d / "in.rawlog_ground_truth.txt", "4 0.5 0 0 0 0 1\n5 1 0 0 0 0 " + id + "\n");
    return a;
}
}  // namespace

/** Large maps and landmark imports. */
Cases largeMapCases()
{
    return {
        {"import-landmark-id-hex", [](const fs::path& d) { return importLandmarkId(d, "0x10"); }},
        {"import-landmark-id-exponent",
         [](const fs::path& d) { return importLandmarkId(d, "1e3"); }},
        {"import-csv-landmark-id-hex",
         [](const fs::path& d) {
             return importCsv(d, {{"lm.csv", "id,label,x,y\n1,buoy,9,5\n0x10,buoy,12,6\n"}});
         }},
        {"import-csv-landmark-id-exponent",
         [](const fs::path& d) {
             return importCsv(d, {{"lm.csv", "id,label,x,y\n1,buoy,9,5\n1e3,buoy,12,6\n"}});
         }},
        {"import-csv-detection-id-exponent",
         [](const fs::path& d)
         {
             return importCsv(d, {{"det.csv",
                                   "t,label,range_m,bearing_rad,id\n1,buoy,3,0.1,1\n"
                                   "2,,,,\n3,buoy,2,0.2,2e0\n"}});
         }},
    };
}

}  // namespace semloc::test::bad_input

/* semloc tests — the bad inputs of docs/bad-input.md's table that a hostile user tries: special
 * files where a file is read, benchmark shards and merges, calibration, large maps. Each case
 * writes its input in a fresh directory and returns the tool's command line (test_BadInput.cpp
 * runs it and checks the row). */
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <cmath>
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
/** The paper world with `extra` beacons on a 29 m grid around the area beside its three (about
 *  150 within the 200 m of the acoustic transducer), 10 m below, as d/world.yaml. */
fs::path worldWithBeacons(const fs::path& d, size_t extra)
{
    World w = World::FromFile(kSrc + "/maps/paper_50x50_lbl.yaml");
    const size_t side = static_cast<size_t>(std::ceil(std::sqrt(static_cast<double>(extra))));
    for (size_t k = 0; k < extra; k++)
    {
        WorldBeacon b;
        b.id = static_cast<int>(100 + k);
        const size_t column = k % side, row = k / side;
        b.x = 25.5 + 29.0 * (static_cast<double>(column) - 0.5 * static_cast<double>(side));
        b.y = 25.5 + 29.0 * (static_cast<double>(row) - 0.5 * static_cast<double>(side));
        b.z = -10;
        w.beacons.push_back(b);
    }
    w.saveToFile((d / "world.yaml").string());
    return d / "world.yaml";
}

/** A 6-step dataset of semloc-simulate's [BeaconRanging] in `world`, localized by
 *  semantic_lbl.ini's maps and filter (semantic.ini with a beacon map, its recovery off; 200
 *  particles). */
std::vector<std::string> localizeBeacons(const fs::path& d, const fs::path& world)
{
    auto o = TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate_lbl.ini");
    o.simulation.world_file = world.string();
    o.simulation.max_steps = 6;
    saveGz(Simulator(o).run().rawlog, d / "data.rawlog");
    return localize(
        d,
        writeIni(d,
                 "[MetricMap]\nbeaconMap_count = 1\n"
                 "[MetricMap_beaconMap_00_likelihoodOpts]\nrangeStd = 0.5\n",
                 {{"map_file", world.string()}, {"trigger", "off"}, {"lost_var_xy_m2", "0"}}),
        d / "data.rawlog");
}

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
        {"beacon-map-sonar-skipped",
         [](const fs::path& d) { return localizeBeacons(d, kSrc + "/maps/paper_50x50_lbl.yaml"); }},
        {"beacon-map-100000-beacons",
         [](const fs::path& d) { return localizeBeacons(d, worldWithBeacons(d, 100000)); }},
    };
}

}  // namespace semloc::test::bad_input

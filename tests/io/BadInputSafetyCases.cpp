/* semloc tests — the bad inputs of docs/bad-input.md's table that a hostile user tries: special
 * files where a file is read, benchmark shards and merges, calibration, large maps, the active
 * control's cost and a vehicle that cannot move. Each case
 * writes its input in a fresh directory and returns the tool's command line (test_BadInput.cpp
 * runs it and checks the row). */
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{

namespace
{
/** A FIFO at `p` (nothing ever writes it: a reader that opened it would wait forever). */
fs::path fifo(const fs::path& p)
{
    if (::mkfifo(p.c_str(), 0600) != 0)
    {
        throw std::runtime_error("mkfifo " + p.string() + ": " + std::strerror(errno));
    }
    return p;
}

/** `argv` with the argument after `option` replaced by `value`. */
std::vector<std::string> with(std::vector<std::string> argv, const std::string& option,
                              const std::string& value)
{
    const auto at = std::find(argv.begin(), argv.end(), option);
    if (at == argv.end() || at + 1 == argv.end())
    {
        throw std::runtime_error("no option " + option);
    }
    *(at + 1) = value;
    return argv;
}
/** Special files (devices, FIFOs), oversized files, link loops and directories as an ini. */
Cases iniSpecialFileCases()
{
    return {
        {"ini-device",
         [](const fs::path& d) { return localize(d, "/dev/zero", d / "data.rawlog"); }},
        {"ini-fifo",
         [](const fs::path& d) { return localize(d, fifo(d / "loc.ini"), d / "data.rawlog"); }},
        {"ini-too-large",
         [](const fs::path& d)
         {
             writeText(d / "loc.ini", "");
             fs::resize_file(d / "loc.ini", 17u << 20);  // sparse: no disk used
             return localize(d, d / "loc.ini", d / "data.rawlog");
         }},
        {"ini-symlink-loop",  // beside the case's directory, whose listing would fail
         [](const fs::path& d)
         {
             const fs::path out = d.parent_path();
             fs::create_symlink("b.ini", out / "a.ini");
             fs::create_symlink("a.ini", out / "b.ini");
             return localize(d, out / "a.ini", d / "data.rawlog");
         }},
        {"ini-base-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "adir");
             writeText(d / "loc.ini", "base = adir\n");
             return localize(d, d / "loc.ini", d / "data.rawlog");
         }},
    };
}

/** The same for rawlogs, ground truth, worlds and the other tools; outputs over a base. */
Cases dataSpecialFileCases()
{
    return {
        {"rawlog-device", [](const fs::path& d) { return localize(d, writeIni(d), "/dev/zero"); }},
        {"rawlog-null", [](const fs::path& d) { return localize(d, writeIni(d), "/dev/null"); }},
        {"rawlog-fifo",
         [](const fs::path& d) { return localize(d, writeIni(d), fifo(d / "data.rawlog")); }},
        {"gt-device",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"ground_truth_path_file", "/dev/zero"}});
         }},
        {"benchmark-ini-device",
         [](const fs::path&) {
             return std::vector<std::string>{"semloc-benchmark", "/dev/zero"};
         }},
        {"simulate-ini-device",
         [](const fs::path&) {
             return std::vector<std::string>{"semloc-simulate", "/dev/zero"};
         }},
        {"world-device",
         [](const fs::path& d)
         {
             return std::vector<std::string>{"semloc-plot-world", "/dev/zero", "-o",
                                             (d / "w.png").string()};
         }},
        {"calibrate-base-device", [](const fs::path& d)
         { return with(calibrate(d, 100, "semantic", "out.ini"), "--base", "/dev/zero"); }},
        {"calibrate-rawlog-device",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             a[1] = "/dev/zero";
             return a;
         }},
        {"import-landmarks-device",
         [](const fs::path& d)
         {
             auto a = importLandmarks(d, {});
             a[1] = "/dev/zero";
             return a;
         }},
        {"simulate-out-replaces-base",
         [](const fs::path& d)
         {
             writeText(d / "d5.ini", "// semloc-simulate: \n[Simulation]\nworld_file = " + kSrc +
                                         "/maps/paper_50x50.yaml\n");
             writeText(d / "over.ini", "base = d5.ini\n[Simulation]\nseed = 3\n");
             return std::vector<std::string>{"semloc-simulate", (d / "over.ini").string(), "-o",
                                             (d / "d5.rawlog").string()};
         }},
        {"calibrate-out-replaces-base",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "cal.ini");
             writeText(d / "cal.ini", "// semloc-calibrate: \n" + readText(d / "base.ini"));
             writeText(d / "base2.ini", "base = cal.ini\n");
             return with(a, "--base", (d / "base2.ini").string());
         }},
    };
}

}  // namespace

/** Special files, oversized files, link loops, directories; outputs over a base. */
Cases specialFileCases()
{
    Cases all = iniSpecialFileCases();
    const Cases more = dataSpecialFileCases();
    all.insert(more.begin(), more.end());
    return all;
}

namespace
{
/** dir/bench.ini: 2 runs of 5 steps of config/localize/semantic.ini (the variant `semantic`,
 *  100 particles, into `out`), then the [Benchmark] lines of `extra`. */
fs::path writeBenchIni(const fs::path& dir, const std::string& extra,
                       const std::string& name = "bench.ini", int particles = 100)
{
    writeText(dir / name, "[Benchmark]\nruns = 2\nvariants = semantic\nvariants_dir = " + kSrc +
                              "/config/localize\nsimulate_ini = " + kSrc +
                              "/config/simulate/simulate.ini\nmax_steps = 5\nparticles = " +
                              std::to_string(particles) + "\njobs = 1\noutput_dir = out\n" + extra);
    return dir / name;
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

/** Runs semloc-benchmark with `args` in `dir` (the making of a case's input), quietly. */
void runBenchmark(const fs::path& dir, const std::string& args)
{
    const std::string cmd = "cd '" + dir.string() + "' && '" + kBin + "/semloc-benchmark' " + args +
                            " > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

/** The shards a (run 1) and b (run 2) of writeBenchIni() in `dir`, `damage` done to a's run
 *  file, then their merge into `merged`. */
Builder mergeDamaged(
    const std::function<void(const fs::path& dir, const fs::path& runFile)>& damage)
{
    return [damage](const fs::path& d)
    {
        writeBenchIni(d, "");
        runBenchmark(d, "bench.ini --runs 1:1 -o a");
        runBenchmark(d, "bench.ini --runs 2:2 -o b");
        damage(d, d / "a" / "runs" / "run_000001.txt");
        return std::vector<std::string>{"semloc-benchmark", "--merge", (d / "a").string(),
                                        (d / "b").string(), "-o",      (d / "merged").string()};
    };
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
        {"benchmark-merge-run-file-of-another-benchmark",
         mergeDamaged(
             [](const fs::path& d, const fs::path& runFile)
             {
                 writeBenchIni(d, "", "other.ini", 300);
                 runBenchmark(d, "other.ini --runs 1:1 -o other");
                 fs::copy_file(d / "other" / "runs" / "run_000001.txt", runFile,
                               fs::copy_options::overwrite_existing);
             })},
        {"benchmark-merge-run-file-edited", mergeDamaged(
                                                [](const fs::path&, const fs::path& runFile)
                                                {
                                                    std::string text = readText(runFile);
                                                    const auto step = text.find(
                                                        "\n0 ");  // the first step: its time edited
                                                    text.insert(step + 3, "1");
                                                    writeText(runFile, text);
                                                })},
        {"benchmark-merge-run-file-symlink", mergeDamaged(
                                                 [](const fs::path&, const fs::path& runFile)
                                                 {
                                                     fs::remove(runFile);
                                                     fs::create_symlink("/dev/zero", runFile);
                                                 })},
        {"benchmark-merge-run-file-missing",
         mergeDamaged([](const fs::path&, const fs::path& runFile) { fs::remove(runFile); })},
        {"benchmark-shard-over-whole-benchmark",
         [](const fs::path& d)
         {
             writeBenchIni(d, "");
             runBenchmark(d, "bench.ini");  // into output_dir = out
             return std::vector<std::string>{"semloc-benchmark", "bench.ini", "--runs", "1:1"};
         }},
        {"benchmark-whole-over-shard",
         [](const fs::path& d)
         {
             writeBenchIni(d, "");
             runBenchmark(d, "bench.ini --runs 1:1 -o out");
             return std::vector<std::string>{"semloc-benchmark", "bench.ini"};
         }},
        {"benchmark-merge-over-shard",
         [](const fs::path& d)
         {
             writeBenchIni(d, "");
             for (const char* runs : {"1:1 -o a", "2:2 -o b", "1:1 -o c"})
             {
                 runBenchmark(d, std::string("bench.ini --runs ") + runs);
             }
             return std::vector<std::string>{"semloc-benchmark", "--merge", "a", "b", "-o", "c"};
         }},
        {"benchmark-runs-blank", shardRuns(" 1:2")},
        {"benchmark-runs-sign", shardRuns("+1:+2")},
    };
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
        {"benchmark-active-series-costly", [=](const fs::path& d)
         { return activeBenchmark(d, "look_around = true\nrepresentatives = 24\n"); }},
        {"benchmark-active-vehicle-stuck",
         [=](const fs::path& d) { return activeBenchmark(d, "distances_m = 1000\n"); }},
    };
}

}  // namespace semloc::test::bad_input

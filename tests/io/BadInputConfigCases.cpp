/* semloc tests — the bad inputs of docs/bad-input.md's table: the command line, ini files, outputs,
 * worlds. Each case builds its input in a fresh directory and returns the tool's command line
 * (test_BadInput.cpp runs it and checks the row). */
#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{

/** The command line of each tool. */
Cases commandLineCases()
{
    return {
        {"cli-unknown-option",
         [](const fs::path& d) {
             return localizeGood(d, "", {}, {"--particle", "500"});
         }},
        {"cli-threads-out-of-range",
         [](const fs::path& d) {
             return localizeGood(d, "", {}, {"-t", "5000"});
         }},
        {"cli-seed-negative",
         [](const fs::path& d) {
             return localizeGood(d, "", {}, {"-s", "-1"});
         }},
        {"cli-particles-beyond-memory",  // a 1 GB RLIMIT_RSS (`ulimit -m`), which the tool inherits
         [](const fs::path& d)
         {
             rlimit r{};
             EXPECT_EQ(::getrlimit(RLIMIT_RSS, &r), 0);
             r.rlim_cur = 1000000000;
             EXPECT_EQ(::setrlimit(RLIMIT_RSS, &r), 0);
             return localizeGood(d, "", {}, {"-n", "10000000"});
         }},
        {"cli-missing-argument",
         [](const fs::path&) { return std::vector<std::string>{"semloc-simulate"}; }},
        {"cli-extra-argument",
         [](const fs::path&) {
             return std::vector<std::string>{"semloc-ini-reference", "semantic.ini"};
         }},
    };
}

/** The ini file: its syntax, keys and values. */
Cases iniFileCases()
{
    return {
        {"ini-missing",
         [](const fs::path& d) { return localize(d, d / "nope.ini", d / "data.rawlog"); }},
        {"ini-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "dir.ini");
             return localize(d, d / "dir.ini", d / "data.rawlog");
         }},
        {"ini-syntax",  // its own file: the line number must not follow semantic.ini's length
         [](const fs::path& d)
         {
             writeText(d / "loc.ini", "[PF_options]\nBETA 0.5\n");
             return std::vector<std::string>{"semloc-localize", (d / "loc.ini").string()};
         }},
        {"ini-unclosed-expansion",  // on a file with a base: MRPT named a line of neither
         [](const fs::path& d)
         {
             writeText(d / "loc.ini", "base = " + kSrc +
                                          "/config/localize/semantic.ini\n[LocalizationExperiment]"
                                          "\nvariant = ${NAME\n");
             return std::vector<std::string>{"semloc-localize", (d / "loc.ini").string()};
         }},
        {"ini-duplicate-key",  // semantic.ini sets BETA in [PF_options] already
         [](const fs::path& d) { return localizeGood(d, "[PF_options]\nbeta = 0.4"); }},
        {"ini-utf8-bom",  // the mark right before the first section, as an editor writes it
         [](const fs::path& d)
         {
             auto a = localizeGood(d, "", {{"convergence_min_steps", "7"}});
             const std::string text = readText(d / "loc.ini");
             writeText(d / "loc.ini",
                       "\xEF\xBB\xBF" + text.substr(text.find("[LocalizationExperiment]")));
             return a;
         }},
        {"ini-unknown-section", [](const fs::path& d) { return localizeGood(d, "[PF_option]"); }},
        {"ini-unknown-key",
         [](const fs::path& d) { return localizeGood(d, "[PF_options]\nBETTA = 0.5"); }},
        {"ini-wrong-type",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"threads", "two"}});
         }},
        {"ini-out-of-range",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"BETA", "1.5"}});
         }},
        {"ini-nan",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"sigma_range_m", "nan"}});
         }},
        {"ini-motion-model-unknown-source",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"source", "recompute"}});
         }},
        {"ini-motion-model-unknown-key",
         [](const fs::path& d) { return localizeGood(d, "[MotionModel]\na5 = 0.1"); }},
        {"ini-motion-model-out-of-range",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"a1", "-0.1"}});
         }},
        {"ini-motion-model-nan",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"a4", "nan"}});
         }},
        {"rawlog-motion-model-scan-matching",
         [](const fs::path& d)
         {
             auto sim = simulate();
             using mrpt::obs::CActionRobotMovement2D;
             auto m = sim.rawlog.getAsAction(2)->getActionByClass<CActionRobotMovement2D>();
             m->estimationMethod = CActionRobotMovement2D::emScan2DMatching;
             saveGz(sim.rawlog, d / "data.rawlog");
             return localize(d, writeIni(d, "", {{"source", "gaussian"}}), d / "data.rawlog");
         }},
    };
}

/** The semantic model's and the recovery's options that only fail together with others or
 *  out of their range. */
Cases iniModelCases()
{
    return {
        {"ini-heading-drift-negative",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"heading_drift_std_deg_per_min", "-5"}});
         }},
        {"ini-heading-drift-needs-standard-proposal",
         [](const fs::path& d)
         {
             return localizeGood(d, "",
                                 {{"heading_drift_std_deg_per_min", "10"},
                                  {"PF_algorithm", "1"},
                                  {"free_space_prior", "0"},
                                  {"trigger", "off"},
                                  {"lost_var_xy_m2", "0"},
                                  {"outage_every_s", "0"}});
         }},
        {"ini-association-needs-probabilistic",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(
                 d, writeConfig(d, "semantic", {{"model", "paper"}, {"association", "marginal"}}),
                 d / "data.rawlog");
         }},
        {"ini-outage-needs-probabilistic",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(
                 d, writeConfig(d, "semantic", {{"model", "paper"}, {"outage_every_s", "300"}}),
                 d / "data.rawlog");
         }},
        {"ini-outage-mean-out-of-range",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"outage_every_s", "300"}, {"outage_mean_s", "0"}});
         }},
        {"ini-outage-needs-standard-proposal",
         [](const fs::path& d)
         {
             return localizeGood(d, "",
                                 {{"outage_every_s", "300"},
                                  {"PF_algorithm", "1"},
                                  {"free_space_prior", "0"},
                                  {"heading_drift_walk_deg_per_min", "0"},
                                  {"trigger", "off"},
                                  {"lost_var_xy_m2", "0"}});
         }},
    };
}

/** The recovery's options, KLD at the resampling steps and the paper model's penalty, each
 *  out of its range or together with an option it cannot go with. */
Cases iniRecoveryCases()
{
    return {
        {"ini-recovery-trigger-unknown",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"trigger", "cusum"}});
         }},
        {"ini-recovery-rates-with-evidence",
         [](const fs::path& d)
         {
             return localizeGood(
                 d, "", {{"trigger", "evidence"}, {"alpha_slow", "0.001"}, {"alpha_fast", "0.1"}});
         }},
        {"ini-recovery-evidence-without-semantic-map",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, writeConfig(d, "geometric", {{"trigger", "evidence"}}),
                             d / "data.rawlog");
         }},
        {"ini-recovery-injected-weight-zero",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"injected_weight", "0"}});
         }},
        {"ini-recovery-challengers-with-mrpt-kld",
         [](const fs::path& d)
         {
             return localizeGood(d, "",
                                 {{"challenger_frames", "20"},
                                  {"adaptiveSampleSize", "1"},
                                  {"resamplingMethod", "0"}});
         }},
        {"ini-recovery-challenger-frames-negative",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"challenger_frames", "-1"}});
         }},
        {"ini-recovery-lost-without-recovery",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"trigger", "off"}, {"lost_var_xy_m2", "10"}});
         }},
        {"ini-recovery-lost-var-negative",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"lost_var_xy_m2", "-1"}});
         }},
        {"ini-kld-at-resampling-without-kld",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"kld_at_resampling", "1"}});
         }},
        {"ini-missed-object-penalty-out-of-range",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"missed_object_penalty", "1.5"}});
         }},
    };
}

/** The maps of an ini, and the other tools' sections. */
Cases iniMapCases()
{
    return {
        {"ini-association-unknown",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"association", "permanent"}});
         }},
        {"ini-unknown-map",
         [](const fs::path& d) { return localizeGood(d, "[MetricMap]\nsemantikMap_count = 1"); }},
        {"ini-map-inf",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, writeConfig(d, "grid_lf", {{"LF_stdHit", "inf"}}),
                             d / "data.rawlog");
         }},
        {"ini-map-enum-unknown",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, writeConfig(d, "grid_lf", {{"likelihoodMethod", "lmBogus"}}),
                             d / "data.rawlog");
         }},
        {"ini-init-detections-needs-semantic-map",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, writeConfig(d, "geometric", {{"init_PDF_mode", "3"}}),
                             d / "data.rawlog");
         }},
        {"ini-rawlog-offset-past-end",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"rawlog_offset", "6"}});
         }},
        {"map-file-missing",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"map_file", (d / "nope.yaml").string()}});
         }},
        {"simulate-out-of-range",
         [](const fs::path& d)
         {
             writeText(d / "sim.ini", "[Simulation]\nworld_file = " + kSrc +
                                          "/maps/paper_50x50.yaml\n[Sonar]\nbeam_count = 0\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "sim.rawlog").string()};
         }},
        {"benchmark-world-removed-share-out-of-range",
         [](const fs::path& d)
         {
             writeText(d / "gone.ini", "[Scenario]\nname = gone\nworld_removed_share = 1.5\n");
             writeText(
                 d / "bench.ini",
                 "[Benchmark]\nruns = 1\nvariants = " + kSrc +
                     "/config/localize/semantic.ini\nsimulate_ini = " + kSrc +
                     "/config/simulate/simulate.ini\nscenarios = " + (d / "gone.ini").string() +
                     "\noutput_dir = " + (d / "results").string() + "\n");
             return std::vector<std::string>{"semloc-benchmark", (d / "bench.ini").string()};
         }},
        {"benchmark-unknown-key",
         [](const fs::path& d)
         {
             writeText(d / "bench.ini", "[Benchmark]\nruns = 1\nrun = 2\noutput_dir = " +
                                            (d / "results").string() + "\n");
             return std::vector<std::string>{"semloc-benchmark", (d / "bench.ini").string()};
         }},
    };
}

/** semloc-benchmark's shards: a cut beyond the benchmark's runs, a merge of shards that
 *  overlap. */
Cases shardCases()
{
    return {
        {"benchmark-shard-beyond-the-runs",
         [](const fs::path& d)
         {
             writeText(d / "bench.ini", "[Benchmark]\nruns = 2\nvariants = " + kSrc +
                                            "/config/localize/semantic.ini\nsimulate_ini = " +
                                            kSrc + "/config/simulate/simulate.ini\n");
             return std::vector<std::string>{
                 "semloc-benchmark",    (d / "bench.ini").string(), "--runs", "2:3", "-o",
                 (d / "shard").string()};
         }},
        {"benchmark-merge-overlapping-shards",
         [](const fs::path& d)
         {
             for (const auto& [dir, first] : {std::pair<const char*, int>{"a", 1}, {"b", 2}})
             {
                 fs::create_directories(d / dir);
                 writeText(d / dir / "shard.txt", "benchmark " + (d / "bench.ini").string() +
                                                      "\ndigest 0123456789abcdef\nruns 4\nfirst " +
                                                      std::to_string(first) + "\nlast " +
                                                      std::to_string(first + 2) + "\n");
             }
             return std::vector<std::string>{
                 "semloc-benchmark", "--merge", (d / "a").string(),
                 (d / "b").string(), "-o",      (d / "merged").string()};
         }},
    };
}

/** semloc-localize's output directory: nothing but a previous output is ever
 *  replaced. */
Cases outputDirectoryCases()
{
    return {
        {"out-dir-working-directory",
         [](const fs::path& d)
         {
             auto a = localizeGood(d);
             a[4] = ".";
             return a;
         }},
        {"out-dir-holds-input",
         [](const fs::path& d)
         {
             fs::create_directory(d / "data");
             saveGz(simulate().rawlog, d / "data" / "data.rawlog");
             auto a = localize(d, writeIni(d), d / "data" / "data.rawlog");
             a[4] = (d / "data").string();
             return a;
         }},
        {"out-dir-not-semloc",
         [](const fs::path& d)
         {
             fs::create_directory(d / "results");
             writeText(d / "results" / "notes.txt", "my notes\n");
             auto a = localizeGood(d);
             a[4] = (d / "results").string();
             return a;
         }},
        {"out-dir-is-a-file",  // with an unreadable rawlog: refused before any reading
         [](const fs::path& d)
         {
             writeText(d / "afile", "my notes\n");
             writeText(d / "data.rawlog", "t x y phi\n1 2 3 4\n");
             auto a = localize(d, writeIni(d), d / "data.rawlog");
             a[4] = (d / "afile").string();
             return a;
         }},
        {"out-dir-dangling-link",
         [](const fs::path& d)
         {
             fs::create_directory_symlink(d / "gone", d / "link");
             auto a = localizeGood(d);
             a[4] = (d / "link").string();
             return a;
         }},
        {"out-dir-unwritable",
         [](const fs::path& d)
         {
             auto a = localizeGood(d);
             a[4] = "/proc/semloc-out";
             return a;
         }},
    };
}

/** The other tools' outputs: nothing but a previous output is ever replaced. */
Cases outputFileCases()
{
    return {
        {"benchmark-out-dir-working-directory",
         [](const fs::path& d)
         {
             writeText(d / "one.ini", "[Benchmark]\nruns = 1\nvariants = " + kSrc +
                                          "/config/localize/semantic.ini\nsimulate_ini = " + kSrc +
                                          "/config/simulate/simulate.ini\n");
             return std::vector<std::string>{"semloc-benchmark", (d / "one.ini").string(), "-o",
                                             "."};
         }},
        {"simulate-out-is-config",
         [](const fs::path& d)
         {
             writeText(d / "sim.ini",
                       "[Simulation]\nworld_file = " + kSrc + "/maps/paper_50x50.yaml\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "sim.rawlog").string()};
         }},
        {"simulate-gap-min-above-max",
         [](const fs::path& d)
         {
             writeText(d / "sim.ini", "[Simulation]\nworld_file = " + kSrc +
                                          "/maps/paper_50x50.yaml\n[SemanticDetector]\n"
                                          "gap_min_s = 90\ngap_max_s = 60\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "sim.rawlog").string()};
         }},
        {"simulate-csv-holds-input",
         [](const fs::path& d)
         {
             fs::create_directory(d / "cfg");
             writeText(d / "cfg" / "sim.ini",
                       "[Simulation]\nworld_file = " + kSrc + "/maps/paper_50x50.yaml\n");
             return std::vector<std::string>{"semloc-simulate",
                                             (d / "cfg" / "sim.ini").string(),
                                             "-o",
                                             (d / "s.rawlog").string(),
                                             "--csv",
                                             (d / "cfg").string()};
         }},
        {"simulate-out-is-a-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "out.rawlog");
             return std::vector<std::string>{"semloc-simulate",
                                             kSrc + "/config/simulate/simulate.ini", "-o",
                                             (d / "out.rawlog").string()};
         }},
        {"simulate-companion-not-semloc",
         [](const fs::path& d)
         {
             writeText(d / "notes.ini", "my notes\n");
             return std::vector<std::string>{"semloc-simulate",
                                             kSrc + "/config/simulate/simulate.ini", "-o",
                                             (d / "notes.rawlog").string()};
         }},
        {"plot-out-is-input",
         [](const fs::path& d)
         {
             auto a = plotWorld(d, kBounds + "objects: []\n");
             a[3] = (d / "w.yaml").string();
             return a;
         }},
        {"import-out-is-input",
         [](const fs::path& d)
         {
             writeText(d / "in.rawlog", plainBytes(d));
             return std::vector<std::string>{"semloc-import-landmarks", (d / "in.rawlog").string(),
                                             "-o", (d / "in.rawlog").string()};
         }},
    };
}

/** Outputs over files semloc did not write, and through symbolic links: refused. */
Cases outputOverUserFileCases()
{
    return {
        {"simulate-out-not-semloc",
         [](const fs::path& d)
         {
             writeText(d / "my.rawlog", plainBytes(d));  // MRPT's rawlog, not semloc's
             return std::vector<std::string>{"semloc-simulate",
                                             kSrc + "/config/simulate/simulate.ini", "-o",
                                             (d / "my.rawlog").string()};
         }},
        {"plot-out-not-semloc",
         [](const fs::path& d)
         {
             writeText(d / "photo.png", "\x89PNG\r\n\x1a\n a photograph");
             auto a = plotWorld(d, kBounds + "objects: []\n");
             a[3] = (d / "photo.png").string();
             return a;
         }},
        {"plot-out-dangling-link",
         [](const fs::path& d)
         {
             fs::create_symlink(d / "nowhere" / "w.png", d / "link.png");
             auto a = plotWorld(d, kBounds + "objects: []\n");
             a[3] = (d / "link.png").string();
             return a;
         }},
    };
}

/** The world YAML: syntax, keys, values and geometry. */
Cases worldSyntaxCases()
{
    return {
        {"yaml-syntax",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: point, "
                                     "center: [5, 5]}\n   extra: 3\n");
         }},
        {"world-unknown-key",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: point, "
                                     "centre: [5, 5]}\n");
         }},
        {"world-wrong-type",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: cylinder, "
                                     "center: [5, 5], radius: wide}\n");
         }},
        {"world-nan",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: cylinder, "
                                     "center: [5, 5], radius: .nan}\n");
         }},
        {"world-duplicate-id",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: point, center: [5, "
                                     "5]}\n  - {id: 1, label: b, shape: point, center: [8, 8]}\n");
         }},
        {"world-self-intersecting",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: polygon, "
                                     "points: [[2, 2], [8, 8], [8, 2], [2, 8]]}\n");
         }},
        {"world-outside-bounds",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: point, center: "
                                     "[25, 5]}\n");
         }},
        {"world-empty-bounds",
         [](const fs::path& d)
         {
             return plotWorld(d,
                              "name: w\nbounds: {x_min: 5, x_max: 5, y_min: 0, y_max: 20}\n"
                              "objects: []\n");
         }},
        {"world-coordinate-too-large",
         [](const fs::path& d)
         {
             return plotWorld(d,
                              "name: w\nbounds: {x_min: 0, x_max: 1e300, y_min: 0, y_max: 20}\n"
                              "objects: []\n");
         }},
    };
}

/** The world YAML: trajectories, grids and what YAML allows but a world does not. */
Cases worldContentCases()
{
    return {
        {"world-trajectory-through-object",
         [](const fs::path& d)
         {
             writeText(d / "w.yaml", kBounds +
                                         "objects:\n  - {id: 1, label: a, shape: box, center: "
                                         "[10, 10], size: [2, 2]}\ntrajectory:\n  speed_mps: 1\n"
                                         "  waypoints: [[2, 2], [2, 10], [18, 10]]\n");
             writeText(d / "sim.ini",
                       "[Simulation]\nworld_file = " + (d / "w.yaml").string() + "\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "data.rawlog").string()};
         }},
        {"world-trajectory-zero-length",
         [](const fs::path& d)
         {
             writeText(d / "w.yaml", kBounds +
                                         "objects: []\ntrajectory:\n  speed_mps: 1\n"
                                         "  waypoints: [[3, 4], [3, 4]]\n");
             writeText(d / "sim.ini",
                       "[Simulation]\nworld_file = " + (d / "w.yaml").string() + "\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "data.rawlog").string()};
         }},
        {"grid-too-large-for-resolution",
         [](const fs::path& d)
         {
             // config/localize/grid_lf.ini (0.1 m cells) on a 7 x 7 km world.
             writeText(d / "w.yaml",
                       "name: w\nbounds: {x_min: 0, x_max: 7000, y_min: 0, y_max: "
                       "7000}\nobjects: []\n");
             std::istringstream in(resolvedIni(kSrc + "/config/localize/grid_lf.ini"));
             std::string ini;
             for (std::string line; std::getline(in, line);)
             {
                 if (line.rfind("map_file ", 0) == 0)
                 {
                     line = "map_file = " + (d / "w.yaml").string();
                 }
                 ini += line + "\n";
             }
             writeText(d / "loc.ini", ini);
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, d / "loc.ini", d / "data.rawlog");
         }},
        {"world-duplicate-key",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: cylinder, "
                                     "center: [5, 5], radius: 1, radius: 3}\n");
         }},
        {"world-yaml-alias",
         [](const fs::path& d)
         {
             return plotWorld(d, kBounds +
                                     "objects:\n  - {id: 1, label: a, shape: point, "
                                     "center: &c [5, 5]}\n  - {id: 2, label: b, shape: point, "
                                     "center: *c}\n");
         }},
        {"world-label-too-long",  // semloc-simulate wrote what semloc-localize refused
         [](const fs::path& d)
         {
             writeText(d / "w.yaml",
                       kBounds + "objects:\n  - {id: 1, label: " + std::string(1000000, 'x') +
                           ", shape: cylinder, center: [10, 10], radius: 1}\n"
                           "trajectory: {speed_mps: 1, waypoints: [[2, 2], [18, 2]]}\n");
             writeText(d / "w.ini", "[Simulation]\nworld_file = " + (d / "w.yaml").string() +
                                        "\nmax_steps = 3\n");
             return std::vector<std::string>{"semloc-simulate", (d / "w.ini").string(), "-o",
                                             (d / "sim.rawlog").string()};
         }},
    };
}

}  // namespace semloc::test::bad_input

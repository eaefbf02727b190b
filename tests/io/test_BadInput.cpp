/* semloc tests — every row of docs/bad-input.md's table, run through the real tools:
 * the case's bad input is built in a fresh directory, the tool runs on it, and
 * - `error` rows: exit code != 0, stderr holds the row's message, the directory is
 *   unchanged (no output, nothing half-written);
 * - `counted` rows: exit code 0 and summary.yaml holds the row's excerpt;
 * - `accepted` rows (an input that looks wrong but is fine): the same as `counted`.
 * A row without a case below, or a case without a row, fails TableAndCasesMatch. */
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

namespace fs = std::filesystem;

namespace
{
const std::string kSrc = SEMLOC_SOURCE_DIR;
const std::string kBin = SEMLOC_BIN_DIR;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

using semloc::test::readText;
void writeText(const fs::path& p, const std::string& s)
{
    std::ofstream(p, std::ios::binary) << s;
}

/** One row of the table. */
struct Row
{
    std::string id, tool, result, message;
};

/** The rows between the bad-input markers: | `id` | tool | input | case | result | `message` |. */
std::vector<Row> tableRows()
{
    std::istringstream in(readText(kSrc + "/docs/bad-input.md"));
    std::vector<Row> rows;
    bool inside = false;
    for (std::string line; std::getline(in, line);)
    {
        if (line.find("<!-- bad-input:begin -->") != std::string::npos)
        {
            inside = true;
            continue;
        }
        if (line.find("<!-- bad-input:end -->") != std::string::npos)
        {
            break;
        }
        if (!inside || line.rfind("| `", 0) != 0)
        {
            continue;
        }
        std::vector<std::string> cells;
        for (size_t b = 1, e; (e = line.find(" | ", b)) != std::string::npos || b < line.size();)
        {
            if (e == std::string::npos)
            {
                e = line.rfind(" |");
            }
            std::string c = line.substr(b, e - b);
            c.erase(0, c.find_first_not_of(' '));
            cells.push_back(c);
            b = e + 3;
            if (b >= line.size())
            {
                break;
            }
        }
        auto unquote = [](std::string s)
        {
            if (s.size() >= 2 && s.front() == '`' && s.back() == '`')
            {
                s = s.substr(1, s.size() - 2);
            }
            return s;
        };
        EXPECT_EQ(cells.size(), 6u) << line;
        if (cells.size() == 6)
        {
            rows.push_back({unquote(cells[0]), cells[1], cells[4], unquote(cells[5])});
        }
    }
    return rows;
}

// ------------------------------------------------------------------ inputs

/** A 6-step simulated paper dataset (action / sensory-frame pairs). */
semloc::SimulationResult simulate()
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate.ini");
    o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
    o.simulation.max_steps = 6;
    return semloc::Simulator(o).run();
}

void saveGz(const mrpt::obs::CRawlog& log, const fs::path& p)
{
    ASSERT_TRUE(log.saveToRawLogFile(p.string()));
}

void savePlain(const mrpt::obs::CRawlog& log, const fs::path& p)
{
    mrpt::io::CFileOutputStream f(p.string());
    auto a = mrpt::serialization::archiveFrom(f);
    for (size_t i = 0; i < log.size(); i++)
    {
        a << *log.getAsGeneric(i);
    }
}

using Keys = std::vector<std::pair<std::string, std::string>>;

/** config/<name>.ini (semantic.ini by default) with an absolute map, 200 particles, the
 *  `keys` replaced (each must be in the file) and `extra` appended, written as dir/loc.ini. */
fs::path writeIni(const fs::path& dir, const std::string& extra = "", Keys keys = {},
                  const std::string& name = "semantic")
{
    for (const auto& kv :
         Keys{{"map_file", kSrc + "/maps/paper_50x50.yaml"}, {"particles_count", "200"}})
    {
        if (std::none_of(keys.begin(), keys.end(),
                         [&](const auto& p) { return p.first == kv.first; }))
        {
            keys.push_back(kv);
        }
    }
    std::istringstream in(readText(kSrc + "/config/" + name + ".ini"));
    std::string out;
    for (std::string line; std::getline(in, line);)
    {
        for (auto k = keys.begin(); k != keys.end(); ++k)
        {
            if (line.rfind(k->first + " ", 0) == 0 || line.rfind(k->first + "=", 0) == 0)
            {
                line = k->first + " = " + k->second;
                keys.erase(k);
                break;
            }
        }
        out += line + "\n";
    }
    EXPECT_TRUE(keys.empty()) << keys.front().first << " is not in " << name << ".ini";
    writeText(dir / "loc.ini", out + extra + "\n");
    return dir / "loc.ini";
}

/** Command line of a semloc-localize run with `ini` on `rawlog` into dir/out. */
std::vector<std::string> localize(const fs::path& dir, const fs::path& ini, const fs::path& rawlog,
                                  std::vector<std::string> extra = {})
{
    std::vector<std::string> a = {"semloc-localize",      ini.string(), rawlog.string(), "-o",
                                  (dir / "out").string(), "-q"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

/** A good dataset (gz rawlog) and the ini (see writeIni). */
std::vector<std::string> localizeGood(const fs::path& dir, const std::string& extra = "",
                                      const Keys& keys = {}, std::vector<std::string> args = {})
{
    saveGz(simulate().rawlog, dir / "data.rawlog");
    return localize(dir, writeIni(dir, extra, keys), dir / "data.rawlog", std::move(args));
}

/** The uncompressed bytes of the simulated rawlog. */
std::string plainBytes(const fs::path& dir)
{
    savePlain(simulate().rawlog, dir / "plain.tmp");
    std::string b = readText(dir / "plain.tmp");
    fs::remove(dir / "plain.tmp");
    return b;
}

/** A ground-truth case: the good dataset plus `gt` as its ground truth file. */
std::vector<std::string> localizeWithGroundTruth(const fs::path& dir, const std::string& gt)
{
    writeText(dir / "gt.txt", gt);
    return localizeGood(dir, "", {{"ground_truth_path_file", (dir / "gt.txt").string()}});
}

/** A world case: `objects`/`bounds` YAML text drawn by semloc-plot-world. */
std::vector<std::string> plotWorld(const fs::path& dir, const std::string& yaml)
{
    writeText(dir / "w.yaml", yaml);
    return {"semloc-plot-world", (dir / "w.yaml").string(), "-o", (dir / "w.png").string()};
}

const std::string kBounds = "name: w\nbounds: {x_min: 0, x_max: 20, y_min: 0, y_max: 20}\n";

/** A small landmark dataset as MRPT's simul-landmarks writes it (in.rawlog: 3 sensory frames
 *  of CObservationBearingRange seeing landmarks 1 and 2; its landmark and robot-path files)
 *  and the command line importing it with `options`. */
std::vector<std::string> importLandmarks(const fs::path& dir,
                                         const std::vector<std::string>& options)
{
    mrpt::obs::CRawlog log;
    for (int k = 0; k < 3; k++)
    {
        auto o = mrpt::obs::CObservationBearingRange::Create();
        o->timestamp = mrpt::Clock::fromDouble(1.0 + k);
        o->maxSensorDistance = 10;
        for (int id = 1; id <= 2; id++)
        {
            mrpt::obs::CObservationBearingRange::TMeasurement m;
            m.range = 3.0f + static_cast<float>(id);
            m.yaw = 0.1f * static_cast<float>(id);
            m.pitch = 0;
            m.landmarkID = id;
            o->sensedData.push_back(m);
        }
        mrpt::obs::CSensoryFrame sf;
        sf.insert(o);
        log.insert(sf);
    }
    saveGz(log, dir / "in.rawlog");
    writeText(dir / "in.rawlog_ground_truth.txt", "4 0.5 0 0 0 0 1\n5 1 0 0 0 0 2\n");
    writeText(dir / "in.rawlog_ground_truth_robot_path.txt",
              "0 0 0 0 0 0\n0.5 0 0 0 0 0\n1 0 0 0 0 0\n");
    std::vector<std::string> a = {"semloc-import-landmarks", (dir / "in.rawlog").string(), "-o",
                                  (dir / "lm.rawlog").string()};
    a.insert(a.end(), options.begin(), options.end());
    return a;
}

/** The simulated rawlog with `edit` applied to it (in memory), saved gz. */
std::vector<std::string> localizeEdited(const fs::path& dir,
                                        const std::function<void(mrpt::obs::CRawlog&)>& edit)
{
    auto sim = simulate();
    edit(sim.rawlog);
    saveGz(sim.rawlog, dir / "data.rawlog");
    return localize(dir, writeIni(dir), dir / "data.rawlog");
}

/** The first sensory frame's observation of class T. */
template <typename T>
std::shared_ptr<T> firstObservation(mrpt::obs::CRawlog& log)
{
    for (size_t i = 0; i < log.size(); i++)
    {
        if (const auto sf =
                std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(log.getAsGeneric(i)))
        {
            if (auto o = sf->getObservationByClass<T>())
            {
                return o;
            }
        }
    }
    return nullptr;
}

/** config/<name>.ini as writeIni() writes semantic.ini. */
fs::path writeConfig(const fs::path& dir, const std::string& name, const Keys& keys = {})
{
    return writeIni(dir, "", keys, name);
}

/** The simulated rawlog with `edit` applied, localized with config/<config>.ini. */
std::vector<std::string> localizeEditedWith(const fs::path& dir, const std::string& config,
                                            const std::function<void(mrpt::obs::CRawlog&)>& edit)
{
    auto sim = simulate();
    edit(sim.rawlog);
    saveGz(sim.rawlog, dir / "data.rawlog");
    return localize(dir, writeConfig(dir, config), dir / "data.rawlog");
}

/** The simulated rawlog with `edit` applied and its ground truth with every time multiplied
 *  by `timeScale`, as gt.txt. */
std::vector<std::string> localizeEditedWithGroundTruth(
    const fs::path& dir, const std::function<void(mrpt::obs::CRawlog&)>& edit, double timeScale = 1)
{
    auto sim = simulate();
    edit(sim.rawlog);
    saveGz(sim.rawlog, dir / "data.rawlog");
    std::string gt;
    for (const auto& r : sim.groundTruth)
    {
        gt += mrpt::format("%.6f %.6f %.6f %.6f\n", r.t * timeScale, r.x, r.y, r.phi);
    }
    writeText(dir / "gt.txt", gt);
    return localize(dir, writeIni(dir, "", {{"ground_truth_path_file", (dir / "gt.txt").string()}}),
                    dir / "data.rawlog");
}

/** Every observation of the rawlog's sensory frames, in order. */
std::vector<mrpt::obs::CObservation::Ptr> allObservations(mrpt::obs::CRawlog& log)
{
    std::vector<mrpt::obs::CObservation::Ptr> out;
    for (size_t i = 0; i < log.size(); i++)
    {
        if (const auto sf =
                std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(log.getAsGeneric(i)))
        {
            for (const auto& o : *sf)
            {
                out.push_back(o);
            }
        }
    }
    return out;
}

/** The observations of class T of the rawlog's sensory frames, in order. */
template <typename T>
std::vector<std::shared_ptr<T>> observationsOf(mrpt::obs::CRawlog& log)
{
    std::vector<std::shared_ptr<T>> out;
    for (const auto& o : allObservations(log))
    {
        if (auto t = std::dynamic_pointer_cast<T>(o))
        {
            out.push_back(t);
        }
    }
    return out;
}

using Builder = std::function<std::vector<std::string>(const fs::path&)>;

/** Every case of the table, by id. */
const std::map<std::string, Builder>& cases()
{
    static const std::map<std::string, Builder> c = {
        // ---- command line
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
        // ---- ini
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
        {"ini-duplicate-key",  // semantic.ini sets BETA in [PF_options] already
         [](const fs::path& d) { return localizeGood(d, "[PF_options]\nbeta = 0.4"); }},
        {"ini-utf8-bom",  // the mark right before the first section, as an editor writes it
         [](const fs::path& d)
         {
             const auto a = localizeGood(d, "", {{"convergence_min_steps", "7"}});
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
        {"benchmark-unknown-key",
         [](const fs::path& d)
         {
             writeText(d / "bench.ini", "[Benchmark]\nruns = 1\nrun = 2\noutput_dir = " +
                                            (d / "results").string() + "\n");
             return std::vector<std::string>{"semloc-benchmark", (d / "bench.ini").string()};
         }},
        // ---- output locations: nothing but a previous output is ever replaced
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
        {"out-dir-unwritable",
         [](const fs::path& d)
         {
             auto a = localizeGood(d);
             a[4] = "/proc/semloc-out";
             return a;
         }},
        {"benchmark-out-dir-working-directory",
         [](const fs::path& d)
         {
             writeText(d / "one.ini", "[Benchmark]\nruns = 1\nvariants = " + kSrc +
                                          "/config/semantic.ini\nsimulate_ini = " + kSrc +
                                          "/config/simulate.ini\n");
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
        {"simulate-out-is-a-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "out.rawlog");
             return std::vector<std::string>{"semloc-simulate", kSrc + "/config/simulate.ini",
                                             "-o", (d / "out.rawlog").string()};
         }},
        {"simulate-companion-not-semloc",
         [](const fs::path& d)
         {
             writeText(d / "notes.ini", "my notes\n");
             return std::vector<std::string>{"semloc-simulate", kSrc + "/config/simulate.ini",
                                             "-o", (d / "notes.rawlog").string()};
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
        // ---- world YAML
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
        {"world-trajectory-through-object",
         [](const fs::path& d)
         {
             writeText(d / "w.yaml", kBounds +
                                         "objects:\n  - {id: 1, label: a, shape: box, center: "
                                         "[10, 10], size: [2, 2]}\ntrajectory:\n  speed_mps: 1\n"
                                         "  waypoints: [[2, 2], [2, 10], [18, 10]]\n");
             writeText(d / "sim.ini", "[Simulation]\nworld_file = " + (d / "w.yaml").string() + "\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "data.rawlog").string()};
         }},
        {"world-trajectory-zero-length",
         [](const fs::path& d)
         {
             writeText(d / "w.yaml", kBounds + "objects: []\ntrajectory:\n  speed_mps: 1\n"
                                               "  waypoints: [[3, 4], [3, 4]]\n");
             writeText(d / "sim.ini", "[Simulation]\nworld_file = " + (d / "w.yaml").string() + "\n");
             return std::vector<std::string>{"semloc-simulate", (d / "sim.ini").string(), "-o",
                                             (d / "data.rawlog").string()};
         }},
        {"grid-too-large-for-resolution",
         [](const fs::path& d)
         {
             // config/grid_lf.ini (0.1 m cells) on a 7 x 7 km world.
             writeText(d / "w.yaml", "name: w\nbounds: {x_min: 0, x_max: 7000, y_min: 0, y_max: "
                                     "7000}\nobjects: []\n");
             std::istringstream in(readText(kSrc + "/config/grid_lf.ini"));
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
        // ---- rawlog
        {"rawlog-missing",
         [](const fs::path& d) { return localize(d, writeIni(d), d / "nope.rawlog"); }},
        {"rawlog-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "dir.rawlog");
             return localize(d, writeIni(d), d / "dir.rawlog");
         }},
        {"rawlog-empty",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", "");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-not-a-rawlog",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", "t x y phi\n1 2 3 4\n");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated-gz",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "full.rawlog");
             const std::string b = readText(d / "full.rawlog");
             fs::remove(d / "full.rawlog");
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated-allowed",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "data.rawlog", b.substr(0, b.size() * 6 / 10));
             return localize(d, writeIni(d), d / "data.rawlog", {"--allow-truncated"});
         }},
        {"rawlog-truncated-entry-0",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", plainBytes(d).substr(0, 40));
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-truncated-entry-0-allowed",
         [](const fs::path& d)
         {
             writeText(d / "data.rawlog", plainBytes(d).substr(0, 40));
             return localize(d, writeIni(d), d / "data.rawlog", {"--allow-truncated"});
         }},
        {"rawlog-corrupted-gz",
         [](const fs::path& d)
         {
             saveGz(simulate().rawlog, d / "full.rawlog");
             std::string b = readText(d / "full.rawlog");
             fs::remove(d / "full.rawlog");
             for (size_t i = b.size() / 2; i < b.size() / 2 + 16; i++)
             {
                 b[i] = static_cast<char>(~b[i]);
             }
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-corrupted-entry",
         [](const fs::path& d)
         {
             // The serialization version byte after the 2nd sensory frame's class name.
             std::string b = plainBytes(d);
             const std::string name = "mrpt::obs::CSensoryFrame";
             const auto p = b.find(name, b.find(name) + 1);
             b[p + name.size()] = 99;
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-unknown-class",
         [](const fs::path& d)
         {
             std::string b = plainBytes(d);
             const std::string name = "CObservationSemantic";
             b[b.find(name, b.find(name) + 1) + name.size() - 1] = 'X';
             writeText(d / "data.rawlog", b);
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-no-odometry",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       mrpt::obs::CRawlog obsOnly;
                                       for (size_t i = 0; i < log.size(); i++)
                                       {
                                           if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
                                           {
                                               for (const auto& o : *log.getAsObservations(i))
                                               {
                                                   obsOnly.insert(o);
                                               }
                                           }
                                       }
                                       log.swap(obsOnly);
                                   });
         }},
        {"rawlog-no-usable-observations",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       for (size_t i = 0; i < log.size(); i++)
                                       {
                                           if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
                                           {
                                               auto sf = log.getAsObservations(i);
                                               sf->eraseByLabel("SEMANTIC");
                                           }
                                       }
                                   });
         }},
        {"rawlog-odometry-nan",
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto acts = log.getAsAction(2);
                     auto m = acts->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
                     m->computeFromOdometry(mrpt::poses::CPose2D(kNaN, 0, 0),
                                            m->motionModelConfiguration);
                 });
         }},
        {"rawlog-odometry-very-noisy",
         [](const fs::path& d)
         {
             auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate.ini");
             o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
             o.simulation.max_steps = 6;
             o.odometry.min_xy_std_m = 5;
             o.odometry.min_phi_std_deg = 60;
             saveGz(semloc::Simulator(o).run().rawlog, d / "data.rawlog");
             return localize(d, writeIni(d), d / "data.rawlog");
         }},
        {"rawlog-odometry-huge-step",  // its covariance as the simulator's model makes it
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto m = log.getAsAction(4)
                                  ->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
                     m->computeFromOdometry(mrpt::poses::CPose2D(1e6, 0, 0),
                                            m->motionModelConfiguration);
                 });
         }},
        {"rawlog-time-repeated",
         [](const fs::path& d)
         {
             return localizeEditedWithGroundTruth(d,
                                                  [](mrpt::obs::CRawlog& log)
                                                  {
                                                      const auto obs = allObservations(log);
                                                      for (const auto& o : obs)
                                                      {
                                                          o->timestamp = obs[0]->timestamp;
                                                      }
                                                  });
         }},
        {"rawlog-time-swapped",  // steps 2 and 3 (entries 4-5 and 6-7) exchanged
         [](const fs::path& d)
         {
             return localizeEditedWithGroundTruth(d,
                                                  [](mrpt::obs::CRawlog& log)
                                                  {
                                                      mrpt::obs::CRawlog swapped;
                                                      for (const size_t i :
                                                           {0, 1, 2, 3, 6, 7, 4, 5, 8, 9, 10, 11})
                                                      {
                                                          swapped.insert(log.getAsGeneric(i));
                                                      }
                                                      log.swap(swapped);
                                                  });
         }},
        // ---- ground truth
        {"gt-missing",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"ground_truth_path_file", (d / "nope.txt").string()}});
         }},
        {"gt-columns", [](const fs::path& d)
         { return localizeWithGroundTruth(d, "# t x y phi\n1 2 3 0\n2 3 4\n"); }},
        {"gt-not-a-number",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n2 3 four 0\n"); }},
        {"gt-nan",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n2 nan 4 0\n"); }},
        {"gt-time-decreasing", [](const fs::path& d)
         { return localizeWithGroundTruth(d, "1 2 3 0\n3 2 3 0\n2 2 3 0\n"); }},
        {"gt-time-repeated",
         [](const fs::path& d) { return localizeWithGroundTruth(d, "1 2 3 0\n1 2 3 0\n"); }},
        {"gt-matches-no-step",  // in milliseconds
         [](const fs::path& d) {
             return localizeEditedWithGroundTruth(d, [](mrpt::obs::CRawlog&) {}, 1000);
         }},
        // ---- observations: skipped and counted
        {"detections-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       auto o = firstObservation<semloc::CObservationSemantic>(log);
                                       for (const double r : {kNaN, kInf, -1.0, 1000.0})
                                       {
                                           semloc::TSemanticDetection det;
                                           det.label = "pillar";
                                           det.range_m = r;
                                           o->detections.push_back(det);
                                       }
                                   });
         }},
        {"beams-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(
                 d,
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto s = firstObservation<mrpt::obs::CObservation2DRangeScan>(log);
                     const float r[] = {std::numeric_limits<float>::quiet_NaN(),
                                        std::numeric_limits<float>::infinity(), -1.0f,
                                        s->maxRange + 5};
                     for (size_t k = 0; k < 4; k++)
                     {
                         s->setScanRange(k, r[k]);
                         s->setScanRangeValidity(k, true);
                     }
                 });
         }},
        {"observations-geometry-invalid",
         [](const fs::path& d)
         {
             return localizeEdited(d,
                                   [](mrpt::obs::CRawlog& log)
                                   {
                                       auto o = observationsOf<semloc::CObservationSemantic>(log);
                                       o[0]->sensorPose.x(kNaN);
                                       o[1]->sensorPose.y(1e300);
                                       o[2]->maxRange_m = kInf;
                                   });
         }},
        {"scans-geometry-invalid",
         [](const fs::path& d)
         {
             return localizeEditedWith(
                 d, "grid_rt",
                 [](mrpt::obs::CRawlog& log)
                 {
                     auto s = observationsOf<mrpt::obs::CObservation2DRangeScan>(log);
                     s[0]->sensorPose.x(kNaN);
                     s[1]->aperture = std::numeric_limits<float>::quiet_NaN();
                     s[2]->resizeScan(0);
                 });
         }},
        {"scans-one-beam-grid",  // semloc-simulate's [Sonar] beam_count = 1
         [](const fs::path& d)
         {
             return localizeEditedWith(
                 d, "grid_lf",
                 [](mrpt::obs::CRawlog& log)
                 {
                     for (const auto& s : observationsOf<mrpt::obs::CObservation2DRangeScan>(log))
                     {
                         s->resizeScan(1);
                     }
                 });
         }},
        // ---- semloc-import-landmarks
        {"import-truncated",
         [](const fs::path& d)
         {
             const std::string b = plainBytes(d);
             writeText(d / "in.rawlog", b.substr(0, b.size() / 2));
             return std::vector<std::string>{"semloc-import-landmarks", (d / "in.rawlog").string(),
                                             "-o", (d / "lm.rawlog").string()};
         }},
        {"import-label-blank",
         [](const fs::path& d) {
             return importLandmarks(d, {"--label", "oil rig"});
         }},
        {"import-label-empty",
         [](const fs::path& d) {
             return importLandmarks(d, {"--label", ""});
         }},
        {"import-margin-huge",
         [](const fs::path& d) {
             return importLandmarks(d, {"--margin", "1e300"});
         }},
    };
    return c;
}

/** Relative paths of every file and directory under `dir`, each file with its contents
 *  (a file overwritten in place changes the listing too). */
std::set<std::string> listing(const fs::path& dir)
{
    std::set<std::string> s;
    for (const auto& e : fs::recursive_directory_iterator(dir))
    {
        const std::string contents = e.is_regular_file() ? readText(e.path()) : std::string();
        s.insert(fs::relative(e.path(), dir).string() + " " +
                 std::to_string(std::hash<std::string>()(contents)));
    }
    return s;
}

std::string quoted(const std::string& s)
{
    std::string q = "'";
    for (const char c : s)
    {
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return q + "'";
}

void PrintTo(const Row& r, std::ostream* os)
{
    *os << r.id;
}

class BadInput : public ::testing::TestWithParam<Row>
{
};

TEST_P(BadInput, FailsClearlyOrCounts)
{
    const Row& row = GetParam();
    const auto it = cases().find(row.id);
    ASSERT_NE(it, cases().end()) << "table row '" << row.id << "' has no case in this test";
    const fs::path base =
        fs::path(SEMLOC_TEST_OUT) / "bad_input" / (row.id + "_" + std::to_string(::getpid()));
    fs::remove_all(base);
    const fs::path dir = base / "case";
    fs::create_directories(dir);
    const auto args = it->second(dir);
    ASSERT_FALSE(args.empty());
    EXPECT_EQ(args[0], row.tool) << "the table names another tool";
    const auto before = listing(dir);

    std::string cmd = "cd " + quoted(dir.string()) + " && " + quoted(kBin + "/" + args[0]);
    for (size_t i = 1; i < args.size(); i++)
    {
        cmd += " " + quoted(args[i]);
    }
    cmd += " >" + quoted((base / "stdout").string()) + " 2>" + quoted((base / "stderr").string());
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << "the tool crashed: " << cmd;
    const int rc = WEXITSTATUS(status);
    const std::string err = readText(base / "stderr");

    if (row.result == "error")
    {
        EXPECT_NE(rc, 0) << cmd;
        EXPECT_NE(err.find(row.message), std::string::npos) << "stderr:\n"
                                                            << err << "\nexpected to contain:\n"
                                                            << row.message;
        EXPECT_EQ(listing(dir), before) << "the failed run left files behind";
    }
    else
    {
        ASSERT_TRUE(row.result.rfind("counted", 0) == 0 || row.result == "accepted")
            << "result must be error, counted or accepted";
        ASSERT_EQ(rc, 0) << err;
        const std::string summary = readText(dir / "out" / "summary.yaml");
        EXPECT_NE(summary.find(row.message), std::string::npos)
            << "summary.yaml:\n"
            << summary << "\nexpected to contain: " << row.message;
        if (row.id == "rawlog-truncated-allowed")
        {
            EXPECT_NE(err.find("--allow-truncated: localizing with the"), std::string::npos) << err;
        }
    }
    if (!HasFailure())
    {
        fs::remove_all(base);
    }
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, ::testing::ValuesIn(tableRows()),
                         [](const ::testing::TestParamInfo<Row>& p)
                         {
                             std::string n = p.param.id;
                             for (char& c : n)
                             {
                                 c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                             }
                             return n;
                         });

TEST(BadInputTable, TableAndCasesMatch)
{
    const auto rows = tableRows();
    ASSERT_GE(rows.size(), 30u) << "docs/bad-input.md's table is missing or short";
    std::set<std::string> ids;
    for (const auto& r : rows)
    {
        EXPECT_TRUE(ids.insert(r.id).second) << "duplicate table row " << r.id;
        EXPECT_TRUE(cases().count(r.id)) << "table row '" << r.id << "' has no case";
        EXPECT_FALSE(r.message.empty()) << r.id << ": no message";
    }
    for (const auto& [id, builder] : cases())
    {
        EXPECT_TRUE(ids.count(id)) << "case '" << id << "' has no table row";
    }
}

}  // namespace

/* semloc tests — the inputs the bad-input cases start from and the tools' command lines. */
#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
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

#include "LandmarkLog.h"
#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{
void writeText(const fs::path& p, const std::string& s)
{
    std::ofstream(p, std::ios::binary) << s;
}

/** A 6-step simulated paper dataset (action / sensory-frame pairs). */
semloc::SimulationResult simulate()
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate.ini");
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

/** config/<name>.ini (semantic.ini by default) with an absolute map, 200 particles, the
 *  `keys` replaced (each must be in the file) and `extra` appended, written as dir/loc.ini. */
fs::path writeIni(const fs::path& dir, const std::string& extra, Keys keys, const std::string& name)
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
    const std::string out = semloc::test::withKeys(
        resolvedIni(kSrc + "/config/localize/" + name + ".ini"), name + ".ini", std::move(keys));
    writeText(dir / "loc.ini", out + extra + "\n");
    return dir / "loc.ini";
}

/** Command line of a semloc-localize run with `ini` on `rawlog` into dir/out. */
std::vector<std::string> localize(const fs::path& dir, const fs::path& ini, const fs::path& rawlog,
                                  std::vector<std::string> extra)
{
    std::vector<std::string> a = {"semloc-localize",      ini.string(), rawlog.string(), "-o",
                                  (dir / "out").string(), "-q"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

/** A good dataset (gz rawlog) and the ini (see writeIni). */
std::vector<std::string> localizeGood(const fs::path& dir, const std::string& extra,
                                      const Keys& keys, std::vector<std::string> args)
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

/** A small landmark dataset as MRPT's simul-landmarks writes it (in.rawlog: 3 sensory frames
 *  of CObservationBearingRange seeing landmarks 1 and 2; its landmark and robot-path files)
 *  and the command line importing it with `options`. */
std::vector<std::string> importLandmarks(const fs::path& dir,
                                         const std::vector<std::string>& options)
{
    const mrpt::obs::CRawlog log = landmarkLog();
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

/** config/<name>.ini as writeIni() writes semantic.ini. */
fs::path writeConfig(const fs::path& dir, const std::string& name, const Keys& keys)
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
    const fs::path& dir, const std::function<void(mrpt::obs::CRawlog&)>& edit, double timeScale)
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

/** A small CSV dataset for semloc-import (see the header). */
std::vector<std::string> importCsv(const fs::path& dir,
                                   const std::map<std::string, std::string>& files,
                                   const std::vector<std::string>& options)
{
    std::map<std::string, std::string> text = {
        {"odom.csv", "t,x,y,phi\n1,0,0,0\n2,1,0,0\n3,2,0,0\n"},
        {"det.csv", "t,label,range_m,bearing_rad\n1,buoy,3,0.1\n2,,,\n3,buoy,2,0.2\n"},
        {"gt.csv", "t,x,y,phi\n1,5,5,0\n2,6,5,0\n3,7,5,0\n"},
        {"lm.csv", "id,label,x,y\n1,buoy,9,5\n2,buoy,12,6\n"}};
    for (const auto& [name, t] : files)
    {
        text[name] = t;
    }
    for (const auto& [name, t] : text)
    {
        writeText(dir / name, t);
    }
    std::vector<std::string> a = {"semloc-import", "-o",           "out.rawlog", "--odometry",
                                  "odom.csv",      "--detections", "det.csv",    "--ground-truth",
                                  "gt.csv",        "--landmarks",  "lm.csv"};
    a.insert(a.end(), options.begin(), options.end());
    return a;
}

}  // namespace semloc::test::bad_input

/* semloc — Simulator: trajectory, sensors, rawlog and ground truth. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/simulator/TrajectoryFollower.h>

#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "io/ExactConfigWrite.h"
#include "io/Text.h"
#include "io/TextFiles.h"
#include "simulator/AuvSensors.h"
#include "simulator/Distractors.h"
#include "simulator/Silences.h"
#include "simulator/SimRandom.h"

namespace semloc
{
namespace
{
const char* const kSimulation = "Simulation";
const char* const kOdometry = "Odometry";
const char* const kSonar = "Sonar";
const char* const kDetector = "SemanticDetector";
const char* const kKidnapping = "Kidnapping";
const char* const kBeaconRanging = "BeaconRanging";
/** The first words of the effective configuration writeDataset() writes. */
const char* const kConfigHeader = "// semloc-simulate: ";

/** config::resolveNextToIni, plus the ini's directory joined with a separator: MRPT 2.5.8's
 *  extractFileDirectory() returns no trailing '/', so resolveNextToIni misses files next to
 *  the ini (reported; this fallback can go once it is fixed there). */
/** `<dir>/<stem><suffix>` for a path `<dir>/<stem>.<ext>`. */
std::string besides(const std::string& path, const std::string& suffix)
{
    std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}
}  // namespace

// ------------------------------------------------------------------ options

void TSimulationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    // An empty world_file is unset, as the effective configuration writes it before one is
    // given (running without one fails: "world_file: not set").
    const std::string given = c.read_string(s, "world_file", "");
    if (!given.empty())
    {
        const std::string found = config::resolveNextToIni(c, given);
        if (!mrpt::system::fileExists(found))
        {
            THROW_EXCEPTION("ini [" + s + "] world_file: " + config::missingFileMessage(c, given));
        }
        world_file = mrpt::system::toAbsolutePath(found, true);
    }
    int seedInt = static_cast<int>(seed);
    config::readInt(c, s, "seed", seedInt, 0, INT_MAX);
    seed = static_cast<uint32_t>(seedInt);
    config::readDouble(c, s, "time_step_s", time_step_s, 1e-6, 1e6);
    config::readDouble(c, s, "speed_mps", speed_mps, 0, 1e3);
    config::readInt(c, s, "max_steps", max_steps, 0, INT_MAX);
    config::readDouble(c, s, "start_time_s", start_time_s, 0, 4e9);
    if (c.keyExists(s, "output_rawlog"))
    {
        output_rawlog = c.read_string(s, "output_rawlog", "");
        if (output_rawlog.empty())
        {
            THROW_EXCEPTION("ini [" + s + "] output_rawlog: empty file name");
        }
    }
}

void TSimulationOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const
{
    using detail::writeExact;
    detail::writeText(c, s, "world_file", world_file, "world YAML with a trajectory");
    c.write(s, "seed", static_cast<int>(seed), 24, 24, "seed of every random stream");
    writeExact(c, s, "time_step_s", time_step_s, "time between steps [s]");
    writeExact(c, s, "speed_mps", speed_mps, "vehicle speed [m/s]; 0: the trajectory's");
    c.write(s, "max_steps", max_steps, 24, 24, "0: the whole trajectory");
    writeExact(c, s, "start_time_s", start_time_s, "time of step 0 [s since 1970]");
    detail::writeText(c, s, "output_rawlog", output_rawlog,
                      "dataset; also <stem>_gt.txt, <stem>.ini");
}

void TKidnappingOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    config::readInt(c, s, "step", step, 1, INT_MAX);
    config::readBool(c, s, "random_pose", random_pose);
    config::readDouble(c, s, "x_m", x_m, -1e6, 1e6);
    config::readDouble(c, s, "y_m", y_m, -1e6, 1e6);
    config::readDouble(c, s, "phi_deg", phi_deg, -360, 360);
}

void TKidnappingOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const
{
    using detail::writeExact;
    c.write(s, "enabled", enabled, 24, 24, "teleport the vehicle once");
    c.write(s, "step", step, 24, 24, "at this step (>= 1)");
    c.write(s, "random_pose", random_pose, 24, 24, "true: a random free pose");
    writeExact(c, s, "x_m", x_m, "else this pose: x [m]");
    writeExact(c, s, "y_m", y_m, "y [m] (free space)");
    writeExact(c, s, "phi_deg", phi_deg, "heading [deg]");
}

void TSimulatorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c)
{
    simulation.loadFromConfigFile(c, kSimulation);
    odometry.loadFromConfigFile(c, kOdometry);
    sonar.loadFromConfigFile(c, kSonar);
    detector.loadFromConfigFile(c, kDetector);
    kidnapping.loadFromConfigFile(c, kKidnapping);
    beacons.loadFromConfigFile(c, kBeaconRanging);
    auv.loadFromConfigFile(c);
}

void TSimulatorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c) const
{
    simulation.saveToConfigFile(c, kSimulation);
    odometry.saveToConfigFile(c, kOdometry);
    sonar.saveToConfigFile(c, kSonar);
    detector.saveToConfigFile(c, kDetector);
    kidnapping.saveToConfigFile(c, kKidnapping);
    beacons.saveToConfigFile(c, kBeaconRanging);
    auv.saveToConfigFile(c);
}

TSimulatorOptions TSimulatorOptions::FromConfigFile(const std::string& iniPath)
{
    config::checkIniFile(iniPath, "ini file");
    TSimulatorOptions o;
    o.loadFromConfigFile(config::IniFileInMemory(iniPath, "ini file"));
    return o;
}

// ------------------------------------------------------------------ results

std::string SimulationResult::summary() const
{
    const std::string lbl =
        pings > 0 ? mrpt::format("%zu pings, %.2f beacon ranges/ping, ", pings, meanBeaconRanges)
                  : "";
    return mrpt::format(
        "%zu steps, %.2f detections/scan, %.1f of %zu sonar beams valid/scan, %ssimulated in "
        "%.3f s",
        steps, meanDetections, meanValidBeams, beamsPerScan, lbl.c_str(), wallTime_s);
}

// ------------------------------------------------------------------ simulator

Simulator::Simulator(const World& world, const TSimulatorOptions& options)
    : m_world(world), m_options(options)
{
    const std::string where = "world '" + world.name + "' (" + world.source + ")";
    if (!world.trajectory || world.trajectory->waypoints.size() < 2)
    {
        THROW_EXCEPTION(where + " has no trajectory: the simulator follows its waypoints");
    }
    if (!(speed() > 0))
    {
        THROW_EXCEPTION(where + ": speed_mps must be > 0 (or set [Simulation] speed_mps)");
    }
    const auto& k = options.kidnapping;
    if (k.enabled && !k.random_pose && !world.isFree(k.x_m, k.y_m))
    {
        THROW_EXCEPTION(mrpt::format("ini [%s] x_m, y_m: (%g, %g) is not free space of %s",
                                     kKidnapping, k.x_m, k.y_m, where.c_str()));
    }
    if (options.beacons.enabled && world.beacons.empty())
    {
        THROW_EXCEPTION(std::string("ini [") + kBeaconRanging + "] enabled: " + where +
                        " has no beacons to range to (a `beacons:` list)");
    }
}

Simulator::Simulator(const TSimulatorOptions& options)
    : Simulator(
          [&]
          {
              if (options.simulation.world_file.empty())
              {
                  THROW_EXCEPTION(std::string("ini [") + kSimulation + "] world_file: not set");
              }
              return World::FromFile(options.simulation.world_file);
          }(),
          options)
{
}

double Simulator::speed() const
{
    return m_options.simulation.speed_mps > 0 ? m_options.simulation.speed_mps
                                              : m_world.trajectory->speed_mps;
}

namespace
{
/** The random streams of a run, one per source of noise (SimRandom.h). */
struct SimStreams
{
    mrpt::random::CRandomGenerator odometry, sonar, detector, kidnap, gaps, distractors, beacons;
    detail::AuvStreams auv;

    explicit SimStreams(uint32_t seed)
        : odometry(detail::streamSeed(seed, detail::SimStream::Odometry)),
          sonar(detail::streamSeed(seed, detail::SimStream::Sonar)),
          detector(detail::streamSeed(seed, detail::SimStream::Detector)),
          kidnap(detail::streamSeed(seed, detail::SimStream::Kidnapping)),
          gaps(detail::streamSeed(seed, detail::SimStream::DetectorGaps)),
          distractors(detail::streamSeed(seed, detail::SimStream::Distractors)),
          beacons(detail::streamSeed(seed, detail::SimStream::BeaconRanging)),
          auv(seed)
    {
    }
};

/** The sensor models of a run. */
struct Sensors
{
    SimulatedOdometry odometry;
    SonarModel sonar;
    SemanticDetectorModel detector;
    BeaconRangingModel beacons;
    detail::AuvSensors auv;
};

/** What the steps of a run add up to, for the summary. */
struct StepCounts
{
    size_t detections = 0, validBeams = 0, pings = 0, beaconRanges = 0;
};

/** The step at `stamp`: the odometry of `increment` as the action, then the sonar scan, the
 *  detections and, if `ping`, the beacons' ranges at the true `pose` as the sensory frame,
 *  appended to the rawlog with the pose as ground truth. Draws odometry, sonar, detector and
 *  beacon noise, each from its own stream. */
void recordStep(const Sensors& sensors, SimStreams& rng, const mrpt::poses::CPose2D& increment,
                const mrpt::math::TPose2D& pose, size_t k, mrpt::Clock::time_point stamp, double dt,
                bool silent, bool ping, const detail::Distractors& distractors,
                SimulationResult& res, StepCounts& counts)
{
    auto action = sensors.auv.dvl() ? sensors.auv.measureDvl(increment, rng.auv.dvl)
                                    : sensors.odometry.measure(increment, rng.odometry, dt);
    action.timestamp = stamp;
    auto actions = mrpt::obs::CActionCollection::Create();
    actions->insert(action);

    auto scan = sensors.sonar.measure(pose, rng.sonar);
    scan->timestamp = stamp;
    auto semantic = sensors.detector.measure(pose, rng.detector, distractors.now());
    semantic->timestamp = stamp;
    if (silent)
    {
        semantic->detections.clear();  // drawn all the same: the other steps keep their noise
    }
    for (size_t b = 0; b < scan->getScanSize(); b++)
    {
        counts.validBeams += scan->getScanRangeValidity(b) ? 1 : 0;
    }
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(scan);
    if (sensors.detector.options().enabled)
    {
        counts.detections += semantic->detections.size();
        frame->insert(semantic);
    }
    if (ping)
    {
        auto ranges = sensors.beacons.measure(pose, rng.beacons);
        ranges->timestamp = stamp;
        counts.pings++;
        counts.beaconRanges += ranges->sensedData.size();
        frame->insert(ranges);  // after the others: they are those of a run without it
    }
    counts.detections += sensors.auv.measure(k, pose, stamp, rng.auv, *frame);

    res.rawlog.insert(actions);
    res.rawlog.insert(frame);
    res.groundTruth.push_back({mrpt::Clock::toDouble(stamp), pose.x, pose.y, pose.phi});
    res.detectorSilent.push_back(silent ? 1 : 0);
}

/** The summary's means from the step counts. */
void finishCounts(const StepCounts& counts, SimulationResult& res)
{
    res.meanDetections = static_cast<double>(counts.detections) / static_cast<double>(res.steps);
    res.meanValidBeams = static_cast<double>(counts.validBeams) / static_cast<double>(res.steps);
    res.pings = counts.pings;
    res.meanBeaconRanges = counts.pings > 0 ? static_cast<double>(counts.beaconRanges) /
                                                  static_cast<double>(counts.pings)
                                            : 0.0;
}

/** Where the kidnapped vehicle is put: a random free pose, or the configured one. */
mrpt::math::TPose2D kidnapPose(const TKidnappingOptions& kidnap, const World& world,
                               mrpt::random::CRandomGenerator& rng)
{
    return kidnap.random_pose
               ? world.sampleFreePose(rng)
               : mrpt::math::TPose2D(kidnap.x_m, kidnap.y_m,
                                     mrpt::math::wrapToPi(mrpt::DEG2RAD(kidnap.phi_deg)));
}
}  // namespace

/** How the vehicle moves in a simulation: the world's route, or a driver. */
class detail::VehicleMotion
{
public:
    virtual ~VehicleMotion() = default;
    /** The pose after step k >= 1 from `pose` (the results so far in `sofar`). */
    virtual mrpt::math::TPose2D next(size_t k, const mrpt::math::TPose2D& pose,
                                     const SimulationResult& sofar) = 0;
    /** The vehicle was teleported to `pose` (kidnapping). */
    virtual void teleported(const mrpt::math::TPose2D& pose) = 0;
    /** True once the motion has nothing more to do. */
    virtual bool finished() const = 0;
};

namespace
{
using detail::VehicleMotion;

/** The world's route (TrajectoryFollower). */
class RouteMotion : public VehicleMotion
{
public:
    explicit RouteMotion(TrajectoryFollower& f) : m_f(f) {}
    mrpt::math::TPose2D next(size_t, const mrpt::math::TPose2D&, const SimulationResult&) override
    {
        m_f.step();
        return m_f.pose();
    }
    void teleported(const mrpt::math::TPose2D& pose) override { m_f.teleport(pose); }
    bool finished() const override { return m_f.finished(); }

private:
    TrajectoryFollower& m_f;
};

/** A driver's increments, the translation dropped where its path leaves the free space. */
class DrivenMotion : public VehicleMotion
{
public:
    DrivenMotion(const World& world, const Simulator::Driver& drive, size_t& blocked)
        : m_world(world), m_drive(drive), m_blocked(blocked)
    {
    }
    mrpt::math::TPose2D next(size_t k, const mrpt::math::TPose2D& pose,
                             const SimulationResult& sofar) override
    {
        const auto to = (mrpt::poses::CPose2D(pose) + m_drive(k, pose, sofar)).asTPose();
        const mrpt::math::TPoint2D a(pose.x, pose.y), b(to.x, to.y);
        if ((a.x == b.x && a.y == b.y) ||
            (m_world.isFree(b.x, b.y) && m_world.firstObjectOnSegment(a, b) < 0))
        {
            return {to.x, to.y, mrpt::math::wrapToPi(to.phi)};
        }
        m_blocked++;
        return {pose.x, pose.y, mrpt::math::wrapToPi(to.phi)};  // stopped by the obstacle
    }
    void teleported(const mrpt::math::TPose2D&) override {}
    bool finished() const override { return false; }

private:
    const World& m_world;
    const Simulator::Driver& m_drive;
    size_t& m_blocked;
};
}  // namespace

SimulationResult Simulator::run() const
{
    TrajectoryFollower vehicle(m_world.trajectory->waypoints,
                               speed() * m_options.simulation.time_step_s);
    RouteMotion route(vehicle);
    const size_t maxSteps = static_cast<size_t>(m_options.simulation.max_steps);
    return simulate(route, vehicle.pose(), maxSteps);
}

SimulationResult Simulator::runDriven(const Driver& drive, size_t steps) const
{
    ASSERTMSG_(steps >= 1, "Simulator::runDriven: no step");
    size_t blocked = 0;
    DrivenMotion driven(m_world, drive, blocked);
    auto res = simulate(driven, routeStart(), steps);
    res.blockedSteps = blocked;
    return res;
}

mrpt::math::TPose2D Simulator::routeStart() const
{
    return TrajectoryFollower(m_world.trajectory->waypoints,
                              speed() * m_options.simulation.time_step_s)
        .pose();
}

size_t Simulator::routeSteps() const
{
    const size_t all = TrajectoryFollower(m_world.trajectory->waypoints,
                                          speed() * m_options.simulation.time_step_s)
                           .stepsToEnd();
    const auto maxSteps = static_cast<size_t>(m_options.simulation.max_steps);
    return maxSteps > 0 ? std::min(all, maxSteps) : all;
}

SimulationResult Simulator::simulate(detail::VehicleMotion& vehicleMotion,
                                     const mrpt::math::TPose2D& start, size_t maxSteps) const
{
    const auto wallStart = std::chrono::steady_clock::now();
    const TSimulatorOptions& o = m_options;
    SimStreams rng(o.simulation.seed);
    const Sensors sensors{SimulatedOdometry(o.odometry), SonarModel(m_world, o.sonar),
                          SemanticDetectorModel(m_world, o.detector),
                          BeaconRangingModel(m_world, o.beacons),
                          detail::AuvSensors(m_world, o.auv)};
    const double dt = o.simulation.time_step_s;
    const auto& kidnap = o.kidnapping;

    SimulationResult res;
    res.beamsPerScan = static_cast<size_t>(o.sonar.beam_count);
    StepCounts counts;
    bool kidnapped = false;
    detail::Silences silences(o.detector, o.simulation.start_time_s, rng.gaps);
    detail::Distractors distractors(m_world, sensors.detector, rng.distractors);
    mrpt::math::TPose2D pose = start;
    mrpt::poses::CPose2D previous(pose);
    for (size_t k = 0;; k++)
    {
        if (interruptRequested())
        {
            throw Interrupted();  // Ctrl-C (installInterruptHandlers): nothing simulated
        }
        if (k > 0)
        {
            pose = vehicleMotion.next(k, pose, res);
            distractors.step(dt);
        }
        const mrpt::poses::CPose2D increment = mrpt::poses::CPose2D(pose) - previous;
        if (kidnap.enabled && k == static_cast<size_t>(kidnap.step))
        {
            // The odometry keeps reporting `increment`: it does not see the teleport.
            pose = kidnapPose(kidnap, m_world, rng.kidnap);
            vehicleMotion.teleported(pose);
            kidnapped = true;
        }
        const auto stamp =
            mrpt::Clock::fromDouble(o.simulation.start_time_s + static_cast<double>(k) * dt);
        const double t = o.simulation.start_time_s + static_cast<double>(k) * dt;
        recordStep(sensors, rng, increment, pose, k, stamp, k > 0 ? dt : 0.0, silences.silent(t),
                   sensors.beacons.pingsAt(k), distractors, res, counts);
        previous = mrpt::poses::CPose2D(pose);
        if (vehicleMotion.finished() || (maxSteps > 0 && k + 1 >= maxSteps))
        {
            break;
        }
    }
    res.steps = res.groundTruth.size();
    if (kidnap.enabled && !kidnapped)
    {
        THROW_EXCEPTION(
            mrpt::format("ini [%s] step: %d is beyond the last step of the "
                         "simulation (%zu steps: 0..%zu)",
                         kKidnapping, kidnap.step, res.steps, res.steps - 1));
    }
    finishCounts(counts, res);
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    return res;
}

// ------------------------------------------------------------------ files

std::string Simulator::configPath(const std::string& rawlogPath)
{
    return besides(rawlogPath, ".ini");
}

void Simulator::writeDataset(const SimulationResult& result, const std::string& rawlogPath) const
{
    ASSERTMSG_(!rawlogPath.empty(), "Simulator::writeDataset: empty output path");
    checkDatasetPaths(rawlogPath, {m_options.simulation.world_file});
    const std::string gtPath = GroundTruthFile::PathFor(rawlogPath),
                      iniPath = configPath(rawlogPath);
    writeOutputFiles(
        {rawlogPath, gtPath, iniPath},
        [&](const std::vector<std::string>& tmp)
        {
            GzOutputFile out(tmp[0]);  // its errors name the file and the reason
            auto ar = mrpt::serialization::archiveFrom(out);
            writeRawlogSignature(ar, "semloc-simulate: seed " +
                                         std::to_string(m_options.simulation.seed) + ", world " +
                                         m_options.simulation.world_file);
            for (const auto& obj : result.rawlog)
            {
                ar << *obj;
                if (interruptRequested())
                {
                    throw Interrupted();  // the temporary files are removed
                }
            }
            out.close();

            GroundTruthFile::Write(result.groundTruth, tmp[1]);

            TSimulatorOptions effective = m_options;
            effective.simulation.output_rawlog = rawlogPath;
            mrpt::config::CConfigFileMemory ini;
            effective.saveToConfigFile(ini);
            detail::writeFile(
                tmp[2], kConfigHeader + std::string("the effective configuration of ") +
                            rawlogPath + " (every key; rerunning it reproduces the dataset)\n" +
                            ini.getContent());
        });
}

void Simulator::checkDatasetPaths(const std::string& rawlogPath,
                                  const std::vector<std::string>& inputs)
{
    const std::string gtPath = GroundTruthFile::PathFor(rawlogPath),
                      iniPath = configPath(rawlogPath);
    if (gtPath == rawlogPath || iniPath == rawlogPath)
    {
        THROW_EXCEPTION("output rawlog '" + rawlogPath +
                        "' collides with its ground-truth or ini file name (give it an "
                        "extension such as .rawlog)");
    }
    checkOutputFile(rawlogPath, inputs, RawlogReader::IsSemlocRawlog);
    checkOutputFile(gtPath, inputs, GroundTruthFile::IsGroundTruthFile);
    checkOutputFile(iniPath, inputs,
                    [](const std::string& p) { return fileStartsWith(p, kConfigHeader); });
}

}  // namespace semloc

/* semloc — semloc-simulate's engine: datasets for the paper's experiment (docs/design.md). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/simulator/AuvSensorModels.h>
#include <semloc/simulator/BeaconRangingModel.h>
#include <semloc/simulator/SemanticDetectorModel.h>
#include <semloc/simulator/SimulatedOdometry.h>
#include <semloc/simulator/SonarModel.h>
#include <semloc/world/World.h>

#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace semloc
{
class StagedDirectory;
namespace detail
{
class VehicleMotion;
}
/** Section [Simulation]: what to simulate and where to write it. */
struct TSimulationOptions : public mrpt::config::CLoadableOptions
{
    /** World YAML with a trajectory; a relative path is resolved next to the ini first
     *  (config::resolveNextToIni) and written out absolute. */
    std::string world_file;
    /** Seed of every random stream (odometry, sonar, detector, kidnapping), [0, 2^31 - 1]. */
    uint32_t seed = 1;
    /** Time between steps [s]. */
    double time_step_s = 1.0;
    /** Vehicle speed [m/s]; 0 takes the world trajectory's `speed_mps`. */
    double speed_mps = 0.0;
    /** Stop after this many steps; 0 runs the whole trajectory. */
    int max_steps = 0;
    /** Time of step 0 [s since 1970-01-01 UTC]; step k is at start_time_s + k time_step_s. */
    double start_time_s = 1.7e9;
    /** Output rawlog (the app's `-o` overrides it); see Simulator::writeDataset(). */
    std::string output_rawlog = "dataset.rawlog";

    /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    /** Writes every key of the section, defaults included, with a comment. */
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Section [Kidnapping]: teleport the vehicle once, unknown to the odometry. */
struct TKidnappingOptions : public mrpt::config::CLoadableOptions
{
    /** Whether the vehicle is kidnapped at all. */
    bool enabled = false;
    /** Step at which it is kidnapped (>= 1); its observations are taken at the new pose. */
    int step = 200;
    /** Teleport to a pose uniform over the free space (World::sampleFreePose) instead of
     *  (x_m, y_m, phi_deg). */
    bool random_pose = false;
    /** The new pose: x position [m] (must be free space). */
    double x_m = 25.0;
    /** The new pose: y position [m] (must be free space). */
    double y_m = 25.0;
    /** The new pose: heading [deg]. */
    double phi_deg = 0.0;

    /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    /** Writes every key of the section, defaults included, with a comment. */
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Every option of a simulation: the sections of `config/simulate/simulate.ini`. */
struct TSimulatorOptions
{
    TSimulationOptions simulation;             //!< [Simulation]
    SimulatedOdometry::TOptions odometry;      //!< [Odometry]
    SonarModel::TOptions sonar;                //!< [Sonar]
    SemanticDetectorModel::TOptions detector;  //!< [SemanticDetector]
    TKidnappingOptions kidnapping;             //!< [Kidnapping]
    BeaconRangingModel::TOptions beacons;      //!< [BeaconRanging]
    /** [Depth], [Compass], [USBL], [DVL], [SideScan], [ForwardSonar], [Camera]. */
    TAuvSensorOptions auv;

    /** Reads the sections (absent keys keep their defaults; unknown keys, bad values
     *  and a world_file that does not exist are errors naming [section] key). Other
     *  sections are ignored, so one ini may also configure other tools. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source);
    /** Writes every key of the sections (the effective configuration). */
    void saveToConfigFile(mrpt::config::CConfigFileBase& target) const;
    /** Loads an ini file. Throws if it cannot be read or on any bad key. */
    static TSimulatorOptions FromConfigFile(const std::string& iniPath);
};

/** A simulated dataset in memory. */
struct SimulationResult
{
    /** Action / sensory-frame rawlog: per step a CActionCollection holding one
     *  CActionRobotMovement2D, then a CSensoryFrame holding the SONAR
     *  CObservation2DRangeScan and the SEMANTIC CObservationSemantic, and at a ping of
     *  [BeaconRanging] the LBL CObservationBeaconRanges last. */
    mrpt::obs::CRawlog rawlog;
    /** One row per step. */
    std::vector<GroundTruthRow> groundTruth;
    /** Per step: 1 if the detector was silent (a gap of [SemanticDetector] gap_every_s). */
    std::vector<uint8_t> detectorSilent;
    /** Number of steps. */
    size_t steps = 0;
    /** Steps of runDriven() whose translation was dropped: its path left the free space. */
    size_t blockedSteps = 0;
    /** Mean detections per semantic scan (false positives included). */
    double meanDetections = 0;
    /** Mean valid sonar beams per scan. */
    double meanValidBeams = 0;
    /** Sonar beams per scan. */
    size_t beamsPerScan = 0;
    /** Pings of [BeaconRanging] (0 when it is disabled). */
    size_t pings = 0;
    /** Mean beacon ranges per ping. */
    double meanBeaconRanges = 0;
    /** Wall-clock time of the simulation [s] (not part of the dataset). */
    double wallTime_s = 0;

    /** "N steps, D detections/scan, B of n sonar beams valid/scan, simulated in T s"; with
     *  pings, ", P pings, R beacon ranges/ping" before "simulated". */
    std::string summary() const;
};

/** Simulates the paper's experiment: an AUV follows the world's trajectory (see
 *  TrajectoryFollower) with a time step `time_step_s`; at step k (time start_time_s +
 *  k time_step_s) it
 *  1. moves (step 0: stays at the first waypoint) and reports the odometry of the true
 *     pose increment (SimulatedOdometry, the noise drawn from the motion model it stores);
 *  2. if kidnapped at this step, is teleported: the odometry of this step is still the
 *     pre-kidnap motion;
 *  3. takes a sonar scan (SonarModel) and a semantic detection scan (SemanticDetectorModel)
 *     at its true pose, which is the step's ground-truth row, and at a ping the beacons'
 *     ranges (BeaconRangingModel).
 *  Deterministic: each component draws from its own mrpt::random::CRandomGenerator seeded
 *  from `seed`; a seed gives a byte-identical rawlog, timestamps included. */
class Simulator
{
public:
    /** Validates the options against `world` (trajectory present, kidnap pose free,
     *  beacons to range to). */
    Simulator(const World& world, const TSimulatorOptions& options);
    /** Loads `options.simulation.world_file`. */
    explicit Simulator(const TSimulatorOptions& options);

    /** Runs the whole simulation in memory. */
    SimulationResult run() const;
    /** What drives the vehicle in runDriven(): at step k >= 1, from the true pose `pose`,
     *  with the data of steps 0..k-1 in `sofar` (its rawlog's last action and sensory frame
     *  are step k-1's), the pose increment to make in the vehicle's frame. */
    using Driver = std::function<mrpt::poses::CPose2D(size_t k, const mrpt::math::TPose2D& pose,
                                                      const SimulationResult& sofar)>;
    /** run() with the vehicle driven by `drive` instead of the route: step 0 at the
     *  route's start (routeStart()), then `steps` - 1 increments of `drive`. An increment
     *  whose straight path leaves the free space (World::isFree, firstObjectOnSegment)
     *  loses its translation: the vehicle turns where it is, and the odometry reports that
     *  (counted in SimulationResult::blockedSteps). Sensors, noise streams and kidnapping
     *  as in run(): the same seed draws the same noise at the same steps. */
    SimulationResult runDriven(const Driver& drive, size_t steps) const;
    /** The route's first pose (run()'s step 0). */
    mrpt::math::TPose2D routeStart() const;
    /** Distance the vehicle covers per step [m]: the speed times [Simulation] time_step_s. */
    double stepLength_m() const { return speed() * m_options.simulation.time_step_s; }
    /** run()'s number of steps: the route's, at most [Simulation] max_steps. */
    size_t routeSteps() const;

    /** Writes `rawlogPath` (gz-compressed rawlog, MRPT's usual format), its ground truth
     *  GroundTruthFile::PathFor() (`t x y phi` per line, the shortest fixed-point decimals that
     * read back bit-exactly) and the effective configuration configPath() (output_rawlog set to
     *  `rawlogPath`; rerunning it reproduces the rawlog). All three are written to
     *  `<name>.tmp` beside them and renamed at the end; on any error none is left behind
     *  and the error is thrown. */
    void writeDataset(const SimulationResult& result, const std::string& rawlogPath) const;

    /** Writes the dataset in semloc-import's CSV format (docs/tools.md, "semloc-import") into
     *  the directory `dir` (a new directory or a previous output of semloc, replaced as a
     *  whole at the end, never half-written; refused if it holds one of `inputs`):
     *  `odometry.csv` (`t,x,y,phi`: the odometry increments composed from (0, 0, 0), a
     *  dead-reckoned pose), `detections.csv` (`t,label,range_m,bearing_rad,id,confidence`;
     *  `id` empty unless the detector reports ids; a scan without detections is a row with
     *  only `t`; a comment gives semloc-import's detector options), `ground_truth.csv`
     *  (`t,x,y,phi`) and `landmarks.csv` (`id,label,x,y`: every object of the world at its
     *  centre). semloc-import of these files gives back the rawlog's steps.
     *
     *  With any of the AUV's sensors on (TAuvSensorOptions), the AUV form: `odometry.csv` is
     *  `t,vx,vy,w` with a DVL (the body-frame velocities whose exact arc over each step is its
     *  increment), `detections.csv` is `t,sensor,label,range_m,bearing_rad,side,id,confidence`
     *  with every detector's scans (the side-scan's in `side`, a camera's range empty),
     *  `landmarks.csv` has `z`, and `depth.csv` (`t,depth_m,altitude_m`), `heading.csv`
     *  (`t,heading_rad`) and `fixes.csv` (`t,x,y,z,sigma_m`) are written for the sensors that
     *  are on. */
    void writeCsvDataset(const SimulationResult& result, const std::string& dir,
                         const std::vector<std::string>& inputs = {}) const;

    /** Checks, before any work, that writeDataset() may write `rawlogPath` and its two
     *  companions (checkOutputFile): none is a directory or one of `inputs`, the directory
     *  exists, and an existing ground-truth or ini companion is a previous output of
     *  semloc-simulate (a readable ground truth; an ini with its header). Throws naming the
     *  file. */
    static void checkDatasetPaths(const std::string& rawlogPath,
                                  const std::vector<std::string>& inputs);

    /** `<dir>/<stem>.ini` for `<dir>/<stem>.rawlog`. */
    static std::string configPath(const std::string& rawlogPath);
    /** The options. */
    const TSimulatorOptions& options() const { return m_options; }
    /** The world. */
    const World& world() const { return m_world; }

private:
    double speed() const;
    /** writeCsvDataset()'s AUV form, into `out` (not committed). */
    void writeAuvCsvDataset(const SimulationResult& result, StagedDirectory& out) const;
    /** The simulation loop of run() and runDriven(). */
    SimulationResult simulate(detail::VehicleMotion& motion, const mrpt::math::TPose2D& start,
                              size_t maxSteps) const;

    World m_world;
    TSimulatorOptions m_options;
};

}  // namespace semloc

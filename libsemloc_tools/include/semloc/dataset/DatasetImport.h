/* semloc — import a vehicle's dataset from plain-text (CSV) files as a semantic rawlog. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkSet.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cmath>
#include <cstddef>
#include <iosfwd>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace semloc
{
// semloc-import's bounds on the values of its files (docs/tools.md, "semloc-import"): a value
// beyond them is refused naming the file, the line and the column. Positions (odometry, ground
// truth, landmarks) and ranges lie within kMaxWorldCoordinate_m (1e7 m).

/** Largest time [s]: 1e11 s (3170 years); times since 1970 in milliseconds or finer are
 *  beyond it. */
constexpr double kMaxImportTime_s = 1e11;
/** Largest odometry speed `v`, `vx`, `vy` [m/s]. */
constexpr double kMaxImportSpeed_mps = 100;
/** Largest odometry yaw rate `w` [rad/s]. */
constexpr double kMaxImportYawRate_radps = 100;
/** Largest heading `phi` [rad] (unwrapped headings are fine; beyond this a double's heading
 *  has lost its precision). */
constexpr double kMaxImportHeading_rad = 1e6;
/** Largest median time between consecutive distinct times of the odometry and detections
 *  together [s]: above it the times look like milliseconds or finer and are refused. */
constexpr double kMaxImportMedianInterval_s = 10;
/** Most steps an import makes (scans and odometry-only steps), checked before any is made. */
constexpr size_t kMaxImportSteps = 10'000'000;

/** Largest depth [m] of a depth file's `depth_m` (and `altitude_m`); a depth above the surface
 *  (negative) is at most kMaxImportHeight_m. */
constexpr double kMaxImportDepth_m = 1e5;
/** Largest height above the surface [m]: `depth_m` down to -kMaxImportHeight_m. */
constexpr double kMaxImportHeight_m = 1e4;

/** The default of `--scan-window-s` [s]: 10 ms, below the frame period of any detector that
 *  reports up to 100 scans a second, above the few milliseconds a detector spends stamping the
 *  readings of one frame one by one. */
constexpr double kDefaultScanWindow_s = 0.01;
/** The default of `--gt-max-gap-s` is the larger of this [s] and kGroundTruthGapPeriods times
 *  the ground truth's median period. */
constexpr double kMinGroundTruthMaxGap_s = 1.0;
/** See kMinGroundTruthMaxGap_s. */
constexpr double kGroundTruthGapPeriods = 10.0;

/** The sensor label of the detections of a row without a `sensor` cell. */
inline const std::string kDefaultImportSensor = "SEMANTIC";

/** One detector's coverage and mount, as its scans' CObservationSemantic carry them. */
struct TImportSensor
{
    /** Maximum range [m] (CObservationSemantic::maxRange_m). */
    double maxRange_m = 20.0;
    /** Horizontal field of view [deg], centred on the sensor's x axis. */
    double fov_deg = 120.0;
    /** Pose on the vehicle: forward and to port [m], yaw (phi, radians). */
    mrpt::math::TPose2D pose{0, 0, 0};
    /** Height on the vehicle [m] (up). */
    double z_m = 0;
};

/** What the `NAME=` forms of `--max-range-m`, `--fov-deg` and `--sensor-pose` set for the
 *  sensor NAME (unset: the option's unnamed value). */
struct TImportSensorOverride
{
    std::optional<double> maxRange_m;  //!< `--max-range-m NAME=R`
    std::optional<double> fov_deg;     //!< `--fov-deg NAME=F`
    /** `--sensor-pose NAME=x,y,yaw_deg[,z_m]` (phi in radians). */
    std::optional<mrpt::math::TPose2D> pose;
    double z_m = 0;  //!< its z_m (0 when not given)
};

/** The options of semloc-import (docs/tools.md, "semloc-import"). */
struct TDatasetImportOptions
{
    /** The detectors' maximum range [m] (`--max-range-m R`), CObservationSemantic::maxRange_m:
     *  of every sensor but those `sensors` gives another. */
    double maxRange_m = 20.0;
    /** The detectors' horizontal field of view [deg] (`--fov-deg F`), centred on their x axis. */
    double fov_deg = 120.0;
    /** The detectors' pose on the vehicle (`--sensor-pose x,y,yaw_deg[,z_m]`; phi in radians). */
    mrpt::math::TPose2D sensorPose{0, 0, 0};
    /** The detectors' height on the vehicle [m] (up; the fourth number of `--sensor-pose`). */
    double sensorZ_m = 0;
    /** The `NAME=` forms of the three options above, by sensor label. */
    std::map<std::string, TImportSensorOverride> sensors;
    /** Longest time between two steps while the detector reports nothing [s]
     *  (`--max-step-s`): odometry-only steps are inserted so that no gap is longer. */
    double maxStep_s = 0.5;
    /** The world's bounds margin around the landmarks and the ground-truth path [m]
     *  (`--margin-m`). */
    double margin_m = 10.0;
    /** Detection rows at most this long after a scan's first row are of that scan [s]
     *  (`--scan-window-s`; 0: only rows of one time): a detector stamping each reading of one
     *  frame a few milliseconds apart still gives one scan. */
    double scanWindow_s = kDefaultScanWindow_s;
    /** Longest time between two ground-truth rows that is interpolated across [s]
     *  (`--gt-max-gap-s`; 0: the default, groundTruthMaxGap()): the steps inside a longer gap
     *  have no ground truth. */
    double gtMaxGap_s = 0;

    /** Throws naming the option ("--fov-deg 400: ...", "--fov-deg sonar=400: ...") for a
     *  value out of its range, the `NAME=` forms' too. */
    void check() const;
    /** The coverage and mount of the sensor `label`: its `NAME=` forms, else the defaults. */
    TImportSensor sensor(const std::string& label) const;
    /** Sets `option` ("--max-range-m", "--fov-deg" or "--sensor-pose") from its values on the
     *  command line, each `VALUE` (the default of every sensor; at most once) or `NAME=VALUE`
     *  (for the sensor NAME, a label; at most once a name). Throws naming the option and the
     *  value for a malformed one ("--max-range-m 'sonar=': expected [NAME=]R, R a number [m]");
     *  the ranges are check()'s. */
    void setSensorOption(const std::string& option, const std::vector<std::string>& values);
};

/** A dead-reckoned pose stream (odometry), times strictly increasing. */
struct OdometryTrack
{
    /** Times [s]. */
    std::vector<double> t;
    /** The pose at each time, in the odometry's own frame. */
    std::vector<mrpt::math::TPose2D> pose;

    /** The pose at `time` (within [t.front(), t.back()]), interpolated linearly between the
     *  rows around it (the heading along the shorter arc). */
    mrpt::math::TPose2D at(double time) const;
};

/** The detections of one scan: the rows of one sensor in the detections file from its first
 *  one to the scan window after it (TDatasetImportOptions::scanWindow_s). */
struct DetectionScan
{
    /** Time [s]: its first row's. */
    double t = 0;
    /** The detections (empty: the detector looked and recognized nothing). */
    std::vector<TSemanticDetection> detections;
    /** The sensor label of the detector that made them (the rows' `sensor`). */
    std::string sensor = kDefaultImportSensor;
};

/** A reading of a depth file: the vehicle's depth and, when measured, its altitude. */
struct DepthReading
{
    double t = 0;        //!< time [s]
    double depth_m = 0;  //!< depth below the surface [m] (positive down)
    /** Altitude over the seabed [m], NaN when not measured. */
    double altitude_m = std::numeric_limits<double>::quiet_NaN();
};

/** A reading of a heading file: the vehicle's yaw, counterclockwise from the world's x axis. */
struct HeadingReading
{
    double t = 0;            //!< time [s]
    double heading_rad = 0;  //!< yaw [rad] in [-pi, pi]
};

/** A position fix of a fixes file (USBL, GPS). */
struct FixReading
{
    double t = 0;  //!< time [s]
    double x = 0;  //!< position [m]
    double y = 0;  //!< position [m]
    double z = 0;  //!< height [m] (up: minus the depth)
    /** Standard deviations of x and y [m]; NaN when the file gives none. */
    double sigma_x_m = std::numeric_limits<double>::quiet_NaN();
    /** See sigma_x_m. */
    double sigma_y_m = std::numeric_limits<double>::quiet_NaN();
};

/** The readings of the optional depth, heading and fix files (empty when not given), each
 *  one a time, times increasing. */
struct VehicleReadings
{
    std::vector<DepthReading> depth;
    std::vector<HeadingReading> heading;
    std::vector<FixReading> fixes;
};

/** How the readings of one file (depth, heading, fixes) were placed in the steps' frames. */
struct TImportReadingCounts
{
    size_t written = 0;        //!< readings written, at most one a frame
    size_t superseded = 0;     //!< left out: a later one falls before the same step
    size_t dropped = 0;        //!< after the last step: left out
    size_t repeatedTimes = 0;  //!< rows followed by one of the same time (the last kept)
};

/** A landmark of the landmarks file: a point object and its position's uncertainty. */
struct ImportedLandmark
{
    /** The point object (id, label, centre; sigma_m from the standard deviations below). */
    WorldObject object;
    /** Standard deviations of the position [m] (`sigma_x_m`, `sigma_y_m`; NaN when not
     *  given: both or neither). The world's uncertainty is isotropic: object.sigma_m =
     *  sqrt((sigma_x_m^2 + sigma_y_m^2) / 2), the same total variance (0 without them). */
    double sigma_x_m = std::numeric_limits<double>::quiet_NaN();
    /** See sigma_x_m. */
    double sigma_y_m = std::numeric_limits<double>::quiet_NaN();
};

/** What an import made and how it read what real logs bring, for the tool's summary line
 *  (summaryCounts()) and its warnings. */
struct TDatasetImportStats
{
    size_t steps = 0;                           //!< steps written (action / sensory-frame pairs)
    size_t scans = 0;                           //!< steps with a scan (a CObservationSemantic)
    size_t scanObservations = 0;                //!< CObservationSemantic written (several a step)
    std::map<std::string, size_t> sensorScans;  //!< CObservationSemantic written by sensor
    size_t stepsOfSeveralScans = 0;             //!< steps holding the scans of several sensors
    size_t odometryOnlySteps = 0;               //!< steps without one (gaps longer than maxStep_s)
    size_t detections = 0;                      //!< detections written
    size_t scansOutsideOdometry = 0;       //!< scans before the first / after the last odometry row
    size_t detectionsOutsideCoverage = 0;  //!< beyond maxRange_m or outside the field of view
    size_t detectionsWithoutRange = 0;     //!< detections written without a range (bearing-only)
    /** Of detectionsOutsideCoverage, those of sensor SEMANTIC without a range: the semantic
     *  models need one. */
    size_t semanticWithoutRange = 0;

    size_t odometryRepeatedTimes = 0;     //!< odometry rows followed by one of the same time
    size_t groundTruthRepeatedTimes = 0;  //!< ground-truth rows followed by one of the same time
    size_t detectionsGrouped = 0;  //!< detection rows after their scan's first, within the window
    double scanWindow_s = 0;       //!< the window they were grouped within

    /** With landmarks, detections written whose id (if any) is no landmark's and whose label
     *  is no landmark's: unknown to the map. */
    size_t detectionsUnknown = 0;
    /** With landmarks, detections written whose id is no landmark's but whose label is one's:
     *  associated by label, as without an id. */
    size_t detectionsIdNotLandmark = 0;
    /** With landmarks, detections written whose id is a landmark's of another label:
     *  associated by id. */
    size_t detectionsLabelNotLandmarks = 0;

    size_t groundTruthGaps = 0;  //!< ground-truth gaps longer than the limit with steps in them
    size_t stepsInGroundTruthGaps = 0;   //!< steps inside those gaps: no ground truth
    size_t stepsOutsideGroundTruth = 0;  //!< steps before its first / after its last row
    double groundTruthMaxGap_s = 0;      //!< the limit used

    TImportReadingCounts depth;    //!< the depth file's readings (`--depth`)
    TImportReadingCounts heading;  //!< the heading file's readings (`--heading`)
    TImportReadingCounts fixes;    //!< the fixes file's readings (`--fixes`)

    /** Warnings for stderr (without the tool's prefix): where a rule may have made the result
     *  wrong. */
    std::vector<std::string> warnings;
};

/** One step of the imported dataset: its time and its scans (the first's index in the scans,
 *  or -1 for an odometry-only step, and how many: scans `scan` to `scan + scanCount - 1`, of
 *  different sensors). */
struct ImportStep
{
    double t = 0;
    long scan = -1;
    size_t scanCount = 1;  //!< ignored when scan is -1
};

/** semloc-import's conversions: CSV files (docs/tools.md, "semloc-import") to a rawlog of
 *  action / sensory-frame pairs, a ground truth and a world. Every reader throws naming the
 *  file, the line and the column (detail::CsvTable). */
class DatasetImport
{
public:
    /** Reads an odometry file (the file may be gz-compressed, as every file here): columns
     *  `t,x,y,phi` (dead-reckoned poses), `t,v,w` (forward speed [m/s] and yaw rate [rad/s])
     *  or `t,vx,vy,w` (body-frame velocities over the ground, forward and to port [m/s], as a
     *  DVL gives them, and the yaw rate), the speeds each held from its row to the next and
     *  integrated exactly (arcs) from the pose (0, 0, 0).
     *  Times never go back; rows of one time collapse to the last (the later reading holds
     *  from then on: counted in `stats`, and a warning when they disagree). At least two
     *  distinct times. */
    static OdometryTrack readOdometry(const std::string& path,
                                      TDatasetImportStats* stats = nullptr);
    /** Reads a detections file: `t,label,range_m,bearing_rad`, optional `id`, `confidence`,
     *  `sensor` (the detector's sensor label; empty: kDefaultImportSensor) and `side` (`port`
     *  or `left`: bearing +pi/2, `starboard` or `right`: -pi/2, `bearing_rad` then empty). A
     *  scan is the rows of one sensor from its first one to `scanWindow_s` after it (to the
     *  microsecond; 0: the rows of one time), timed by its first row (the later rows counted
     *  in `stats`, with a warning when the grouping looks wrong: a grouped scan holding one id
     *  twice, or a sensor's scans less than 5 windows apart); the rows of different sensors
     *  interleave freely. A row whose label, range and bearing are empty marks a scan with no
     *  detections; an empty range of a detection is a bearing-only one (range_m NaN). Times
     *  never go back. The scans are in the order of their first rows. */
    static std::vector<DetectionScan> readDetections(const std::string& path,
                                                     double scanWindow_s = kDefaultScanWindow_s,
                                                     TDatasetImportStats* stats = nullptr);
    /** Reads a ground-truth file: `t,x,y,phi`, times never going back; rows of one time are
     *  one pose, the last (counted in `stats`, a warning when they disagree). */
    static std::vector<GroundTruthRow> readGroundTruth(const std::string& path,
                                                       TDatasetImportStats* stats = nullptr);
    /** Reads a landmarks file: `id,label,x,y`, optional `sigma_x_m,sigma_y_m`; ids positive
     *  and unique, labels as a world file takes them. */
    static std::vector<ImportedLandmark> readLandmarks(const std::string& path);
    /** Reads a depth file: `t,depth_m` (finite, in [-kMaxImportHeight_m, kMaxImportDepth_m]),
     *  optional `altitude_m` (in [0, kMaxImportDepth_m]; empty: not measured). Times as the
     *  odometry's: never going back, rows of one time collapse to the last (counted in
     *  `stats`, a warning when they disagree), never 0 (MRPT's "no timestamp"). */
    static std::vector<DepthReading> readDepth(const std::string& path,
                                               TDatasetImportStats* stats = nullptr);
    /** Reads a heading file: `t,heading_rad` (the vehicle's yaw counterclockwise from the
     *  world's x axis, as the odometry's phi; within +-kMaxImportHeading_rad, wrapped to
     *  [-pi, pi]). Times as readDepth()'s. */
    static std::vector<HeadingReading> readHeading(const std::string& path,
                                                   TDatasetImportStats* stats = nullptr);
    /** Reads a fixes file: `t,x,y`, optional `z` (metres up; empty or absent: minus the depth
     *  of the last of `depth` at or before the fix, the first one before any, 0 without
     *  `depth`) and the standard deviations [m], `sigma_m` (of x and y) or both `sigma_x_m`,
     *  `sigma_y_m` (positive; a given column's cells are never empty; without any, a warning
     *  in `stats`). Times as readDepth()'s. */
    static std::vector<FixReading> readFixes(const std::string& path,
                                             const std::vector<DepthReading>& depth = {},
                                             TDatasetImportStats* stats = nullptr);
    /** readLandmarks() into a LandmarkSet (40 bytes a landmark, sigma_m the isotropic
     *  standard deviation): what semloc-import holds of a large landmark map. */
    static LandmarkSet readLandmarkSet(const std::string& path);

    /** The readers above on the text of `in` (e.g. a std::istringstream), `name` standing for
     *  the file in their messages. */
    static OdometryTrack readOdometry(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&). */
    static std::vector<DetectionScan> readDetections(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&). */
    static std::vector<GroundTruthRow> readGroundTruth(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&). */
    static std::vector<ImportedLandmark> readLandmarks(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&). */
    static std::vector<DepthReading> readDepth(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&). */
    static std::vector<HeadingReading> readHeading(std::istream& in, const std::string& name);
    /** See readOdometry(std::istream&, const std::string&); the fixes' z is 0 when not given. */
    static std::vector<FixReading> readFixes(std::istream& in, const std::string& name);

    /** The steps: one per scan within the odometry's time span (the others are counted in
     *  `stats.scansOutsideOdometry`), the scans of other sensors that follow a step's first
     *  within `scanWindow_s` of it (to the microsecond) sharing its step, and evenly spaced
     *  odometry-only steps between two steps more than `maxStep_s` apart, so that no gap is
     *  longer. Throws if no scan is left, and before making any step if the times look like
     *  milliseconds or finer (checkTimeUnit) or if there would be more than kMaxImportSteps
     *  steps; `odometryName` and `detectionsName` name the files in the messages. */
    static std::vector<ImportStep> steps(const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry, double maxStep_s,
                                         TDatasetImportStats& stats,
                                         const std::string& odometryName = "odometry",
                                         const std::string& detectionsName = "detections",
                                         double scanWindow_s = kDefaultScanWindow_s);
    /** Throws if the median time between consecutive distinct times of the odometry and the
     *  scans together is above kMaxImportMedianInterval_s: "times of 'odom.csv' and
     *  'det.csv': the median time between consecutive rows is 1000 s, more than 10 s: are the
     *  times in milliseconds? semloc-import takes seconds". */
    static void checkTimeUnit(const std::vector<DetectionScan>& scans,
                              const OdometryTrack& odometry, const std::string& odometryName,
                              const std::string& detectionsName);
    /** The unit times seem to be in when they read `ratio` times what seconds would:
     *  "milliseconds" (below 3e4), "microseconds" (below 3e7) or "nanoseconds". */
    static const char* likelyTimeUnit(double ratio);

    /** The rawlog of `steps`: per step a CActionCollection holding a CActionRobotMovement2D
     *  (the odometry increment since the previous step, zero for the first; its Gaussian from
     *  MRPT's default motion model, CActionRobotMovement2D::computeFromOdometry), then a
     *  CSensoryFrame holding, in this order, the last depth reading (CObservationDepth, label
     *  `depth`), heading (CObservationIMU's IMU_YAW, label `compass`) and fix
     *  (CObservationRobotPose, label `usbl`) of `readings` since the previous step (each
     *  reading in the frame of the first step at or after its time; the earlier ones of a
     *  step counted as superseded, those after the last step as dropped), then one
     *  CObservationSemantic per scan of the step (its sensor's label, coverage and mount from
     *  `options`); an odometry-only step's frame holds the readings alone. */
    static mrpt::obs::CRawlog makeRawlog(const std::vector<ImportStep>& steps,
                                         const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry,
                                         const VehicleReadings& readings,
                                         const TDatasetImportOptions& options,
                                         TDatasetImportStats& stats);
    /** makeRawlog() without readings. */
    static mrpt::obs::CRawlog makeRawlog(const std::vector<ImportStep>& steps,
                                         const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry,
                                         const TDatasetImportOptions& options,
                                         TDatasetImportStats& stats);
    /** Writes the rawlog makeRawlog() makes to `path` (gz-compressed, the bytes
     *  saveRawlog(log, path, "semloc-import") writes of it: the signature first) entry by entry,
     *  never holding more than one step in memory; throws "cannot write 'PATH': REASON" on an
     *  error. */
    static void writeRawlog(const std::vector<ImportStep>& steps,
                            const std::vector<DetectionScan>& scans, const OdometryTrack& odometry,
                            const VehicleReadings& readings, const TDatasetImportOptions& options,
                            TDatasetImportStats& stats, const std::string& path);
    /** writeRawlog() without readings. */
    static void writeRawlog(const std::vector<ImportStep>& steps,
                            const std::vector<DetectionScan>& scans, const OdometryTrack& odometry,
                            const TDatasetImportOptions& options, TDatasetImportStats& stats,
                            const std::string& path);
    /** A warning in `stats` for each sensor a `NAME=` option names and no scan is of
     *  ("--max-range-m sonar=: no detection row is of sensor 'sonar' (the detections'
     *  sensors: SEMANTIC): not used"). */
    static void checkSensors(const std::vector<DetectionScan>& scans,
                             const TDatasetImportOptions& options, TDatasetImportStats& stats);

    /** The ground truth at each step time within its span, interpolated as OdometryTrack::at
     *  does, except inside a gap between two rows longer than `maxGap_s` (0: the default,
     *  groundTruthMaxGap()): a step strictly inside one has no row (counted in `stats`, with a
     *  warning naming the longest gap), as has a step outside the span. Throws naming `path`
     *  if no step has a row. */
    static std::vector<GroundTruthRow> groundTruthAtSteps(const std::vector<GroundTruthRow>& gt,
                                                          const std::vector<ImportStep>& steps,
                                                          const std::string& path,
                                                          double maxGap_s = 0,
                                                          TDatasetImportStats* stats = nullptr);
    /** The longest ground-truth gap interpolated across [s]: `option` if positive, else the
     *  larger of kMinGroundTruthMaxGap_s and kGroundTruthGapPeriods times the median time
     *  between consecutive rows. */
    static double groundTruthMaxGap(const std::vector<GroundTruthRow>& gt, double option);
    /** With a map: counts the detections of the written scans that no landmark explains in
     *  `stats` (unknown to the map; an id no landmark has; a label unlike its landmark's),
     *  each kind with a warning naming a few labels and ids. They are written as they are. */
    static void checkLandmarks(const std::vector<ImportStep>& steps,
                               const std::vector<DetectionScan>& scans,
                               const std::vector<ImportedLandmark>& landmarks,
                               TDatasetImportStats& stats);
    /** checkLandmarks() of a LandmarkSet (memory beyond it: 8 bytes a landmark). */
    static void checkLandmarkSet(const std::vector<ImportStep>& steps,
                                 const std::vector<DetectionScan>& scans,
                                 const LandmarkSet& landmarks, TDatasetImportStats& stats);
    /** The counts of `stats` the summary line gives after the detections ("3 repeated odometry
     *  times (the later reading kept), 12 detections grouped into scans within 0.01 s"), the
     *  zero ones left out; "" when all are zero. */
    static std::string summaryCounts(const TDatasetImportStats& stats);
    /** The world of the landmarks (point objects): bounds around them and the ground-truth
     *  path, grown by `margin_m`; checked by the world loader. */
    static World makeWorld(const std::vector<ImportedLandmark>& landmarks,
                           const std::vector<GroundTruthRow>& groundTruth, double margin_m,
                           const std::string& name);
    /** makeWorld() of a LandmarkSet without its objects (LandmarkImport::makeWorldFrame()):
     *  World::saveToFile(file, landmarks.objectList()) writes the world makeWorld() makes. */
    static World makeWorldFrame(const LandmarkSet& landmarks,
                                const std::vector<GroundTruthRow>& groundTruth, double margin_m,
                                const std::string& name);
};

}  // namespace semloc

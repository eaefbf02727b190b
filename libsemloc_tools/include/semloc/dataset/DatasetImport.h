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
/** Largest odometry speed `v` [m/s]. */
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

/** The default of `--scan-window-s` [s]: 10 ms, below the frame period of any detector that
 *  reports up to 100 scans a second, above the few milliseconds a detector spends stamping the
 *  readings of one frame one by one. */
constexpr double kDefaultScanWindow_s = 0.01;
/** The default of `--gt-max-gap-s` is the larger of this [s] and kGroundTruthGapPeriods times
 *  the ground truth's median period. */
constexpr double kMinGroundTruthMaxGap_s = 1.0;
/** See kMinGroundTruthMaxGap_s. */
constexpr double kGroundTruthGapPeriods = 10.0;

/** The options of semloc-import (docs/tools.md, "semloc-import"). */
struct TDatasetImportOptions
{
    /** The detector's maximum range [m] (`--max-range-m`), CObservationSemantic::maxRange_m. */
    double maxRange_m = 20.0;
    /** The detector's horizontal field of view [deg] (`--fov-deg`), centred on its x axis. */
    double fov_deg = 120.0;
    /** The detector's pose on the vehicle (`--sensor-pose x,y,yaw_deg`; phi in radians). */
    mrpt::math::TPose2D sensorPose{0, 0, 0};
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

    /** Throws naming the option ("--fov-deg 400: ...") for a value out of its range. */
    void check() const;
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

/** The detections of one scan: the rows of the detections file from its first one to the
 *  scan window after it (TDatasetImportOptions::scanWindow_s). */
struct DetectionScan
{
    /** Time [s]: its first row's. */
    double t = 0;
    /** The detections (empty: the detector looked and recognized nothing). */
    std::vector<TSemanticDetection> detections;
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
    size_t steps = 0;                      //!< steps written (action / sensory-frame pairs)
    size_t scans = 0;                      //!< steps with a scan (a CObservationSemantic)
    size_t odometryOnlySteps = 0;          //!< steps without one (gaps longer than maxStep_s)
    size_t detections = 0;                 //!< detections written
    size_t scansOutsideOdometry = 0;       //!< scans before the first / after the last odometry row
    size_t detectionsOutsideCoverage = 0;  //!< beyond maxRange_m or outside the field of view

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

    /** Warnings for stderr (without the tool's prefix): where a rule may have made the result
     *  wrong. */
    std::vector<std::string> warnings;
};

/** One step of the imported dataset: its time and its scan (an index in the scans, or -1
 *  for an odometry-only step). */
struct ImportStep
{
    double t = 0;
    long scan = -1;
};

/** semloc-import's conversions: CSV files (docs/tools.md, "semloc-import") to a rawlog of
 *  action / sensory-frame pairs, a ground truth and a world. Every reader throws naming the
 *  file, the line and the column (detail::CsvTable). */
class DatasetImport
{
public:
    /** Reads an odometry file (the file may be gz-compressed, as every file here): columns
     *  `t,x,y,phi` (dead-reckoned poses) or `t,v,w` (forward speed [m/s] and yaw rate [rad/s],
     *  each held from its row to the next and integrated exactly from the pose (0, 0, 0)).
     *  Times never go back; rows of one time collapse to the last (the later reading holds
     *  from then on: counted in `stats`, and a warning when they disagree). At least two
     *  distinct times. */
    static OdometryTrack readOdometry(const std::string& path,
                                      TDatasetImportStats* stats = nullptr);
    /** Reads a detections file: `t,label,range_m,bearing_rad`, optional `id`, `confidence`.
     *  A scan is the rows from its first one to `scanWindow_s` after it (to the microsecond;
     *  0: the rows of one time), timed by its first row (the later rows counted in `stats`,
     *  with a warning when the grouping looks wrong: a grouped scan holding one id twice, or
     *  scans less than 5 windows apart); a row whose label, range and bearing are empty marks
     *  a scan with no detections. Times never go back. */
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

    /** The steps: one per scan within the odometry's time span (the others are counted in
     *  `stats.scansOutsideOdometry`), and evenly spaced odometry-only steps between two scans
     *  more than `maxStep_s` apart, so that no gap is longer. Throws if no scan is left, and
     *  before making any step if the times look like milliseconds or finer (checkTimeUnit)
     *  or if there would be more than kMaxImportSteps steps; `odometryName` and
     *  `detectionsName` name the files in the messages. */
    static std::vector<ImportStep> steps(const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry, double maxStep_s,
                                         TDatasetImportStats& stats,
                                         const std::string& odometryName = "odometry",
                                         const std::string& detectionsName = "detections");
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
     *  CSensoryFrame holding the scan's CObservationSemantic (label SEMANTIC), or nothing for
     *  an odometry-only step. */
    static mrpt::obs::CRawlog makeRawlog(const std::vector<ImportStep>& steps,
                                         const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry,
                                         const TDatasetImportOptions& options,
                                         TDatasetImportStats& stats);
    /** Writes the rawlog makeRawlog() makes to `path` (gz-compressed, the bytes
     *  saveRawlog(log, path, "semloc-import") writes of it: the signature first) entry by entry,
     * never holding more than one step in memory; throws "cannot write 'PATH': REASON" on an error.
     */
    static void writeRawlog(const std::vector<ImportStep>& steps,
                            const std::vector<DetectionScan>& scans, const OdometryTrack& odometry,
                            const TDatasetImportOptions& options, TDatasetImportStats& stats,
                            const std::string& path);

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

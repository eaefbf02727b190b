/* semloc — import a vehicle's dataset from plain-text (CSV) files as a semantic rawlog. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <cmath>
#include <cstddef>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace semloc
{
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

/** The detections of one scan: every row of the detections file with one time. */
struct DetectionScan
{
    /** Time [s]. */
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

/** What an import made, for the tool's summary. */
struct TDatasetImportStats
{
    size_t steps = 0;                      //!< steps written (action / sensory-frame pairs)
    size_t scans = 0;                      //!< steps with a scan (a CObservationSemantic)
    size_t odometryOnlySteps = 0;          //!< steps without one (gaps longer than maxStep_s)
    size_t detections = 0;                 //!< detections written
    size_t scansOutsideOdometry = 0;       //!< scans before the first / after the last odometry row
    size_t detectionsOutsideCoverage = 0;  //!< beyond maxRange_m or outside the field of view
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
    /** Reads an odometry file: columns `t,x,y,phi` (dead-reckoned poses) or `t,v,w` (forward
     *  speed [m/s] and yaw rate [rad/s], each held from its row to the next and integrated
     *  exactly from the pose (0, 0, 0)). At least two rows; times strictly increasing. */
    static OdometryTrack readOdometry(const std::string& path);
    /** Reads a detections file: `t,label,range_m,bearing_rad`, optional `id`, `confidence`.
     *  Rows with one `t` form a scan; a row whose label, range and bearing are empty marks a
     *  scan with no detections. Times never go back. */
    static std::vector<DetectionScan> readDetections(const std::string& path);
    /** Reads a ground-truth file: `t,x,y,phi`, times strictly increasing. */
    static std::vector<GroundTruthRow> readGroundTruth(const std::string& path);
    /** Reads a landmarks file: `id,label,x,y`, optional `sigma_x_m,sigma_y_m`; ids positive
     *  and unique, labels as a world file takes them. */
    static std::vector<ImportedLandmark> readLandmarks(const std::string& path);

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
     *  more than `maxStep_s` apart, so that no gap is longer. Throws if no scan is left. */
    static std::vector<ImportStep> steps(const std::vector<DetectionScan>& scans,
                                         const OdometryTrack& odometry, double maxStep_s,
                                         TDatasetImportStats& stats);

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

    /** The ground truth at each step time within its span, interpolated as OdometryTrack::at
     *  does. Throws naming `path` if it covers no step. */
    static std::vector<GroundTruthRow> groundTruthAtSteps(const std::vector<GroundTruthRow>& gt,
                                                          const std::vector<ImportStep>& steps,
                                                          const std::string& path);
    /** Writes `t x y phi` rows (semloc-localize's ground truth); throws naming the file. */
    static void writeGroundTruth(const std::vector<GroundTruthRow>& rows, const std::string& path);

    /** The world of the landmarks (point objects): bounds around them and the ground-truth
     *  path, grown by `margin_m`; checked by the world loader. */
    static World makeWorld(const std::vector<ImportedLandmark>& landmarks,
                           const std::vector<GroundTruthRow>& groundTruth, double margin_m,
                           const std::string& name);
};

}  // namespace semloc

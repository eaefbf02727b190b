/* semloc — the noise of the water column's sensor models (side-scan, forward-looking sonar,
 * camera, compass, position fixes) and of the DVL's motion model, fitted against a dataset's
 * ground truth (semloc-calibrate, docs/tools.md). */
#pragma once

#include <semloc/calibration/SensorCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace semloc
{
/** The fits of one model of the base ini: a map of its [MetricMap] or its [MotionModel]. */
struct TModelFits
{
    /** The ini section the keys are written into ("MetricMap_sideScanMap_00_likelihoodOpts",
     *  "MotionModel"). */
    std::string section;
    /** The model as the summary names it ("sideScanMap 'sidescan'", "[MotionModel] dvl"). */
    std::string name;
    /** What the fits were made from: scans, readings, fixes or increments, and their unit. */
    size_t samples = 0;
    std::string unit;
    /** The keys fitted, in the order written. */
    std::vector<std::pair<std::string, TCalibrationFit>> keys;
};

/** Fits the models of the water column a base ini runs, each against the readings of its own
 *  sensor (its `sensor_label`), the vehicle at the ground-truth row nearest each reading
 *  (within `gtTolerance_s`; readings without one are left out):
 *
 *  - **detector kinds** (sideScanMap, forwardSonarMap, bearingCameraMap): each scan's
 *    detections are matched one to one, greedily from the nearest, to the objects of their
 *    label the kind's geometry puts in view (CObjectDetectorMap::inView, the depth readings
 *    taken in frame order as the filter takes them), first within `gate_m` (range and
 *    bearing as metres across), then within 4 sigmas of the first pass's fits.
 *    sigma_range_m and sigma_bearing_deg: 1.4826 MAD of the residuals (of the quantities the
 *    kind measures); p_detect_near/far: least-squares line of detected (0/1) against
 *    range / max_range_m over the objects in view, at 0 and 1; clutter_per_scan: the
 *    detections left unmatched per scan;
 *  - **compassMap**: the heading residuals (reading less the mount's yaw, less the true
 *    heading). p_outlier: the share beyond 5 robust sigmas of their median. sigma_deg: the
 *    RMS of the others (a constant or slowly changing deviation included) times the square
 *    root of their integrated autocorrelation time in readings (1 + 2 sum of the
 *    autocorrelations up to the first that is not positive): a deviation that lasts a
 *    survey leg is not averaged away by the readings of the leg, and the filter must not
 *    believe it is;
 *  - **poseFixMap**: the fixes' x and y residuals. sigma_m: their pooled robust sigma;
 *    p_outlier: the share of fixes beyond the 99.99 % radius of that Gaussian;
 *    outlier_sigma_m: the outliers' RMS component (with at least 3 of them);
 *  - **[MotionModel] kind = dvl**: the body-frame error of each odometry increment against
 *    the true one: a1 (each axis' sigma per metre) and a3 (the heading's, deg per metre) by
 *    maximum likelihood of sigma = a d over the increments that moved (kMinMove_m).
 *
 *  A fit from too few samples (TCalibrationResult's kMin* counts) is not written (the base's
 *  value stays, and the ini's comment says so); a fit outside the range the model's key
 *  takes is clamped into it. */
class SensorModelCalibration
{
public:
    /** Whether the ini text `baseIni` runs a model this class fits. */
    static bool HasModels(const std::string& baseIni);

    /** The fits of every such model of `baseIni` (the base ini `basePath`'s text, its bases
     *  resolved) from the rawlog file `rawlogPath` (streamed, twice), the world file
     *  `worldPath` and the ground truth `gt`. */
    static std::vector<TModelFits> Estimate(const std::string& rawlogPath,
                                            const std::string& baseIni, const std::string& basePath,
                                            const std::string& worldPath,
                                            const std::vector<GroundTruthRow>& gt,
                                            double gtTolerance_s, double gate_m);

    /** `ini` (an ini text named `name` in messages) with the fits set in their sections,
     *  each with its comment (a fit not made: a comment line saying so), and, when
     *  `worldPath` is not empty, [LocalizationExperiment] map_file set to it (absolute). */
    static std::string ApplyToIni(const std::string& ini, const std::string& name,
                                  const std::vector<TModelFits>& fits,
                                  const std::string& worldPath = "");

    /** report.md into `out`: the fits of each model with how they were made. */
    static std::vector<TFigureWarning> WriteReport(const std::vector<TModelFits>& fits,
                                                   StagedDirectory& out);

    /** One line per model for semloc-calibrate's summary: "sideScanMap 'sidescan': 1200
     *  scans: sigma_range_m 0.31, ...". */
    static std::string SummaryText(const std::vector<TModelFits>& fits);

    /** The fits not written as fitted (too little data, clamped), one sentence each. */
    static std::vector<std::string> Warnings(const std::vector<TModelFits>& fits);
};

}  // namespace semloc

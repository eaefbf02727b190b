/* semloc — the detector's and the odometry's noise estimated from a dataset with ground truth
 * (semloc-calibrate's engine). */
#pragma once

#include <mrpt/obs/CRawlog.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/plot/FigureWarning.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace semloc
{
/** One estimated value and how it was fitted. */
struct TCalibrationFit
{
    /** The estimate, in the unit of the ini key it fills. */
    double value = 0;
    /** Number of samples it was fitted from. */
    size_t n = 0;
    /** Half-width of its approximate 95 % confidence interval (same unit; 0: not computed). */
    double ci95 = 0;
    /** How it was fitted, one phrase (written as the ini key's comment). */
    std::string method;
    /** What is written for it. */
    enum class Status
    {
        /** The fit, within the range the filter accepts. */
        Fitted,
        /** The fit moved into the range the filter accepts (`fitted` holds it). */
        Clamped,
        /** Too little data to fit it: the base ini's value is written. */
        TooLittleData
    };
    Status status = Status::Fitted;
    /** Clamped: the value fitted, before it was moved into the range. */
    double fitted = 0;
    /** Clamped, TooLittleData: why, one phrase (in the ini comment and the warning). */
    std::string why;
    /** The factor the consistency stage multiplied the fit by (1: not widened). */
    double widenedBy = 1;
};

/** The mean of the matched residuals (a detector's bias) and the sigmas around and about it. */
struct TCalibrationBias
{
    /** Mean range [m] and bearing [deg] residual (of those within 3 sigma of the median). */
    double range_m = 0, bearing_deg = 0;
    /** The robust sigmas around that mean (1.4826 MAD). */
    double sigmaRangeAround_m = 0, sigmaBearingAround_deg = 0;
    /** The robust sigmas of the residuals at the ground-truth poses as given, the map offset
     *  not removed (what the sigmas would be without the offset's fit). */
    double sigmaRangeAtTruth_m = 0, sigmaBearingAtTruth_deg = 0;
};

/** The rigid 2D transform that best aligns the matched detections (placed by the ground-truth
 *  pose, the sensor pose and their range and bearing) with their map objects: a map, or a
 *  ground truth, offset or rotated against the other. p -> R(dtheta) (p - c) + c + (dx, dy). */
struct TMapOffset
{
    /** False: too few matched detections, or of fewer than 2 objects (identity then). */
    bool fitted = false;
    /** True when the fits were made at the ground-truth poses moved by it (it moves the
     *  objects by more than TCalibrationResult::kBiasSigmas sigma_range_m). */
    bool removed = false;
    double dx_m = 0, dy_m = 0, dtheta_deg = 0;
    /** The rotation's centre: the matched objects' centroid [m]. */
    double cx_m = 0, cy_m = 0;
    /** RMS displacement of the matched objects' positions under the transform [m]. */
    double rms_m = 0;
    /** Matched detections (those within 3.5 median distances of the first fit) and distinct
     *  objects it is fitted from. */
    size_t n = 0, objects = 0;
};

/** The samples behind the fits (the report's histograms and curves). */
struct TCalibrationSamples
{
    std::vector<double> rangeResiduals_m;  //!< detection minus object range
    /** ... the detection's bearing over half the field of view (over pi for a full circle):
     *  the variable of the range bias (rangeBias()). */
    std::vector<double> rangeResidualBearing;
    std::vector<double> bearingResiduals_deg;  //!< detection minus object bearing
    std::vector<double> visibleRanges_m;       //!< range of every in-view object ...
    std::vector<int> visibleDetected;          //!< ... 1 when a detection matched it
    /** ... |bearing| over half the field of view, in [0, 1] (0 for a 360-degree view). */
    std::vector<double> visibleOffAxis;
    /** ... per unit of clutter rate, the expected other-label clutter within its gate when no
     *  detection of its label matched it (else 0): what the confusion pass may take for it. */
    std::vector<double> visibleSpurious;
    /** ... per unit of clutter rate, the expected same-label clutter within its misread strip
     *  (its bearing gate at any range, outside its gate) when no detection matched it in a
     *  gate (else 0): what the misread pass may take for a misread range. */
    std::vector<double> visibleMisreadSpurious;
    std::vector<double> odomDist_m;      //!< true increment length per step
    std::vector<double> odomTurn_rad;    //!< |true increment rotation| per step
    std::vector<double> odomErrXY_m;     //!< |position error| of the odometry per step
    std::vector<double> odomErrPhi_rad;  //!< |heading error| of the odometry per step
    /** Signed heading error of the odometry per step (odometry minus truth) [rad]. */
    std::vector<double> odomErrPhiSigned_rad;
    /** Seconds of each step (between the two ground-truth rows it spans). */
    std::vector<double> odomDt_s;
    /** The odometry over the spans the filter integrates without a detection, from one scan
     *  with a detection to the next: the first and one-past-last increment (indices into
     *  the odom* vectors), the span's |position error| [m] and signed heading error [rad] of
     *  the odometry composed over it against the truth composed over it, and its seconds. */
    std::vector<size_t> spanBegin, spanEnd;
    std::vector<double> spanErrXY_m, spanErrPhi_rad, spanDt_s;
    /** Per matched detection (same label): where it puts its object in the map frame (the
     *  pose as corrected by the map offset so far) and the object's centre [m]. */
    std::vector<double> detectedX_m, detectedY_m, objectX_m, objectY_m;
    /** The residuals of rangeResiduals_m and bearingResiduals_deg at the ground-truth pose as
     *  given (no map offset removed). */
    std::vector<double> rangeResidualsAtTruth_m, bearingResidualsAtTruth_deg;
    /** Per clutter detection of a map label (matched to no in-view object): what the
     *  look-alike memory (LookAlikeMemory, the detections of the earlier scans placed by the
     *  poses of the fits) gives it, r max_j N(p; p_j, S) [1/(m rad)], and the uniform clutter
     *  density per unit of clutter rate there, 1 / (max range x field of view x labels). */
    std::vector<double> lookAlikeDensity, lookAlikeUniform;
    /** Per scan: the remembered detections of earlier scans within its coverage (each may be
     *  seen again as a look-alike). */
    std::vector<double> lookAlikeInView;
};

/** One setting the consistency stage ran the filter with (SensorCalibration::Consistency). */
struct TConsistencyTrial
{
    /** Factors on the detector's sigmas and on the motion model's noise, and the likelihood's
     *  tempering (the factor on the base's [PF_options] powFactor). */
    double sensorScale = 1, motionScale = 1, temper = 1;
    /** Filter runs (one per seed) and those that converged. */
    size_t runs = 0, converged = 0;
    /** Steps with ground truth, summed over the runs. */
    size_t steps = 0;
    /** Means over the runs: share of the steps with ground truth whose pose NEES is inside
     *  its 95 % bound, mean NEES, and the error (mean_err_after_conv_m; rmse_m of a run that
     *  did not converge) [m]. */
    double insideShare = 0, neesMean = 0, meanErr_m = 0;
};

/** What the consistency stage tried and chose. */
struct TConsistency
{
    /** Every setting run, in the order run (empty: the stage did not run). */
    std::vector<TConsistencyTrial> trials;
    /** Index of the setting written. */
    size_t chosen = 0;
    /** True when the setting written is consistent (SensorCalibration::Consistent()). */
    bool consistent = false;
    /** The share of steps inside the NEES bound asked for. */
    double minInsideShare = 0.95;
};

/** Every fit semloc-calibrate writes. The keys are those of
 *  [MetricMap_semanticMap_00_likelihoodOpts] and [MotionModel] (MotionModelConfig.h units). */
struct TCalibrationResult
{
    TCalibrationFit sigma_range_m, sigma_bearing_deg;
    TCalibrationFit p_detect_near, p_detect_far, p_detect_edge_ratio;
    TCalibrationFit clutter_per_scan, p_confusion, p_range_outlier;
    /** The chance that a detection is seen again as a look-alike near where it was in the
     *  next scans ([MetricMap_semanticMap_00_likelihoodOpts] lookalike_persistence): the
     *  maximum likelihood of (uniform clutter rate, rho) of the clutter detections as a Poisson
     *  process of intensity kappa + rho r max_j N (LookAlikeMemory), by expectation-
     *  maximization; 0 unless it raises the likelihood significantly (twice the log-ratio
     *  over kLookAlikeChi2, one parameter at 0.1 %). clutter_per_scan is then the uniform part
     *  (less the re-sightings). */
    TCalibrationFit lookalike_persistence;
    /** Clutter detections the fit takes for re-sightings of a look-alike (sum of their
     *  posterior shares). */
    double lookAlikeResightings = 0;
    static constexpr double kLookAlikeChi2 = 10.83;
    TCalibrationFit a1, a2, a3, a4, minStdXY, minStdPHI;
    /** The odometry's heading drift: what its heading gains per minute beyond the truth
     *  [deg/min] (signed; the heading errors' sum over the time they span). */
    TCalibrationFit heading_drift_deg_per_min;
    /** The detector's range bias by bearing ([MetricMap_semanticMap_00_likelihoodOpts]
     *  range_bias_m: coefficients of rangeBias(), empty: none) and each coefficient's 95 %
     *  half-width [m]: robust least squares (residuals over 4 robust sigmas left out) of the
     *  range residuals against 1, u, u^2, u^3, u the bearing over half the view, one pass at a
     *  time, each pass matching the detections with the ranges less the bias so far; kept
     *  when the pass's fit lowers the squared residuals significantly (n ln(SSE(0) / SSE) over
     *  kRangeBiasChi2, a likelihood-ratio test of 4 parameters at 0.1 %). The sigmas and the
     *  other fits are of the detections with the bias taken off, as the filter takes it. */
    std::vector<double> rangeBias_m, rangeBiasCi95_m;
    /** The robust sigma of the range residuals with no bias taken off [m] (0: not computed). */
    double sigmaRangeUncorrected_m = 0;
    static constexpr double kRangeBiasChi2 = 18.47;
    /** How late the vehicle follows its odometry [s] ([MotionModel] odometry_delay_s): the
     *  delay whose re-cut increments (OdometryDelay) err least in heading against the ground
     *  truth, over a grid of kDelayStep_s up to kMaxFittedDelay_s; 0 unless it lowers their
     *  squared heading errors significantly (n ln(SSE(0) / SSE(d)) over kDelayChi2, a
     *  likelihood-ratio test of one parameter at 0.1 %). ci95: the profile interval's
     *  half-width. The odometry fits below are made on the re-cut increments. */
    TCalibrationFit odometry_delay_s;
    /** RMS heading error of the odometry's increments as they come and re-cut by the delay
     *  written [deg]. */
    double odomHeadingRms_deg = 0, odomHeadingRmsDelayed_deg = 0;
    static constexpr double kDelayStep_s = 0.01, kMaxFittedDelay_s = 2.0, kDelayChi2 = 10.83;
    /** The factor on the base's [PF_options] powFactor the consistency stage chose (1: the
     *  base's kept). */
    double temper = 1;
    /** The factors the odometry's position and heading noise were multiplied by so that the
     *  errors over the spans between detections (TCalibrationSamples::span*) are those the
     *  per-step model adds up to (1: the per-step fit already covers them). */
    double spanFactorXY = 1, spanFactorPhi = 1;
    /** True when that drift is real: its 95 % interval excludes 0 and it is at least
     *  kMinHeadingDriftDegPerMin; then the heading noise (minStdPHI, a3, a4) is fitted to
     *  the errors less the drift, and the calibrated ini turns the drift state on. */
    bool headingDrifts = false;
    /** The smallest drift rate the calibration turns the drift state on for [deg/min]
     *  (1 deg/min: under 2 degrees over a two-minute silence). */
    static constexpr double kMinHeadingDriftDegPerMin = 1;
    /** Semantic scans with a ground-truth pose, and the detector's max range of the first. */
    size_t scans = 0;
    double maxRange_m = 0;
    /** Detections matched to an object of their label, of another label, unmatched. */
    size_t matched = 0, confused = 0, clutter = 0;
    /** Of the detections not matched in the gate, those taken as a misread range of an
     *  object of their label (its bearing, any range). */
    size_t misread = 0;
    /** The share of [0, max range] a misread range falls into and is still matched in the
     *  gate (2 gateSigmas sigma_range / max range, at most 1). */
    double misreadInGate = 0;
    /** Odometry increments compared with ground-truth increments. */
    size_t increments = 0;
    /** Of those, the increments in which the vehicle moved (kMinMove_m or kMinTurn_deg). */
    size_t movingIncrements = 0;
    /** The detector's bias; the map's offset against the ground truth. */
    TCalibrationBias bias;
    TMapOffset mapOffset;
    TCalibrationSamples samples;
    /** The consistency stage's trials, when it ran (the fits are then those it chose). */
    TConsistency consistency;

    /** @name The least data a fit is made from (docs/tools.md, "semloc-calibrate"): with less,
     *  the base ini's value is written and a warning says so. @{ */
    /** Matched residuals of a sigma, matched detections of the map offset. */
    static constexpr size_t kMinResiduals = 10;
    /** In-view objects of p_detect_near/far; matched detections of p_confusion and
     *  p_range_outlier. */
    static constexpr size_t kMinChances = 20;
    /** Scans of clutter_per_scan. */
    static constexpr size_t kMinScans = 10;
    /** Odometry increments in which the vehicle moved, for [MotionModel]. */
    static constexpr size_t kMinMovingIncrements = 10;
    /** An increment moved when its true length or turn reaches these. */
    static constexpr double kMinMove_m = 1e-3, kMinTurn_deg = 0.05;
    /** @} */
    /** A bias over this many of its sigma, a map offset moving the objects by over this many
     *  sigma_range_m, is warned of (and the offset removed from the poses of the fits). */
    static constexpr double kBiasSigmas = 0.5;
};

/** Where semloc-calibrate's long steps are, for a progress display (a bar on a terminal):
 *  `done` of `total` `unit`s of `stage` ("pass 2 of 3: matching", 1234 of 60000 "entries");
 *  `total` is 0 while it is not known (the rawlog's first reading). */
struct TCalibrationProgress
{
    std::string stage;
    size_t done = 0, total = 0;
    std::string unit;
};
/** Called as a step goes on (after each rawlog entry, each step of a search). */
using CalibrationProgress = std::function<void(const TCalibrationProgress&)>;

/** Estimates the noise of a dataset's detector and odometry against its ground truth
 *  (docs/tools.md, "semloc-calibrate").
 *
 *  **Matching.** At each semantic scan the vehicle is at the ground-truth row nearest in time
 *  (at most `gtTolerance_s` away, else an error naming the rawlog entry). The in-view objects
 *  are the world's objects the detector sees from there, occlusion included
 *  (SemanticDetectorModel::visibleObjects with the observation's max range, field of view
 *  and sensor pose). A detection is matched to an in-view object of its label within the
 *  **gate**, one to one, greedily from the nearest pair; the detections left are then
 *  matched, the same way, to the in-view objects left of any other label (confusions); the
 *  rest are clutter. From the second pass on, a detection left after that is matched to an
 *  in-view object left of its label whose bearing is within the gate's bearing half-width
 *  (gateSigmas sigma_bearing) at any range, greedily from the nearest bearing: a misread
 *  range. The first pass's gate is a disc of `gate_m` (default 3 m) around the
 *  object's centre in the sensor frame; each of the `gatePasses` next passes (default 2)
 *  gates with the ellipse (d_range / sigma_range)^2 + (d_bearing / sigma_bearing)^2 <=
 *  `gateSigmas`^2 (default 4) with the sigmas the previous pass fitted, so a large bearing
 *  noise at long range is not cut by a fixed distance, and the fits are those of the last
 *  pass. Clutter that falls within the gate of an object left after the first matching is
 *  counted as a confusion there: its expected number (the clutter is uniform in range and
 *  bearing: the gate's area in that plane) is moved back from the confusions and detections
 *  to the clutter (iterated to a fixed point, as it depends on the clutter rate).
 *
 *  **Fits.** sigma_range_m, sigma_bearing_deg: 1.4826 x the median absolute deviation of the
 *  matched residuals (robust to the few clutter points the gate lets in). p_detect_near/far:
 *  least-squares line of "detected" (0/1) against r / max_range over every in-view object,
 *  at 0 and at 1. clutter_per_scan: unmatched detections per scan (Poisson interval),
 *  corrected as above. p_confusion: confused / (matched + confused), corrected as above.
 *  p_range_outlier: misread ranges over the detections of an object of their label, less the
 *  same-label clutter expected in the misread strips (uniform: the strips' area less the
 *  gates'), over the share of [0, max range] outside the gate (a misread inside it is
 *  matched); P_D's line is divided by 1 - p_range_outlier x that share (the misreads it did
 *  not count). lookalike_persistence: TCalibrationResult::lookalike_persistence, the
 *  detections remembered by LookAlikeMemory placed by the poses of the fits. Odometry: the error of
 * each odometry increment against the ground-truth increment (both in the previous true pose's
 * frame); E|e_xy| = std_xy sqrt(pi/2) for an isotropic 2D Gaussian and E|e_phi| = std_phi
 * sqrt(2/pi), so least squares of |e| against [1, d, |dphi|] gives minStdXY, a1, a2 and minStdPHI,
 * a3, a4 (clamped at 0); a coefficient whose regressor does not vary (e.g. no turns) is 0.
 *
 *  **Bias and map offset.** The sigmas are written about 0, sqrt(sigma^2 + mean^2), the
 *  residuals' mean in TCalibrationResult::bias. After each pass the rigid transform aligning
 *  the matched detections with their objects is fitted (TCalibrationResult::mapOffset); when
 *  it moves them by more than kBiasSigmas sigma_range, the next pass places the scans at the
 *  ground-truth poses moved by it (the fits are then in the map's frame, where the filter
 *  localizes).
 *
 *  **Limits.** Every fit is then kept to the range semloc-localize accepts for its key
 *  (CSemanticMap::TLikelihoodOptions::range, MotionModelConfig::TOptions::range): clamped into it,
 *  or TooLittleData under the kMin* counts of TCalibrationResult (docs/tools.md). */
class SensorCalibration
{
public:
    /** Tunables of the estimator. */
    struct TOptions
    {
        /** Gate of the first matching pass [m]. */
        double gate_m = 3.0;
        /** Gate of the next passes, in sigmas of the range and bearing residuals. */
        double gateSigmas = 4.0;
        /** Number of passes after the first. */
        int gatePasses = 2;
        /** Largest time between a scan and its ground-truth row [s]. */
        double gtTolerance_s = 0.05;
        /** The look-alikes' speed and the memory's window the persistence is fitted with
         *  (the base ini's lookalike_speed_mps and lookalike_window_s: ReadBaseOptions()). */
        double lookAlikeSpeed_mps = 0.3, lookAlikeWindow_s = 1.0;
    };

    /** `o` with the look-alike speed and window of the base ini `baseIni`'s semantic map (its
     *  defaults where the base has none). */
    static void ReadBaseOptions(const std::string& baseIni, TOptions& o);

    /** Fits every value from `rawlog` (read from `rawlogName`, used in errors), the world's
     *  objects and the ground truth. Throws on a dataset without semantic scans, a scan without
     *  a ground-truth row, too few samples for a fit. */
    static TCalibrationResult Estimate(const mrpt::obs::CRawlog& rawlog,
                                       const std::string& rawlogName, const World& world,
                                       const std::vector<GroundTruthRow>& groundTruth,
                                       const TOptions& options);

    /** Estimate() of the rawlog file `rawlogPath`, streamed: read once for the odometry's
     *  delay and once per matching pass (gatePasses + 2 times), one entry in memory at a
     *  time, so that memory grows only with the samples of the fits (TCalibrationSamples),
     *  not with the rawlog. The same fits as Estimate() of the file loaded
     *  (RawlogReader::Load); its errors too (a truncated or corrupted entry, a file without
     *  entries), thrown when the first reading reaches them. `progress` is told each entry of
     *  each reading and each step of the detection model's search. The ground truth is taken
     *  (move it in: it is not copied). */
    static TCalibrationResult EstimateFromFile(const std::string& rawlogPath, const World& world,
                                               std::vector<GroundTruthRow> groundTruth,
                                               const TOptions& options,
                                               const CalibrationProgress& progress = {});

    /** Checks the base ini `basePath` as semloc-localize checks an ini
     *  (LocalizationExperiment::CheckConfig, with `worldPath` as its map_file), so the
     *  calibrated ini is never refused for something of the base; then throws naming the file
     *  and [MetricMap] semanticMap_count when it has no semantic map whose noise the fits could
     *  fill. */
    static void CheckBase(const std::string& basePath, const std::string& worldPath);

    /** What the user must know of the fits, one sentence each (semloc-calibrate prints them
     *  on stderr as warnings; report.md lists them): a fit clamped into the range the filter
     *  accepts, a fit with too little data (the base's value written), a bias of the
     *  residuals over half their sigma, a range bias by bearing over half the range sigma on
     *  the axis or at an edge of the view (taken off, but that large), a map offset moving
     *  the objects more than sigma_range_m. */
    static std::vector<std::string> Warnings(const TCalibrationResult& result);

    /** semloc-calibrate's summary on stdout: "N scans, M odometry increments: sigma_range_m
     *  V, sigma_bearing_deg V, p_detect V .. V, clutter_per_scan V, p_confusion V,
     *  p_range_outlier V", each V as the ini `ini` (ApplyToIni() of `result`) writes it, with
     *  why in brackets when it is not the fit as made (its comment there, without the fit's
     *  method: "not fitted, too little data (...): the base ini's value kept", "fitted 0 (...),
     *  clamped to the smallest value the filter takes", "widened x8 by the consistency stage
     *  (fitted 0.03416)"); then, when [MotionModel] is the base's, that and why. */
    static std::string SummaryText(const TCalibrationResult& result, const std::string& ini);

    /** The bias and map offset as lines for the terminal and report.md. */
    static std::string BiasText(const TCalibrationResult& result);

    /** Whether trial `t` is consistent: every run converged and its share of steps inside the
     *  NEES bound is not significantly below `minShare`: at least minShare - 2 sqrt(minShare
     *  (1 - minShare) / t.steps). A filter exactly as consistent as asked has a measured share
     *  below minShare in half of its runs; the tolerance (2 standard errors over the steps,
     *  counted as independent) keeps the stage from widening the noise for that. */
    static bool Consistent(const TConsistencyTrial& t, double minShare);

    /** The consistency stage's search (Consistency()). */
    struct TConsistencyOptions
    {
        /** One filter run per seed and setting. */
        std::vector<uint32_t> seeds = {1, 2};
        /** The factors tried on the detector's sigmas and on the motion noise. */
        std::vector<double> sensorScales = {1, 1.5, 2, 3, 4, 6, 8};
        std::vector<double> motionScales = {1, 1.5, 2, 4};
        /** The likelihood temperings tried, in order: the search above is made with each in
         *  turn until a setting is consistent (every detection counted as 1/temper of one
         *  independent reading: a detector whose errors are alike from scan to scan). */
        std::vector<double> tempers = {1, 0.5, 0.25};
        /** The share of the steps with ground truth whose NEES must be inside its bound
         *  (less its sampling tolerance: Consistent()). */
        double minInsideShare = 0.95;
        /** When no setting reaches it: the most consistent of those within this share of the
         *  lowest error (the runs' error differs that much from seed to seed). */
        double errorTolerance = 0.1;
        /** [PF_options] threads of the runs (results do not depend on it); 0: every core. */
        int threads = 0;
    };

    /** `r` with its detector sigmas (sigma_range_m, sigma_bearing_deg) multiplied by
     *  `sensorScale`, its motion noise (a1..a4, minStdXY, minStdPHI) by `motionScale` and its
     *  temper set to `temper`,
     *  each kept to the range semloc-localize accepts (TooLittleData fits are left alone). */
    static TCalibrationResult Widened(const TCalibrationResult& r, double sensorScale,
                                      double motionScale, double temper = 1);

    /** The consistency stage: runs semloc-localize's filter (the ini ApplyToIni() makes from
     *  `baseIni` and the fits, from its own start) on the calibration run itself against its
     *  ground truth, once per seed, for settings of Widened() — for each motion factor in
     *  turn the sensor factors from the smallest up to the first whose runs all converge with
     *  the pose NEES inside its 95 % bound (RunMetrics::nees_inside_share) in minInsideShare of
     *  the steps (Consistent()); the next motion factor only while the last one gave a setting
     * whose runs all converged within errorTolerance of the lowest error so far (or none has
     * converged in every run yet); that whole search for each tempering of `tempers` in turn
     * until one of its settings is consistent — and returns `r` widened by the consistent setting
     * of the lowest error, with the trials in `consistency`. When none is consistent: of the
     * settings whose runs all converged within errorTolerance of the lowest error, the one with the
     * most steps inside (none converged: the lowest error). `trial` is called after each setting,
     * `progress` after each entry of each run. The settings are made from `r` without its
     * samples (given back to the result: move a large result in). The runs' outputs go to a
     * temporary directory, removed afterwards (and by the interrupt watchdog; one a killed
     * run left is removed by the next: detail::TemporaryDirectory). Nothing fitted to widen
     * (every sigma and minStd too little data): `r` as given, no trial run. */
    static TCalibrationResult Consistency(
        TCalibrationResult r, const std::string& baseIni, const std::string& baseName,
        const std::string& worldPath, const std::string& rawlogPath,
        const std::string& groundTruthPath, const TConsistencyOptions& options,
        const std::function<void(const TConsistencyTrial&)>& trial = {},
        const CalibrationProgress& progress = {});

    /** The consistency stage's before and after, one line (empty when it did not run). */
    static std::string ConsistencyText(const TCalibrationResult& result);

    /** The first line of every ini ApplyToIni() writes: semloc-calibrate replaces only a file
     *  that starts with it. */
    static constexpr const char* kIniHeader = "// semloc-calibrate: ";

    /** kIniHeader's line, then the text of `baseIni` (read from `baseName`) with the fitted
     *  values in place: each key
     *  of [MetricMap_semanticMap_00_likelihoodOpts] and [MotionModel] replaced (or added) with
     *  a comment giving its fit, `model = probabilistic` and `source = gaussian`. Throws naming
     *  the file and [section] key when the base has no semantic map. */
    static std::string ApplyToIni(const std::string& baseIni, const std::string& baseName,
                                  const TCalibrationResult& result,
                                  const std::string& worldPath = "");

    /** Writes the fits into `out`'s staging directory: report.md (a table of the fits) and
     *  its figures drawn by gnuplot (fig_residuals.png: the range and bearing residuals'
     *  histograms with the fitted Gaussians; fig_detection.png: the detected share by range
     *  with the fitted P_D(r); fig_odometry.png: the odometry errors against the distance
     *  travelled with the fitted standard deviations), the data in *.dat and figures.gp.
     *  A figure gnuplot cannot draw is left out and returned as a warning (report.md names
     *  it with gnuplot's first error line). */
    static std::vector<TFigureWarning> WriteReport(const TCalibrationResult& result,
                                                   const StagedDirectory& out);
};

}  // namespace semloc

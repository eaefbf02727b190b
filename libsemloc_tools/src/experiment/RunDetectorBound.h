/* semloc — the detector's Cramér–Rao bound along the true path of a localization run, built
 * from the filter's configuration step by step (docs/design.md, "The detector's bound")
 * (private). */
#pragma once

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <semloc/experiment/RunMetrics.h>
#include <semloc/filter/Localizer.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/simulator/DetectorBound.h>
#include <semloc/simulator/SemanticDetectorModel.h>

#include <optional>

namespace semloc::detail
{
/** detectorCramerRaoBound() of a real run, fed one step at a time in constant memory, with
 *  the detector the filter is configured with:
 *  - the pose of a step is its ground truth; the objects it sees are those of the (first)
 *    semantic map inside the coverage of each valid CObservationSemantic of its frame
 *    (CSemanticMap::objectsInView: the likelihood options' max range and field of view, else
 *    the observation's, from the observation's sensor pose), hidden by the world's outlines
 *    as the simulator hides them when the map's objects are the world's (a world YAML map
 *    file); P_D(rho, theta) and the noise are the likelihood options' (detectionProbability(),
 *    sigma_range_m, sigma_bearing_deg); a frame without one is silent;
 *  - the odometry increment's covariance is the filter's movement's motion model
 *    (incrementCovariance()) at the true increment;
 *  - [MotionModel] heading_drift_*: the drift is a state the estimator must learn;
 *  - a step without ground truth is left out: its detections are not counted and its
 *    movement is composed (mean and covariance, at the measured increments) into the
 *    increment of the next step with ground truth, which the bound predicts by from the last
 *    pose it has; a step without a 2D movement starts the bound again at the next step with
 *    ground truth, as does the first one. */
class RunDetectorBound
{
public:
    /** The bound of a run of `filter` over `maps`; inactive without a semantic map. */
    RunDetectorBound(const LocalizationMap& maps, const Localizer::TOptions& filter);

    /** True with a semantic map to bound. */
    bool active() const { return m_map != nullptr; }
    /** The step `r` (its ground truth matched) that weighed the frame `sf` after moving by
     *  `movement` (Localizer::lastMovement()); `soFar`: the run's metrics with `r` added. */
    void add(const TStepRecord& r, const mrpt::obs::CSensoryFrame& sf,
             const mrpt::obs::CActionRobotMovement2D* movement, const RunMetrics& soFar);
    /** The mean of the bound's mean_err_xy_m over the steps with ground truth; NaN without
     *  one or inactive. */
    double mean() const;
    /** The same over the steps from the convergence step of `m` (the run's final metrics) on:
     *  those of mean_err_after_conv_m; NaN when not converged. */
    double meanAfterConvergence(const RunMetrics& m) const;

private:
    /** The detector's information from `pose`: each valid CObservationSemantic of `sf`. */
    void update(const mrpt::math::TPose2D& pose, const mrpt::obs::CSensoryFrame& sf);
    /** Moves the bound to `pose`, the truth of step `r`, by the increment since its last
     *  pose (the movements since, ending with `movement`). */
    void moveTo(const mrpt::math::TPose2D& pose, const TStepRecord& r,
                const mrpt::obs::CActionRobotMovement2D* movement);

    mrpt::maps::CMultiMetricMap::Ptr m_maps;
    CSemanticMap::Ptr m_map;
    /** The world's line-of-sight test, when the map's objects are the world's and it has
     *  outlines. */
    std::optional<SemanticDetectorModel> m_sight;
    DetectorBoundRecursion m_recursion;
    /** Time of the bound's last step [s] (NaN: unknown). */
    double m_lastT = 0;
    /** The increment composed over the steps without ground truth since the bound's last
     *  step; `m_lost`: one of them had no 2D movement. */
    std::optional<mrpt::poses::CPosePDFGaussian> m_span;
    bool m_lost = false;
    /** Sums of mean_err_xy_m over every step with ground truth and over those from the
     *  current convergence candidate `m_convStep` on. */
    double m_sum = 0, m_sumSince = 0;
    size_t m_count = 0, m_countSince = 0;
    long m_convStep = -1;
};

/** The covariance of the odometry increment `trueIncrement` under the motion model `move`
 *  was made with: MRPT's Gaussian model it stores (motionModelConfiguration) when that model
 *  at its raw reading gives back its covariance (CActionRobotMovement2D::computeFromOdometry:
 *  semloc-simulate's and semloc-import's actions, [MotionModel] source = gaussian, the
 *  odometry readings' model); else the covariance it carries (at the measured increment). */
mrpt::math::CMatrixDouble33 incrementCovariance(const mrpt::obs::CActionRobotMovement2D& move,
                                                const mrpt::poses::CPose2D& trueIncrement);

}  // namespace semloc::detail

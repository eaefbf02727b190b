/* semloc — the posterior Cramér–Rao bound of a semantic detector along a simulated run. */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <functional>
#include <vector>

namespace semloc
{
class Simulator;
struct SimulationResult;

/** What the detector could tell about the pose at one step: the posterior Cramér–Rao bound
 *  of the position after that step's detections. */
struct TDetectorBoundStep
{
    /** Lower bound of the root-mean-square position error sqrt(E|e_xy|²) [m]: the square
     *  root of the trace of the bound's x-y block. */
    double rms_xy_m = 0;
    /** Mean position error E|e_xy| of Gaussian errors whose covariance is the bound's x-y
     *  block [m] (gaussianMeanError): the figure comparable with a filter's mean error. */
    double mean_err_xy_m = 0;
};

/** One step of a run as the bound sees it. */
struct TDetectorBoundInput
{
    /** The true pose when the step's detections were taken. */
    mrpt::math::TPose2D pose;
    /** Covariance of the odometry increment from the previous step (in the previous pose's
     *  frame, as CActionRobotMovement2D carries it: x, y, phi). Ignored at the first step. */
    mrpt::math::CMatrixDouble33 incrementCov;
    /** The true position of each object the detector sees at this step [m]. */
    std::vector<mrpt::math::TPoint2D> visible;
    /** The detector was silent at this step (a gap): no information. */
    bool silent = false;
    /** The vehicle was teleported at this step (a kidnapping): the bound starts again from
     *  no knowledge, as the filter cannot know the new pose from the odometry. */
    bool restart = false;
    /** Seconds since the previous step (the heading drift's lever; ignored without it). */
    double dt_s = 0;
};

/** The detector's noise and detection probability, as the bound uses them. */
struct TDetectorBoundSensor
{
    /** Range noise [m] and bearing noise [rad] of a detection (both > 0). */
    double sigma_range_m = 0.5, sigma_bearing_rad = 0.05;
    /** P_D(r, b): the probability that a visible object at range r [m] and bearing b [rad]
     *  in the sensor frame is detected. */
    std::function<double(double, double)> detectionProbability = [](double, double) { return 1.0; };
    /** The sensor on the vehicle. */
    mrpt::poses::CPose3D sensorPose;
};

/** The posterior Cramér–Rao bound (Tichavský, Muravchik & Nehorai, IEEE TSP 1998) of the pose
 *  along `steps`, for a detector of range-bearing measurements of the visible objects' true
 *  positions: a lower bound of the error covariance of any estimator of the pose from the
 *  odometry and the detections, linearized along the true path (the usual evaluation for a
 *  known trajectory). It is optimistic on purpose, so that no filter can beat it:
 *  - each detection is known to come from its object (no association to find), with no
 *    false positive, confusion or misread range, and with its information P_D(r) HᵀR⁻¹H (the
 *    expectation over detected or missed);
 *  - a missed detection adds nothing (the only information it holds is P_D's slope in
 *    range, under 0.2 % of a detection's with the shipped detector; the jump of P_D at the
 *    field of view's edge is not a point a Cramér–Rao bound can count);
 *  - the map is the world (no object moved, removed or added).
 *  Recursion in covariance form, P_k = ((F P_{k-1} Fᵀ + G Σ_k Gᵀ)⁻¹ + Σ_j P_D HⱼᵀR⁻¹Hⱼ)⁻¹ with
 *  F, G the Jacobians of the pose composition x ⊕ u and Hⱼ the Jacobian of object j's range
 *  and bearing from the sensor; P_0 is a vague prior (1e6 in x, y and phi).
 *
 *  With `unknownHeadingDrift`, the odometry's heading increments carry a constant drift b
 *  [rad/s] that no estimator is told: the state is (x, y, phi, b), each prediction adds
 *  -b dt_s to phi, b has a vague prior and no process noise, and a restart forgets the pose
 *  but keeps what the detections told of b (the drift is the odometry's). The bound is then
 *  that of an estimator that must learn the drift from the detections. */
std::vector<TDetectorBoundStep> detectorCramerRaoBound(
    const std::vector<TDetectorBoundInput>& steps, const TDetectorBoundSensor& sensor,
    bool unknownHeadingDrift = false);

/** detectorCramerRaoBound()'s recursion one step at a time, in constant memory (a run of any
 *  length): restart() or predict() to the step's true pose, then update() with what each
 *  detector sees there (none: a silent step), then bound(). */
class DetectorBoundRecursion
{
public:
    /** `unknownHeadingDrift`: see detectorCramerRaoBound(). */
    explicit DetectorBoundRecursion(bool unknownHeadingDrift = false)
        : m_unknownHeadingDrift(unknownHeadingDrift)
    {
    }
    /** Starts again at `pose` from the vague prior: the first step, or a step the odometry
     *  cannot reach (a kidnapping); after the first, what was learned of the drift is kept. */
    void restart(const mrpt::math::TPose2D& pose);
    /** Moves to `pose` through the odometry increment from the current pose, of covariance
     *  `incrementCov` (in the current pose's frame), `dt_s` seconds later (the drift's lever).
     *  Before the first restart(): restart(pose). */
    void predict(const mrpt::math::TPose2D& pose, const mrpt::math::CMatrixDouble33& incrementCov,
                 double dt_s);
    /** Adds the information of one detector's view from the current pose: the objects at
     *  `visible` (their true positions), each detected with P_D at its range. */
    void update(const std::vector<mrpt::math::TPoint2D>& visible,
                const TDetectorBoundSensor& sensor);
    /** The bound at the current pose (0 before the first restart()). */
    TDetectorBoundStep bound() const;
    /** True once restart() (or predict()) was called. */
    bool started() const { return m_started; }
    /** The current (true) pose. */
    const mrpt::math::TPose2D& pose() const { return m_pose; }

private:
    bool m_unknownHeadingDrift;
    bool m_started = false;
    mrpt::math::TPose2D m_pose;
    /** The bound of (x, y, phi, b); b's block stays 0 without an unknown heading drift. */
    mrpt::math::CMatrixDouble44 m_P;
};

/** detectorCramerRaoBound() of a simulated run: the simulator's detector (noise, P_D, sensor
 *  pose, visibility with occlusion and field of view), its odometry's motion model at the
 *  true increments, its heading drift (unknown to the estimator) when it has one, its
 *  silences and kidnapping, and the world it simulated. */
std::vector<TDetectorBoundStep> detectorCramerRaoBound(const Simulator& simulator,
                                                       const SimulationResult& run);

/** E|e| of a zero-mean 2-D Gaussian e with covariance `cov` (2 x 2, symmetric, positive
 *  semi-definite): sqrt(2 λ₁ / π) E(sqrt(1 - λ₂ / λ₁)) with λ₁ ≥ λ₂ its eigenvalues and E the
 *  complete elliptic integral of the second kind (σ sqrt(π / 2) when isotropic). */
double gaussianMeanError(double cxx, double cxy, double cyy);

}  // namespace semloc

/* semloc — simulated odometry: the true pose increment plus MRPT's Gaussian motion noise. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPose2D.h>

#include <string>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** Odometry of the simulated vehicle (dead reckoning, e.g. DVL + compass).
 *
 *  The noise is MRPT's Gaussian motion model itself (CActionRobotMovement2D,
 *  "Probabilistic motion models" in MRPT's docs): for an increment of length d [m] and
 *  rotation dphi [rad] the model's standard deviations are
 *
 *      std_xy  = min_xy_std_m + xy_std_per_m d      + xy_std_m_per_rad |dphi|
 *      std_phi = min_phi_std  + phi_std_per_m d     + phi_std_per_rad  |dphi|
 *
 *  (min_phi_std and phi_std_per_m are given in degrees: `min_phi_std_deg`,
 *  `phi_std_deg_per_m`)
 *
 *  (in the frame half-way through the rotation, then propagated by the model's Jacobian).
 *  measure() builds that covariance at the true increment, draws the noise from it and
 *  stores the noisy reading with computeFromOdometry() and the same parameters, so the
 *  filter's motion model is exactly the one the data was generated with. */
class SimulatedOdometry
{
public:
    /** Section [Odometry]: the motion-model parameters; all >= 0 (0 everywhere: exact). */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** @name Noise per unit of motion
         *  @{ */
        /** Position std per metre travelled [m/m] (MRPT's a1). */
        double xy_std_per_m = 0.05;
        /** Position std per radian turned [m/rad] (MRPT's a2). */
        double xy_std_m_per_rad = 0.0;
        /** Heading std per metre travelled [deg/m] (MRPT's a3). */
        double phi_std_deg_per_m = 0.5;
        /** Heading std per radian turned [rad/rad] (MRPT's a4). */
        double phi_std_per_rad = 0.05;
        /** @} */
        /** @name Noise of every step, moving or not
         *  @{ */
        /** Minimum position std [m] (MRPT's minStdXY). */
        double min_xy_std_m = 0.01;
        /** Minimum heading std [deg] (MRPT's minStdPHI). */
        double min_phi_std_deg = 0.2;
        /** @} */
        /** A bias of the heading increments [deg/min] (a gyro or compass that drifts): added
         *  to every reading, not to the Gaussian the action carries (the filter does not
         *  know it). */
        double heading_drift_deg_per_min = 0.0;

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;

        /** These parameters as MRPT's Gaussian motion model (SI units). */
        mrpt::obs::CActionRobotMovement2D::TMotionModelOptions motionModel() const;
    };

    /** A model with the given noise options. */
    explicit SimulatedOdometry(const TOptions& options);

    /** The odometry action of one step whose true pose increment (vehicle frame) is
     *  `trueIncrement`: reading = trueIncrement + noise ~ N(0, Sigma(trueIncrement)),
     *  plus the heading drift over `dt_s` seconds, heading wrapped to [-pi, pi]; timestamp
     *  left unset. */
    mrpt::obs::CActionRobotMovement2D measure(const mrpt::poses::CPose2D& trueIncrement,
                                              mrpt::random::CRandomGenerator& rng,
                                              double dt_s = 0) const;

    /** The parameters. */
    const TOptions& options() const { return m_options; }

private:
    TOptions m_options;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions m_model;
};

}  // namespace semloc

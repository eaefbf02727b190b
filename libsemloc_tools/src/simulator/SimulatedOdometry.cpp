/* semloc — SimulatedOdometry: true increment plus noise drawn from MRPT's Gaussian motion model. */
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/SimulatedOdometry.h>

#include <Eigen/Eigenvalues>

#include "io/ExactConfigWrite.h"

namespace semloc
{
void SimulatedOdometry::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                     const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readDouble(c, s, "xy_std_per_m", xy_std_per_m, 0, 1e3);
    config::readDouble(c, s, "xy_std_m_per_rad", xy_std_m_per_rad, 0, 1e3);
    config::readDouble(c, s, "phi_std_deg_per_m", phi_std_deg_per_m, 0, 1e3);
    config::readDouble(c, s, "phi_std_per_rad", phi_std_per_rad, 0, 1e3);
    config::readDouble(c, s, "min_xy_std_m", min_xy_std_m, 0, 1e3);
    config::readDouble(c, s, "min_phi_std_deg", min_phi_std_deg, 0, 1e3);
    config::readDouble(c, s, "heading_drift_deg_per_min", heading_drift_deg_per_min, -1e4, 1e4);
}

void SimulatedOdometry::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                   const std::string& s) const
{
    using detail::writeExact;
    writeExact(c, s, "xy_std_per_m", xy_std_per_m, "position std per metre travelled [m/m]");
    writeExact(c, s, "xy_std_m_per_rad", xy_std_m_per_rad, "position std per radian turned");
    writeExact(c, s, "phi_std_deg_per_m", phi_std_deg_per_m, "heading std per metre [deg/m]");
    writeExact(c, s, "phi_std_per_rad", phi_std_per_rad, "heading std per radian turned");
    writeExact(c, s, "min_xy_std_m", min_xy_std_m, "minimum position std per step [m]");
    writeExact(c, s, "min_phi_std_deg", min_phi_std_deg, "minimum heading std per step [deg]");
    writeExact(c, s, "heading_drift_deg_per_min", heading_drift_deg_per_min,
               "heading bias unknown to the filter [deg/min]");
}

mrpt::obs::CActionRobotMovement2D::TMotionModelOptions SimulatedOdometry::TOptions::motionModel()
    const
{
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions m;
    m.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    m.gaussianModel.a1 = xy_std_per_m;
    m.gaussianModel.a2 = xy_std_m_per_rad;
    m.gaussianModel.a3 = mrpt::DEG2RAD(phi_std_deg_per_m);
    m.gaussianModel.a4 = phi_std_per_rad;
    m.gaussianModel.minStdXY = min_xy_std_m;
    m.gaussianModel.minStdPHI = mrpt::DEG2RAD(min_phi_std_deg);
    return m;
}

SimulatedOdometry::SimulatedOdometry(const TOptions& options)
    : m_options(options), m_model(options.motionModel())
{
}

mrpt::obs::CActionRobotMovement2D SimulatedOdometry::measure(
    const mrpt::poses::CPose2D& trueIncrement, mrpt::random::CRandomGenerator& rng,
    double dt_s) const
{
    // The model's covariance at the true increment, computed by MRPT itself.
    mrpt::obs::CActionRobotMovement2D truth;
    truth.computeFromOdometry(trueIncrement, m_model);
    const Eigen::Matrix3d cov = truth.poseChange->getCovariance().asEigen();

    // noise = V sqrt(L) n, n ~ N(0, I3): eigen-decomposition, so a singular (e.g. all-zero)
    // covariance gives exactly zero noise; tiny negative round-off eigenvalues clamp to 0.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    Eigen::Vector3d n;
    for (int i = 0; i < 3; i++)
    {
        n[i] = std::sqrt(std::max(0.0, eig.eigenvalues()[i])) * rng.drawGaussian1D_normalized();
    }
    const Eigen::Vector3d noise = eig.eigenvectors() * n;

    mrpt::poses::CPose2D reading(
        trueIncrement.x() + noise[0], trueIncrement.y() + noise[1],
        trueIncrement.phi() + noise[2] +
            mrpt::DEG2RAD(m_options.heading_drift_deg_per_min) * dt_s / 60.0);
    reading.normalizePhi();
    mrpt::obs::CActionRobotMovement2D action;
    action.computeFromOdometry(reading, m_model);
    return action;
}

}  // namespace semloc

/* semloc — the posterior Cramér–Rao bound of a semantic detector along a simulated run. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPose2D.h>
#include <semloc/simulator/DetectorBound.h>
#include <semloc/simulator/Simulator.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace semloc
{
namespace
{
/** Variance of the vague prior in x, y and phi. */
constexpr double kPriorVariance = 1e6;

TDetectorBoundStep summarize(const Eigen::Matrix3d& P)
{
    TDetectorBoundStep s;
    s.rms_xy_m = std::sqrt(std::max(0.0, P(0, 0) + P(1, 1)));
    s.mean_err_xy_m = gaussianMeanError(P(0, 0), 0.5 * (P(0, 1) + P(1, 0)), P(1, 1));
    return s;
}

/** Information of one detection of the object at `p` from vehicle pose `x`: HᵀR⁻¹H. */
Eigen::Matrix3d detectionInformation(const mrpt::math::TPose2D& x, const mrpt::math::TPoint2D& p,
                                     const TDetectorBoundSensor& sensor, double& range,
                                     double& bearing)
{
    const double c = std::cos(x.phi), s = std::sin(x.phi);
    const double ox = sensor.sensorPose.x(), oy = sensor.sensorPose.y();
    // The sensor's position and its derivative with respect to (x, y, phi).
    const double sx = x.x + c * ox - s * oy, sy = x.y + s * ox + c * oy;
    Eigen::Matrix<double, 2, 3> ds;
    ds << 1, 0, -s * ox - c * oy, 0, 1, c * ox - s * oy;
    const double dx = p.x - sx, dy = p.y - sy;
    range = std::hypot(dx, dy);
    bearing = mrpt::math::wrapToPi(std::atan2(dy, dx) - x.phi - sensor.sensorPose.yaw());
    if (!(range > 1e-9))
    {
        return Eigen::Matrix3d::Zero();  // at the sensor: no bearing, no gradient
    }
    Eigen::Matrix<double, 2, 3> H;
    H.row(0) = Eigen::RowVector2d(-dx / range, -dy / range) * ds;
    H.row(1) = Eigen::RowVector2d(dy / (range * range), -dx / (range * range)) * ds;
    H(1, 2) -= 1.0;
    const Eigen::Vector2d rInv(1.0 / (sensor.sigma_range_m * sensor.sigma_range_m),
                               1.0 / (sensor.sigma_bearing_rad * sensor.sigma_bearing_rad));
    return H.transpose() * rInv.asDiagonal() * H;
}
}  // namespace

double gaussianMeanError(double cxx, double cxy, double cyy)
{
    // Eigenvalues of [[cxx, cxy], [cxy, cyy]].
    const double mid = 0.5 * (cxx + cyy);
    const double half = std::hypot(0.5 * (cxx - cyy), cxy);
    const double l1 = std::max(0.0, mid + half), l2 = std::clamp(mid - half, 0.0, l1);
    if (!(l1 > 0))
    {
        return 0.0;
    }
    const double k = std::sqrt(1.0 - l2 / l1);
    return std::sqrt(2.0 * l1 / M_PI) * std::comp_ellint_2(k);
}

void DetectorBoundRecursion::restart(const mrpt::math::TPose2D& pose)
{
    const double pbb = m_started ? m_P(3, 3) : m_unknownHeadingDrift ? kPriorVariance : 0.0;
    m_P.setZero();
    for (int i = 0; i < 3; i++)
    {
        m_P(i, i) = kPriorVariance;
    }
    m_P(3, 3) = pbb;
    m_pose = pose;
    m_started = true;
}

void DetectorBoundRecursion::predict(const mrpt::math::TPose2D& pose,
                                     const mrpt::math::CMatrixDouble33& incrementCov, double dt_s)
{
    if (!m_started)
    {
        restart(pose);
        return;
    }
    // Prediction through x_k = x_{k-1} ⊕ (u_k - (0, 0, b dt)), u_k's covariance in x_{k-1}'s
    // frame.
    using Matrix4d = Eigen::Matrix4d;
    const auto& x0 = m_pose;
    const mrpt::poses::CPose2D u = mrpt::poses::CPose2D(pose) - mrpt::poses::CPose2D(x0);
    const double c = std::cos(x0.phi), s = std::sin(x0.phi);
    Matrix4d F = Matrix4d::Identity();
    F(0, 2) = -s * u.x() - c * u.y();
    F(1, 2) = c * u.x() - s * u.y();
    F(2, 3) = -dt_s;
    Eigen::Matrix<double, 4, 3> G = Eigen::Matrix<double, 4, 3>::Zero();
    G.topLeftCorner<3, 3>().setIdentity();
    G.topLeftCorner<2, 2>() << c, -s, s, c;
    const Matrix4d P = m_P.asEigen();
    m_P = Matrix4d(F * P * F.transpose() + G * incrementCov.asEigen() * G.transpose());
    m_pose = pose;
}

void DetectorBoundRecursion::update(const std::vector<mrpt::math::TPoint2D>& visible,
                                    const TDetectorBoundSensor& sensor)
{
    ASSERTMSG_(sensor.sigma_range_m > 0 && sensor.sigma_bearing_rad > 0,
               "detectorCramerRaoBound: the detector's noise must be > 0");
    if (!m_started || visible.empty())
    {
        return;
    }
    using Matrix4d = Eigen::Matrix4d;
    Matrix4d J = Matrix4d::Zero();
    for (const auto& p : visible)
    {
        double range = 0, bearing = 0;
        const Eigen::Matrix3d I = detectionInformation(m_pose, p, sensor, range, bearing);
        J.topLeftCorner<3, 3>() +=
            std::clamp(sensor.detectionProbability(range, bearing), 0.0, 1.0) * I;
    }
    // (P⁻¹ + J)⁻¹ = P (I + J P)⁻¹: no inverse of a nearly singular P.
    Matrix4d P = m_P.asEigen();
    P = P * (Matrix4d::Identity() + J * P).inverse();
    m_P = Matrix4d(0.5 * (P + P.transpose()));
}

TDetectorBoundStep DetectorBoundRecursion::bound() const
{
    return summarize(m_P.asEigen().topLeftCorner<3, 3>());
}

std::vector<TDetectorBoundStep> detectorCramerRaoBound(
    const std::vector<TDetectorBoundInput>& steps, const TDetectorBoundSensor& sensor,
    bool unknownHeadingDrift)
{
    ASSERTMSG_(sensor.sigma_range_m > 0 && sensor.sigma_bearing_rad > 0,
               "detectorCramerRaoBound: the detector's noise must be > 0");
    DetectorBoundRecursion recursion(unknownHeadingDrift);
    std::vector<TDetectorBoundStep> out;
    out.reserve(steps.size());
    for (size_t k = 0; k < steps.size(); k++)
    {
        const auto& st = steps[k];
        if (k == 0 || st.restart)
        {
            recursion.restart(st.pose);
        }
        else
        {
            recursion.predict(st.pose, st.incrementCov, st.dt_s);
        }
        if (!st.silent)
        {
            recursion.update(st.visible, sensor);
        }
        out.push_back(recursion.bound());
    }
    return out;
}

std::vector<TDetectorBoundStep> detectorCramerRaoBound(const Simulator& simulator,
                                                       const SimulationResult& run)
{
    const auto& o = simulator.options();
    const SemanticDetectorModel detector(simulator.world(), o.detector);
    const auto model = o.odometry.motionModel();
    TDetectorBoundSensor sensor;
    sensor.sigma_range_m = o.detector.range_noise_std_m;
    sensor.sigma_bearing_rad = mrpt::DEG2RAD(o.detector.bearing_noise_std_deg);
    sensor.detectionProbability = [&detector](double r, double b)
    { return detector.detectionProbability(r, b); };
    sensor.sensorPose = o.detector.sensorPose();

    std::vector<TDetectorBoundInput> steps(run.groundTruth.size());
    for (size_t k = 0; k < steps.size(); k++)
    {
        auto& st = steps[k];
        st.pose = run.groundTruth[k].pose();
        st.silent = k < run.detectorSilent.size() && run.detectorSilent[k] != 0;
        st.restart = o.kidnapping.enabled && k == static_cast<size_t>(o.kidnapping.step);
        if (k > 0 && !st.restart)
        {
            mrpt::obs::CActionRobotMovement2D a;
            a.computeFromOdometry(
                mrpt::poses::CPose2D(st.pose) - mrpt::poses::CPose2D(steps[k - 1].pose), model);
            st.incrementCov = a.poseChange->getCovariance();
            st.dt_s = run.groundTruth[k].t - run.groundTruth[k - 1].t;
        }
        for (const auto& v : detector.visibleObjects(st.pose))
        {
            st.visible.push_back(simulator.world().objects[v.index].center);
        }
    }
    return detectorCramerRaoBound(steps, sensor, o.odometry.heading_drift_deg_per_min != 0);
}

}  // namespace semloc

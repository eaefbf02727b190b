/* semloc — the AUV's simulated sensors: depth, compass, USBL, DVL and the seabed detectors. */
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/observation/CObservationDepth.h>
#include <semloc/observation/CObservationSemantic.h>

#include <algorithm>
#include <cmath>

#include "simulator/AuvSensors.h"
#include "simulator/SimRandom.h"

namespace semloc::detail
{
namespace
{
constexpr double kDeg = M_PI / 180;
using Kind = TObjectDetectorSimOptions::Kind;
}  // namespace

AuvStreams::AuvStreams(uint32_t seed)
    : depth(streamSeed(seed, SimStream::Depth)),
      compass(streamSeed(seed, SimStream::Compass)),
      usbl(streamSeed(seed, SimStream::Usbl)),
      dvl(streamSeed(seed, SimStream::Dvl)),
      sidescan(streamSeed(seed, SimStream::SideScan)),
      fls(streamSeed(seed, SimStream::ForwardSonar)),
      camera(streamSeed(seed, SimStream::Camera))
{
}

AuvSensors::AuvSensors(const World& world, const TAuvSensorOptions& options) : m_o(options)
{
    for (const auto& o : world.objects)
    {
        m_objects.push_back({o.center.x, o.center.y, o.z, o.label});
        if (std::find(m_labels.begin(), m_labels.end(), o.label) == m_labels.end())
        {
            m_labels.push_back(o.label);
        }
    }
}

mrpt::obs::CActionRobotMovement2D AuvSensors::measureDvl(const mrpt::poses::CPose2D& increment,
                                                         mrpt::random::CRandomGenerator& rng) const
{
    const auto& o = m_o.dvl;
    const double d = std::hypot(increment.x(), increment.y());
    const double sxy = std::max(o.xy_std_per_m * d, o.min_xy_std_m);
    const double sphi = std::max(o.phi_std_deg_per_m * d, o.min_phi_std_deg) * kDeg;
    const double du = (1 + o.scale_error) * increment.x() + sxy * rng.drawGaussian1D_normalized();
    const double dv = (1 + o.scale_error) * increment.y() + sxy * rng.drawGaussian1D_normalized();
    const double dphi = increment.phi() + sphi * rng.drawGaussian1D_normalized();
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;
    model.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    model.gaussianModel.a1 = static_cast<float>(o.xy_std_per_m);
    model.gaussianModel.a2 = 0;
    model.gaussianModel.a3 = static_cast<float>(o.phi_std_deg_per_m);
    model.gaussianModel.a4 = 0;
    model.gaussianModel.minStdXY = static_cast<float>(o.min_xy_std_m);
    model.gaussianModel.minStdPHI = static_cast<float>(o.min_phi_std_deg);
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(du, dv, dphi), model);
    return move;
}

size_t AuvSensors::measure(size_t k, const mrpt::math::TPose2D& pose, mrpt::Clock::time_point stamp,
                           AuvStreams& rng, mrpt::obs::CSensoryFrame& frame) const
{
    const auto every = [k](int period) { return k % static_cast<size_t>(period) == 0; };
    if (m_o.depth.enabled && every(m_o.depth.period_steps))
    {
        auto depth = CObservationDepth::Create();
        depth->sensorLabel = "depth";
        depth->timestamp = stamp;
        depth->depth_m =
            m_o.depth.depth_m + m_o.depth.noise_std_m * rng.depth.drawGaussian1D_normalized();
        const double alt = m_o.depth.altitude_noise_std_m * rng.depth.drawGaussian1D_normalized();
        if (m_o.depth.seabed_depth_m > 0)
        {
            depth->altitude_m = std::max(0.0, m_o.depth.seabed_depth_m - m_o.depth.depth_m + alt);
        }
        frame.insert(depth);
    }
    if (m_o.compass.enabled && every(m_o.compass.period_steps))
    {
        auto imu = mrpt::obs::CObservationIMU::Create();
        imu->sensorLabel = m_o.compass.sensor_label;
        imu->timestamp = stamp;
        const double noise = m_o.compass.sigma_deg * kDeg * rng.compass.drawGaussian1D_normalized();
        const bool out = bernoulli(rng.compass, m_o.compass.p_outlier);
        const double uniform = (2 * uniform01(rng.compass) - 1) * M_PI;
        const auto& c = m_o.compass;
        const double deviation =
            c.deviation_deg * kDeg * std::cos(pose.phi - c.deviation_phase_deg * kDeg);
        imu->set(mrpt::obs::IMU_YAW,
                 out ? uniform
                     : std::remainder(pose.phi + c.bias_deg * kDeg + deviation + noise, 2 * M_PI));
        frame.insert(imu);
    }
    if (m_o.usbl.enabled && k > 0 && every(m_o.usbl.period_steps))
    {
        const bool out = bernoulli(rng.usbl, m_o.usbl.p_outlier);
        const double s = out ? m_o.usbl.outlier_sigma_m : m_o.usbl.sigma_m;
        const double ex = s * rng.usbl.drawGaussian1D_normalized();
        const double ey = s * rng.usbl.drawGaussian1D_normalized();
        auto fix = mrpt::obs::CObservationRobotPose::Create();
        fix->sensorLabel = m_o.usbl.sensor_label;
        fix->timestamp = stamp;
        fix->pose.mean =
            mrpt::poses::CPose3D(pose.x + ex, pose.y + ey, -m_o.depth.depth_m, 0, 0, 0);
        fix->pose.cov.setZero();
        fix->pose.cov(0, 0) = fix->pose.cov(1, 1) = m_o.usbl.sigma_m * m_o.usbl.sigma_m;
        fix->pose.cov(2, 2) = 1;
        for (int i = 3; i < 6; i++)
        {
            fix->pose.cov(i, i) = 100;  // no attitude in a fix
        }
        frame.insert(fix);
    }
    size_t detections = 0;
    if (m_o.sidescan.enabled)
    {
        detections += detect(m_o.sidescan, pose, stamp, rng.sidescan, frame);
    }
    if (m_o.fls.enabled)
    {
        detections += detect(m_o.fls, pose, stamp, rng.fls, frame);
    }
    if (m_o.camera.enabled)
    {
        detections += detect(m_o.camera, pose, stamp, rng.camera, frame);
    }
    return detections;
}

size_t AuvSensors::detect(const TObjectDetectorSimOptions& o, const mrpt::math::TPose2D& pose,
                          mrpt::Clock::time_point stamp, mrpt::random::CRandomGenerator& rng,
                          mrpt::obs::CSensoryFrame& frame) const
{
    auto scan = CObservationSemantic::Create();
    scan->sensorLabel = o.sensor_label;
    scan->timestamp = stamp;
    scan->sensorPose = mrpt::poses::CPose3D(o.sensor_x_m, o.sensor_y_m, o.sensor_z_m,
                                            o.sensor_yaw_deg * kDeg, 0, 0);
    scan->maxRange_m = o.max_range_m;
    scan->fov_rad = o.kind == Kind::SideScan ? 2 * M_PI : o.fov_deg * kDeg;
    const mrpt::poses::CPose3D sensor =
        mrpt::poses::CPose3D(pose.x, pose.y, -m_o.depth.depth_m, pose.phi, 0, 0) + scan->sensorPose;
    const double halfFov = 0.5 * o.fov_deg * kDeg, halfBeam = 0.5 * o.beam_width_deg * kDeg;
    for (const auto& obj : m_objects)
    {
        double u = 0, w = 0, dz = 0;
        sensor.inverseComposePoint(obj.x, obj.y, obj.z, u, w, dz);
        const double ground = std::hypot(u, w), slant = std::sqrt(u * u + w * w + dz * dz);
        const double bearing = std::atan2(w, u);
        bool seen = slant >= o.min_range_m && slant <= o.max_range_m;
        if (o.kind == Kind::SideScan)
        {
            seen =
                seen && std::abs(w) >= o.nadir_gap_m && std::abs(std::asin(u / slant)) <= halfBeam;
        }
        else
        {
            seen = seen && std::abs(bearing) <= halfFov &&
                   (o.vertical_fov_deg >= 180 ||
                    std::abs(std::atan2(-dz, ground) - o.tilt_deg * kDeg) <=
                        0.5 * o.vertical_fov_deg * kDeg);
        }
        // One draw of each kind per object, seen or not: the stream does not depend on the
        // geometry.
        const double pd = o.p_detect_near +
                          (o.p_detect_far - o.p_detect_near) * std::min(slant / o.max_range_m, 1.0);
        const bool detected = bernoulli(rng, pd);
        const double nr = rng.drawGaussian1D_normalized(), nb = rng.drawGaussian1D_normalized();
        if (!seen || !detected)
        {
            continue;
        }
        TSemanticDetection d;
        d.label = obj.label;
        d.range_m = o.kind == Kind::Camera ? std::nan("")
                                           : std::clamp(slant + o.range_noise_std_m * nr,
                                                        o.min_range_m, o.max_range_m);
        d.bearing_rad =
            o.kind == Kind::SideScan
                ? (w >= 0 ? M_PI / 2 : -M_PI / 2)
                : std::clamp(bearing + o.bearing_noise_std_deg * kDeg * nb, -halfFov, halfFov);
        scan->detections.push_back(d);
    }
    const unsigned clutter = poisson(rng, o.clutter_per_scan);
    for (unsigned c = 0; c < clutter && !m_labels.empty(); c++)
    {
        TSemanticDetection d;
        d.label = m_labels[uniformIndex(rng, m_labels.size())];
        d.range_m = o.min_range_m + (o.max_range_m - o.min_range_m) * uniform01(rng);
        const double side = uniform01(rng);
        d.bearing_rad = o.kind == Kind::SideScan ? (side < 0.5 ? M_PI / 2 : -M_PI / 2)
                                                 : (2 * side - 1) * halfFov;
        if (o.kind == Kind::Camera)
        {
            d.range_m = std::nan("");
        }
        scan->detections.push_back(d);
    }
    frame.insert(scan);
    return scan->detections.size();
}

}  // namespace semloc::detail

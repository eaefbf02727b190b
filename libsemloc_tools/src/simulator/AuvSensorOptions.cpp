/* semloc — the AUV sensors' sections of a simulation ini: read strictly, written whole. */
#include <mrpt/core/exceptions.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/AuvSensorModels.h>

#include <climits>
#include <string>

#include "io/ExactConfigWrite.h"

namespace semloc
{
using detail::writeExact;

void TDepthSensorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                             const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    config::readDouble(c, s, "depth_m", depth_m, 0, 11000);
    config::readDouble(c, s, "noise_std_m", noise_std_m, 0, 100);
    config::readDouble(c, s, "seabed_depth_m", seabed_depth_m, 0, 11000);
    config::readDouble(c, s, "altitude_noise_std_m", altitude_noise_std_m, 0, 100);
    config::readInt(c, s, "period_steps", period_steps, 1, INT_MAX);
    if (seabed_depth_m > 0 && seabed_depth_m < depth_m)
    {
        THROW_EXCEPTION_FMT("ini [%s] seabed_depth_m: %g is above the vehicle's depth_m %g",
                            s.c_str(), seabed_depth_m, depth_m);
    }
}

void TDepthSensorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                           const std::string& s) const
{
    c.write(s, "enabled", enabled, 24, 24, "CObservationDepth readings");
    writeExact(c, s, "depth_m", depth_m, "the vehicle's true depth (level flight) [m]");
    writeExact(c, s, "noise_std_m", noise_std_m, "depth noise [m]");
    writeExact(c, s, "seabed_depth_m", seabed_depth_m, "seabed depth for the altitude; 0: none");
    writeExact(c, s, "altitude_noise_std_m", altitude_noise_std_m, "altitude noise [m]");
    c.write(s, "period_steps", period_steps, 24, 24, "a reading every N steps, from step 0");
}

void TCompassSimOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    sensor_label = c.read_string(s, "sensor_label", sensor_label);
    config::readDouble(c, s, "sigma_deg", sigma_deg, 0, 180);
    config::readDouble(c, s, "bias_deg", bias_deg, -180, 180);
    config::readDouble(c, s, "p_outlier", p_outlier, 0, 1);
    config::readDouble(c, s, "deviation_deg", deviation_deg, 0, 90);
    config::readDouble(c, s, "deviation_phase_deg", deviation_phase_deg, -360, 360);
    config::readInt(c, s, "period_steps", period_steps, 1, INT_MAX);
}

void TCompassSimOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const
{
    c.write(s, "enabled", enabled, 24, 24, "CObservationIMU yaw readings");
    detail::writeText(c, s, "sensor_label", sensor_label, "their sensorLabel");
    writeExact(c, s, "sigma_deg", sigma_deg, "heading noise [deg]");
    writeExact(c, s, "bias_deg", bias_deg, "constant heading bias [deg]");
    writeExact(c, s, "p_outlier", p_outlier, "share of disturbed readings (uniform)");
    writeExact(c, s, "deviation_deg", deviation_deg,
               "deviation amplitude: this x cos(heading - phase) [deg]");
    writeExact(c, s, "deviation_phase_deg", deviation_phase_deg, "deviation phase [deg]");
    c.write(s, "period_steps", period_steps, 24, 24, "a reading every N steps, from step 0");
}

void TFixSimOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    sensor_label = c.read_string(s, "sensor_label", sensor_label);
    config::readInt(c, s, "period_steps", period_steps, 1, INT_MAX);
    config::readDouble(c, s, "sigma_m", sigma_m, 1e-3, 1e4);
    config::readDouble(c, s, "p_outlier", p_outlier, 0, 1);
    config::readDouble(c, s, "outlier_sigma_m", outlier_sigma_m, 1e-3, 1e6);
}

void TFixSimOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "enabled", enabled, 24, 24, "CObservationRobotPose fixes");
    detail::writeText(c, s, "sensor_label", sensor_label, "their sensorLabel");
    c.write(s, "period_steps", period_steps, 24, 24, "a fix every N steps, the first at N");
    writeExact(c, s, "sigma_m", sigma_m, "fix noise in x and y [m] (and their covariance)");
    writeExact(c, s, "p_outlier", p_outlier, "share of fixes off by outlier_sigma_m");
    writeExact(c, s, "outlier_sigma_m", outlier_sigma_m, "outliers' spread [m]");
}

void TDvlSimOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    config::readDouble(c, s, "xy_std_per_m", xy_std_per_m, 0, 10);
    config::readDouble(c, s, "min_xy_std_m", min_xy_std_m, 0, 100);
    config::readDouble(c, s, "scale_error", scale_error, -0.5, 0.5);
    config::readDouble(c, s, "phi_std_deg_per_m", phi_std_deg_per_m, 0, 360);
    config::readDouble(c, s, "min_phi_std_deg", min_phi_std_deg, 0, 360);
}

void TDvlSimOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "enabled", enabled, 24, 24, "odometry as a DVL's body-frame increments");
    writeExact(c, s, "xy_std_per_m", xy_std_per_m, "each body axis' std per metre [m/m]");
    writeExact(c, s, "min_xy_std_m", min_xy_std_m, "its floor per step [m]");
    writeExact(c, s, "scale_error", scale_error, "velocity scale error (0.005: 0.5 %)");
    writeExact(c, s, "phi_std_deg_per_m", phi_std_deg_per_m, "heading std per metre [deg/m]");
    writeExact(c, s, "min_phi_std_deg", min_phi_std_deg, "its floor per step [deg]");
}

TObjectDetectorSimOptions::TObjectDetectorSimOptions(Kind k) : kind(k)
{
    switch (k)
    {
        case Kind::SideScan:
            sensor_label = "sidescan";
            break;
        case Kind::ForwardSonar:
            sensor_label = "fls";
            max_range_m = 60;
            range_noise_std_m = 0.3;
            fov_deg = 130;
            break;
        case Kind::Camera:
            sensor_label = "camera";
            max_range_m = 8;
            p_detect_near = 0.9;
            p_detect_far = 0.5;
            fov_deg = 60;
            break;
    }
}

void TObjectDetectorSimOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                   const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this, std::to_string(static_cast<int>(kind))));
    config::readBool(c, s, "enabled", enabled);
    sensor_label = c.read_string(s, "sensor_label", sensor_label);
    config::readDouble(c, s, "min_range_m", min_range_m, 0, 1e6);
    config::readDouble(c, s, "max_range_m", max_range_m, 1e-3, 1e6);
    if (!(min_range_m < max_range_m))
    {
        THROW_EXCEPTION_FMT("ini [%s] min_range_m: %g is not below max_range_m %g", s.c_str(),
                            min_range_m, max_range_m);
    }
    config::readDouble(c, s, "p_detect_near", p_detect_near, 0, 1);
    config::readDouble(c, s, "p_detect_far", p_detect_far, 0, 1);
    config::readDouble(c, s, "clutter_per_scan", clutter_per_scan, 0, 100);
    if (kind != Kind::Camera)
    {
        config::readDouble(c, s, "range_noise_std_m", range_noise_std_m, 0, 1e3);
    }
    if (kind != Kind::SideScan)
    {
        config::readDouble(c, s, "bearing_noise_std_deg", bearing_noise_std_deg, 0, 180);
        config::readDouble(c, s, "fov_deg", fov_deg, 1e-3, 360);
        config::readDouble(c, s, "tilt_deg", tilt_deg, -90, 90);
        config::readDouble(c, s, "vertical_fov_deg", vertical_fov_deg, 1e-3, 180);
    }
    else
    {
        config::readDouble(c, s, "beam_width_deg", beam_width_deg, 1e-3, 90);
        config::readDouble(c, s, "nadir_gap_m", nadir_gap_m, 0, 1e6);
    }
    config::readDouble(c, s, "sensor_x_m", sensor_x_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_y_m", sensor_y_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_z_m", sensor_z_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_yaw_deg", sensor_yaw_deg, -360, 360);
}

void TObjectDetectorSimOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                 const std::string& s) const
{
    c.write(s, "enabled", enabled, 24, 24, "CObservationSemantic scans of the seabed's objects");
    detail::writeText(c, s, "sensor_label", sensor_label, "their sensorLabel");
    writeExact(c, s, "min_range_m", min_range_m, "nearest slant range seen [m]");
    writeExact(c, s, "max_range_m", max_range_m, "farthest slant range seen [m]");
    writeExact(c, s, "p_detect_near", p_detect_near, "P(detect) at range 0");
    writeExact(c, s, "p_detect_far", p_detect_far, "P(detect) at max_range_m (linear between)");
    writeExact(c, s, "clutter_per_scan", clutter_per_scan, "Poisson mean of false alarms per scan");
    if (kind != Kind::Camera)
    {
        writeExact(c, s, "range_noise_std_m", range_noise_std_m, "slant range noise [m]");
    }
    if (kind != Kind::SideScan)
    {
        writeExact(c, s, "bearing_noise_std_deg", bearing_noise_std_deg, "bearing noise [deg]");
        writeExact(c, s, "fov_deg", fov_deg, "horizontal field of view [deg]");
        writeExact(c, s, "tilt_deg", tilt_deg, "depression of the fan [deg]");
        writeExact(c, s, "vertical_fov_deg", vertical_fov_deg, "vertical field of view [deg]");
    }
    else
    {
        writeExact(c, s, "beam_width_deg", beam_width_deg, "along-track width of the fan [deg]");
        writeExact(c, s, "nadir_gap_m", nadir_gap_m, "across-track blind distance [m]");
    }
    writeExact(c, s, "sensor_x_m", sensor_x_m, "sensor on the vehicle: forward [m]");
    writeExact(c, s, "sensor_y_m", sensor_y_m, "left [m]");
    writeExact(c, s, "sensor_z_m", sensor_z_m, "up [m]");
    writeExact(c, s, "sensor_yaw_deg", sensor_yaw_deg, "yaw [deg]");
}

void TAuvSensorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c)
{
    depth.loadFromConfigFile(c, "Depth");
    compass.loadFromConfigFile(c, "Compass");
    usbl.loadFromConfigFile(c, "USBL");
    dvl.loadFromConfigFile(c, "DVL");
    sidescan.loadFromConfigFile(c, "SideScan");
    fls.loadFromConfigFile(c, "ForwardSonar");
    camera.loadFromConfigFile(c, "Camera");
}

void TAuvSensorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c) const
{
    depth.saveToConfigFile(c, "Depth");
    compass.saveToConfigFile(c, "Compass");
    usbl.saveToConfigFile(c, "USBL");
    dvl.saveToConfigFile(c, "DVL");
    sidescan.saveToConfigFile(c, "SideScan");
    fls.saveToConfigFile(c, "ForwardSonar");
    camera.saveToConfigFile(c, "Camera");
}

}  // namespace semloc

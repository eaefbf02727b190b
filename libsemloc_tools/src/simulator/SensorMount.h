/* semloc — the sensor-on-vehicle keys every simulated sensor has (private):
 * sensor_x_m, sensor_y_m, sensor_yaw_deg in its own ini section. */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/io/ConfigHelpers.h>

#include <string>

#include "io/ExactConfigWrite.h"

namespace semloc::detail
{
/** Reads the three keys (if present) into x [m], y [m], yaw [deg], checking their ranges. */
inline void readSensorMount(const mrpt::config::CConfigFileBase& c, const std::string& s,
                            double& x_m, double& y_m, double& yaw_deg)
{
    config::readDouble(c, s, "sensor_x_m", x_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_y_m", y_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_yaw_deg", yaw_deg, -360, 360);
}

/** Writes the three keys; `what` names the sensor in the first comment ("sonar"). */
inline void writeSensorMount(mrpt::config::CConfigFileBase& c, const std::string& s,
                             const std::string& what, double x_m, double y_m, double yaw_deg)
{
    writeExact(c, s, "sensor_x_m", x_m, what + " pose on the vehicle: forward [m]");
    writeExact(c, s, "sensor_y_m", y_m, "left [m]");
    writeExact(c, s, "sensor_yaw_deg", yaw_deg, "yaw [deg]");
}

/** The mounting pose as MRPT observations carry it (sensorPose). */
inline mrpt::poses::CPose3D sensorMountPose(double x_m, double y_m, double yaw_deg)
{
    return mrpt::poses::CPose3D(x_m, y_m, 0, mrpt::DEG2RAD(yaw_deg), 0, 0);
}
}  // namespace semloc::detail

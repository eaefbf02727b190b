/* semloc — SonarModel: exact expected ranges plus range noise and dropouts. */
#include <mrpt/core/bits_math.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/SonarModel.h>

#include <algorithm>
#include <cmath>

#include "io/ExactConfigWrite.h"
#include "simulator/SensorMount.h"
#include "simulator/SimRandom.h"

namespace semloc
{
void SonarModel::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                              const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readInt(c, s, "beam_count", beam_count, 1, 100000);
    config::readDouble(c, s, "aperture_deg", aperture_deg, 1e-6, 360);
    config::readDouble(c, s, "max_range_m", max_range_m, 1e-3, 1e5);
    config::readDouble(c, s, "range_noise_std_m", range_noise_std_m, 0, 1e3);
    config::readDouble(c, s, "dropout_probability", dropout_probability, 0, 1);
    detail::readSensorMount(c, s, sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

void SonarModel::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                            const std::string& s) const
{
    using detail::writeExact;
    c.write(s, "beam_count", beam_count, 24, 24, "beams per scan, right to left");
    writeExact(c, s, "aperture_deg", aperture_deg, "width of the fan [deg]");
    writeExact(c, s, "max_range_m", max_range_m, "maximum range [m]; no echo reads this");
    writeExact(c, s, "range_noise_std_m", range_noise_std_m, "range noise of a hit [m]");
    writeExact(c, s, "dropout_probability", dropout_probability, "P(beam lost: invalid)");
    detail::writeSensorMount(c, s, "sonar", sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

mrpt::poses::CPose3D SonarModel::TOptions::sensorPose() const
{
    return detail::sensorMountPose(sensor_x_m, sensor_y_m, sensor_yaw_deg);
}

SonarModel::SonarModel(const World& world, const TOptions& options)
    : m_options(options), m_caster(world.outlineSegments())
{
}

mrpt::obs::CObservation2DRangeScan::Ptr SonarModel::measure(
    const mrpt::math::TPose2D& vehicle, mrpt::random::CRandomGenerator& rng) const
{
    const TOptions& o = m_options;
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    scan->sensorLabel = "SONAR";
    scan->aperture = static_cast<float>(mrpt::DEG2RAD(o.aperture_deg));
    scan->maxRange = static_cast<float>(o.max_range_m);
    scan->rightToLeft = true;
    scan->stdError = static_cast<float>(o.range_noise_std_m);
    scan->sensorPose = o.sensorPose();
    const size_t n = static_cast<size_t>(o.beam_count);
    scan->resizeScan(n);

    // Sensor pose in the world: vehicle (+) sensorPose, in 2D (as CStructureMap computes it).
    const double c = std::cos(vehicle.phi), s = std::sin(vehicle.phi);
    const double spx = scan->sensorPose.x(), spy = scan->sensorPose.y();
    const double sx = vehicle.x + c * spx - s * spy;
    const double sy = vehicle.y + s * spx + c * spy;
    const double sphi = vehicle.phi + scan->sensorPose.yaw();
    const double aperture = scan->aperture;
    const double maxRange = scan->maxRange;
    for (size_t k = 0; k < n; k++)
    {
        const double a =
            n > 1 ? -0.5 * aperture + aperture * static_cast<double>(k) / static_cast<double>(n - 1)
                  : 0.0;
        const double r = m_caster.cast(sx, sy, sphi + a, maxRange);
        // Draw both variates for every beam: the stream does not depend on the geometry.
        const double noise = o.range_noise_std_m * rng.drawGaussian1D_normalized();
        const bool dropped = detail::bernoulli(rng, o.dropout_probability);
        float z = static_cast<float>(maxRange);
        if (!dropped && r < maxRange)
        {
            z = static_cast<float>(std::clamp(r + noise, 0.0, maxRange));
        }
        scan->setScanRange(k, z);
        scan->setScanRangeValidity(k, !dropped);
    }
    return scan;
}

}  // namespace semloc

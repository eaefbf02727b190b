/* semloc — BeaconRangingModel: slant ranges to the world's beacons plus Gaussian noise. */
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/simulator/BeaconRangingModel.h>

#include <algorithm>
#include <climits>
#include <cmath>

#include "io/ExactConfigWrite.h"

namespace semloc
{
void BeaconRangingModel::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                      const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readBool(c, s, "enabled", enabled);
    config::readDouble(c, s, "range_std_m", range_std_m, 0, 1e3);
    config::readDouble(c, s, "max_range_m", max_range_m, 1e-3, 1e7);
    config::readInt(c, s, "period_steps", period_steps, 1, INT_MAX);
    config::readDouble(c, s, "sensor_x_m", sensor_x_m, -1e3, 1e3);
    config::readDouble(c, s, "sensor_y_m", sensor_y_m, -1e3, 1e3);
}

void BeaconRangingModel::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                    const std::string& s) const
{
    using detail::writeExact;
    c.write(s, "enabled", enabled, 24, 24, "range to the world's beacons (LBL)");
    writeExact(c, s, "range_std_m", range_std_m, "Gaussian range noise [m]");
    writeExact(c, s, "max_range_m", max_range_m, "farther beacons do not answer [m]");
    c.write(s, "period_steps", period_steps, 24, 24, "a ping every N steps, from step 0");
    writeExact(c, s, "sensor_x_m", sensor_x_m, "transducer on the vehicle: forward [m]");
    writeExact(c, s, "sensor_y_m", sensor_y_m, "left [m]");
}

BeaconRangingModel::BeaconRangingModel(const World& world, const TOptions& options)
    : m_options(options), m_beacons(world.beacons)
{
}

bool BeaconRangingModel::pingsAt(size_t step) const
{
    return m_options.enabled && step % static_cast<size_t>(m_options.period_steps) == 0;
}

mrpt::obs::CObservationBeaconRanges::Ptr BeaconRangingModel::measure(
    const mrpt::math::TPose2D& vehicle, mrpt::random::CRandomGenerator& rng) const
{
    const TOptions& o = m_options;
    auto obs = mrpt::obs::CObservationBeaconRanges::Create();
    obs->sensorLabel = "LBL";
    obs->minSensorDistance = 0;
    obs->maxSensorDistance = static_cast<float>(o.max_range_m);
    obs->stdError = static_cast<float>(o.range_std_m);
    // The transducer in the world: vehicle (+) (sensor_x_m, sensor_y_m, 0), as MRPT's
    // CBeaconMap composes the robot's pose and sensorLocationOnRobot.
    const double c = std::cos(vehicle.phi), s = std::sin(vehicle.phi);
    const double tx = vehicle.x + c * o.sensor_x_m - s * o.sensor_y_m;
    const double ty = vehicle.y + s * o.sensor_x_m + c * o.sensor_y_m;
    for (const auto& b : m_beacons)
    {
        const double range =
            std::sqrt((b.x - tx) * (b.x - tx) + (b.y - ty) * (b.y - ty) + b.z * b.z);
        // Drawn for every beacon: the stream does not depend on which ones answer.
        const double noise = o.range_std_m * rng.drawGaussian1D_normalized();
        if (range > o.max_range_m)
        {
            continue;
        }
        mrpt::obs::CObservationBeaconRanges::TMeasurement m;
        m.sensorLocationOnRobot = mrpt::poses::CPoint3D(o.sensor_x_m, o.sensor_y_m, 0);
        m.beaconID = b.id;
        m.sensedDistance = static_cast<float>(std::max(range + noise, 0.0));
        obs->sensedData.push_back(m);
    }
    return obs;
}

}  // namespace semloc

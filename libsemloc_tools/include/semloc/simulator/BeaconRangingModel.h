/* semloc — simulated range-only acoustic positioning (LBL): ranges to the world's beacons. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <semloc/world/World.h>

#include <string>
#include <vector>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** A long-baseline (LBL) acoustic positioning system: the vehicle pings every
 *  `period_steps` steps and each beacon of the world (World::beacons) whose true slant range
 *  from the transducer is within `max_range_m` answers. One MRPT CObservationBeaconRanges per
 *  ping (label "LBL"), one TMeasurement per answering beacon in the world's order:
 *  `sensorLocationOnRobot` the transducer (sensor_x_m, sensor_y_m, 0), `beaconID` the
 *  beacon's id, `sensedDistance` the 3D range from the transducer (the vehicle's plane is
 *  z = 0) to (x, y, z) plus N(0, range_std_m^2), clamped at 0 (a range <= 0 carries nothing
 *  for MRPT's CBeaconMap); `stdError` = range_std_m, `minSensorDistance` 0,
 *  `maxSensorDistance` = max_range_m. This is the model MRPT's CBeaconMap scores (its
 *  likelihoodOpts rangeStd set to range_std_m).
 *
 *  One Gaussian draw per beacon and ping, answering or not: the stream does not depend on
 *  the geometry. Nothing is drawn between pings or when the sensor is disabled. */
class BeaconRangingModel
{
public:
    /** Section [BeaconRanging]. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Whether the vehicle ranges to the beacons at all (off: no observation, no draw). */
        bool enabled = false;
        /** Standard deviation of a range [m]. */
        double range_std_m = 0.5;
        /** Beacons farther than this do not answer [m]. */
        double max_range_m = 200.0;
        /** A ping every this many steps, the first at step 0 (1: every step). */
        int period_steps = 1;
        /** Transducer position on the vehicle: forward [m]. */
        double sensor_x_m = 0.0;
        /** Transducer position on the vehicle: left [m]. */
        double sensor_y_m = 0.0;

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** Ranges to `world.beacons`. */
    BeaconRangingModel(const World& world, const TOptions& options);

    /** True if the vehicle pings at step `step` (enabled, and `step` a multiple of
     *  period_steps). */
    bool pingsAt(size_t step) const;

    /** One ping from vehicle pose `vehicle` (timestamp unset). */
    mrpt::obs::CObservationBeaconRanges::Ptr measure(const mrpt::math::TPose2D& vehicle,
                                                     mrpt::random::CRandomGenerator& rng) const;

    /** The parameters. */
    const TOptions& options() const { return m_options; }

private:
    TOptions m_options;
    std::vector<WorldBeacon> m_beacons;
};

}  // namespace semloc

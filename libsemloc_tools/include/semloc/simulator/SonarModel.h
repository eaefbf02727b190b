/* semloc — simulated sonar: exact ray casting against the world's outlines, plus noise. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/models/structure/RayCaster.h>
#include <semloc/world/World.h>

#include <string>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** A planar multibeam sonar: a fan of `beam_count` beams over `aperture_deg`, centred on the
 *  sensor's x axis, ordered right to left (MRPT's getScanAngle()). Each beam's true range is
 *  cast exactly by RayCaster against World::outlineSegments() (the same caster and segments
 *  as CStructureMap, so a noise-free scan is what the geometric likelihood predicts).
 *
 *  - A beam that hits nothing reads `max_range_m` and is **valid**: a max-range reading is
 *    information (CStructureMap's p_max term), unlike MRPT's own simulator, which marks
 *    such beams invalid.
 *  - A beam that hits reads true + N(0, range_noise_std_m^2), clamped to [0, max_range_m]
 *    (a hit pushed beyond the maximum becomes a max-range reading).
 *  - With probability `dropout_probability` a beam is lost: invalid, range = max_range_m.
 *  - Beam angles are computed from the scan's stored (float) aperture, as every reader of
 *    the scan computes them. */
class SonarModel
{
public:
    /** Section [Sonar]. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Number of beams per scan. */
        int beam_count = 61;
        /** Angular width of the fan [deg], (0, 360]. */
        double aperture_deg = 180.0;
        /** Maximum range [m]. */
        double max_range_m = 20.0;
        /** Std. dev. of the range noise of a beam that hits [m]. */
        double range_noise_std_m = 0.1;
        /** Probability that a beam returns nothing (an invalid beam). */
        double dropout_probability = 0.02;
        /** @name Pose of the sonar on the vehicle
         *  @{ */
        double sensor_x_m = 0.0;      //!< [m] forward
        double sensor_y_m = 0.0;      //!< [m] to the left
        double sensor_yaw_deg = 0.0;  //!< [deg] counter-clockwise
        /** @} */

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;

        /** The sensor pose on the vehicle. */
        mrpt::poses::CPose3D sensorPose() const;
    };

    /** Casts against `world.outlineSegments()` (default cylinder tolerance). */
    SonarModel(const World& world, const TOptions& options);

    /** One scan taken from vehicle pose `vehicle` (label "SONAR", timestamp unset). */
    mrpt::obs::CObservation2DRangeScan::Ptr measure(const mrpt::math::TPose2D& vehicle,
                                                    mrpt::random::CRandomGenerator& rng) const;

    /** The parameters. */
    const TOptions& options() const { return m_options; }
    /** The ray caster over the world's outlines. */
    const RayCaster& rayCaster() const { return m_caster; }

private:
    TOptions m_options;
    RayCaster m_caster;
};

}  // namespace semloc

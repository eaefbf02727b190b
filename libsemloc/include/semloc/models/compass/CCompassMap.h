/* semloc — a compass or AHRS: the vehicle's absolute heading (docs/design.md, "Heading and
 * position fixes"). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <semloc/models/CSensorModelMap.h>

#include <string>

namespace semloc
{
/** The compass model (`[MetricMap] compassMap_count = 1`): MRPT's CObservationIMU with its
 *  yaw (IMU_YAW, the sensor's heading in the map's frame, counter-clockwise from x) scores
 *  the vehicle's heading phi as
 *
 *      log((1 - eps) N(wrap(yaw - phi - mount yaw); sigma) + eps / (2 pi))
 *
 *  sigma `sigma_deg`, eps `p_outlier` (a heading disturbed near a wreck's steel: uniform).
 *  An IMU reading without a yaw is not used. It holds nothing: a map only to be one of
 *  MRPT's registry. */
class CCompassMap : public CSensorModelMap
{
    DEFINE_SERIALIZABLE(CCompassMap, semloc)

public:
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        /** The readings scored: this sensorLabel ("": every CObservationIMU with a yaw). */
        std::string sensor_label;
        /** The heading's noise [deg]. */
        double sigma_deg = 2;
        /** The probability that a reading is disturbed (uniform over the circle). */
        double p_outlier = 0.01;
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };
    TLikelihoodOptions likelihoodOptions;

    /** log p(yaw | the vehicle's heading phi) for the sensor's mount yaw. */
    double logLik(double yaw, double mountYaw, double phi) const;

    // BatchLikelihood
    bool uses(const mrpt::obs::CObservation& obs) const override;
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;

    // CMetricMap
    std::string asString() const override { return "compass"; }

    MAP_DEFINITION_START(CCompassMap)
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CCompassMap)

private:
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
};

}  // namespace semloc

/* semloc — position fixes: a USBL fix from the ship, a GPS fix at the surface (docs/design.md,
 * "Heading and position fixes"). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <semloc/models/CSensorModelMap.h>

#include <string>

namespace semloc
{
/** The position-fix model (`[MetricMap] poseFixMap_count = 1`): MRPT's CObservationRobotPose
 *  (a pose with its covariance) scores the vehicle's x, y by the fix's Gaussian, its
 *  covariance the fix's own x-y block (`sigma_m` = 0, the default) or sigma_m^2 I, mixed with
 *  a wide Gaussian of `outlier_sigma_m` with probability `p_outlier` (an acoustic fix off by
 *  a multipath):
 *
 *      log((1 - eps) N(d; C) + eps N(d; outlier_sigma_m^2 I)),  d = fix - (x, y)
 *
 *  The fix's heading is not used (a USBL fix has none; a compass scores headings). */
class CPoseFixMap : public CSensorModelMap
{
    DEFINE_SERIALIZABLE(CPoseFixMap, semloc)

public:
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        /** The fixes scored: this sensorLabel ("": every CObservationRobotPose). */
        std::string sensor_label;
        /** > 0: the fixes' standard deviation in x and y [m], whatever they carry; 0: the
         *  covariance each fix carries. */
        double sigma_m = 0;
        /** The probability that a fix is an outlier, and the outliers' spread [m]. */
        double p_outlier = 0.02;
        double outlier_sigma_m = 50;
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };
    TLikelihoodOptions likelihoodOptions;

    /** The fix's x-y covariance as scored (sxx, sxy, syy), or false when it is not positive
     *  definite. */
    bool covariance(const mrpt::obs::CObservationRobotPose& fix, double& sxx, double& sxy,
                    double& syy) const;
    /** log p(fix | x, y). */
    double logLik(const mrpt::obs::CObservationRobotPose& fix, double x, double y) const;

    // BatchLikelihood
    bool uses(const mrpt::obs::CObservation& obs) const override;
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;

    // CMetricMap
    std::string asString() const override { return "position fixes"; }

    MAP_DEFINITION_START(CPoseFixMap)
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CPoseFixMap)

private:
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
};

}  // namespace semloc

/* semloc tests — a sensor model defined only in the tests, created by name from an ini: a
 * Gaussian position fix (MRPT's CObservationRobotPose: a surfaced AUV's GPS, a USBL fix),
 * `[MetricMap] positionFixMap_count = 1`. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <semloc/models/BatchLikelihood.h>

namespace semloc::test
{
/** log p(fix | pose) = -d^2 / (2 sigma^2), d the distance from the pose to the fix's
 *  position, sigma `[..._likelihoodOpts] sigma_m` (> 0). It holds nothing: a map only to be
 *  a CMetricMap of MRPT's registry. */
class CPositionFixMap : public mrpt::maps::CMetricMap, public semloc::BatchLikelihood
{
    DEFINE_SERIALIZABLE(CPositionFixMap, semloc::test)

public:
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        /** The fixes' standard deviation [m]. */
        double sigma_m = 1.0;
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };
    TLikelihoodOptions likelihoodOptions;

    double logLik(const mrpt::obs::CObservationRobotPose& fix, double x, double y) const;

    // BatchLikelihood
    bool uses(const mrpt::obs::CObservation& obs) const override;
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;

    // CMetricMap
    bool isEmpty() const override { return false; }
    void saveMetricMapRepresentationToFile(const std::string&) const override {}
    std::string asString() const override { return "position fixes"; }
    void getVisualizationInto(mrpt::opengl::CSetOfObjects&) const override {}

    MAP_DEFINITION_START(CPositionFixMap)
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CPositionFixMap)

private:
    void internal_clear() override {}
    bool internal_insertObservation(const mrpt::obs::CObservation&,
                                    const std::optional<const mrpt::poses::CPose3D>&) override
    {
        return false;
    }
    bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override
    {
        return uses(obs);
    }
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
};
}  // namespace semloc::test

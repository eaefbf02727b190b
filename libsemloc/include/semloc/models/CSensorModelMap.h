/* semloc — a sensor model as an MRPT metric map: the part of MRPT's map interface a model that
 * is not built by mapping leaves empty (docs/design.md, "Adding a sensor model"). */
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <semloc/models/BatchLikelihood.h>

#include <optional>
#include <string>

namespace semloc
{
/** The base of semloc's models that MRPT's registry creates from an ini but that no
 *  observation inserts into: the compass, the position fixes, the detectors of the water
 *  column. It is not empty (a map of nothing to hold still scores), has no file or 3D
 *  representation, takes no insertion, and scores what its BatchLikelihood uses(). A model
 *  implements uses(), logLikelihoods(), asString() and MRPT's per-pose
 *  internal_computeObservationLikelihood(). */
class CSensorModelMap : public mrpt::maps::CMetricMap, public BatchLikelihood
{
public:
    bool isEmpty() const override { return false; }
    void saveMetricMapRepresentationToFile(const std::string&) const override {}
    void getVisualizationInto(mrpt::opengl::CSetOfObjects&) const override {}

protected:
    CSensorModelMap() = default;
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
};

}  // namespace semloc

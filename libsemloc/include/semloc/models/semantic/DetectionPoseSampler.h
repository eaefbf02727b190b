/* semloc — vehicle poses drawn from a semantic observation: sensor-resetting localization. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cstddef>
#include <vector>

namespace semloc
{
class CSemanticMap;

/** Draws vehicle poses from which the current observation could have been taken: the
 *  measurement-driven injection of sensor-resetting localization (Lenser & Veloso 2000;
 *  Probabilistic Robotics §8.3.5, "generate particles according to the measurement").
 *
 *  One draw: a usable detection (label, range r, bearing b) of the observation uniformly, a
 *  map object it may be (CSemanticMap::candidatesOf: by id, else by label) uniformly, an
 *  angle theta uniform in [-pi, pi); with r' = r + N(0, sigma_range) and
 *  b' = b + N(0, sigma_bearing) (the map's likelihood noise):
 *
 *      sensor position = object + r' (cos theta, sin theta)
 *      sensor heading  = theta + pi - b'
 *
 *  so the object is seen at range r' and bearing b' from the sensor; the vehicle pose is that
 *  sensor pose (-) the detector's pose on the vehicle (sensorPose, projected to 2D). */
class DetectionPoseSampler final : public BatchLikelihood::PoseProposal
{
public:
    /** The (detection, candidate objects) pairs of `obs` against `map`. */
    DetectionPoseSampler(const CSemanticMap& map, const CObservationSemantic& obs);

    /** True if no detection of the observation can be associated with a map object. */
    bool empty() const { return m_detections.empty(); }
    /** One vehicle pose (requires !empty()). */
    mrpt::math::TPose2D draw(mrpt::random::CRandomGenerator& rng) const override;

private:
    struct Detection
    {
        double range_m = 0, bearing_rad = 0;
        std::vector<size_t> objects;
    };
    const CSemanticMap& m_map;
    std::vector<Detection> m_detections;
    double m_sensorX = 0, m_sensorY = 0, m_sensorYaw = 0;
    double m_sigmaRange = 0, m_sigmaBearing = 0;
};

}  // namespace semloc

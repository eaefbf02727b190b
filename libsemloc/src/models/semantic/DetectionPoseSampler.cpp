/* semloc — DetectionPoseSampler: poses consistent with one detection. */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionPoseSampler.h>

#include <algorithm>
#include <cmath>

namespace semloc
{
namespace
{
/** Uniform index in [0, n). */
size_t drawIndex(mrpt::random::CRandomGenerator& rng, size_t n)
{
    const auto i = static_cast<size_t>(rng.drawUniform(0.0, static_cast<double>(n)));
    return std::min(i, n - 1);
}
}  // namespace

DetectionPoseSampler::DetectionPoseSampler(const CSemanticMap& map, const CObservationSemantic& obs)
    : m_map(map),
      m_sensorX(obs.sensorPose.x()),
      m_sensorY(obs.sensorPose.y()),
      m_sensorYaw(obs.sensorPose.yaw()),
      m_sigmaRange(map.likelihoodOptions.detector.sigma_range_m),
      m_sigmaBearing(mrpt::DEG2RAD(map.likelihoodOptions.detector.sigma_bearing_deg))
{
    for (const auto& d : obs.detections)
    {
        auto objects = map.candidatesOf(obs, d);
        if (!objects.empty())
        {
            m_detections.push_back({d.range_m, d.bearing_rad, std::move(objects)});
        }
    }
}

mrpt::math::TPose2D DetectionPoseSampler::draw(mrpt::random::CRandomGenerator& rng) const
{
    ASSERTMSG_(!m_detections.empty(), "DetectionPoseSampler::draw: no usable detection");
    const Detection& d = m_detections[drawIndex(rng, m_detections.size())];
    const auto& obj = m_map.objects()[d.objects[drawIndex(rng, d.objects.size())]];
    const double theta = rng.drawUniform(-M_PI, M_PI);
    const double r = std::max(0.0, d.range_m + m_sigmaRange * rng.drawGaussian1D_normalized());
    const double b = d.bearing_rad + m_sigmaBearing * rng.drawGaussian1D_normalized();
    // The sensor, at range r from the object, looks back at it under bearing b.
    const double sx = obj.x + r * std::cos(theta), sy = obj.y + r * std::sin(theta);
    const double phi = mrpt::math::wrapToPi(theta + M_PI - b - m_sensorYaw);
    const double c = std::cos(phi), s = std::sin(phi);
    return {sx - (c * m_sensorX - s * m_sensorY), sy - (s * m_sensorX + c * m_sensorY), phi};
}

}  // namespace semloc

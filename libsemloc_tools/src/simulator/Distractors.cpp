/* semloc — Distractors: unmapped moving objects for the simulated detector. */
#include "simulator/Distractors.h"

#include <mrpt/random/RandomGenerators.h>

#include <cmath>

#include "simulator/SimRandom.h"

namespace semloc::detail
{
namespace
{
/** Reflects coordinate v moving with velocity component dv into [lo, hi]. */
void reflect(double& v, double& dv, double lo, double hi)
{
    for (int k = 0; k < 4 && (v < lo || v > hi); k++)  // a step longer than the box: a few
    {
        v = v < lo ? 2 * lo - v : 2 * hi - v;
        dv = -dv;
    }
    v = std::fmin(std::fmax(v, lo), hi);
}
}  // namespace

Distractors::Distractors(const World& world, const SemanticDetectorModel& detector,
                         mrpt::random::CRandomGenerator& rng)
    : m_bounds(world.bounds), m_speed(detector.options().distractor_speed_mps)
{
    const auto n = static_cast<size_t>(detector.options().distractors);
    const size_t nLabels = detector.labels().size();
    if (nLabels == 0)
    {
        return;  // a world without objects: nothing to be mistaken for
    }
    for (size_t i = 0; i < n; i++)
    {
        const auto p = world.sampleFreePose(rng);
        m_now.push_back({p.x, p.y, uniformIndex(rng, nLabels)});
        m_heading.push_back(p.phi);
    }
}

void Distractors::step(double dt)
{
    for (size_t i = 0; i < m_now.size(); i++)
    {
        auto& d = m_now[i];
        double vx = m_speed * std::cos(m_heading[i]), vy = m_speed * std::sin(m_heading[i]);
        d.x += vx * dt;
        d.y += vy * dt;
        reflect(d.x, vx, m_bounds.x_min, m_bounds.x_max);
        reflect(d.y, vy, m_bounds.y_min, m_bounds.y_max);
        m_heading[i] = std::atan2(vy, vx);
    }
}
}  // namespace semloc::detail

/* semloc — the filter's particles during a step, each with its motion state. */
#include "filter/ParticleStore.h"

#include <mrpt/core/exceptions.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace semloc::detail
{
namespace
{
uint64_t bitsOf(double v)
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

/** The same pose bit for bit (a NaN pose equals itself). */
bool samePose(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b)
{
    return bitsOf(a.x) == bitsOf(b.x) && bitsOf(a.y) == bitsOf(b.y) &&
           bitsOf(a.phi) == bitsOf(b.phi);
}
}  // namespace

void ParticleStore::setDim(const ParticleMotionModel& model)
{
    const size_t dim = model.stateSize();
    if (dim != m_dim)
    {
        m_dim = dim;
        m_state.clear();  // the old states are not this model's
        particles.clear();
    }
}

void ParticleStore::assign(const MrptParticleList& from, const ParticleMotionModel& model,
                           mrpt::random::CRandomGenerator& rng)
{
    setDim(model);
    particles.assign(from.begin(), from.end());
    m_state.resize(particles.size() * m_dim);
    for (size_t i = 0; m_dim > 0 && i < particles.size(); i++)
    {
        model.drawState(state(i), rng);
    }
}

void ParticleStore::syncFrom(const MrptParticleList& from, const ParticleMotionModel& model,
                             mrpt::random::CRandomGenerator& rng)
{
    setDim(model);
    if (m_dim == 0)
    {
        particles.assign(from.begin(), from.end());
        return;
    }
    if (particles.size() != from.size())
    {
        // A set of another size came from outside: every particle is new.
        assign(from, model, rng);
        return;
    }
    particles.resize(from.size());
    m_state.resize(from.size() * m_dim);
    size_t i = 0;
    for (const Particle& p : from)
    {
        if (!samePose(p.d, particles[i].d))
        {
            model.drawState(state(i), rng);
        }
        particles[i] = p;
        i++;
    }
}

void ParticleStore::adopt(const MrptParticleList& from, const ParticleMotionModel& model,
                          mrpt::random::CRandomGenerator& rng)
{
    setDim(model);
    if (particles.size() != from.size())
    {
        syncFrom(from, model, rng);
        return;
    }
    std::copy(from.begin(), from.end(), particles.begin());
}

void ParticleStore::syncTo(MrptParticleList& to) const
{
    to.resize(particles.size());
    std::copy(particles.begin(), particles.end(), to.begin());
}

void ParticleStore::append(const ParticleStore& tail)
{
    ASSERT_EQUAL_(tail.m_dim, m_dim);
    particles.insert(particles.end(), tail.particles.begin(), tail.particles.end());
    m_state.insert(m_state.end(), tail.m_state.begin(), tail.m_state.end());
}

void ParticleStore::splitTail(size_t first, ParticleStore& tail)
{
    ASSERT_LE_(first, particles.size());
    const auto cut = particles.begin() + static_cast<std::ptrdiff_t>(first);
    tail.particles.assign(cut, particles.end());
    particles.erase(cut, particles.end());
    tail.m_dim = m_dim;
    const auto stateCut = m_state.begin() + static_cast<std::ptrdiff_t>(first * m_dim);
    tail.m_state.assign(stateCut, m_state.end());
    m_state.erase(stateCut, m_state.end());
}

void ParticleStore::copyState(size_t from, ParticleStore& dest, size_t to) const
{
    dest.m_dim = m_dim;
    dest.m_state.resize(dest.particles.size() * m_dim);
    for (size_t d = 0; d < m_dim; d++)
    {
        dest.m_state[to * m_dim + d] = m_state[from * m_dim + d];
    }
}

const CarriedValues* ParticleStore::carried(size_t count)
{
    if (m_dim == 0)
    {
        return nullptr;
    }
    m_resampledState.resize(count * m_dim);
    m_carried = CarriedValues{m_state.data(), m_resampledState.data(), m_dim};
    return &m_carried;
}
}  // namespace semloc::detail

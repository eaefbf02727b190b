/* semloc — the filter's particles during a step: contiguous, each with its motion state
 * (private). */
#pragma once

#include <mrpt/poses/CPosePDFParticles.h>

#include <cstddef>
#include <vector>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
class ParticleMotionModel;
}

namespace semloc::detail
{
/** One particle: MRPT's (a pose and its log-weight). */
using Particle = mrpt::poses::PFDataTPose2D::CParticleList::value_type;
/** MRPT's particle list (CPosePDFParticles::m_particles, a std::deque). */
using MrptParticleList = mrpt::poses::PFDataTPose2D::CParticleList;
/** Particles in one contiguous array: the filter's loops are plain pointer loops. */
using ParticleList = std::vector<Particle>;

/** Calls `run(first, b, e - b)` with first = &particles[b]: the particles [b, e) as one
 *  contiguous run. */
template <typename Particles, typename Run>
inline void forEachRun(Particles& particles, size_t b, size_t e, Run&& run)
{
    if (b < e)
    {
        run(particles.data() + b, b, e - b);
    }
}

/** A block of values per particle that follows its particle through a resampling: from[j *
 *  dim ...] belongs to the old particle j, to[k * dim ...] receives the values of the
 *  particle that new particle k copies. */
struct CarriedValues
{
    const double* from;
    double* to;
    size_t dim;

    /** New particle k copies old particle j. */
    void copy(size_t j, size_t k) const
    {
        for (size_t d = 0; d < dim; d++)
        {
            to[k * dim + d] = from[j * dim + d];
        }
    }
};

/** The particle set of a step: each particle's pose and log-weight (MRPT's particle) and its
 *  motion state (ParticleMotionModel::stateSize() values, e.g. the odometry's heading drift
 *  rate), kept together: a resampling copies a particle's state with its pose, and nothing
 *  outside the store indexes the states.
 *
 *  MRPT's CPosePDFParticles::m_particles (a std::deque, public, which MRPT's own methods and
 *  the filter's users read and write between steps) stays the set's public face: the step
 *  takes the particles from it (syncFrom) and gives them back (syncTo). A particle whose pose
 *  the deque changed since (placed from outside the filter, e.g. a reset) gets a new state
 *  from the model's prior. */
class ParticleStore
{
public:
    ParticleList particles;

    /** Values of state per particle. */
    size_t dim() const { return m_dim; }
    /** Particle i's state (dim() values). */
    double* state(size_t i) { return m_state.data() + i * m_dim; }
    const double* state(size_t i) const { return m_state.data() + i * m_dim; }
    /** Every particle's state, particle after particle (nullptr when dim() is 0). */
    double* states() { return m_dim ? m_state.data() : nullptr; }

    /** The store becomes `from`, every state drawn from `model`'s prior (in particle
     *  order, from `rng`). */
    void assign(const MrptParticleList& from, const ParticleMotionModel& model,
                mrpt::random::CRandomGenerator& rng);
    /** The store becomes `from`: a particle whose pose differs from the store's (or that the
     *  store did not have) gets a state from `model`'s prior (in particle order, from
     *  `rng`); the others keep theirs. */
    void syncFrom(const MrptParticleList& from, const ParticleMotionModel& model,
                  mrpt::random::CRandomGenerator& rng);
    /** The store takes `from`'s particles keeping every state (their number must be the
     *  store's; else as syncFrom()). */
    void adopt(const MrptParticleList& from, const ParticleMotionModel& model,
               mrpt::random::CRandomGenerator& rng);
    /** `to` becomes the store's particles. */
    void syncTo(MrptParticleList& to) const;

    /** Appends `tail`'s particles and states (a store of the same model's states). */
    void append(const ParticleStore& tail);
    /** The particles from `first` on, with their states, move to `tail` (replacing what it
     *  held); the store keeps the first `first`. */
    void splitTail(size_t first, ParticleStore& tail);
    /** Particle `from`'s state (dim() values) copied to particle `to` of `dest`, a store of
     *  the same model's states. */
    void copyState(size_t from, ParticleStore& dest, size_t to) const;
    /** No particle. */
    void clear()
    {
        particles.clear();
        m_state.clear();
    }

    /** What a resampling into `count` particles writes the states to (carried values of the
     *  particles' states), or nullptr without states; swapResampled() makes it the set. */
    const CarriedValues* carried(size_t count);
    /** The resampled particles (and states) become the set. */
    void swapResampled()
    {
        particles.swap(resampled);
        m_state.swap(m_resampledState);
    }
    /** The buffer a resampling writes the new particles to. */
    ParticleList resampled;

private:
    void setDim(const ParticleMotionModel& model);

    size_t m_dim = 0;
    std::vector<double> m_state, m_resampledState;
    CarriedValues m_carried{};
};
}  // namespace semloc::detail

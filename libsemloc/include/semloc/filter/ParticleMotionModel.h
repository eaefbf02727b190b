/* semloc — the motion model of the filter's prediction: an interface a program implements to
 * move the particles its own way, and the odometry model semloc ships. */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPoseRandomSampler.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace mrpt::obs
{
class CActionCollection;
class CSensoryFrame;
}  // namespace mrpt::obs
namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
namespace detail
{
class GaussianIncrementDrawer;
}

/** What a motion model prepares a step's prediction from. */
struct TMotionStep
{
    /** The step's actions (the odometry). */
    const mrpt::obs::CActionCollection& actions;
    /** The step's frame (its timestamp is the step's time), or nullptr. */
    const mrpt::obs::CSensoryFrame* frame;
    /** The number of particles. */
    size_t particles;
    /** Every particle's state (stateSize() values per particle, particle after particle;
     *  nullptr when stateSize() is 0): prepare() may change them, on its own thread. */
    double* states;
};

/** The prediction of CParallelMonteCarloLocalization2D: how a step's actions move each
 *  particle, and the state beyond its pose that a particle carries (a bias of the odometry,
 *  the water current...).
 *
 *  A particle's state is part of the particle: the filter draws it from drawState() when
 *  the particle is placed (a reset, a particle placed from outside the filter), copies it
 *  with the particle at every resampling, and keeps it when recovery moves the particle (the
 *  state belongs to the vehicle's sensors, not to the pose). The filter calls, per step:
 *  prepare() once on its own thread, then move() on the executor's threads, for disjoint
 *  ranges of particles split in any way. For results that do not depend on the number of
 *  threads, a particle's new pose and state must depend only on its index, its pose and
 *  state and what prepare() computed (e.g. a key drawn from `rng` there, from which each
 *  particle draws its own numbers: OdometryMotionModel's streams). */
class ParticleMotionModel
{
public:
    virtual ~ParticleMotionModel() = default;

    /** Values of state per particle beyond its pose (0: the pose alone). */
    virtual size_t stateSize() const { return 0; }
    /** A particle's initial state (stateSize() values) from the model's prior; random
     *  numbers from `rng` (MRPT's generator, on the filter's thread). */
    virtual void drawState(double* state, mrpt::random::CRandomGenerator& rng) const
    {
        (void)state;
        (void)rng;
    }
    /** A new run: forgets what the model keeps from step to step besides the particles'
     *  states (e.g. the time of the last step). */
    virtual void reset() {}

    /** Prepares the step's prediction from `step`; random numbers from `rng` (MRPT's
     *  generator: the seed decides them). Throws when the actions cannot move the particles
     *  (no odometry). */
    virtual void prepare(const TMotionStep& step, mrpt::random::CRandomGenerator& rng) = 0;
    /** Moves the n particles i0 .. i0 + n - 1: poses[k] is particle i0 + k's pose and
     *  states + k * stateSize() its state (nullptr when stateSize() is 0), both updated in
     *  place. Called from several threads at once on disjoint ranges. */
    virtual void move(size_t i0, size_t n, mrpt::math::TPose2D* poses, double* states) const = 0;
};

/** The odometry's motion model: every particle moves by a sample of the step's odometry
 *  increment (its CActionRobotMovement2D's Gaussian, drawn per particle from a stream of its
 *  own; another odometry PDF or a 3D action: MRPT's sampler, on the filter's thread), with,
 *  optionally, the odometry's heading drift as a state of every particle.
 *
 *  Heading drift (off by default; [MotionModel] heading_drift_std_deg_per_min,
 *  heading_drift_walk_deg_per_min): a rate r_i per particle [rad/s], the heading the
 *  odometry gains per second beyond the truth (a gyro's bias, Titterton & Weston ch. 4; a
 *  compass-less DVL's heading). The prediction takes r_i dt off the increment's heading, dt
 *  the time since the previous step (from the frame's timestamp, else the action's), and
 *  r_i walks by N(0, walk_std² dt). A particle's rate starts from N(0, prior_std²). */
class OdometryMotionModel : public ParticleMotionModel
{
public:
    OdometryMotionModel();
    ~OdometryMotionModel() override;

    /** The heading drift: the standard deviation of a particle's initial rate [rad/s] and of
     *  its change over one second [rad/s per sqrt(s)]; both 0: off (no state). */
    void setHeadingDrift(double priorStd, double walkStd);
    /** True when every particle carries a heading drift rate. */
    bool headingDrift() const { return m_priorStd > 0 || m_walkStd > 0; }

    size_t stateSize() const override { return headingDrift() ? 1 : 0; }
    void drawState(double* state, mrpt::random::CRandomGenerator& rng) const override;
    void reset() override { m_last.reset(); }
    void prepare(const TMotionStep& step, mrpt::random::CRandomGenerator& rng) override;
    void move(size_t i0, size_t n, mrpt::math::TPose2D* poses, double* states) const override;

private:
    /** Seconds from the previous step to the step's time (0 at the first and when time goes
     *  back); throws for a step without a timestamp. */
    double elapsed(const TMotionStep& step);
    /** MRPT's sampler for the other PDFs: every particle's increment, the drift taken off. */
    void prepareSampled(const TMotionStep& step, mrpt::random::CRandomGenerator& rng);

    double m_priorStd = 0, m_walkStd = 0;
    std::optional<mrpt::Clock::time_point> m_last;  ///< the previous step's time
    // This step.
    std::unique_ptr<detail::GaussianIncrementDrawer> m_drawer;  ///< Gaussian odometry
    uint64_t m_key = 0;
    double m_dt = 0, m_walk = 0;
    /** MRPT's sampler's increments (other odometry PDFs), one per particle. */
    mrpt::poses::CPoseRandomSampler m_sampler;
    std::vector<mrpt::poses::CPose3D> m_increments;
    bool m_sampled = false;
};

}  // namespace semloc

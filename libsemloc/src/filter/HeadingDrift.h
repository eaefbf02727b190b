/* semloc — the odometry's heading drift as a state of every particle: a rate the particle's
 * prediction takes off the odometry's heading increment, drawn from a prior and walking
 * (private). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/random/RandomGenerators.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace semloc
{
class ParallelExecutor;
}

namespace semloc::detail
{
/** A heading drift rate r_i per particle [rad/s]: the odometry's heading increment over dt
 *  seconds reads r_i dt too much, so the prediction takes r_i dt off it, and r_i walks by
 *  N(0, walk² dt) (a gyro's bias, Titterton & Weston ch. 4; a compass-less DVL's heading).
 *  Each r_i starts from N(0, prior²). Off (prior = walk = 0): no rate, the prediction is the
 *  odometry's alone. The rates follow their particles through resampling (substitute); a
 *  re-initialized or injected particle keeps its rate (the drift is the odometry's). */
class HeadingDrift
{
public:
    /** The model [SI]. */
    struct TOptions
    {
        /** Standard deviation of a particle's initial rate [rad/s]. */
        double prior_std = 0;
        /** Standard deviation of a rate's change over one second [rad/s per sqrt(s)]. */
        double walk_std = 0;
        bool enabled() const { return prior_std > 0 || walk_std > 0; }
    };

    void setOptions(const TOptions& o) { m_options = o; }
    const TOptions& options() const { return m_options; }
    bool enabled() const { return m_options.enabled(); }

    /** Every one of `count` rates from the prior. */
    void reset(size_t count, mrpt::random::CRandomGenerator& rng);
    /** Forgets the time of the last motion (a new run). */
    void forgetClock() { m_last.reset(); }
    /** Rate i from the prior. */
    void redraw(size_t i, mrpt::random::CRandomGenerator& rng)
    {
        m_rate[i] = m_options.prior_std * rng.drawGaussian1D_normalized();
    }
    /** `count` rates: all of them from the prior when their number is not `count` (the set
     *  was resized outside the filter's own steps, e.g. MRPT's resetUniform()). */
    void match(size_t count, mrpt::random::CRandomGenerator& rng);
    /** Seconds from the previous motion to `t` (0 at the first and when time goes back);
     *  throws when `t` is INVALID_TIMESTAMP. */
    double elapsed(mrpt::Clock::time_point t);

    /** The rates, one per particle. */
    double* rates() { return m_rate.data(); }
    const std::vector<double>& rateVector() const { return m_rate; }
    /** A buffer of `count` rates for a resampling to write to; swap() makes it the rates. */
    double* resampledBuffer(size_t count)
    {
        m_resampled.resize(count);
        return m_resampled.data();
    }
    void swapResampled() { m_rate.swap(m_resampled); }

private:
    TOptions m_options;
    std::vector<double> m_rate, m_resampled;
    std::optional<mrpt::Clock::time_point> m_last;
};
}  // namespace semloc::detail

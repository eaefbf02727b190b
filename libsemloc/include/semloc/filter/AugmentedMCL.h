/* semloc — recovery from localization failures: augmented MCL's random particle injection. */
#pragma once

#include <limits>

namespace semloc
{
/** The short- and long-term averages of the measurement likelihood of augmented MCL
 *  (Thrun, Burgard, Fox, Probabilistic Robotics, §8.3.5, Table 8.3), kept in the log domain
 *  so that likelihoods of e^-1000 do not underflow:
 *
 *      w_avg  = sum_m w_prev[m] p(z | x[m])        (the prior-weighted average likelihood)
 *      w_slow = w_slow + alpha_slow (w_avg - w_slow)
 *      w_fast = w_fast + alpha_fast (w_avg - w_fast)
 *      p_inject = max(0, 1 - w_fast / w_slow)
 *
 *  A sudden drop of the likelihood (kidnapping, a wrong convergence) makes w_fast fall
 *  below w_slow, and a fraction p_inject of the particles is replaced by random poses:
 *  `from_detections` of them drawn from the current detections (sensor-resetting, Lenser &
 *  Veloso 2000), the rest uniform over the free space, each with `injected_weight` times a
 *  resampled particle's weight. */
class AugmentedMCL
{
public:
    /** Decay rates; recovery is on when 0 < alpha_slow < alpha_fast <= 1. */
    struct TOptions
    {
        /** Rate of the long-term average (Thrun: alpha_slow << alpha_fast). 0 = off. */
        double alpha_slow = 0;
        /** Rate of the short-term average. 0 = off. */
        double alpha_fast = 0;
        /** Fraction in [0, 1] of the injected particles drawn from the current semantic
         *  detections (DetectionPoseSampler, sensor-resetting localization) instead of
         *  uniformly over the free space; 0 = all uniform. Without a semantic map or a
         *  usable detection, every injected particle is uniform. */
        double from_detections = 0.8;
        /** Weight in (0, 1] of an injected particle relative to a resampled one: 1 is
         *  Thrun's (an injected particle counts in the estimate at once); below, it must earn
         *  its weight from the next frames first (a detection-consistent pose after a
         *  kidnapping gains orders of magnitude per frame; one beside a well-localized cloud
         *  does not), so injections that were not needed barely move the estimate. */
        double injected_weight = 1;

        /** True when 0 < alpha_slow < alpha_fast. */
        bool enabled() const { return alpha_slow > 0 && alpha_fast > alpha_slow; }
    };

    /** Off. */
    AugmentedMCL() = default;
    /** With rates `o`. */
    explicit AugmentedMCL(const TOptions& o) : m_options(o) {}

    /** Feeds log(w_avg) of one update; returns the injection probability p_inject. */
    double update(double logWAvg);
    /** Forgets the averages (after a re-initialization). */
    void reset();

    /** log(w_slow), -inf before the first update. */
    double logWSlow() const { return m_logSlow; }
    /** log(w_fast), -inf before the first update. */
    double logWFast() const { return m_logFast; }
    /** The rates. */
    const TOptions& options() const { return m_options; }

private:
    TOptions m_options;
    double m_logSlow = -std::numeric_limits<double>::infinity();
    double m_logFast = -std::numeric_limits<double>::infinity();
};

}  // namespace semloc

/* semloc — the detector's outages as a hidden two-state Markov process of the filter
 * (private). */
#pragma once

#include <semloc/filter/SensoryFrameLikelihood.h>

#include <cstddef>
#include <optional>

namespace semloc::detail
{
/** The outage mixture's log-weights at a silent frame: log pi and log(1 - pi). */
struct OutageMix
{
    double logOut = 0;
    double logOn = 0;
};

/** The probability that the semantic detector is out: it reports nothing of the map's objects
 *  (no object, no false positive), whatever is in view — a camera in turbid water, a stalled
 *  detector, a view blocked by something the map does not know.
 *
 *  The detector is on or out, a continuous-time Markov chain: it goes out at rate
 *  a = 1 / outage_every_s and comes back at rate b = 1 / outage_mean_s. A frame with a
 *  detection the map knows proves it on. A silent frame
 *  (SensoryFrameLikelihood::TOutageTerms::silent) is scored as the mixture
 *      p(z | x) = pi + (1 - pi) p_on(z | x),
 *  pi the probability of an outage carried to the frame's time, p_on the model's likelihood
 *  of an empty scan (no clutter, every object in view missed). The state is one for the
 *  filter (the detector is one): after the weighting, its posterior is the weighted mean over
 *  the particles of P(out | z, x_i). A long silence thus costs a pose that should see
 *  objects a bounded factor while pi grows, instead of (1 - P_D) per object and scan: the
 *  evidence of missed detections no longer piles up. */
class DetectorOutage
{
public:
    /** Forgets the state (the next frame starts from the chain's stationary probability). */
    void reset() { m_known = false; }

    /** True, with mix() set, when the frame of `terms` (present) is silent: the mixture of
     *  the last probability carried to the frame's time. A frame with a detection sets the
     *  probability to 0 and has no mixture (false). Throws for a frame without a timestamp. */
    bool predict(const SensoryFrameLikelihood::TOutageTerms& terms);
    /** The mixture of the last predict() that returned true. */
    const OutageMix* mix() const { return &m_mix; }

    /** In place for n particles: logLik[i] (containing the outage terms' sum outage[i]) gets
     *  the mixture instead of outage[i]; outage[i] becomes log P(out | z, x_i). */
    static void apply(const OutageMix& mix, double* logLik, double* outage, size_t n);

    /** The posterior from the n particles' updated log-weights and apply()'s outage[]. */
    void update(const double* logW, const double* outage, size_t n);

    /** The probability of an outage after the last frame (its prediction if that frame
     *  left no weight). */
    double probability() const { return m_p; }

private:
    bool m_known = false;
    double m_p = 0;
    OutageMix m_mix;
    mrpt::Clock::time_point m_t{};
};
}  // namespace semloc::detail

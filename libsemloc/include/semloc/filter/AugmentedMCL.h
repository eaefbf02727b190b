/* semloc — recovery from localization failures: augmented MCL's random particle injection. */
#pragma once

#include <cstddef>
#include <limits>

namespace semloc
{
/** When to inject random particles (see AugmentedMCL). */
enum class RecoveryTrigger
{
    /** Never. */
    Off,
    /** Augmented MCL's averages (Thrun): when w_fast falls below w_slow. */
    Amcl,
    /** Sustained evidence: when the particles explain the frames with detections worse than
     *  the map with no object in view, for long enough (a CUSUM test). */
    Evidence
};

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
 *  resampled particle's weight.
 *
 *  w_avg is a density of the frame's measurements: its scale changes with the number of
 *  detections, so the averages compare frames unlike each other and, on a map that is
 *  slightly wrong, fire for long stretches while nothing is lost. The evidence trigger
 *  compares each frame with the map's own reference instead, the likelihood with no object
 *  in view (every detection clutter): b_t = log w_avg - log p(z_t | no object), the frame's
 *  log Bayes factor (comparable across frames), and keeps Page's CUSUM of its shortfall,
 *
 *      S_t = max(0, S_{t-1} + min(evidence_margin - b_t, evidence_threshold / 2))
 *
 *  over the frames with detections (one frame alone cannot trigger), injecting inject_share
 *  of the particles at each frame while S_t >= evidence_threshold:
 *  after a kidnapping every frame's b_t is near or below 0 and S_t climbs at once; a region
 *  where the map is wrong lowers some frames' b_t while the others keep it down. */
class AugmentedMCL
{
public:
    /** When and how much to inject. Recovery is on with trigger Amcl and 0 < alpha_slow <
     *  alpha_fast <= 1, or with trigger Evidence. */
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

        /** Which test decides an injection. Amcl with both rates 0 is off too. */
        RecoveryTrigger trigger = RecoveryTrigger::Amcl;
        /** Evidence trigger: the log Bayes factor [nats] a frame with detections is
         *  expected to give at least when the particles are where the vehicle is (the
         *  CUSUM's drift). */
        double evidence_margin = 2;
        /** Evidence trigger: the shortfall [nats] accumulated over the frames with
         *  detections (each adds margin - its log Bayes factor, at most half this; the sum
         *  kept >= 0) from which particles are injected. */
        double evidence_threshold = 20;
        /** Evidence trigger: share in (0, 1] of the particles replaced at each frame while
         *  the shortfall is at or above the threshold. */
        double inject_share = 0.1;
        /** Where injected particles go. 0: into the cloud, replacing resampled particles
         *  (Thrun's). n > 0: into a challenger set apart from the cloud (one at a time,
         *  inject_share of the particles, or p_inject of them with the amcl trigger), moved and
         *  weighed as the cloud and resampled among themselves; the evidence of each weighted
         *  frame is summed for the cloud (L_M) and for the challengers (L_C), and the
         *  challengers join the cloud when their posterior odds injected_weight e^(L_C - L_M)
         *  reach 1, are dropped when they fall to injected_weight^2 or after n weighted
         *  frames. */
        std::size_t challenger_frames = 0;
        /** Sensor resetting while lost [m^2]: while the weighted particles' x-y variance
         *  (the trace of their x-y covariance) is above this, every weighed frame with a
         *  detection the map can place replaces inject_share of the resampled particles by
         *  recovery poses (from_detections of them from its detections) of a resampled
         *  particle's weight, when the trigger does not fire: the particles of a cloud spread
         *  this wide stand for a belief no denser where they are than where a detection
         *  puts a pose (a global start whose first detections were clutter, a look-alike
         *  place taken for the true one before the cloud closes in). Into the cloud, also
         *  with challenger_frames. 0: off. */
        double lost_var_xy_m2 = 0;

        /** True when recovery is on. */
        bool enabled() const
        {
            return trigger == RecoveryTrigger::Evidence ||
                   (trigger == RecoveryTrigger::Amcl && alpha_slow > 0 && alpha_fast > alpha_slow);
        }
    };

    /** Off. */
    AugmentedMCL() = default;
    /** With rates `o`. */
    explicit AugmentedMCL(const TOptions& o) : m_options(o) {}

    /** Amcl trigger: feeds log(w_avg) of one update; returns the injection probability
     *  p_inject (0 with another trigger). */
    double update(double logWAvg);
    /** Evidence trigger: feeds the log Bayes factor of one frame with detections,
     *  log(w_avg) - log p(z | no object in view) (SensoryFrameLikelihood::withoutObjects);
     *  returns the share of the particles to replace: inject_share while the shortfall
     *  S = max(0, S + min(evidence_margin - logBayesFactor, evidence_threshold / 2)) is at
     *  or above evidence_threshold, else 0 (0 with another trigger). */
    double updateEvidence(double logBayesFactor);
    /** Forgets the averages (after a re-initialization). */
    void reset();

    /** log(w_slow), -inf before the first update. */
    double logWSlow() const { return m_logSlow; }
    /** log(w_fast), -inf before the first update. */
    double logWFast() const { return m_logFast; }
    /** The evidence trigger's shortfall S [nats], 0 before the first frame. */
    double shortfall() const { return m_shortfall; }
    /** The options. */
    const TOptions& options() const { return m_options; }

private:
    TOptions m_options;
    double m_logSlow = -std::numeric_limits<double>::infinity();
    double m_logFast = -std::numeric_limits<double>::infinity();
    double m_shortfall = 0;
};

}  // namespace semloc

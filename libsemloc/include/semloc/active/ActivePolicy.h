/* semloc — active semantic localization: the motion that is expected to tell the particle
 * filter's hypotheses apart best (docs/design.md, "Active localization"). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFParticles.h>
#include <semloc/io/ConfigHelpers.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace semloc
{
class CSemanticMap;
class CObservationSemantic;
class ParallelExecutor;
class World;

/** A motion the policy can ask for: turn on the spot by `turn_rad`, then go `distance_m`
 *  straight ahead (0: a look-around, the turn alone). */
struct TActiveMotion
{
    /** Turn first [rad], in (-pi, pi]. */
    double turn_rad = 0;
    /** Then straight ahead [m], >= 0. */
    double distance_m = 0;
    /** The pose increment in the vehicle's frame: (d cos t, d sin t, t). */
    mrpt::poses::CPose2D increment() const;
};

/** True when the straight path of `m` from `from` (a turn alone always is) stays in the free
 *  space of `world`: its end is free (World::isFree) and no object touches it
 *  (World::firstObjectOnSegment). */
bool pathIsFree(const World& world, const mrpt::math::TPose2D& from, const TActiveMotion& m);

/** Active localization over a semantic map: the greedy one-step choice of the next motion
 *  that minimizes the expected entropy of the pose after it plus a travel cost,
 *
 *      u* = argmin_u  E_{z ~ p(z | x (+) u)} [ H(x | z, u) ] + c d(u),
 *
 *  the expectation over the detections z the vehicle would report after the motion u,
 *  "nothing detected" included; or (objective gain_per_metre) that removes the most entropy
 *  per metre of effort, u* = argmax_u (H(x) - E_z[H(x | z, u)]) / (d(u) + d0), d0 =
 *  `overhead_m`. Approximations (docs/design.md, "Active localization"):
 *  - the particles are summarised by at most `representatives` (K) poses: the weighted mean
 *    of each occupied bin of `bin_xy_m` x `bin_xy_m` x `bin_heading_deg`; with more than K
 *    bins, K of them by systematic sampling in proportion to their weight (each keeping
 *    the share of the K draws that fell on it), so that they spread over every hypothesis;
 *    H is the entropy of those weights;
 *  - each representative is moved by u without noise to the points of its path (one every
 *    `scan_every_m` and the end; a turn alone: one), and `outcomes` paths of scans are
 *    drawn there from the semantic map's own detector model (P_D by range and bearing times the
 *    object's p_exist, confusion, Poisson clutter, the range bias; exact ranges and
 *    bearings), with the same random numbers for every motion (common random numbers: the
 *    motions are compared on the same draws);
 *  - every representative is re-weighted by each drawn path of scans with the map's
 *    likelihood (the filter's own), H taken, and the expectation is the representatives'
 *    weighted mean.
 *  Cost per decision: for each admissible candidate, representatives^2 x outcomes x path
 *  points likelihood evaluations (TDecision::evaluations), against a filter step's one per
 *  particle (filterSteps(); the budget, kBudgetFilterSteps, is ten filter steps).
 *
 *  Candidates: `headings` turns evenly spaced over the circle (0 first) times each of
 *  `distances_m`, and with `look_around` each non-zero turn alone. A motion is a candidate
 *  only if, with a world, its straight path stays in the world's free space for
 *  representatives holding at least `min_free_share` of the weight (the look-arounds always
 *  do); with none admissible, see TDecision::motion. Stop rule: when the trace of the
 *  particles' x-y covariance is at most `converged_var_xy_m2`, decide() says so and
 *  evaluates nothing: the mission's route takes over.
 *
 *  Deterministic: decision k draws from a generator seeded by (seed, k), the candidates are
 *  evaluated independently (on `threads` threads) and ties go to the first one, so the
 *  choice is the same bits for any thread count. */
class ActivePolicy
{
public:
    /** What the choice minimizes: E[H] + travel_cost_per_m d ("entropy_plus_cost"), or
     *  minus the expected entropy drop per metre of effort, -(H - E[H]) / (d + overhead_m)
     *  ("gain_per_metre"). */
    enum class TObjective
    {
        EntropyPlusCost,
        GainPerMetre
    };

    /** Section [ActiveLocalization]. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Candidate turns, evenly over the circle, 1..kMaxHeadings. */
        int headings = 8;
        /** Candidate distances [m] (each > 0), 1..kMaxDistances of them. */
        std::vector<double> distances_m{6.0, 12.0};
        /** Also the turns on the spot (distance 0). */
        bool look_around = false;
        /** Most representatives of the particles, 1..kMaxRepresentatives. */
        int representatives = 24;
        /** Bin size of the representatives in x and y [m]. */
        double bin_xy_m = 1.0;
        /** Bin size of the representatives in heading [deg]. */
        double bin_heading_deg = 45.0;
        /** Scans drawn per representative and motion, 1..kMaxOutcomes. */
        int outcomes = 2;
        /** One predicted scan every this many metres along a path and one at its end [m]. */
        double scan_every_m = 2.0;
        /** What the choice minimizes (see the class documentation). */
        TObjective objective = TObjective::EntropyPlusCost;
        /** Travel cost [nats per metre] added to the expected entropy (entropy_plus_cost). */
        double travel_cost_per_m = 0.02;
        /** gain_per_metre: every motion counts this many metres more than its distance (a
         *  turn on the spot: this alone) [m]. */
        double overhead_m = 2.5;
        /** Share of the weight for which a motion must stay in the free space, in [0, 1]. */
        double min_free_share = 0.9;
        /** Stop rule: converged when the particles' x-y covariance trace is at most this
         *  [m^2] (the benchmark's convergence_max_var_xy_m2 by default). */
        double converged_var_xy_m2 = 1.0;
        /** Seed of the drawn scans. */
        uint32_t seed = 1;
        /** Threads over the candidates, 0..kMaxThreads; 0 = every hardware thread. */
        int threads = 1;

        static constexpr int kMaxHeadings = 360, kMaxDistances = 16, kMaxRepresentatives = 4096,
                             kMaxOutcomes = 64, kMaxThreads = 1024;
        /** The values loadFromConfigFile() accepts for the numeric key `key`. */
        static config::TValueRange range(const std::string& key);
        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** One candidate motion as evaluated. */
    struct TCandidate
    {
        TActiveMotion motion;
        /** Weight share of the representatives for which its path is free. */
        double free_share = 1;
        /** Whether it was evaluated (free_share >= min_free_share). */
        bool admissible = true;
        /** Likelihood evaluations of a pose against a drawn scan it takes: representatives^2 x
         *  outcomes x path points when admissible, else 0. */
        double evaluations = 0;
        /** E[H] after it [nats] (NaN when not admissible). */
        double expected_entropy = 0;
        /** What the objective minimizes: expected_entropy + travel_cost_per_m x distance, or
         *  -(entropy - expected_entropy) / (distance + overhead_m). */
        double score = 0;
    };

    /** What decide() found. */
    struct TDecision
    {
        /** The stop rule holds: hand back to the route (no motion chosen). */
        bool converged = false;
        /** The chosen motion; when nothing was admissible, the first turn on the spot (with
         *  look_around), else the first candidate (straight ahead, the shortest distance:
         *  the vehicle's own obstacle avoidance has the last word); zero when converged. */
        TActiveMotion motion;
        /** Trace of the particles' x-y covariance [m^2]. */
        double var_xy_m2 = 0;
        /** Representatives used. */
        size_t representatives = 0;
        /** Entropy of their weights now [nats]. */
        double entropy = 0;
        /** Every candidate, in order (empty when converged). */
        std::vector<TCandidate> candidates;
        /** Index of the chosen one in candidates (-1 when converged). */
        int chosen = -1;
        /** Likelihood evaluations the decision took: the sum of its candidates' (its cost; see
         *  filterSteps()). */
        double evaluations = 0;
    };

    /** The budget of a decision, in filter steps of the same particles (docs/active.md). */
    static constexpr double kBudgetFilterSteps = 10;
    /** A decision of `evaluations` likelihood evaluations in filter steps of `particles`
     *  particles: a filter step evaluates each particle's likelihood once, and the two
     *  evaluations cost about the same (bench_ActiveDecision: ~0.12 us each), so
     *  evaluations / particles (infinite without particles). Besides them a decision costs about
     *  two or three filter steps of 2 000 particles (the representatives, the free shares). */
    static double filterSteps(double evaluations, size_t particles);
    /** `observer(decision)` in every decide() that evaluates candidates, once their
     *  admissibility and TCandidate::evaluations are known and before any scan is drawn (only
     *  free_share, admissible and evaluations are set, and TDecision::evaluations, entropy and
     *  representatives): a costly decision can be told before it is made. None by default. */
    void setCostObserver(std::function<void(const TDecision&)> observer);

    /** A policy over `map` (kept by reference: it must outlive the policy), the free space
     *  of `world` if given (also kept), `options` validated. */
    ActivePolicy(const TOptions& options, const CSemanticMap& map, const World* world = nullptr);
    ~ActivePolicy();
    ActivePolicy(const ActivePolicy&) = delete;
    ActivePolicy& operator=(const ActivePolicy&) = delete;

    /** The next motion for the particles `pdf`, with the detector of `sensor` (its
     *  sensorPose, maxRange_m and fov_rad; its detections are not used). Decision k of this
     *  policy draws from (seed, k). */
    TDecision decide(const mrpt::poses::CPosePDFParticles& pdf, const CObservationSemantic& sensor);

    /** The candidate motions, in order. */
    std::vector<TActiveMotion> candidates() const;
    /** Decisions made so far. */
    uint64_t decisions() const { return m_decisions; }
    /** The options. */
    const TOptions& options() const { return m_options; }
    /** The ini name of an objective: "entropy_plus_cost" or "gain_per_metre". */
    static std::string objectiveName(TObjective o);

    /** A weighted pose standing for the particles of one bin. */
    struct TRepresentative
    {
        mrpt::math::TPose2D pose;
        double weight = 0;
    };
    /** The representatives of `pdf` (see the class documentation), heaviest first, weights
     *  summing to 1. */
    std::vector<TRepresentative> representatives(const mrpt::poses::CPosePDFParticles& pdf) const;

private:
    TOptions m_options;
    const CSemanticMap& m_map;
    const World* m_world;
    std::unique_ptr<ParallelExecutor> m_executor;
    uint64_t m_decisions = 0;
    std::function<void(const TDecision&)> m_costObserver;
};

}  // namespace semloc

/* semloc — a simulated vehicle driven by its own filter: the active policy, a random walk
 * (private; Benchmark's controls). */
#pragma once

#include <semloc/active/ActivePolicy.h>
#include <semloc/filter/Localizer.h>
#include <semloc/filter/StepRecord.h>
#include <semloc/simulator/Simulator.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace semloc::detail
{
/** Who drives the simulated vehicle. */
enum class Control
{
    /** The world's route (Simulator::run()). */
    Route,
    /** ActivePolicy until its stop rule holds, then back to the route. */
    Active,
    /** A random walk: each motion one of the policy's candidates drawn uniformly among those
     *  whose path is free from the true pose, until the same stop rule holds. */
    Random
};

/** "route", "active", "random". */
const std::vector<std::string>& controlNames();
/** The control named `name` (one of controlNames()). */
Control controlFromName(const std::string& name);

/** What a closed-loop run produced. */
struct TClosedLoopRun
{
    /** The simulated data (rawlog, ground truth) as driven. */
    SimulationResult data;
    /** One record per filter step, ground truth attached. */
    std::vector<TStepRecord> records;
    /** Decisions of the policy (Active) or motions drawn (Random). */
    size_t decisions = 0;
    /** The step at which the stop rule handed the vehicle back to the route; -1: never. */
    long handedBackAtStep = -1;
    /** Total wall time of the decisions [s]. */
    double decisionWall_s = 0;
    /** The policy's decisions in filter steps of the filter's particles
     *  (ActivePolicy::filterSteps of TDecision::evaluations; 0 for the random walk): their sum
     *  and the largest. */
    double decisionFilterSteps = 0, maxDecisionFilterSteps = 0;
    /** Decisions (or draws) at which no candidate motion that goes somewhere was free from
     *  the true pose (pathIsFree: every path leaves the free space or meets an object): the
     *  vehicle turned on the spot or stood instead. */
    size_t stuckDecisions = 0;
};

/** A note of a closed-loop run on what it costs or cannot do, once per run and kind: "cost",
 *  a decision over ten budgets (ActivePolicy::kBudgetFilterSteps: told before it is made);
 *  "stuck", a vehicle that could not move (at the end of the run). Decisions over the budget
 *  on average are judged over a series' runs, once they are all done (Benchmark::TResult::
 *  warnings). Each text names the [ActiveLocalization] keys that set it,
 *  with their values. */
using ClosedLoopNote = std::function<void(const std::string& kind, const std::string& text)>;

/** Simulates `simulator`'s scenario for its route's number of steps (Simulator::routeSteps)
 *  with the vehicle driven by `control` (Active or Random) while `loc` localizes it in
 *  `map` (the policy's map), one
 *  step at a time: a motion of the policy (turn, then straight ahead at the route's speed
 *  over as many steps as it takes) runs to its end unless the stop rule holds first (checked
 *  at every step: the particles' x-y variance at most policy.converged_var_xy_m2) or the
 *  vehicle is stopped by an obstacle. The vehicle's own obstacle avoidance (the simulated
 *  world, as a real vehicle's sonar) vetoes a motion whose path from the true pose hits
 *  something: the policy's best admissible candidate that is free is taken instead. Once
 *  handed back, the vehicle heads straight for the nearest point of the route it can reach
 *  in a straight line, follows the route to its end and then back along it to its start
 *  (at the route's start: the route itself). The policy (and the random walk's draws) is seeded
 * with `seed`. `note` (if any) is told of a decision over budget and of a vehicle that could
 * not move, once per run each (ClosedLoopNote). */
TClosedLoopRun runClosedLoop(const Simulator& simulator, Localizer& loc, const CSemanticMap& map,
                             Control control, const ActivePolicy::TOptions& policy, uint32_t seed,
                             const ClosedLoopNote& note = {});

/** The note of a decision of `filterSteps` filter steps of `particles` particles (of
 *  `evaluations` likelihood evaluations): the cost and the keys that set it. */
std::string costlyDecisionNote(const ActivePolicy::TOptions& policy, double filterSteps,
                               double evaluations, size_t particles);
/** The active policy's decisions of a series over its runs: how many, their cost in filter
 *  steps (the sum and the largest). */
struct TDecisionCost
{
    size_t runs = 0, decisions = 0;
    double filterSteps = 0, maxFilterSteps = 0;
};
/** The note of a series whose decisions (`cost`, of filters of `particles` particles) cost
 *  over the budget on average. */
std::string costlySeriesNote(const ActivePolicy::TOptions& policy, const TDecisionCost& cost,
                             size_t particles);
/** The note of a vehicle that found no free motion in `stuck` of its `decisions`. */
std::string stuckVehicleNote(const ActivePolicy::TOptions& policy, size_t stuck, size_t decisions);

/** The path of a vehicle handed back at `here`: straight to the nearest point of `world`'s
 *  route it can reach in a straight line (the first such leg on a tie), along the route to its
 *  end, then back along it to its start (the legs skipped by joining it are driven too). Empty
 *  when no point of the route can be reached in a straight line. */
std::vector<mrpt::math::TPoint2D> routeFrom(const World& world, const mrpt::math::TPoint2D& here);

/** Distance driven [m] along the records' ground truth up to and including step `step`
 *  (NaN when step < 0 or a record before it lacks ground truth). */
double distanceDriven(const std::vector<TStepRecord>& records, long step);
}  // namespace semloc::detail

/* semloc — the closed loop of Benchmark's controls: simulate a step, localize it, decide. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/geometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/TrajectoryFollower.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "experiment/ClosedLoop.h"

namespace semloc::detail
{
const std::vector<std::string>& controlNames()
{
    static const std::vector<std::string> names{"route", "active", "random"};
    return names;
}

Control controlFromName(const std::string& name)
{
    const auto& n = controlNames();
    const auto it = std::find(n.begin(), n.end(), name);
    ASSERTMSG_(it != n.end(), "unknown control '" + name + "'");
    return static_cast<Control>(it - n.begin());
}

double distanceDriven(const std::vector<TStepRecord>& records, long step)
{
    if (step < 0 || static_cast<size_t>(step) >= records.size())
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    double d = 0;
    for (size_t k = 1; k <= static_cast<size_t>(step); k++)
    {
        const auto& a = records[k - 1].gt;
        const auto& b = records[k].gt;
        if (!a || !b)
        {
            return std::numeric_limits<double>::quiet_NaN();
        }
        d += std::hypot(b->x - a->x, b->y - a->y);
    }
    return d;
}

std::vector<mrpt::math::TPoint2D> routeFrom(const World& world, const mrpt::math::TPoint2D& here)
{
    const auto& wps = world.trajectory->waypoints;
    size_t leg = wps.size();
    mrpt::math::TPoint2D join;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i + 1 < wps.size(); i++)
    {
        const auto q = mrpt::math::closestFromPointToSegment(here, wps[i], wps[i + 1]);
        const double d = std::hypot(q.x - here.x, q.y - here.y);
        if (d < best && world.firstObjectOnSegment(here, q) < 0)
        {
            best = d;
            leg = i;
            join = q;
        }
    }
    if (leg == wps.size())
    {
        return {};  // no part of the route in a straight line
    }
    std::vector<mrpt::math::TPoint2D> path{here};
    const auto add = [&](const mrpt::math::TPoint2D& p)
    {
        if (std::hypot(p.x - path.back().x, p.y - path.back().y) > 1e-9)
        {
            path.push_back(p);
        }
    };
    add(join);
    for (size_t i = leg + 1; i < wps.size(); i++)
    {
        add(wps[i]);
    }
    for (size_t i = wps.size() - 1; i-- > 0;)
    {
        add(wps[i]);  // then back along the route to its start, the legs skipped included
    }
    return path;
}

namespace
{
/** A decision over this many budgets is told before it is made, not at the run's end: the
 *  shipped active.ini's decisions reach 2.6 budgets, 4.6 with every candidate admissible. */
constexpr double kTellAtOnce = 10;

/** The motion under way: a turn still to make and a distance still to go. */
struct Plan
{
    double turn_rad = 0;
    double remaining_m = 0;
    bool turned = true;
    bool active() const { return !turned || remaining_m > 0; }
};

/** Simulator::Driver of a closed-loop run: feeds each simulated step to the filter, then
 *  says how the vehicle moves next. */
class LoopDriver
{
public:
    LoopDriver(const Simulator& sim, Localizer& loc, Control control,
               const ActivePolicy::TOptions& policy, const CSemanticMap& map, uint32_t seed,
               TClosedLoopRun& out, const ClosedLoopNote& note)
        : m_sim(sim),
          m_loc(loc),
          m_control(control),
          m_policyOptions(withSeed(policy, seed)),
          m_policy(m_policyOptions, map, &sim.world()),
          m_rng(seed),
          m_step(sim.stepLength_m()),
          m_out(out),
          m_note(note)
    {
        m_policy.setCostObserver([this](const ActivePolicy::TDecision& d) { costOf(d); });
    }

    mrpt::poses::CPose2D operator()(size_t k, const mrpt::math::TPose2D& pose,
                                    const SimulationResult& sofar)
    {
        feed(sofar, k - 1);
        if (m_expectMove && pose.x == m_lastPose.x && pose.y == m_lastPose.y)
        {
            m_plan = Plan();  // stopped by an obstacle: think again
        }
        m_lastPose = pose;
        if (m_out.handedBackAtStep < 0 && m_loc.varianceXY() <= m_policyOptions.converged_var_xy_m2)
        {
            handBack(k - 1, pose);  // the stop rule, checked at every step
        }
        if (m_out.handedBackAtStep >= 0)
        {
            return followRoute(pose);
        }
        if (!m_plan.active())
        {
            decide(k - 1, pose);
            if (m_out.handedBackAtStep >= 0)
            {
                return followRoute(pose);
            }
        }
        return planStep();
    }

    /** Feeds step `k` of `data` (its action and sensory frame) to the filter. */
    void feed(const SimulationResult& data, size_t k)
    {
        const auto action = data.rawlog.getAsAction(2 * k);
        const auto sf = data.rawlog.getAsObservations(2 * k + 1);
        m_loc.step(*action, *sf);
        TStepRecord s = m_loc.lastStepRecord(*sf);
        s.step = m_out.records.size();
        const auto& g = data.groundTruth[k];
        s.gt = mrpt::math::TPose2D(g.x, g.y, g.phi);
        m_out.records.push_back(s);
        m_lastFrame = sf;
    }

    /** The run's note at its end: a vehicle that could not move. (Decisions over the budget
     *  on average are judged over a series' runs: costlySeries.) */
    void finish() const
    {
        if (m_note && m_out.stuckDecisions > 0)
        {
            m_note("stuck",
                   stuckVehicleNote(m_policyOptions, m_out.stuckDecisions, m_out.decisions));
        }
    }

private:
    static ActivePolicy::TOptions withSeed(ActivePolicy::TOptions o, uint32_t seed)
    {
        o.seed = seed;
        return o;
    }

    /** The cost of a decision about to be made (ActivePolicy's cost observer). */
    void costOf(const ActivePolicy::TDecision& d)
    {
        const size_t particles = m_loc.pdf().size();
        const double steps = ActivePolicy::filterSteps(d.evaluations, particles);
        m_out.decisionFilterSteps += steps;
        m_out.maxDecisionFilterSteps = std::max(m_out.maxDecisionFilterSteps, steps);
        if (steps > kTellAtOnce * ActivePolicy::kBudgetFilterSteps && !m_toldCost && m_note)
        {
            m_toldCost = true;
            m_note("cost", costlyDecisionNote(m_policyOptions, steps, d.evaluations, particles));
        }
    }

    /** True when a candidate that goes somewhere is free from the true `pose`. */
    bool canMove(const mrpt::math::TPose2D& pose) const
    {
        const auto cs = m_policy.candidates();
        return std::any_of(cs.begin(), cs.end(),
                           [&](const TActiveMotion& m)
                           { return m.distance_m > 0 && freeFromHere(m, pose); });
    }

    void decide(size_t step, const mrpt::math::TPose2D& pose)
    {
        const auto t0 = std::chrono::steady_clock::now();
        TActiveMotion m;
        if (m_control == Control::Active)
        {
            const auto sensor = m_lastFrame->getObservationByClass<CObservationSemantic>();
            ASSERTMSG_(sensor, "closed loop: the simulated frame has no semantic observation");
            const auto d = m_policy.decide(m_loc.pdf(), *sensor);
            if (d.converged)
            {
                handBack(step, pose);
                return;
            }
            m = bestFreeMotion(d, pose);
        }
        else
        {
            m = randomFreeMotion(pose);
        }
        m_out.decisions++;
        m_out.stuckDecisions += canMove(pose) ? 0 : 1;
        m_out.decisionWall_s +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        m_plan = Plan{m.turn_rad, m.distance_m, false};
    }

    /** True when the vehicle at its true `pose` can make `m` without hitting anything: its
     *  own obstacle avoidance (a real vehicle's sonar), which vetoes the others. */
    bool freeFromHere(const TActiveMotion& m, const mrpt::math::TPose2D& pose) const
    {
        return pathIsFree(m_sim.world(), pose, m);
    }

    /** The policy's best admissible candidate the vehicle can make from where it is (the
     *  policy's choice unless the obstacle avoidance vetoes it); its first look-around if
     *  none. */
    TActiveMotion bestFreeMotion(const ActivePolicy::TDecision& d, const mrpt::math::TPose2D& pose)
    {
        const ActivePolicy::TCandidate* best = nullptr;
        for (const auto& c : d.candidates)
        {
            if (c.admissible && freeFromHere(c.motion, pose) && (!best || c.score < best->score))
            {
                best = &c;
            }
        }
        return best ? best->motion : d.motion;
    }

    /** One of the policy's candidates, uniformly among those free from the true pose. */
    TActiveMotion randomFreeMotion(const mrpt::math::TPose2D& pose)
    {
        std::vector<TActiveMotion> free;
        for (const auto& m : m_policy.candidates())
        {
            if (freeFromHere(m, pose))
            {
                free.push_back(m);
            }
        }
        if (free.empty())
        {
            return {M_PI / 2, 0.0};
        }
        std::uniform_int_distribution<size_t> pick(0, free.size() - 1);
        return free[pick(m_rng)];
    }

    mrpt::poses::CPose2D planStep()
    {
        const double go = std::min(m_step, m_plan.remaining_m);
        const double turn = m_plan.turned ? 0.0 : m_plan.turn_rad;
        m_plan.turned = true;
        m_plan.remaining_m -= go;
        m_expectMove = go > 0;
        return TActiveMotion{turn, go}.increment();
    }

    /** From now on, the route (routeFrom); the vehicle holds its place without one. */
    void handBack(size_t step, const mrpt::math::TPose2D& pose)
    {
        m_out.handedBackAtStep = static_cast<long>(step);
        const auto path = routeFrom(m_sim.world(), mrpt::math::TPoint2D(pose.x, pose.y));
        if (path.size() >= 2)
        {
            m_route = std::make_unique<TrajectoryFollower>(path, m_step);
        }
    }

    mrpt::poses::CPose2D followRoute(const mrpt::math::TPose2D& pose)
    {
        m_expectMove = false;
        if (!m_route || m_route->finished())
        {
            return {};  // the route is done (or out of reach): the vehicle holds its place
        }
        m_route->step();
        return mrpt::poses::CPose2D(m_route->pose()) - mrpt::poses::CPose2D(pose);
    }

    const Simulator& m_sim;
    Localizer& m_loc;
    Control m_control;
    ActivePolicy::TOptions m_policyOptions;
    ActivePolicy m_policy;
    std::mt19937_64 m_rng;
    double m_step;
    TClosedLoopRun& m_out;
    const ClosedLoopNote& m_note;
    bool m_toldCost = false;
    Plan m_plan;
    bool m_expectMove = false;
    mrpt::math::TPose2D m_lastPose;
    mrpt::obs::CSensoryFrame::Ptr m_lastFrame;
    std::unique_ptr<TrajectoryFollower> m_route;
};
}  // namespace

TClosedLoopRun runClosedLoop(const Simulator& simulator, Localizer& loc, const CSemanticMap& map,
                             Control control, const ActivePolicy::TOptions& policy, uint32_t seed,
                             const ClosedLoopNote& note)
{
    ASSERTMSG_(control != Control::Route,
               "runClosedLoop: the route needs no loop (Simulator::run)");
    TClosedLoopRun out;
    LoopDriver driver(simulator, loc, control, policy, map, seed, out, note);
    out.data = simulator.runDriven(
        [&](size_t k, const mrpt::math::TPose2D& pose, const SimulationResult& sofar)
        { return driver(k, pose, sofar); },
        simulator.routeSteps());
    driver.feed(out.data, out.data.steps - 1);  // the last step: no decision after it
    driver.finish();
    return out;
}

namespace
{
/** `v` as an ini list. */
std::string listText(const std::vector<double>& v)
{
    std::string s;
    for (const double x : v)
    {
        s += (s.empty() ? "" : ", ") + mrpt::format("%g", x);
    }
    return s;
}

/** The [ActiveLocalization] keys that set a decision's cost, with their values. */
std::string costKeys(const ActivePolicy::TOptions& o)
{
    return mrpt::format(
        "[ActiveLocalization] headings = %d, distances_m = %s, look_around = %s, representatives "
        "= %d, outcomes = %d, scan_every_m = %g",
        o.headings, listText(o.distances_m).c_str(), o.look_around ? "true" : "false",
        o.representatives, o.outcomes, o.scan_every_m);
}
}  // namespace

std::string costlyDecisionNote(const ActivePolicy::TOptions& o, double filterSteps,
                               double evaluations, size_t particles)
{
    return mrpt::format(
               "a decision of the active policy costs %.3g filter steps of %zu particles (%.3g "
               "likelihood evaluations: for each admissible candidate, representatives^2 x "
               "outcomes x "
               "path points), against a budget of %g a decision (docs/active.md), so the run will "
               "be "
               "slow: ",
               filterSteps, particles, evaluations, ActivePolicy::kBudgetFilterSteps) +
           costKeys(o);
}

std::string costlySeriesNote(const ActivePolicy::TOptions& o, const TDecisionCost& cost,
                             size_t particles)
{
    return mrpt::format(
               "the active policy's decisions cost %.3g filter steps of %zu particles on average "
               "over %zu decision(s) of %zu run(s) (the largest %.3g), over the budget of %g a "
               "decision (docs/active.md): ",
               cost.filterSteps / static_cast<double>(cost.decisions), particles, cost.decisions,
               cost.runs, cost.maxFilterSteps, ActivePolicy::kBudgetFilterSteps) +
           costKeys(o);
}

std::string stuckVehicleNote(const ActivePolicy::TOptions& o, size_t stuck, size_t decisions)
{
    return mrpt::format(
        "the vehicle could not move at %zu of its %zu decisions: no candidate motion's path from "
        "where it was stayed in the free space, so it turned on the spot or stood "
        "([ActiveLocalization] distances_m = %s, headings = %d)",
        stuck, decisions, listText(o.distances_m).c_str(), o.headings);
}
}  // namespace semloc::detail

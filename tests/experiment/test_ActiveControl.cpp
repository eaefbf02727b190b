/* Tests of the benchmark's controls: the simulated vehicle driven step by step (the world's
 * free space respected), the active policy and the random walk in closed loop with the filter,
 * the stop rule, determinism, and the results' control columns. */
#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"
#include "experiment/BenchmarkReport.h"
#include "experiment/BenchmarkTables.h"
#include "experiment/ClosedLoop.h"

namespace
{
const std::string kConfig = std::string(SEMLOC_SOURCE_DIR) + "/config/";
const std::string kOut = std::string(SEMLOC_TEST_OUT) + "/";

/** A benchmark of the semantic variant (or `variantIni`) on the paper's harbour with a
 *  detector of 8 m and 90 degrees, `steps` steps, `particles` particles, with `body`
 *  appended. */
std::string benchmarkIni(const std::string& name, const std::string& body,
                         const std::string& variantIni = kConfig + "localize/semantic.ini",
                         int steps = 60, int particles = 300)
{
    std::ofstream(kOut + name + "_scenario.ini")
        << "[Scenario]\nmap_from_world = true\n[SemanticDetector]\nmax_range_m = 8\nfov_deg = 90\n";
    std::string path = kOut + name + ".ini";
    std::ofstream(path) << "[Benchmark]\nsimulate_ini = " << kConfig
                        << "simulate/simulate.ini\nvariants = " << variantIni
                        << "\noutput_dir = " << kOut << name << "_out\nmax_steps = " << steps
                        << "\nparticles = " << particles << "\nscenarios = " << kOut << name
                        << "_scenario.ini\n"
                        << body;
    return path;
}

std::string errorOf(const std::string& path)
{
    try
    {
        (void)semloc::Benchmark::FromConfigFile(path);
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);
    }
    return {};
}
}  // namespace

TEST(ActiveControl, ADrivenVehicleStopsAtTheEdgeOfTheFreeSpace)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    const semloc::Simulator sim(o);
    // Straight east from the route's start (3, 4) at 1 m a step: the harbour ends at x = 50.
    const auto drive = [](size_t, const mrpt::math::TPose2D&, const semloc::SimulationResult&)
    { return mrpt::poses::CPose2D(1.0, 0.0, 0.0); };
    const auto a = sim.runDriven(drive, 60), b = sim.runDriven(drive, 60);
    ASSERT_EQ(a.steps, 60u);
    EXPECT_EQ(a.groundTruth.front().x, sim.routeStart().x);
    EXPECT_EQ(a.blockedSteps, 60u - 1 - 47u);  // 47 steps reach x = 50, the others are refused
    for (size_t k = 0; k < a.steps; k++)
    {
        EXPECT_TRUE(sim.world().isFree(a.groundTruth[k].x, a.groundTruth[k].y)) << k;
        EXPECT_EQ(a.groundTruth[k].x, b.groundTruth[k].x);  // the same seed, the same run
    }
    EXPECT_EQ(a.groundTruth.back().x, 50.0);
    EXPECT_EQ(sim.routeSteps(), sim.run().steps);
}

TEST(ActiveControl, AHandedBackVehicleDrivesTheWholeRouteNotJustItsRest)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    const semloc::Simulator sim(o);
    const auto& wps = sim.world().trajectory->waypoints;
    ASSERT_GE(wps.size(), 3u);
    // Handed back at the route's end: back along the route to its start, every waypoint.
    const auto back = semloc::detail::routeFrom(sim.world(), wps.back());
    ASSERT_EQ(back.size(), wps.size());
    for (size_t i = 0; i < wps.size(); i++)
    {
        EXPECT_EQ(back[i].x, wps[wps.size() - 1 - i].x) << i;
        EXPECT_EQ(back[i].y, wps[wps.size() - 1 - i].y) << i;
    }
    // At its start: the route, then back to the start.
    const auto whole = semloc::detail::routeFrom(sim.world(), wps.front());
    ASSERT_EQ(whole.size(), 2 * wps.size() - 1);
    for (size_t i = 0; i < wps.size(); i++)
    {
        EXPECT_EQ(whole[i].x, wps[i].x) << i;
        EXPECT_EQ(whole[whole.size() - 1 - i].x, wps[i].x) << i;
    }
}

TEST(ActiveControl, ARunThatStartsConvergedHandsBackAtOnceAndDrivesTheRoute)
{
    // The filter starts at the true pose (3, 4, 0), 0.1 m and 2 degrees wide.
    std::string text = semloc::test::resolvedIni(kConfig + "localize/semantic.ini");
    for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
             {"init_PDF_mode", "2"}, {"init_PDF_std_xy", "0.1"}, {"init_PDF_std_yaw_deg", "2"}})
    {
        const size_t at = text.find("\n" + key + " ");
        ASSERT_NE(at, std::string::npos) << key;
        const size_t end = text.find('\n', at + 1);
        std::string line = key;
        line += " = ";
        line += value;
        text.replace(at + 1, end - at - 1, line);
    }
    ASSERT_NE(text.find("\ninit_PDF_mean_x         = 3\n"), std::string::npos);
    ASSERT_NE(text.find("\ninit_PDF_mean_y         = 4\n"), std::string::npos);
    const std::string variant = kOut + "active_converged_variant.ini";
    std::ofstream(variant) << text;
    const auto b = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_converged", "controls = route, active\n", variant));
    const auto rs = b.scenarios().front().runOne(1);
    ASSERT_EQ(rs.size(), 2u);
    EXPECT_EQ(rs[0].control, "route");
    EXPECT_EQ(rs[1].control, "active");
    EXPECT_LT(rs[1].records.front().var_xy, 1.0);
    EXPECT_EQ(rs[1].decisions, 0u);  // no motion of its own: no detour
    ASSERT_EQ(rs[0].records.size(), rs[1].records.size());
    for (size_t k = 0; k < rs[0].records.size(); k++)
    {
        ASSERT_TRUE(rs[0].records[k].gt && rs[1].records[k].gt);
        EXPECT_NEAR(rs[0].records[k].gt->x, rs[1].records[k].gt->x, 1e-9) << k;
        EXPECT_NEAR(rs[0].records[k].gt->y, rs[1].records[k].gt->y, 1e-9) << k;
    }
}

TEST(ActiveControl, EveryControlRunsTheSameSeedsTheSameForOneAndTwoThreads)
{
    const std::string body = "controls = route, active, random\n";
    const auto one = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_threads1", body + "filter_threads = 1\n"));
    const auto two = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_threads2", body + "filter_threads = 2\n"));
    const auto a = one.scenarios().front().runOne(3), b = two.scenarios().front().runOne(3);
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 3u);
    for (size_t i = 0; i < a.size(); i++)
    {
        EXPECT_EQ(a[i].control, semloc::detail::controlNames()[i]);
        ASSERT_EQ(a[i].records.size(), 60u);
        ASSERT_EQ(b[i].records.size(), 60u);
        for (size_t k = 0; k < 60; k++)
        {
            EXPECT_EQ(a[i].records[k].est.x, b[i].records[k].est.x) << a[i].control << " " << k;
            EXPECT_EQ(a[i].records[k].gt->x, b[i].records[k].gt->x) << a[i].control << " " << k;
            EXPECT_EQ(a[i].records[k].gt->y, b[i].records[k].gt->y) << a[i].control << " " << k;
        }
    }
    // The policy and the walk decided; the walk left the route.
    EXPECT_GT(a[1].decisions, 0u);
    EXPECT_GT(a[2].decisions, 0u);
    double offRoute = 0;
    for (size_t k = 0; k < 60; k++)
    {
        const auto &r = *a[0].records[k].gt, &q = *a[2].records[k].gt;
        offRoute += std::hypot(q.x - r.x, q.y - r.y);
    }
    EXPECT_GT(offRoute, 1.0);
}

TEST(ActiveControl, ALostFilterKeepsTheTrueHarbourAmongItsHypotheses)
{
    // Seeds 6 and 35 of config/benchmark/active.ini's paper harbour: the first detections the
    // filter places are clutter. Not re-seeded from the detections while spread
    // (semantic_no_reseed.ini), its particles close in on the wrong places and stay there
    // along the whole route; as shipped (semantic.ini), it converges on the route's first
    // stretch.
    const auto shipped = semloc::Benchmark::FromConfigFile(benchmarkIni(
        "active_lost", "controls = route\n", kConfig + "localize/semantic.ini", 120, 2000));
    const auto without = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_no_reseed", "controls = route\n",
                     kConfig + "localize/semantic_no_reseed.ini", 120, 2000));
    for (const int seed : {6, 35})
    {
        const auto rs = shipped.scenarios().front().runOne(seed);
        ASSERT_EQ(rs.size(), 1u);
        EXPECT_TRUE(rs[0].metrics.converged) << "seed " << seed;
        EXPECT_LT(semloc::detail::distanceDriven(rs[0].records, rs[0].metrics.convergence_step),
                  40.0)
            << "seed " << seed;
        EXPECT_LT(rs[0].records.back().errXY(), 1.0) << "seed " << seed;
        const auto ws = without.scenarios().front().runOne(seed);
        ASSERT_EQ(ws.size(), 1u);
        EXPECT_GT(ws[0].records.back().errXY(), 1.0) << "seed " << seed;
    }
}

TEST(ActiveControl, ResultsNameTheControlAndTheDistanceToConvergence)
{
    semloc::Benchmark::TRunResult r;
    r.variant = "semantic";
    r.control = "active";
    r.distance_to_convergence_m = 12.5;
    EXPECT_EQ(r.series(), "semantic/active");
    const std::string csv = semloc::detail::resultsCsv({r});
    const std::string header = csv.substr(0, csv.find('\n'));
    const std::string tail = ",control,distance_to_convergence_m";
    EXPECT_EQ(header.substr(header.size() - tail.size()), tail) << header;
    EXPECT_NE(csv.find(",active,12.5\n"), std::string::npos) << csv;
    // Three records 1 m apart, converged at the last: 2 m driven.
    std::vector<semloc::TStepRecord> recs(3);
    for (size_t k = 0; k < 3; k++)
    {
        recs[k].gt = mrpt::math::TPose2D(static_cast<double>(k), 0, 0);
    }
    EXPECT_DOUBLE_EQ(semloc::detail::distanceDriven(recs, 2), 2.0);
    EXPECT_TRUE(std::isnan(semloc::detail::distanceDriven(recs, -1)));
}

TEST(ActiveControl, ControlsAreCheckedByName)
{
    EXPECT_NE(errorOf(benchmarkIni("active_bad1", "controls = route, activ\n"))
                  .find("[Benchmark] controls: 'activ' is not one of route, active, random"),
              std::string::npos);
    EXPECT_NE(errorOf(benchmarkIni("active_bad2", "controls = active, active\n"))
                  .find("'active' appears twice"),
              std::string::npos);
    EXPECT_NE(errorOf(benchmarkIni("active_bad3", "controls = active\n",
                                   kConfig + "localize/geometric.ini"))
                  .find("has no semantic map"),
              std::string::npos);
    EXPECT_NE(errorOf(benchmarkIni("active_bad4",
                                   "controls = active\n[ActiveLocalization]\n"
                                   "headings = 0\n"))
                  .find("[ActiveLocalization] headings"),
              std::string::npos);
}

namespace
{
/** The warnings told (Benchmark::SetWarningReporter) while `f` runs. */
template <typename F>
std::vector<std::string> warningsOf(F&& f)
{
    std::vector<std::string> told;
    semloc::Benchmark::SetWarningReporter([&](const std::string& w) { told.push_back(w); });
    f();
    semloc::Benchmark::SetWarningReporter({});
    return told;
}

/** config/benchmark/active.ini's [ActiveLocalization], with `outcomes` drawn scans. */
std::string shippedPolicy(int outcomes = 2)
{
    return "[ActiveLocalization]\nheadings = 8\ndistances_m = 6, 12\nlook_around = true\n"
           "representatives = 24\noutcomes = " +
           std::to_string(outcomes) + "\nobjective = gain_per_metre\noverhead_m = 2.5\n";
}
}  // namespace

TEST(ActiveControl, AVehicleThatCannotMoveIsToldOnceAtTheRunsEnd)
{
    // Every candidate 1 km straight ahead, no look-around: no path stays in the harbour, so
    // the policy and the walk turn on the spot or stand at every decision.
    const auto b = semloc::Benchmark::FromConfigFile(benchmarkIni(
        "active_stuck", "controls = active, random\n[ActiveLocalization]\ndistances_m = 1000\n",
        kConfig + "localize/semantic.ini", 30));
    std::vector<semloc::Benchmark::TRunResult> rs;
    const auto told = warningsOf([&] { rs = b.scenarios().front().runOne(1); });
    ASSERT_EQ(rs.size(), 2u);
    for (const auto& r : rs)
    {
        EXPECT_GT(r.decisions, 0u) << r.control;
        EXPECT_EQ(r.stuckDecisions, r.decisions) << r.control;
    }
    ASSERT_EQ(told.size(), 2u) << "one a run";
    EXPECT_NE(told[0].find("run 1, semantic/active: the vehicle could not move at " +
                           std::to_string(rs[0].decisions) + " of its " +
                           std::to_string(rs[0].decisions) + " decisions"),
              std::string::npos)
        << told[0];
    EXPECT_NE(told[0].find("[ActiveLocalization] distances_m = 1000, headings = 8"),
              std::string::npos)
        << told[0];
    EXPECT_NE(told[1].find("semantic/random: the vehicle could not move"), std::string::npos)
        << told[1];
    const std::string table = semloc::Benchmark::controlsTable(rs);
    EXPECT_NE(table.find("| 100 |\n"), std::string::npos) << table;
}

TEST(ActiveControl, ADecisionOverTenBudgetsIsToldBeforeItIsMadeOnceARun)
{
    // 64 drawn scans per representative instead of 2, 300 particles: a look-around alone
    // costs 24^2 x 64 / 300 = 123 filter steps.
    const auto b = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_costly", "controls = active\n" + shippedPolicy(64),
                     kConfig + "localize/semantic.ini", 20));
    std::vector<semloc::Benchmark::TRunResult> rs;
    const auto told = warningsOf([&] { rs = b.scenarios().front().runOne(1); });
    ASSERT_EQ(rs.size(), 1u);
    ASSERT_GT(rs[0].decisions, 1u);
    EXPECT_GT(rs[0].maxDecisionFilterSteps, 100.0);
    EXPECT_GE(rs[0].decisionFilterSteps, rs[0].maxDecisionFilterSteps);
    ASSERT_EQ(told.size(), 1u) << "once a run, not once a decision";
    EXPECT_NE(told[0].find("run 1, semantic/active: a decision of the active policy costs "),
              std::string::npos)
        << told[0];
    EXPECT_NE(told[0].find("filter steps of 300 particles"), std::string::npos) << told[0];
    EXPECT_NE(told[0].find("representatives = 24, outcomes = 64, scan_every_m = 2"),
              std::string::npos)
        << told[0];
    const std::string table = semloc::Benchmark::controlsTable(rs);
    const double mean = rs[0].decisionFilterSteps / static_cast<double>(rs[0].decisions);
    EXPECT_NE(table.find(mrpt::format("| %.1f | 0 |", mean)), std::string::npos) << table;
}

TEST(ActiveControl, DecisionsOverTheBudgetOnAverageAreJudgedOverTheSeriesRuns)
{
    // active.ini's policy with 500 particles instead of 2 000: its decisions cost four times
    // as many filter steps, over the budget of 10 on average but none over ten budgets. Not
    // told by the run; its series is over the budget on average, unless its other runs'
    // decisions bring the series' mean under it.
    const auto b = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_over", "controls = active\n" + shippedPolicy(),
                     kConfig + "localize/semantic.ini", 20, 500));
    std::vector<semloc::Benchmark::TRunResult> rs;
    const auto told = warningsOf([&] { rs = b.scenarios().front().runOne(1); });
    ASSERT_EQ(rs.size(), 1u);
    ASSERT_GT(rs[0].decisions, 0u);
    const double mean = rs[0].decisionFilterSteps / static_cast<double>(rs[0].decisions);
    ASSERT_GT(mean, 10.0);
    ASSERT_LT(rs[0].maxDecisionFilterSteps, 100.0);
    EXPECT_TRUE(told.empty()) << told.front();
    const auto& policy = b.options().active;
    const auto notes = semloc::detail::costlySeries(rs, policy);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0].series, "semantic/active");
    EXPECT_NE(notes[0].text.find(mrpt::format(
                  "decisions cost %.3g filter steps of 500 particles on average over %zu "
                  "decision(s) of 1 run(s) (the largest %.3g)",
                  mean, rs[0].decisions, rs[0].maxDecisionFilterSteps)),
              std::string::npos)
        << notes[0].text;
    EXPECT_NE(notes[0].text.find("representatives = 24, outcomes = 2"), std::string::npos)
        << notes[0].text;
    // A second run of the series with many cheap decisions: the series' mean is under the
    // budget, nothing to say.
    auto cheap = rs[0];
    cheap.decisions = 20 * rs[0].decisions;
    cheap.decisionFilterSteps = static_cast<double>(cheap.decisions);
    rs.push_back(cheap);
    EXPECT_TRUE(semloc::detail::costlySeries(rs, policy).empty());
    // Another series (the random walk) is never judged on cost.
    rs.pop_back();
    rs[0].control = "random";
    EXPECT_TRUE(semloc::detail::costlySeries(rs, policy).empty());
}

TEST(ActiveControl, TheShippedPolicyStaysWithinItsBudgetAndMoves)
{
    // config/benchmark/active.ini's policy and particles on the paper's harbour: nothing told.
    const auto b = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_shipped", "controls = active, random\n" + shippedPolicy(),
                     kConfig + "localize/semantic.ini", 60, 2000));
    std::vector<semloc::Benchmark::TRunResult> rs;
    const auto told = warningsOf([&] { rs = b.scenarios().front().runOne(1); });
    ASSERT_EQ(rs.size(), 2u);
    EXPECT_GT(rs[0].decisions, 0u);
    EXPECT_LE(rs[0].decisionFilterSteps / static_cast<double>(rs[0].decisions), 10.0);
    EXPECT_EQ(rs[0].stuckDecisions, 0u);
    EXPECT_EQ(rs[1].stuckDecisions, 0u);
    EXPECT_TRUE(told.empty()) << told.front();
}

TEST(ActiveControl, TheBenchmarkTellsEachKindOnceWhileItRunsAndReportsEveryRun)
{
    // Two runs in child processes, each of whose vehicles cannot move: one warning on stderr's
    // reporter, as soon as the first run ends; report.md counts both runs of both controls.
    const auto b = semloc::Benchmark::FromConfigFile(
        benchmarkIni("active_stuck_bench",
                     "runs = 2\njobs = 2\ncontrols = active, random\n[ActiveLocalization]\n"
                     "distances_m = 1000\n",
                     kConfig + "localize/semantic.ini", 20));
    std::filesystem::remove_all(kOut + "active_stuck_bench_out");
    std::vector<size_t> runsDoneWhenTold;
    size_t runsDone = 0;
    std::vector<std::string> told;
    semloc::Benchmark::SetWarningReporter(
        [&](const std::string& w)
        {
            told.push_back(w);
            runsDoneWhenTold.push_back(runsDone);
        });
    const auto res = b.run([&](size_t done, size_t) { runsDone = done; });
    semloc::Benchmark::SetWarningReporter({});
    ASSERT_EQ(told.size(), 1u) << "once per benchmark and kind";
    EXPECT_NE(told[0].find("the vehicle could not move at"), std::string::npos) << told[0];
    EXPECT_EQ(runsDoneWhenTold[0], 0u) << "told as the first run ended, before it was counted";
    const std::string report = semloc::test::readText(
        res.outputDir + "/" + b.scenarios().front().scenario().name + "/report.md");
    for (const char* series : {"semantic/active", "semantic/random"})
    {
        EXPECT_NE(report.find(std::string("`: the vehicle could not move at ")), std::string::npos)
            << report;
        EXPECT_NE(report.find(std::string(series) + "`: the vehicle could not move at"),
                  std::string::npos)
            << series << "\n"
            << report;
    }
    EXPECT_NE(report.find("decisions, in 2 of 2 runs"), std::string::npos) << report;
}

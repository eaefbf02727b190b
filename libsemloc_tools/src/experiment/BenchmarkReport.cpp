/* semloc — Benchmark's report: report.md, the paper's Table I beside ours, the figures. */
#include "experiment/BenchmarkReport.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/plot/WorldPlot.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <sstream>
#include <system_error>

#include "experiment/BenchmarkTables.h"
#include "experiment/ClosedLoop.h"
#include "experiment/RunFigures.h"
#include "experiment/Statistics.h"
#include "io/TextFiles.h"
#include "plot/Gnuplot.h"

namespace semloc::detail
{
std::vector<TSeriesNote> costlySeries(const std::vector<Benchmark::TRunResult>& runs,
                                      const ActivePolicy::TOptions& policy)
{
    struct TSeries
    {
        TSeriesNote note;
        TDecisionCost cost;
        size_t particles = 0;
    };
    std::vector<TSeries> series;
    for (const auto& r : runs)
    {
        if (r.control != "active" || r.decisions == 0)
        {
            continue;
        }
        auto it =
            std::find_if(series.begin(), series.end(),
                         [&](const TSeries& s)
                         { return s.note.scenario == r.scenario && s.note.series == r.series(); });
        if (it == series.end())
        {
            it = series.insert(series.end(), {{r.scenario, r.series(), {}}, {}, r.particles});
        }
        auto& c = it->cost;
        c.runs++;
        c.decisions += r.decisions;
        c.filterSteps += r.decisionFilterSteps;
        c.maxFilterSteps = std::max(c.maxFilterSteps, r.maxDecisionFilterSteps);
    }
    std::vector<TSeriesNote> out;
    for (auto& s : series)
    {
        if (s.cost.filterSteps / static_cast<double>(s.cost.decisions) >
            ActivePolicy::kBudgetFilterSteps)
        {
            s.note.text = costlySeriesNote(policy, s.cost, s.particles);
            out.push_back(std::move(s.note));
        }
    }
    return out;
}

namespace
{
/** Most series a figure draws: world_paths.png's panels (3 x 3), the curves of fig_*.png. */
constexpr size_t kMaxFigureSeries = 9;

// The paper's Table I: average execution time of one run [ns].
constexpr double kPaperSemanticNs = 1171934146.0;
constexpr double kPaperGeometricNs = 6977878010.0;

/** `path` as report.md shows it: from the working directory when it lies under it (a report
 *  made in a clone names config/simulate/simulate.ini, not the machine's layout), else as
 *  given. */
std::string shownPath(const std::string& path)
{
    std::error_code ec;
    const std::filesystem::path cwd = std::filesystem::current_path(ec);
    const std::filesystem::path p(path);
    if (ec || !p.is_absolute())
    {
        return path;
    }
    const auto rel = p.lexically_proximate(cwd);
    return rel.empty() || rel.is_absolute() || *rel.begin() == ".." ? path : rel.string();
}

/** The series the figures draw, as indices into the `n` series: every one up to
 *  kMaxFigureSeries, else kMaxFigureSeries of them evenly spread, the first and the last among
 *  them (a sweep's ends and its middle); the tables have every series. */
std::vector<size_t> figureSeries(size_t n)
{
    std::vector<size_t> k;
    const size_t most = std::min(n, kMaxFigureSeries);
    for (size_t i = 0; i < most; i++)
    {
        k.push_back(most < 2 ? i : (i * (n - 1) + (most - 1) / 2) / (most - 1));
    }
    return k;
}

/** "" when the figures draw every one of `n` series, else what they draw. */
std::string figureSeriesNote(size_t n)
{
    if (n <= kMaxFigureSeries)
    {
        return {};
    }
    return mrpt::format(
        " (%zu of the %zu series, evenly spread over them from the first to the "
        "last; the tables above have every one)",
        kMaxFigureSeries, n);
}

/** What the NEES columns of the tables are (docs/design.md, "Consistency"). */
std::string neesText()
{
    return mrpt::format(
        "Median NEES is the median over the runs of a run's median normalized estimation error "
        "squared of the pose (e' P⁻¹ e over its steps with ground truth, e the error of (x, y, "
        "φ), P the particles' covariance): about %.2f, the χ² median with 3 degrees of freedom, "
        "for a consistent filter; NEES inside 95 %% is the mean share of those steps whose NEES "
        "is at most %.2f, the χ² 95 %% quantile (a one-sided bound): about 95 %% for a "
        "consistent filter, less for an overconfident one. The mean NEES (about 3 for a "
        "consistent filter) is over the well-conditioned steps only, the mean over the runs of "
        "a run's mean over them: steps whose P rests on at least %.0f effective particles (ESS "
        "× particles), its condition number at most 10⁹ and its eigenvalues at least 10⁻⁹; "
        "the next column is their share of the steps. A degenerate P (a cloud collapsed on a "
        "few particles) gives a NEES up to 10¹² times the squared error, which alone would set "
        "a mean over every step.",
        RunMetrics::kNeesChi2Median, RunMetrics::kNeesChi2_95,
        TStepRecord::kNeesMinEffectiveParticles);
}
static_assert(TStepRecord::kNeesMaxCondition == 1e9 && TStepRecord::kNeesMinEigenvalue == 1e-9,
              "neesText() says 10⁹ and 10⁻⁹");

/** Every value of `field` over every step of every run. */
template <typename Field>
std::vector<double> stepValues(const std::vector<Benchmark::TRunResult>& runs, Field field)
{
    std::vector<double> v;
    for (const auto& r : runs)
    {
        for (const auto& s : r.records)
        {
            v.push_back(field(s));
        }
    }
    return v;
}

std::string figuresScript(const std::vector<std::string>& allVariants,
                          const std::vector<Benchmark::TRunResult>& runs)
{
    std::vector<std::string> variants;
    for (const size_t k : figureSeries(allVariants.size()))
    {
        variants.push_back(allVariants[k]);
    }
    // Fig. 3 of the paper: average particle variance and average error over time, on a log
    // axis unless nothing is positive (one particle: no variance).
    std::ostringstream g;
    g << "# semloc-benchmark: the paper's Fig. 3 from curves.csv (gnuplot figures.gp; gnuplot -e\n"
      << "# \"figure='fig_error.png'\" figures.gp draws only that one)\n"
      << figureSelector() << "set datafile separator ','\n"
      << "set terminal pngcairo size 1000,600 noenhanced\n"
      << "set key outside right top\nset grid\nset xlabel 'time [s]'\n";
    auto plot = [&](const std::string& png, const std::string& ylabel, int col,
                    const std::vector<double>& values)
    {
        std::ostringstream b;
        b << axisY(values, true, "no data") << "set output '" << png << "'\nset ylabel '" << ylabel
          << "'\nplot ";
        for (size_t i = 0; i < variants.size(); i++)
        {
            b << (i ? ", \\\n     " : "") << "'curves.csv' skip 1 using 3:(strcol(1) eq '"
              << variants[i] << "' ? $" << col << " : 1/0) with lines lw 2 title '" << variants[i]
              << "'";
        }
        b << "\nunset output\n" << unsetAxisY();
        g << figureBlock(png, b.str());
    };
    plot("fig_variance.png", "mean particle variance var_xy [m^2]", 9,
         stepValues(runs, [](const TStepRecord& s) { return s.var_xy; }));
    plot("fig_error.png", "mean position error err_xy [m]", 5,
         stepValues(runs, [](const TStepRecord& s) { return s.errXY(); }));
    return g.str();
}

std::string paperTable(const std::vector<Benchmark::TRunResult>& runs)
{
    auto st = variantStatistics(runs);
    std::ostringstream o;
    o << "| variant | paper: mean execution time [ns] | ours: mean wall time per run [ns] | "
         "ours: mean filter time per run [ns] |\n|---|---:|---:|---:|\n";
    for (const std::string v : {"semantic", "geometric"})
    {
        const double paper = v == "semantic" ? kPaperSemanticNs : kPaperGeometricNs;
        const bool have = st.count(v) > 0;
        o << "| " << v << " | " << mrpt::format("%.0f", paper) << " | "
          << (have ? mrpt::format("%.0f", mean(st[v].wall) * 1e9) : "-") << " | "
          << (have ? mrpt::format("%.0f", mean(st[v].filter) * 1e9) : "-") << " |\n";
    }
    const bool both = st.count("semantic") && st.count("geometric");
    o << "| geometric / semantic | " << mrpt::format("%.2f", kPaperGeometricNs / kPaperSemanticNs)
      << " | "
      << (both ? mrpt::format("%.2f", mean(st["geometric"].wall) / mean(st["semantic"].wall)) : "-")
      << " | "
      << (both ? mrpt::format("%.2f", mean(st["geometric"].filter) / mean(st["semantic"].filter))
               : "-")
      << " |\n";
    return o.str();
}

/** world_paths.gp and its data: one panel per variant, the world, run 1's true path and the
 *  variant's estimate coloured by its error, where it converged; drawn as world_paths.png. */
std::vector<TFigureWarning> drawWorldPaths(const StagedDirectory& out,
                                           const TSimulatorOptions& simulation,
                                           const std::vector<Benchmark::TRunResult>& runs)
{
    const Simulator simulator(simulation);
    const World& world = simulator.world();
    std::vector<const Benchmark::TRunResult*> all1, run1;
    for (const auto& r : runs)
    {
        if (r.run == 1)
        {
            all1.push_back(&r);
        }
    }
    for (const size_t k : figureSeries(all1.size()))
    {
        run1.push_back(all1[k]);
    }
    const size_t n = std::max<size_t>(run1.size(), 1), cols = std::min<size_t>(n, 3);
    const size_t rows = (n + cols - 1) / cols;
    const auto& b = world.bounds;
    const double aspect = std::clamp((b.y_max - b.y_min) / (b.x_max - b.x_min), 0.3, 3.0);
    const int panelW = 600, panelH = static_cast<int>(panelW * aspect) + 130;
    writeFile(out.path("world_paths_world.dat"), WorldPlot(world).data());
    std::ostringstream g;
    g << "set terminal pngcairo size " << cols * panelW << "," << rows * panelH
      << " enhanced font 'Sans,9'\nset output 'world_paths.png'\nset multiplot layout " << rows
      << "," << cols << "\n";
    for (size_t k = 0; k < run1.size(); k++)
    {
        const auto& r = *run1[k];
        const std::string data = "world_paths_" + std::to_string(k + 1) + ".dat";
        writeFile(out.path(data), trackData(r.records));
        const bool conv = r.metrics.converged;
        WorldPlot panel(
            world, r.series() + ", run 1: " +
                       (conv ? "converged at step " + std::to_string(r.metrics.convergence_step)
                             : std::string("did not converge")));
        g << panel.settings() << errorPalette() << "plot "
          << panel.worldLayers("world_paths_world.dat")
          << trackLayers(data, true, conv ? r.metrics.convergence_step : -1) << "\nunset label\n";
    }
    g << "unset multiplot\nunset output\n";
    writeFile(out.path("world_paths.gp"),
              "# semloc-benchmark: run 1 of each variant over the world" +
                  figureSeriesNote(all1.size()) + " (gnuplot world_paths.gp)\n" + figureSelector() +
                  figureBlock("world_paths.png", g.str()));
    return drawFigures(out, "world_paths.gp", {"world_paths.png"});
}

/** report.md's lines on the map: the one every variant localizes against, and each one
 *  that differs from the simulated world. */
std::string mapLines(const Benchmark& b)
{
    std::ostringstream md;
    md << "- map: "
       << (b.mapFromWorld()
               ? "the simulated world `" + shownPath(b.simulation().simulation.world_file) +
                     "` for every variant (map_from_world = true)"
               : std::string("each variant's own map_file (map_from_world = false)"))
       << "\n";
    for (const auto& w : b.mapWarnings())
    {
        md << "- **warning: the map differs from the simulated world**: " << w << "\n";
    }
    return md.str();
}

/** report.md's title and "the experiment": scenario, runs, steps, particles, threads. */
std::string experimentSection(const Benchmark& b, const Benchmark::TResult& res, size_t jobs)
{
    const auto& o = b.options();
    const auto& sc = b.scenario();
    const auto& first = b.variants().front().options.filter;
    std::ostringstream md;
    md << "# semloc-benchmark report\n\n";
    if (!sc.name.empty())
    {
        md << "Scenario **" << sc.name << "**: " << sc.description << "\n\n";
    }
    md << "The experiment of the paper (§IV): " << o.runs
       << " runs; run i simulates the scenario of `" << shownPath(o.simulate_ini)
       << "` with seed i and localizes it with every variant (filter seeded with i).\n\n"
       << "- steps per run: " << res.runs.front().metrics.steps
       << "\n- particles: " << first.particles_count
       << (o.same_filter ? " (every variant runs the same filter: particles, PF_options, "
                           "KLD_options, initial distribution, convergence criterion of `" +
                               b.variants().front().name() + "`)"
                         : " (each variant's own filter)")
       << "\n- filter threads: " << o.filter_threads << ", parallel runs: " << jobs
       << "\n- total wall time: " << mrpt::format("%.1f", res.wallTime_s) << " s\n"
       << mapLines(b) << "\n";
    return md.str();
}

/** report.md's warnings on the controls: the series whose decisions cost more than the
 *  budget on average over their runs (costlySeries), and per series the runs in which the
 *  vehicle could not move. */
std::string controlWarnings(const std::vector<Benchmark::TRunResult>& runs,
                            const ActivePolicy::TOptions& policy)
{
    std::ostringstream md;
    for (const auto& c : costlySeries(runs, policy))
    {
        md << "- **warning**: `" << (c.scenario.empty() ? "" : c.scenario + ", ") << c.series
           << "`: " << c.text << "\n";
    }
    std::vector<std::string> order;
    std::map<std::string, std::array<size_t, 4>> n;  // runs, stuck runs, stuck, decisions
    for (const auto& r : runs)
    {
        if (r.decisions == 0)
        {
            continue;
        }
        const std::string key = (r.scenario.empty() ? "" : r.scenario + ", ") + r.series();
        if (n.count(key) == 0)
        {
            order.push_back(key);
        }
        auto& c = n[key];
        c[0]++;
        c[1] += r.stuckDecisions > 0 ? 1 : 0;
        c[2] += r.stuckDecisions;
        c[3] += r.decisions;
    }
    for (const auto& key : order)
    {
        const auto& c = n[key];
        if (c[1] > 0)
        {
            md << mrpt::format(
                "- **warning**: `%s`: the vehicle could not move at %zu of %zu decisions, in %zu "
                "of %zu runs (every candidate path left the free space: [ActiveLocalization] "
                "distances_m, headings)\n",
                key.c_str(), c[2], c[3], c[1], c[0]);
        }
    }
    const std::string text = md.str();
    return text.empty() ? text : "\n" + text;
}

/** report.md's "Controls" (Benchmark::controlsTable()); empty when the route alone drove.
 *  `series`: how many world_paths.png has to show. */
std::string controlsSection(const Benchmark::TOptions& o,
                            const std::vector<Benchmark::TRunResult>& runs, size_t series)
{
    if (o.controls.size() == 1 && o.controls.front() == "route")
    {
        return {};
    }
    const auto& a = o.active;
    std::ostringstream md;
    md << "\n## Controls\n\n"
       << "Every run was driven by each control from the same start with the same seeds: "
          "`route` (the world's trajectory), `active` (the active policy of "
          "[ActiveLocalization] until the particles' x-y variance is at most "
       << a.converged_var_xy_m2
       << " m², then back to the route), `random` (a random walk over the same candidate "
          "motions, free from the true pose, until the same stop rule). The distance is the "
          "length of the true path up to the convergence step; `world_paths.png` shows run 1 "
          "of each"
       << figureSeriesNote(series)
       << ". A decision's cost is its likelihood evaluations (for each admissible candidate, "
          "representatives² × outcomes × path points) over the particles, those of a filter "
          "step; the budget is "
       << ActivePolicy::kBudgetFilterSteps
       << " (docs/active.md). A decision could not move when no candidate motion that goes "
          "somewhere was free from the true pose.\n\n"
       << Benchmark::controlsTable(runs) << controlWarnings(runs, o.active);
    return md.str();
}

/** report.md's "Results": the success criterion and reportTable(). */
std::string resultsSection(const Benchmark& b, const Benchmark::TResult& res)
{
    const auto& crit = b.variants().front().options.convergence;
    const std::vector<std::string> names = b.seriesNames();
    std::ostringstream md;
    md << "## Results\n\n"
       << "Success: converged (err_xy < " << crit.max_err_xy_m << " m and var_xy < "
       << crit.max_var_xy_m2 << " m² held for the rest of the run or " << crit.min_steps
       << " consecutive steps). Times to convergence and errors after convergence are means "
          "over the converged runs; variance is the mean var_xy over every step of every "
          "run. "
       << neesText()
       << " Filter time is the sum of the filter updates (update_us); wall time adds "
          "building the filter and reading the results. The ratio is the filter time over "
          "`"
       << referenceVariant(names) << "`'s.\n\n"
       << res.table;
    if (const std::string paired = Benchmark::pairedTable(res.runs, names); !paired.empty())
    {
        const std::string ref = referenceVariant(names);
        md << "\n## Paired against `" << ref << "`\n\n"
           << "Every variant ran the same simulated runs as `" << ref
           << "`, so their errors compare run by run: the difference of the mean error after "
              "convergence (the variant's minus `"
           << ref
           << "`'s) over the runs both converged, its mean and the standard error of that "
              "mean (a difference within about two standard errors of 0 is not one these runs "
              "can tell), the runs where the variant's error was the lower, and the runs only "
              "one of the two converged.\n\n"
           << paired;
    }
    md << controlsSection(b.options(), res.runs, names.size());
    return md.str();
}

}  // namespace

std::vector<TFigureWarning> writeFigures(const StagedDirectory& out,
                                         const std::vector<std::string>& variants,
                                         const TSimulatorOptions& simulation,
                                         const std::vector<Benchmark::TRunResult>& runs,
                                         const std::string& stagePrefix)
{
    reportStage(stagePrefix + "drawing fig_variance.png and fig_error.png");
    writeFile(out.path("figures.gp"), figuresScript(variants, runs));
    auto warnings = drawFigures(out, "figures.gp", {"fig_variance.png", "fig_error.png"});
    reportStage(stagePrefix + "drawing world_paths.png");
    for (auto& w : drawWorldPaths(out, simulation, runs))
    {
        warnings.push_back(std::move(w));
    }
    return warnings;
}

std::string reportMarkdown(const Benchmark& b, const Benchmark::TResult& res, size_t jobs,
                           long kidnapStep)
{
    std::ostringstream md;
    md << experimentSection(b, res, jobs) << resultsSection(b, res);
    if (!b.scenario().name.empty() || kidnapStep >= 0)
    {
        md << "\n## Success and recovery\n\n"
           << "Success: converged; with a kidnapping, re-converged (the criterion above, "
              "from the kidnap step on) within "
           << b.scenario().recovery_max_steps << " steps of it.\n\n"
           << Benchmark::scenariosTable(res.summaries);
    }
    md << "\n## Table I of the paper beside ours\n\n"
       << "The paper reports the average execution time of a run: semantic "
          "1171934146 ns, geometric 6977878010 ns (about 6x). Ours were measured on this "
          "machine with the run length and particle count above, so only the ratios "
          "compare.\n\n"
       << paperTable(res.runs) << "\n## Figures\n\n"
       << "- `fig_variance.png`, `fig_error.png`: mean particle variance and mean error "
          "over time per variant"
       << figureSeriesNote(b.seriesNames().size())
       << " (the paper's Fig. 3; data in `curves.csv`, script `figures.gp`)\n"
       << "- `world_paths.png`: the world, run 1's true path and each variant's estimate (one "
          "panel per variant and control"
       << figureSeriesNote(b.seriesNames().size()) << ")\n"
       << figureWarningsMarkdown(res.figureWarnings);
    return md.str();
}

namespace
{
/** The most series of any of the scenarios. */
size_t mostSeries(const std::vector<Benchmark>& scenarios)
{
    size_t n = 0;
    for (const auto& sc : scenarios)
    {
        n = std::max(n, sc.seriesNames().size());
    }
    return n;
}
}  // namespace

std::string scenariosReportMarkdown(const Benchmark& b, const Benchmark::TResult& res)
{
    const auto& scenarios = b.scenarios();
    const auto& crit = scenarios.front().variants().front().options.convergence;
    std::ostringstream md;
    md << "# semloc-benchmark report: scenarios\n\n"
       << b.options().runs << " runs per scenario; run i simulates the scenario with seed i and "
       << "localizes it with the scenario's variants (filter seeded with i); "
       << scenarios.front().variants().front().options.filter.particles_count
       << " particles; total wall time " << mrpt::format("%.1f", res.wallTime_s) << " s.\n\n"
       << "Success: converged (err_xy < " << crit.max_err_xy_m << " m and var_xy < "
       << crit.max_var_xy_m2 << " m² held for the rest of the run or " << crit.min_steps
       << " consecutive steps); with a kidnapping, the same criterion met again from the kidnap "
          "step on within the scenario's bound (recovery steps = first such step - kidnap "
          "step). "
       << neesText() << "\n\n"
       << res.table << controlsSection(b.options(), res.runs, mostSeries(scenarios));
    if (!b.mapWarnings().empty())
    {
        md << "\n## Maps\n\n";
        for (const auto& w : b.mapWarnings())
        {
            md << "- **warning: the map differs from the simulated world**: " << w << "\n";
        }
    }
    md << "\n## Scenarios\n\n";
    for (size_t i = 0; i < scenarios.size(); i++)
    {
        const auto& sc = scenarios[i];
        const std::string& name = sc.scenario().name;
        md << "- [" << name << "](" << name << "/report.md): " << sc.scenario().description << " (`"
           << shownPath(sc.options().simulate_ini) << "` + `" << b.options().scenarios[i] << "`)\n";
    }
    md << figureWarningsMarkdown(res.figureWarnings);
    return md.str();
}

}  // namespace semloc::detail

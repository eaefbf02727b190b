/* semloc — Benchmark's report: report.md, the paper's Table I beside ours, the figures. */
#include "experiment/BenchmarkReport.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/filesystem.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/world/WorldPlot.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "experiment/BenchmarkTables.h"
#include "experiment/Statistics.h"
#include "io/TextFiles.h"

namespace semloc::detail
{
namespace
{
// The paper's Table I: average execution time of one run [ns].
constexpr double kPaperSemanticNs = 1171934146.0;
constexpr double kPaperGeometricNs = 6977878010.0;

std::string figuresScript(const std::vector<std::string>& variants)
{
    // Fig. 3 of the paper: average particle variance and average error over time.
    std::ostringstream g;
    g << "# semloc-benchmark: the paper's Fig. 3 from curves.csv (gnuplot figures.gp)\n"
      << "set datafile separator ','\n"
      << "set terminal pngcairo size 1000,600 noenhanced\n"
      << "set key outside right top\nset grid\nset logscale y\nset xlabel 'time [s]'\n";
    auto plot = [&](const std::string& png, const std::string& ylabel, int col)
    {
        g << "set output '" << png << "'\nset ylabel '" << ylabel << "'\nplot ";
        for (size_t i = 0; i < variants.size(); i++)
        {
            g << (i ? ", \\\n     " : "") << "'curves.csv' skip 1 using 3:(strcol(1) eq '"
              << variants[i] << "' ? $" << col << " : 1/0) with lines lw 2 title '" << variants[i]
              << "'";
        }
        g << "\nunset output\n";
    };
    plot("fig_variance.png", "mean particle variance var_xy [m^2]", 9);
    plot("fig_error.png", "mean position error err_xy [m]", 5);
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

/** Runs gnuplot on figures.gp in `out`: fig_variance.png and fig_error.png. */
void drawFigures(const StagedDirectory& out)
{
    const std::string log = out.path("figures.log");
    int rc = 0;
    try
    {
        rc = runChildProcess({"gnuplot", "figures.gp"}, log, out.path(""));
    }
    catch (const Interrupted&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION(errorMessage(e) + " (is the Debian package gnuplot-nox installed?)");
    }
    std::ifstream f(log);
    std::stringstream msg;
    msg << f.rdbuf();
    if (rc != 0 || !mrpt::system::fileExists(out.path("fig_variance.png")) ||
        !mrpt::system::fileExists(out.path("fig_error.png")))
    {
        THROW_EXCEPTION("gnuplot failed on figures.gp (it " + waitStatusText(rc) +
                        "): " + msg.str());
    }
    std::filesystem::remove(log);
}

/** world_paths.png: the world, run 1's true path and each variant's estimate. */
void drawWorldPaths(const StagedDirectory& out, const TSimulatorOptions& simulation,
                    const std::vector<Benchmark::TRunResult>& runs)
{
    const Simulator simulator(simulation);
    WorldPlot plot(simulator.world(), "run 1 (seed 1): true path and estimates");
    std::vector<mrpt::math::TPoint2D> truth;
    for (const auto& s : runs.front().records)
    {
        if (s.gt)
        {
            truth.emplace_back(s.gt->x, s.gt->y);
        }
    }
    plot.addPath("true path", truth);
    for (const auto& r : runs)
    {
        if (r.run != 1)
        {
            continue;
        }
        std::vector<mrpt::math::TPoint2D> est;
        for (const auto& s : r.records)
        {
            est.emplace_back(s.est.x, s.est.y);
        }
        plot.addPath(r.variant, est);
    }
    plot.savePng(out.path("world_paths.png"));
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
       << " runs; run i simulates the scenario of `" << o.simulate_ini
       << "` with seed i and localizes it with every variant (filter seeded with i).\n\n"
       << "- steps per run: " << res.runs.front().metrics.steps
       << "\n- particles: " << first.particles_count
       << (o.same_filter ? " (every variant runs the same filter: particles, PF_options, "
                           "KLD_options, initial distribution, convergence criterion of `" +
                               b.variants().front().name() + "`)"
                         : " (each variant's own filter)")
       << "\n- filter threads: " << o.filter_threads << ", parallel runs: " << jobs
       << "\n- total wall time: " << mrpt::format("%.1f", res.wallTime_s) << " s\n\n";
    return md.str();
}

/** report.md's "Results": the success criterion and reportTable(). */
std::string resultsSection(const Benchmark& b, const Benchmark::TResult& res)
{
    const auto& crit = b.variants().front().options.convergence;
    std::vector<std::string> names;
    for (const auto& v : b.variants())
    {
        names.push_back(v.name());
    }
    std::ostringstream md;
    md << "## Results\n\n"
       << "Success: converged (err_xy < " << crit.max_err_xy_m << " m and var_xy < "
       << crit.max_var_xy_m2 << " m² held for the rest of the run or " << crit.min_steps
       << " consecutive steps). Times to convergence and errors after convergence are means "
          "over the converged runs; variance is the mean var_xy over every step of every "
          "run. Filter time is the sum of the filter updates (update_us); wall time adds "
          "building the filter and reading the results. The ratio is the filter time over "
          "`"
       << referenceVariant(names) << "`'s.\n\n"
       << res.table;
    return md.str();
}

}  // namespace

void writeFigures(const StagedDirectory& out, const std::vector<std::string>& variants,
                  const TSimulatorOptions& simulation,
                  const std::vector<Benchmark::TRunResult>& runs)
{
    writeFile(out.path("figures.gp"), figuresScript(variants));
    drawFigures(out);
    drawWorldPaths(out, simulation, runs);
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
          "over time per variant (the paper's Fig. 3; data in `curves.csv`, script "
          "`figures.gp`)\n"
       << "- `world_paths.png`: the world, run 1's true path and each variant's estimate\n";
    return md.str();
}

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
          "step).\n\n"
       << res.table << "\n## Scenarios\n\n";
    for (size_t i = 0; i < scenarios.size(); i++)
    {
        const auto& sc = scenarios[i];
        const std::string& name = sc.scenario().name;
        md << "- [" << name << "](" << name << "/report.md): " << sc.scenario().description << " (`"
           << sc.options().simulate_ini << "` + `" << b.options().scenarios[i] << "`)\n";
    }
    return md.str();
}

}  // namespace semloc::detail

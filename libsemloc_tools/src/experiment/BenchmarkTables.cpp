/* semloc — Benchmark's result tables: results.csv, curves.csv, scenarios.csv, the summaries
 * per scenario and variant and the markdown tables of report.md. */
#include "experiment/BenchmarkTables.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "experiment/Statistics.h"

namespace semloc
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string num(double v)
{
    return std::isfinite(v) ? mrpt::format("%.6g", v) : std::string();
}

/** `fmt` of v, "-" when v is NaN (e.g. no converged run). */
std::string cell(const char* fmt, double v)
{
    return std::isfinite(v) ? mrpt::format(fmt, v) : std::string("-");
}
}  // namespace

namespace detail
{
std::string resultsCsv(const std::vector<Benchmark::TRunResult>& runs)
{
    std::ostringstream o;
    o << "run,seed,variant,particles,threads,steps,steps_with_ground_truth,converged,"
         "convergence_step,convergence_time_s,mean_err_after_conv_m,rmse_m,final_err_m,"
         "total_update_s,mean_update_us_per_particle,final_particles,reinitializations,"
         "wall_time_s,kidnap_step,recovery_steps,nees_median,nees_inside_share,"
         "nees_mean_well_conditioned,nees_well_conditioned_share,control,"
         "distance_to_convergence_m\n";
    for (const auto& r : runs)
    {
        const auto& m = r.metrics;
        o << r.run << ',' << r.seed << ',' << r.variant << ',' << r.particles << ',' << r.threads
          << ',' << m.steps << ',' << m.steps_with_ground_truth << ','
          << (m.converged ? "true" : "false") << ','
          << (m.converged ? std::to_string(m.convergence_step) : "") << ','
          << num(m.convergence_time_s) << ',' << num(m.mean_err_after_conv_m) << ','
          << num(m.rmse_m) << ',' << num(m.final_err_m) << ',' << num(m.total_update_s) << ','
          << num(m.mean_update_us_per_particle) << ','
          << (r.records.empty() ? 0 : r.records.back().n_particles) << ',' << r.reinitializations
          << ',' << num(r.wallTime_s) << ','
          << (m.kidnap_step >= 0 ? std::to_string(m.kidnap_step) : "") << ','
          << (m.recovery_steps >= 0 ? std::to_string(m.recovery_steps) : "") << ','
          << num(m.nees_median) << ',' << num(m.nees_inside_share) << ','
          << num(m.nees_mean_well_conditioned) << ',' << num(m.nees_well_conditioned_share) << ','
          << r.control << ',' << num(r.distance_to_convergence_m) << '\n';
    }
    return o.str();
}

std::string curvesCsv(const std::vector<Benchmark::TRunResult>& runs,
                      const std::vector<std::string>& variants)
{
    std::ostringstream o;
    o << "variant,step,t_s,runs,err_xy_mean,err_xy_p10,err_xy_p50,err_xy_p90,var_xy_mean,"
         "var_xy_p10,var_xy_p50,var_xy_p90\n";
    for (const auto& v : variants)
    {
        std::map<size_t, std::vector<double>> err, var, t;
        for (const auto& r : runs)
        {
            if (r.series() != v || r.records.empty())
            {
                continue;
            }
            for (const auto& s : r.records)
            {
                const double e = s.errXY();
                if (std::isfinite(e))
                {
                    err[s.step].push_back(e);
                }
                var[s.step].push_back(s.var_xy);
                t[s.step].push_back(s.t - r.records.front().t);
            }
        }
        for (auto& [step, vs] : var)
        {
            auto& es = err[step];
            std::sort(es.begin(), es.end());
            std::sort(vs.begin(), vs.end());
            o << v << ',' << step << ',' << num(mean(t[step])) << ',' << vs.size() << ','
              << num(mean(es)) << ',' << num(percentile(es, 0.1)) << ',' << num(percentile(es, 0.5))
              << ',' << num(percentile(es, 0.9)) << ',' << num(mean(vs)) << ','
              << num(percentile(vs, 0.1)) << ',' << num(percentile(vs, 0.5)) << ','
              << num(percentile(vs, 0.9)) << '\n';
        }
    }
    return o.str();
}

void NeesOverRuns::add(const RunMetrics& m)
{
    if (!std::isfinite(m.nees_median))
    {
        return;  // no ground truth
    }
    median.push_back(m.nees_median);
    inside.push_back(m.nees_inside_share);
    wellConditionedShare.push_back(m.nees_well_conditioned_share);
    if (std::isfinite(m.nees_mean_well_conditioned))
    {
        meanWellConditioned.push_back(m.nees_mean_well_conditioned);
    }
}

double NeesOverRuns::medianOfMedians() const
{
    auto v = median;
    std::sort(v.begin(), v.end());
    return percentile(v, 0.5);
}

std::map<std::string, VariantStatistics> variantStatistics(
    const std::vector<Benchmark::TRunResult>& runs)
{
    std::map<std::string, VariantStatistics> st;
    for (const auto& r : runs)
    {
        auto& s = st[r.series()];
        s.runs++;
        if (r.metrics.converged)
        {
            s.converged++;
            s.convTime.push_back(r.metrics.convergence_time_s);
            s.errAfter.push_back(r.metrics.mean_err_after_conv_m);
            if (const double b = r.detectorBoundAfterConvergence(); std::isfinite(b))
            {
                s.boundAfter.push_back(b);
            }
        }
        for (const auto& x : r.records)
        {
            s.var.push_back(x.var_xy);
        }
        s.nees.add(r.metrics);
        s.filter.push_back(r.metrics.total_update_s);
        s.perParticle.push_back(r.metrics.mean_update_us_per_particle);
        s.wall.push_back(r.wallTime_s);
    }
    return st;
}

std::string referenceVariant(const std::vector<std::string>& variants)
{
    return std::find(variants.begin(), variants.end(), "semantic") != variants.end()
               ? "semantic"
               : (variants.empty() ? std::string() : variants.front());
}

std::string scenariosCsv(const std::vector<Benchmark::TScenarioSummary>& summaries)
{
    std::ostringstream csv;
    csv << "scenario,variant,runs,successes,success_rate,converged,mean_convergence_time_s,"
           "mean_err_after_conv_m,kidnap_step,recovery_max_steps,mean_recovery_steps,"
           "max_recovery_steps,nees_median,nees_inside_share,nees_mean_well_conditioned,"
           "nees_well_conditioned_share\n";
    for (const auto& s : summaries)
    {
        const bool kidnap = s.kidnap_step >= 0;
        csv << s.scenario << ',' << s.variant << ',' << s.runs << ',' << s.successes << ','
            << num(s.successRate()) << ',' << s.converged << ',' << num(s.mean_convergence_time_s)
            << ',' << num(s.mean_err_after_conv_m) << ','
            << (kidnap ? std::to_string(s.kidnap_step) : "") << ','
            << (kidnap ? std::to_string(s.recovery_max_steps) : "") << ','
            << (kidnap ? num(s.mean_recovery_steps) : "") << ','
            << (kidnap ? num(s.max_recovery_steps) : "") << ',' << num(s.nees_median) << ','
            << num(s.nees_inside_share) << ',' << num(s.nees_mean_well_conditioned) << ','
            << num(s.nees_well_conditioned_share) << '\n';
    }
    return csv.str();
}

}  // namespace detail

using detail::mean;
using detail::standardError;

double Benchmark::TRunResult::detectorBoundAfterConvergence() const
{
    if (!metrics.converged || detectorBound.size() != records.size())
    {
        return kNaN;
    }
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k < records.size(); k++)
    {
        if (records[k].gt && static_cast<long>(records[k].step) >= metrics.convergence_step)
        {
            sum += detectorBound[k].mean_err_xy_m;
            n++;
        }
    }
    return n ? sum / static_cast<double>(n) : kNaN;
}

double Benchmark::TScenarioSummary::successRate() const
{
    return runs ? static_cast<double>(successes) / static_cast<double>(runs) : 0.0;
}

std::vector<Benchmark::TScenarioSummary> Benchmark::summarize(
    const std::vector<TRunResult>& runs) const
{
    std::vector<TScenarioSummary> out;
    for (const auto& name : seriesNames())
    {
        TScenarioSummary s;
        s.scenario = m_scenario.name;
        s.description = m_scenario.description;
        s.variant = name;
        s.kidnap_step = kidnapStep();
        s.recovery_max_steps = m_scenario.recovery_max_steps;
        std::vector<double> conv, err, rec;
        detail::NeesOverRuns nees;
        for (const auto& r : runs)
        {
            if (r.series() != s.variant)
            {
                continue;
            }
            const auto& m = r.metrics;
            s.runs++;
            if (m.converged)
            {
                s.converged++;
                conv.push_back(m.convergence_time_s);
                err.push_back(m.mean_err_after_conv_m);
            }
            if (m.recovery_steps >= 0)
            {
                rec.push_back(static_cast<double>(m.recovery_steps));
            }
            nees.add(m);
            const bool ok = s.kidnap_step >= 0
                                ? m.recovery_steps >= 0 && m.recovery_steps <= s.recovery_max_steps
                                : m.converged;
            s.successes += ok ? 1 : 0;
        }
        s.mean_convergence_time_s = mean(conv);
        s.mean_err_after_conv_m = mean(err);
        s.mean_recovery_steps = mean(rec);
        s.nees_median = nees.medianOfMedians();
        s.nees_inside_share = mean(nees.inside);
        s.nees_mean_well_conditioned = mean(nees.meanWellConditioned);
        s.nees_well_conditioned_share = mean(nees.wellConditionedShare);
        s.max_recovery_steps = rec.empty() ? kNaN : *std::max_element(rec.begin(), rec.end());
        out.push_back(s);
    }
    return out;
}

std::string Benchmark::scenariosTable(const std::vector<TScenarioSummary>& summaries)
{
    std::ostringstream o;
    o << "| scenario | variant | runs | success | converged | mean conv. time [s] | "
         "mean err after conv. [m] | median NEES | NEES inside 95 % [%] | mean NEES, "
         "well-conditioned steps | well-conditioned steps [%] | kidnap step | "
         "recovered within | mean recovery steps | max recovery steps |\n"
         "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& s : summaries)
    {
        const bool kidnap = s.kidnap_step >= 0;
        o << "| " << (s.scenario.empty() ? "-" : s.scenario) << " | " << s.variant << " | "
          << s.runs << " | " << mrpt::format("%.0f%%", 100.0 * s.successRate()) << " | "
          << s.converged << " | " << cell("%.1f", s.mean_convergence_time_s) << " | "
          << cell("%.3f", s.mean_err_after_conv_m) << " | " << cell("%.3g", s.nees_median) << " | "
          << cell("%.0f", 100.0 * s.nees_inside_share) << " | "
          << cell("%.3g", s.nees_mean_well_conditioned) << " | "
          << cell("%.0f", 100.0 * s.nees_well_conditioned_share) << " | "
          << (kidnap ? std::to_string(s.kidnap_step) : "-") << " | "
          << (kidnap ? std::to_string(s.recovery_max_steps) + " steps" : "-") << " | "
          << (kidnap ? cell("%.1f", s.mean_recovery_steps) : "-") << " | "
          << (kidnap ? cell("%.0f", s.max_recovery_steps) : "-") << " |\n";
    }
    return o.str();
}

std::string Benchmark::reportTable(const std::vector<TRunResult>& runs,
                                   const std::vector<std::string>& variants)
{
    auto st = detail::variantStatistics(runs);
    const std::string ref = detail::referenceVariant(variants);
    const double refFilter = st.count(ref) ? mean(st[ref].filter) : kNaN;
    std::ostringstream o;
    o << "| variant | runs | converged | mean conv. time [s] | mean err after conv. [m] | "
         "detector bound after conv. [m] | median NEES | NEES inside 95 % [%] | mean NEES, "
         "well-conditioned steps | well-conditioned steps [%] | mean var_xy [m²] | "
         "filter time / run [s] | filter time / particle-step [µs] | wall time / run [s] | "
         "filter time / "
      << ref << " |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& v : variants)
    {
        const auto& s = st[v];
        o << "| " << v << " | " << s.runs << " | "
          << mrpt::format("%.0f%%", s.runs ? 100.0 * static_cast<double>(s.converged) /
                                                 static_cast<double>(s.runs)
                                           : 0.0)
          << " | " << cell("%.1f", mean(s.convTime)) << " | " << cell("%.3f", mean(s.errAfter))
          << " | " << cell("%.3f", mean(s.boundAfter)) << " | "
          << cell("%.3g", s.nees.medianOfMedians()) << " | "
          << cell("%.0f", 100.0 * mean(s.nees.inside)) << " | "
          << cell("%.3g", mean(s.nees.meanWellConditioned)) << " | "
          << cell("%.0f", 100.0 * mean(s.nees.wellConditionedShare)) << " | "
          << cell("%.3f", mean(s.var)) << " | " << cell("%.3f", mean(s.filter)) << " | "
          << cell("%.3f", mean(s.perParticle)) << " | " << cell("%.3f", mean(s.wall)) << " | "
          << cell("%.2f", mean(s.filter) / refFilter) << " |\n";
    }
    return o.str();
}

std::string Benchmark::pairedTable(const std::vector<TRunResult>& runs,
                                   const std::vector<std::string>& variants)
{
    if (variants.size() < 2)
    {
        return {};
    }
    const std::string ref = detail::referenceVariant(variants);
    // Per run index: the reference's metrics.
    std::map<int, const RunMetrics*> reference;
    for (const auto& r : runs)
    {
        if (r.series() == ref)
        {
            reference[r.run] = &r.metrics;
        }
    }
    std::ostringstream o;
    o << "| variant | against | runs both converged | mean difference of the err after conv. "
         "[m] | standard error [m] | runs with the lower error | converged only by the "
         "variant | converged only by "
      << ref << " |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& v : variants)
    {
        if (v == ref)
        {
            continue;
        }
        std::vector<double> diff;
        size_t lower = 0, onlyVariant = 0, onlyRef = 0;
        for (const auto& r : runs)
        {
            const auto it = reference.find(r.run);
            if (r.series() != v || it == reference.end())
            {
                continue;
            }
            const RunMetrics& a = r.metrics;
            const RunMetrics& b = *it->second;
            if (a.converged && b.converged)
            {
                diff.push_back(a.mean_err_after_conv_m - b.mean_err_after_conv_m);
                lower += diff.back() < 0 ? 1 : 0;
            }
            onlyVariant += a.converged && !b.converged ? 1 : 0;
            onlyRef += b.converged && !a.converged ? 1 : 0;
        }
        o << "| " << v << " | " << ref << " | " << diff.size() << " | " << cell("%+.4f", mean(diff))
          << " | " << cell("%.4f", standardError(diff)) << " | " << lower << " | " << onlyVariant
          << " | " << onlyRef << " |\n";
    }
    return o.str();
}

std::string Benchmark::controlsTable(const std::vector<TRunResult>& runs)
{
    std::vector<std::pair<std::string, std::string>> keys;  // (scenario, series), first-run order
    for (const auto& r : runs)
    {
        const std::pair<std::string, std::string> k{r.scenario, r.series()};
        if (std::find(keys.begin(), keys.end(), k) == keys.end())
        {
            keys.push_back(k);
        }
    }
    std::ostringstream o;
    o << "| scenario | variant | control | runs | converged | median distance to conv. [m] | "
         "90th percentile [m] | decisions per run | mean decision time [ms] | mean decision "
         "cost [filter steps] | decisions that could not move [%] |\n"
         "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& [scenario, series] : keys)
    {
        std::vector<double> dist;
        double decisions = 0, decisionWall = 0, filterSteps = 0, stuck = 0;
        const TRunResult* any = nullptr;
        for (const auto& r : runs)
        {
            if (r.scenario != scenario || r.series() != series)
            {
                continue;
            }
            any = &r;
            dist.push_back(r.metrics.converged ? r.distance_to_convergence_m
                                               : std::numeric_limits<double>::infinity());
            decisions += static_cast<double>(r.decisions);
            decisionWall += r.decisionWall_s;
            filterSteps += r.decisionFilterSteps;
            stuck += static_cast<double>(r.stuckDecisions);
        }
        std::sort(dist.begin(), dist.end());
        const auto quantile = [&](double p)
        {
            // The nearest rank: a rank that did not converge shows "-".
            const auto k = static_cast<size_t>(std::ceil(p * static_cast<double>(dist.size())));
            return cell("%.1f", dist[std::max<size_t>(k, 1) - 1]);
        };
        const auto converged = static_cast<size_t>(
            std::count_if(dist.begin(), dist.end(), [](double d) { return std::isfinite(d); }));
        o << "| " << (scenario.empty() ? "-" : scenario) << " | " << any->variant << " | "
          << any->control << " | " << dist.size() << " | " << converged << " | " << quantile(0.5)
          << " | " << quantile(0.9) << " | "
          << mrpt::format("%.1f", decisions / static_cast<double>(dist.size())) << " | "
          << cell("%.2f", decisions > 0 ? 1e3 * decisionWall / decisions : kNaN) << " | "
          << cell("%.1f",
                  decisions > 0 && any->control == "active" ? filterSteps / decisions : kNaN)
          << " | " << cell("%.0f", decisions > 0 ? 100 * stuck / decisions : kNaN) << " |\n";
    }
    return o.str();
}

}  // namespace semloc

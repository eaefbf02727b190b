/* semloc — Benchmark: R seeds × variants of simulate + localize, aggregated (paper §IV). */
#include <fcntl.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/system/filesystem.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/GroundTruth.h>
#include <semloc/filter/Localizer.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/world/WorldPlot.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <thread>
#include "io/ExactConfigWrite.h"
#include "io/Text.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
using detail::trim;
using detail::writeFile;
const std::string kSection = "Benchmark";
const std::vector<std::string> kKeys = {
    "runs",           "variants",  "simulate_ini", "output_dir",  "jobs",
    "filter_threads", "max_steps", "particles",    "same_filter", "scenarios"};
const std::string kScenarioSection = "Scenario";
const std::vector<std::string> kScenarioKeys = {"name",
                                                "description",
                                                "variants",
                                                "particles",
                                                "recovery",
                                                "recovery_alpha_slow",
                                                "recovery_alpha_fast",
                                                "recovery_max_steps"};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The paper's Table I: average execution time of one run [ns].
constexpr double kPaperSemanticNs = 1171934146.0;
constexpr double kPaperGeometricNs = 6977878010.0;

std::vector<std::string> splitList(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        out.push_back(trim(item));
    }
    return out;
}

/** A comma-separated list of names or files, each without blanks; `key` names errors. */
std::vector<std::string> readList(const mrpt::config::CConfigFileBase& c, const std::string& s,
                                  const std::string& key)
{
    const std::string text = c.read_string(s, key, "");
    auto out = splitList(text);
    for (const auto& v : out)
    {
        if (v.empty() || v.find_first_of(" \t") != std::string::npos)
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s] %s: '%s' is not a comma-separated list of names or ini files", s.c_str(),
                key.c_str(), text.c_str()));
        }
    }
    return out;
}

/** `file` resolved next to `ini` (config::resolveNextToIni), absolute; throws naming `key`. */
std::string resolveFile(const mrpt::config::CConfigFileBase& ini, const std::string& iniPath,
                        const std::string& section, const std::string& key, const std::string& file)
{
    const std::string p = config::resolveNextToIni(ini, file);
    if (!mrpt::system::fileExists(p))
    {
        THROW_EXCEPTION("ini [" + section + "] " + key + ": '" + file +
                        "' does not exist (looked next to '" + iniPath +
                        "' and in the working directory)");
    }
    return std::filesystem::absolute(p).lexically_normal().string();
}

std::string joinList(const std::vector<std::string>& v)
{
    std::string s;
    for (const auto& x : v)
    {
        s += (s.empty() ? "" : ",") + x;
    }
    return s;
}

std::string num(double v)
{
    return std::isfinite(v) ? mrpt::format("%.6g", v) : std::string();
}

/** `fmt` of v, "-" when v is NaN (e.g. no converged run). */
std::string cell(const char* fmt, double v)
{
    return std::isfinite(v) ? mrpt::format(fmt, v) : std::string("-");
}

std::string exact(double v)
{
    return mrpt::format("%.17g", v);
}

double mean(const std::vector<double>& v)
{
    if (v.empty())
    {
        return kNaN;
    }
    double s = 0;
    for (double x : v)
    {
        s += x;
    }
    return s / static_cast<double>(v.size());
}

/** Linear interpolation between closest ranks; `v` sorted. */
double percentile(const std::vector<double>& v, double p)
{
    if (v.empty())
    {
        return kNaN;
    }
    const double r = p * static_cast<double>(v.size() - 1);
    const auto i = static_cast<size_t>(std::floor(r));
    const size_t j = std::min(i + 1, v.size() - 1);
    return v[i] + (r - static_cast<double>(i)) * (v[j] - v[i]);
}

// ---------------------------------------------------------- a run's file (child -> parent)
// Per variant: "V <variant> <particles> <threads> <wall_s> <n>" then n step lines; doubles
// printed with 17 digits read back bit-exactly, so the parent's metrics equal the child's.

std::string runFile(const std::vector<Benchmark::TRunResult>& rs)
{
    std::ostringstream o;
    for (const auto& r : rs)
    {
        o << "V " << r.variant << ' ' << r.particles << ' ' << r.threads << ' '
          << exact(r.wallTime_s) << ' ' << r.reinitializations << ' ' << r.records.size() << '\n';
        for (const auto& s : r.records)
        {
            o << s.step << ' ' << exact(s.t) << ' ' << (s.gt ? 1 : 0) << ' '
              << exact(s.gt ? s.gt->x : 0) << ' ' << exact(s.gt ? s.gt->y : 0) << ' '
              << exact(s.gt ? s.gt->phi : 0) << ' ' << exact(s.est.x) << ' ' << exact(s.est.y)
              << ' ' << exact(s.est.phi) << ' ' << exact(s.var_xy) << ' ' << exact(s.ess) << ' '
              << s.n_particles << ' ' << exact(s.update_us) << '\n';
        }
    }
    return o.str();
}

std::vector<Benchmark::TRunResult> readRunFile(const std::string& path, int run)
{
    std::ifstream f(path);
    std::vector<Benchmark::TRunResult> rs;
    std::string tag;
    while (f >> tag)
    {
        ASSERTMSG_(tag == "V", "corrupt run file '" + path + "'");
        Benchmark::TRunResult r;
        r.run = run;
        r.seed = static_cast<uint32_t>(run);
        size_t n = 0;
        f >> r.variant >> r.particles >> r.threads >> r.wallTime_s >> r.reinitializations >> n;
        r.records.resize(n);
        for (auto& s : r.records)
        {
            int hasGt = 0;
            mrpt::math::TPose2D g;
            f >> s.step >> s.t >> hasGt >> g.x >> g.y >> g.phi >> s.est.x >> s.est.y >> s.est.phi >>
                s.var_xy >> s.ess >> s.n_particles >> s.update_us;
            if (hasGt)
            {
                s.gt = g;
            }
        }
        ASSERTMSG_(static_cast<bool>(f), "corrupt run file '" + path + "'");
        rs.push_back(std::move(r));
    }
    return rs;
}

// ---------------------------------------------------------------- outputs

std::string resultsCsv(const std::vector<Benchmark::TRunResult>& runs)
{
    std::ostringstream o;
    o << "run,seed,variant,particles,threads,steps,steps_with_ground_truth,converged,"
         "convergence_step,convergence_time_s,mean_err_after_conv_m,rmse_m,final_err_m,"
         "total_update_s,mean_update_us_per_particle,final_particles,reinitializations,"
         "wall_time_s,kidnap_step,recovery_steps\n";
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
          << (m.recovery_steps >= 0 ? std::to_string(m.recovery_steps) : "") << '\n';
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
            if (r.variant != v || r.records.empty())
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

struct TStat
{
    size_t runs = 0, converged = 0;
    std::vector<double> convTime, errAfter, var, filter, perParticle, wall;
};

std::map<std::string, TStat> statistics(const std::vector<Benchmark::TRunResult>& runs)
{
    std::map<std::string, TStat> st;
    for (const auto& r : runs)
    {
        auto& s = st[r.variant];
        s.runs++;
        if (r.metrics.converged)
        {
            s.converged++;
            s.convTime.push_back(r.metrics.convergence_time_s);
            s.errAfter.push_back(r.metrics.mean_err_after_conv_m);
        }
        for (const auto& x : r.records)
        {
            s.var.push_back(x.var_xy);
        }
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

std::string paperTable(const std::vector<Benchmark::TRunResult>& runs)
{
    auto st = statistics(runs);
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

/** Why a run failed: its error message, else how its process ended (the signal named) and
 *  the end of what it printed (its log). */
std::string runFailure(const std::string& scenario, int run, int status, const std::string& error,
                       const std::string& logPath)
{
    std::string s = (scenario.empty() ? std::string() : "scenario '" + scenario + "', ") +
                    mrpt::format("run %d (seed %d) failed: ", run, run);
    if (!error.empty())
    {
        return s + error;
    }
    s += "its process " + waitStatusText(status);
    std::ifstream f(logPath);
    std::stringstream log;
    log << f.rdbuf();
    std::string tail = log.str();
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' '))
    {
        tail.pop_back();
    }
    constexpr size_t kTail = 2000;
    if (tail.size() > kTail)
    {
        tail = "..." + tail.substr(tail.size() - kTail);
    }
    return tail.empty() ? s + " (it printed nothing)" : s + "; the end of its output:\n" + tail;
}

}  // namespace

// ------------------------------------------------------------------ options

void Benchmark::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                             const std::string& s)
{
    using namespace semloc::config;
    rejectUnknownKeys(c, s, kKeys);
    readInt(c, s, "runs", runs, 1, kMaxRuns);
    if (c.keyExists(s, "variants"))
    {
        variants = readList(c, s, "variants");
    }
    if (c.keyExists(s, "scenarios") && !trim(c.read_string(s, "scenarios", "")).empty())
    {
        scenarios = readList(c, s, "scenarios");
    }
    simulate_ini = trim(c.read_string(s, "simulate_ini", simulate_ini));
    output_dir = trim(c.read_string(s, "output_dir", output_dir));
    readInt(c, s, "jobs", jobs, 0, 4096);
    readInt(c, s, "filter_threads", filter_threads, 0, 4096);
    readInt(c, s, "max_steps", max_steps, 0, std::numeric_limits<int>::max());
    readInt(c, s, "particles", particles, 0, 100000000);
    readBool(c, s, "same_filter", same_filter);
    if (output_dir.empty())
    {
        THROW_EXCEPTION("ini [" + s + "] output_dir: empty");
    }
    if (simulate_ini.empty())
    {
        THROW_EXCEPTION("ini [" + s + "] simulate_ini: empty");
    }
}

void Benchmark::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                           const std::string& s) const
{
    c.write(s, "runs", runs);
    c.write(s, "variants", joinList(variants));
    c.write(s, "simulate_ini", simulate_ini);
    c.write(s, "output_dir", output_dir);
    c.write(s, "jobs", jobs);
    c.write(s, "filter_threads", filter_threads);
    c.write(s, "max_steps", max_steps);
    c.write(s, "particles", particles);
    c.write(s, "same_filter", same_filter ? "true" : "false");
    c.write(s, "scenarios", joinList(scenarios));
}

void Benchmark::TScenario::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                              const std::string& s)
{
    using namespace semloc::config;
    rejectUnknownKeys(c, s, kScenarioKeys);
    name = trim(c.read_string(s, "name", name));
    description = trim(c.read_string(s, "description", description));
    if (c.keyExists(s, "variants"))
    {
        variants = readList(c, s, "variants");
    }
    readInt(c, s, "particles", particles, 0, 100000000);
    readBool(c, s, "recovery", recovery);
    readDouble(c, s, "recovery_alpha_slow", recovery_alpha_slow, 0, 1);
    readDouble(c, s, "recovery_alpha_fast", recovery_alpha_fast, 0, 1);
    readInt(c, s, "recovery_max_steps", recovery_max_steps, 0, std::numeric_limits<int>::max());
    if (name.find_first_of("/\\ \t") != std::string::npos || name == "." || name == "..")
    {
        THROW_EXCEPTION("ini [" + s + "] name: '" + name + "' is not a directory name");
    }
    if (recovery && !(recovery_alpha_slow > 0 && recovery_alpha_fast > recovery_alpha_slow))
    {
        THROW_EXCEPTION("ini [" + s +
                        "] recovery_alpha_slow, recovery_alpha_fast: recovery needs 0 < "
                        "recovery_alpha_slow < recovery_alpha_fast");
    }
}

void Benchmark::TScenario::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                            const std::string& s) const
{
    c.write(s, "name", name);
    c.write(s, "description", description);
    c.write(s, "variants", joinList(variants));
    c.write(s, "particles", particles);
    c.write(s, "recovery", recovery ? "true" : "false");
    detail::writeExact(c, s, "recovery_alpha_slow", recovery_alpha_slow, "");
    detail::writeExact(c, s, "recovery_alpha_fast", recovery_alpha_fast, "");
    c.write(s, "recovery_max_steps", recovery_max_steps);
}

double Benchmark::TScenarioSummary::successRate() const
{
    return runs ? static_cast<double>(successes) / static_cast<double>(runs) : 0.0;
}

// ------------------------------------------------------------------ setup

Benchmark Benchmark::FromConfigFile(const std::string& iniPath, const std::string& outputDir,
                                    int runs)
{
    ASSERTMSG_(runs >= 0 && runs <= TOptions::kMaxRuns,
               "runs must be in [0, " + std::to_string(TOptions::kMaxRuns) + "] (0: the ini's)");
    config::checkIniFile(iniPath);
    mrpt::config::CConfigFile ini(iniPath);
    if (!ini.sectionExists(kSection))
    {
        THROW_EXCEPTION("ini '" + iniPath + "': no [" + kSection + "] section");
    }
    Benchmark b;
    b.m_iniPath = iniPath;
    auto& o = b.m_options;
    o.loadFromConfigFile(ini, kSection);
    if (!outputDir.empty())
    {
        o.output_dir = outputDir;
    }
    if (runs > 0)
    {
        o.runs = runs;
    }

    o.simulate_ini = resolveFile(ini, iniPath, kSection, "simulate_ini", o.simulate_ini);
    b.m_simulation = TSimulatorOptions::FromConfigFile(o.simulate_ini);
    if (o.max_steps > 0)
    {
        b.m_simulation.simulation.max_steps = o.max_steps;
    }
    (void)Simulator(b.m_simulation);  // the world and the trajectory fail here, not in a child
    if (o.scenarios.empty())
    {
        b.loadVariants(ini);
        checkOutputDirectory(o.output_dir, b.inputFiles());  // before any work
        return b;
    }

    for (const auto& file : o.scenarios)
    {
        Benchmark sc = b;
        const std::string path = resolveFile(ini, iniPath, kSection, "scenarios", file);
        try
        {
            config::checkIniFile(path, "scenario file");
            mrpt::config::CConfigFile sini(path);
            if (!sini.sectionExists(kScenarioSection))
            {
                THROW_EXCEPTION("no [" + kScenarioSection + "] section");
            }
            sc.m_scenario.loadFromConfigFile(sini, kScenarioSection);
            // The overlay: its keys replace the base simulation's.
            sc.m_simulation.loadFromConfigFile(sini);
            if (o.max_steps > 0)
            {
                sc.m_simulation.simulation.max_steps = o.max_steps;
            }
            (void)Simulator(sc.m_simulation);
        }
        catch (const std::exception& e)
        {
            THROW_EXCEPTION("scenario '" + path + "': " + errorMessage(e));
        }
        auto& s = sc.m_scenario;
        if (s.name.empty())
        {
            s.name = std::filesystem::path(path).stem().string();
        }
        for (const auto& other : b.m_scenarios)
        {
            if (other.m_scenario.name == s.name)
            {
                THROW_EXCEPTION("ini [" + kSection + "] scenarios: the name '" + s.name +
                                "' appears twice");
            }
        }
        if (!s.variants.empty())
        {
            sc.m_options.variants = s.variants;
        }
        sc.m_options.scenarios.clear();
        sc.m_scenarios.clear();
        sc.loadVariants(ini);
        b.m_scenarios.push_back(std::move(sc));
    }
    checkOutputDirectory(o.output_dir, b.inputFiles());  // before any work
    return b;
}

std::vector<std::string> Benchmark::inputFiles() const
{
    std::vector<std::string> files = {m_iniPath, m_options.simulate_ini,
                                      m_simulation.simulation.world_file};
    for (const auto& v : m_variants)
    {
        files.push_back(v.iniPath);
        files.push_back(v.options.map_file);
    }
    for (const auto& sc : m_scenarios)
    {
        const auto more = sc.inputFiles();
        files.insert(files.end(), more.begin(), more.end());
    }
    return files;
}

void Benchmark::loadVariants(const mrpt::config::CConfigFileBase& ini)
{
    const auto& o = m_options;
    for (const auto& name : o.variants)
    {
        const bool isFile = name.size() > 4 && name.substr(name.size() - 4) == ".ini";
        TVariant v;
        v.iniPath =
            resolveFile(ini, m_iniPath, kSection, "variants", isFile ? name : name + ".ini");
        try
        {
            config::checkIniFile(v.iniPath);
            mrpt::config::CConfigFile vini(v.iniPath);
            v.options.loadFromConfigFile(vini, "LocalizationExperiment");
            v.maps = LocalizationMap::FromConfig(vini, v.options.map_file);
        }
        catch (const std::exception& e)
        {
            THROW_EXCEPTION("variant '" + name + "' (" + v.iniPath + "): " + errorMessage(e));
        }
        if (v.options.variant.empty())
        {
            v.options.variant = v.maps.variant();
        }
        for (const auto& w : m_variants)
        {
            if (w.name() == v.name())
            {
                THROW_EXCEPTION("ini [" + kSection + "] variants: '" + v.name() +
                                "' appears twice");
            }
        }
        m_variants.push_back(std::move(v));
    }
    if (m_variants.empty())
    {
        THROW_EXCEPTION("ini [" + kSection + "] variants: empty");
    }

    // Only the likelihood differs between variants: the first one's filter for all.
    const auto reference = m_variants.front().options;
    for (auto& v : m_variants)
    {
        if (o.same_filter)
        {
            v.options.filter = reference.filter;
            v.options.convergence = reference.convergence;
        }
        if (o.particles > 0)
        {
            v.options.filter.particles_count = o.particles;
        }
        if (m_scenario.particles > 0)
        {
            v.options.filter.particles_count = m_scenario.particles;
        }
        v.options.filter.threads = o.filter_threads;
        if (m_scenario.recovery)
        {
            v.options.filter.recovery.alpha_slow = m_scenario.recovery_alpha_slow;
            v.options.filter.recovery.alpha_fast = m_scenario.recovery_alpha_fast;
        }
    }
}

long Benchmark::kidnapStep() const
{
    const auto& k = m_simulation.kidnapping;
    return k.enabled ? static_cast<long>(k.step) : -1L;
}

size_t Benchmark::effectiveJobs() const
{
    const size_t hw = std::max(1u, std::thread::hardware_concurrency());
    const size_t j = m_options.jobs > 0 ? static_cast<size_t>(m_options.jobs) : hw;
    return std::min(j, static_cast<size_t>(m_options.runs));
}

// ------------------------------------------------------------------ one run

std::vector<Benchmark::TRunResult> Benchmark::runOne(int run) const
{
    auto simOptions = m_simulation;
    simOptions.simulation.seed = static_cast<uint32_t>(run);
    const Simulator simulator(simOptions);
    const SimulationResult data = simulator.run();
    const GroundTruth gt(data.groundTruth);
    const double tolerance = 0.5 * simOptions.simulation.time_step_s;

    std::vector<TRunResult> out;
    for (const auto& v : m_variants)
    {
        const auto wall0 = std::chrono::steady_clock::now();
        auto filter = v.options.filter;
        filter.seed = static_cast<uint32_t>(run);
        Localizer loc(filter, v.maps.map, v.maps.world ? &*v.maps.world : nullptr);
        TRunResult r;
        r.scenario = m_scenario.name;
        r.run = run;
        r.seed = filter.seed;
        r.variant = v.name();
        r.particles = static_cast<size_t>(filter.particles_count);
        r.threads = loc.threads();
        mrpt::obs::CActionCollection::Ptr action;
        for (size_t i = 0; i < data.rawlog.size(); i++)
        {
            if (data.rawlog.getType(i) == mrpt::obs::CRawlog::etActionCollection)
            {
                action = data.rawlog.getAsAction(i);
                continue;
            }
            if (data.rawlog.getType(i) != mrpt::obs::CRawlog::etSensoryFrame || !action)
            {
                continue;
            }
            const auto sf = data.rawlog.getAsObservations(i);
            loc.step(*action, *sf);
            action.reset();
            TStepRecord s = loc.lastStepRecord(*sf);
            s.step = r.records.size();
            if (const auto* row = gt.nearest(s.t, tolerance))
            {
                s.gt = row->pose();
            }
            r.records.push_back(s);
        }
        r.wallTime_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        r.metrics = RunMetrics::compute(r.records, v.options.convergence, kidnapStep());
        r.reinitializations = loc.recoveryStats().reinitializations;
        out.push_back(std::move(r));
    }
    return out;
}

// ------------------------------------------------------------------ the benchmark

Benchmark::TResult Benchmark::run(const std::function<void(size_t, size_t)>& progress) const
{
    if (!m_scenarios.empty())
    {
        return runScenarios(progress);
    }
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;
    StagedDirectory out(o.output_dir, inputFiles());
    const std::string runsDir = out.path("runs");
    std::filesystem::create_directories(runsDir);
    auto runPath = [&](int run, const char* ext)
    { return runsDir + mrpt::format("/run_%06d.%s", run, ext); };

    // One child process per run (see the class documentation: MRPT's global generator).
    const size_t jobs = effectiveJobs();
    std::map<pid_t, int> children;
    std::string failure;
    int next = 1;
    size_t done = 0;
    auto reap = [&]
    {
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, 0);
        if (pid < 0)
        {
            if (errno == EINTR)
            {
                return;  // a signal: the loop looks at interruptRequested()
            }
            THROW_EXCEPTION(std::string("waiting for the runs failed: ") + std::strerror(errno));
        }
        const auto it = children.find(pid);
        if (it == children.end())
        {
            return;
        }
        const int run = it->second;
        children.erase(it);
        unregisterChildProcess(pid);
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        {
            std::ifstream f(runPath(run, "err"));
            std::stringstream msg;
            msg << f.rdbuf();
            if (failure.empty())
            {
                failure = runFailure(m_scenario.name, run, status, msg.str(), runPath(run, "log"));
            }
        }
        done++;
        if (progress)
        {
            progress(done, static_cast<size_t>(o.runs));
        }
    };
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    if (progress)
    {
        progress(0, static_cast<size_t>(o.runs));
    }
    // Ctrl-C (installInterruptHandlers): no new run, the running ones ended, then Interrupted;
    // the staging directory goes with the exception.
    bool interrupted = false;
    while ((next <= o.runs && failure.empty() && !interrupted) || !children.empty())
    {
        if (interruptRequested() && !interrupted)
        {
            interrupted = true;
            for (const auto& child : children)
            {
                ::kill(child.first, SIGTERM);
            }
            continue;
        }
        if (next <= o.runs && failure.empty() && !interrupted && children.size() < jobs)
        {
            const int run = next++;
            pid_t pid = -1;
            int forkErrno = 0;
            {
                const InterruptExitDeferral defer;  // started and registered as one step
                pid = ::fork();
                forkErrno = errno;
                if (pid > 0)
                {
                    registerChildProcess(pid);
                }
            }
            if (pid < 0)
            {
                failure = std::string("cannot start run ") + std::to_string(run) +
                          ": fork failed: " + std::strerror(forkErrno);
                continue;
            }
            if (pid == 0)
            {
                // The run ends at Ctrl-C or the parent's SIGTERM (its outputs are not kept).
                ::signal(SIGINT, SIG_DFL);
                ::signal(SIGTERM, SIG_DFL);
                // MRPT's warnings (e.g. re-initializations, counted in results.csv) go to the
                // run's log, not over the progress bar.
                const int log =
                    ::open(runPath(run, "log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
                if (log >= 0)
                {
                    ::dup2(log, STDOUT_FILENO);
                    ::dup2(log, STDERR_FILENO);
                    ::close(log);
                }
                int rc = 0;
                try
                {
                    writeFile(runPath(run, "txt"), runFile(runOne(run)));
                }
                catch (const std::exception& e)
                {
                    std::ofstream(runPath(run, "err")) << errorMessage(e);
                    rc = 1;
                }
                std::cout.flush();
                std::cerr.flush();
                std::fflush(nullptr);
                ::_exit(rc);  // no destructors: the staging directory is the parent's
            }
            children[pid] = run;
            continue;
        }
        reap();
    }
    if (interrupted)
    {
        throw Interrupted();
    }
    if (!failure.empty())
    {
        THROW_EXCEPTION(failure);
    }

    TResult res;
    for (int run = 1; run <= o.runs; run++)
    {
        auto rs = readRunFile(runPath(run, "txt"), run);
        ASSERTMSG_(rs.size() == m_variants.size(),
                   "incomplete results of run " + std::to_string(run));
        for (size_t k = 0; k < rs.size(); k++)
        {
            rs[k].scenario = m_scenario.name;
            rs[k].metrics =
                RunMetrics::compute(rs[k].records, m_variants[k].options.convergence, kidnapStep());
            res.runs.push_back(std::move(rs[k]));
        }
    }
    std::filesystem::remove_all(runsDir);

    std::vector<std::string> names;
    for (const auto& v : m_variants)
    {
        names.push_back(v.name());
    }
    writeFile(out.path("results.csv"), resultsCsv(res.runs));
    writeFile(out.path("curves.csv"), curvesCsv(res.runs, names));
    writeFile(out.path("figures.gp"), figuresScript(names));
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
    {
        const Simulator simulator(m_simulation);
        WorldPlot plot(simulator.world(), "run 1 (seed 1): true path and estimates");
        std::vector<mrpt::math::TPoint2D> truth;
        for (const auto& s : res.runs.front().records)
        {
            if (s.gt)
            {
                truth.emplace_back(s.gt->x, s.gt->y);
            }
        }
        plot.addPath("true path", truth);
        for (const auto& r : res.runs)
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

    res.table = reportTable(res.runs, names);
    res.summaries = summarize(res.runs);
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    {
        const auto& first = m_variants.front().options.filter;
        std::ostringstream md;
        md << "# semloc-benchmark report\n\n";
        if (!m_scenario.name.empty())
        {
            md << "Scenario **" << m_scenario.name << "**: " << m_scenario.description << "\n\n";
        }
        md << "The experiment of the paper (§IV): " << o.runs
           << " runs; run i simulates the scenario of `" << o.simulate_ini
           << "` with seed i and localizes it with every variant (filter seeded with i).\n\n"
           << "- steps per run: " << res.runs.front().metrics.steps
           << "\n- particles: " << first.particles_count
           << (o.same_filter ? " (every variant runs the same filter: particles, PF_options, "
                               "KLD_options, initial distribution, convergence criterion of `" +
                                   m_variants.front().name() + "`)"
                             : " (each variant's own filter)")
           << "\n- filter threads: " << o.filter_threads << ", parallel runs: " << jobs
           << "\n- total wall time: " << mrpt::format("%.1f", res.wallTime_s) << " s\n\n"
           << "## Results\n\n"
           << "Success: converged (err_xy < " << m_variants.front().options.convergence.max_err_xy_m
           << " m and var_xy < " << m_variants.front().options.convergence.max_var_xy_m2
           << " m² held for the rest of the run or "
           << m_variants.front().options.convergence.min_steps
           << " consecutive steps). Times to convergence and errors after convergence are means "
              "over the converged runs; variance is the mean var_xy over every step of every "
              "run. Filter time is the sum of the filter updates (update_us); wall time adds "
              "building the filter and reading the results. The ratio is the filter time over "
              "`"
           << referenceVariant(names) << "`'s.\n\n"
           << res.table;
        if (!m_scenario.name.empty() || kidnapStep() >= 0)
        {
            md << "\n## Success and recovery\n\n"
               << "Success: converged; with a kidnapping, re-converged (the criterion above, "
                  "from the kidnap step on) within "
               << m_scenario.recovery_max_steps << " steps of it.\n\n"
               << scenariosTable(res.summaries);
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
        writeFile(out.path("report.md"), md.str());
    }
    res.outputDir = out.target();
    out.commit();
    return res;
}

std::vector<Benchmark::TScenarioSummary> Benchmark::summarize(
    const std::vector<TRunResult>& runs) const
{
    std::vector<TScenarioSummary> out;
    for (const auto& v : m_variants)
    {
        TScenarioSummary s;
        s.scenario = m_scenario.name;
        s.description = m_scenario.description;
        s.variant = v.name();
        s.kidnap_step = kidnapStep();
        s.recovery_max_steps = m_scenario.recovery_max_steps;
        std::vector<double> conv, err, rec;
        for (const auto& r : runs)
        {
            if (r.variant != s.variant)
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
            const bool ok = s.kidnap_step >= 0
                                ? m.recovery_steps >= 0 && m.recovery_steps <= s.recovery_max_steps
                                : m.converged;
            s.successes += ok ? 1 : 0;
        }
        s.mean_convergence_time_s = mean(conv);
        s.mean_err_after_conv_m = mean(err);
        s.mean_recovery_steps = mean(rec);
        s.max_recovery_steps = rec.empty() ? kNaN : *std::max_element(rec.begin(), rec.end());
        out.push_back(s);
    }
    return out;
}

std::string Benchmark::scenariosTable(const std::vector<TScenarioSummary>& summaries)
{
    std::ostringstream o;
    o << "| scenario | variant | runs | success | converged | mean conv. time [s] | "
         "mean err after conv. [m] | kidnap step | recovered within | mean recovery steps | "
         "max recovery steps |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& s : summaries)
    {
        const bool kidnap = s.kidnap_step >= 0;
        o << "| " << (s.scenario.empty() ? "-" : s.scenario) << " | " << s.variant << " | "
          << s.runs << " | " << mrpt::format("%.0f%%", 100.0 * s.successRate()) << " | "
          << s.converged << " | " << cell("%.1f", s.mean_convergence_time_s) << " | "
          << cell("%.3f", s.mean_err_after_conv_m) << " | "
          << (kidnap ? std::to_string(s.kidnap_step) : "-") << " | "
          << (kidnap ? std::to_string(s.recovery_max_steps) + " steps" : "-") << " | "
          << (kidnap ? cell("%.1f", s.mean_recovery_steps) : "-") << " | "
          << (kidnap ? cell("%.0f", s.max_recovery_steps) : "-") << " |\n";
    }
    return o.str();
}

Benchmark::TResult Benchmark::runScenarios(
    const std::function<void(size_t, size_t)>& progress) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    StagedDirectory out(m_options.output_dir, inputFiles());
    const size_t total = m_scenarios.size() * static_cast<size_t>(m_options.runs);
    TResult res;
    std::ostringstream sections;
    for (size_t i = 0; i < m_scenarios.size(); i++)
    {
        Benchmark sc = m_scenarios[i];
        const std::string name = sc.m_scenario.name;
        sc.m_options.output_dir = out.path(name);
        const size_t offset = i * static_cast<size_t>(m_options.runs);
        const auto r = sc.run(
            [&](size_t done, size_t)
            {
                if (progress && (done > 0 || i == 0))
                {
                    progress(offset + done, total);
                }
            });
        res.runs.insert(res.runs.end(), r.runs.begin(), r.runs.end());
        res.summaries.insert(res.summaries.end(), r.summaries.begin(), r.summaries.end());
        sections << "- [" << name << "](" << name << "/report.md): " << sc.m_scenario.description
                 << " (`" << sc.m_options.simulate_ini << "` + `" << m_options.scenarios[i]
                 << "`)\n";
    }
    res.table = scenariosTable(res.summaries);

    std::ostringstream csv;
    csv << "scenario,variant,runs,successes,success_rate,converged,mean_convergence_time_s,"
           "mean_err_after_conv_m,kidnap_step,recovery_max_steps,mean_recovery_steps,"
           "max_recovery_steps\n";
    for (const auto& s : res.summaries)
    {
        const bool kidnap = s.kidnap_step >= 0;
        csv << s.scenario << ',' << s.variant << ',' << s.runs << ',' << s.successes << ','
            << num(s.successRate()) << ',' << s.converged << ',' << num(s.mean_convergence_time_s)
            << ',' << num(s.mean_err_after_conv_m) << ','
            << (kidnap ? std::to_string(s.kidnap_step) : "") << ','
            << (kidnap ? std::to_string(s.recovery_max_steps) : "") << ','
            << (kidnap ? num(s.mean_recovery_steps) : "") << ','
            << (kidnap ? num(s.max_recovery_steps) : "") << '\n';
    }
    writeFile(out.path("scenarios.csv"), csv.str());

    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const auto& crit = m_scenarios.front().m_variants.front().options.convergence;
    std::ostringstream md;
    md << "# semloc-benchmark report: scenarios\n\n"
       << m_options.runs << " runs per scenario; run i simulates the scenario with seed i and "
       << "localizes it with the scenario's variants (filter seeded with i); "
       << m_scenarios.front().m_variants.front().options.filter.particles_count
       << " particles; total wall time " << mrpt::format("%.1f", res.wallTime_s) << " s.\n\n"
       << "Success: converged (err_xy < " << crit.max_err_xy_m << " m and var_xy < "
       << crit.max_var_xy_m2 << " m² held for the rest of the run or " << crit.min_steps
       << " consecutive steps); with a kidnapping, the same criterion met again from the kidnap "
          "step on within the scenario's bound (recovery steps = first such step - kidnap "
          "step).\n\n"
       << res.table << "\n## Scenarios\n\n"
       << sections.str();
    writeFile(out.path("report.md"), md.str());
    res.outputDir = out.target();
    out.commit();
    return res;
}

std::string Benchmark::reportTable(const std::vector<TRunResult>& runs,
                                   const std::vector<std::string>& variants)
{
    auto st = statistics(runs);
    const std::string ref = referenceVariant(variants);
    const double refFilter = st.count(ref) ? mean(st[ref].filter) : kNaN;
    std::ostringstream o;
    o << "| variant | runs | converged | mean conv. time [s] | mean err after conv. [m] | "
         "mean var_xy [m²] | filter time / run [s] | filter time / particle-step [µs] | "
         "wall time / run [s] | filter time / "
      << ref << " |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& v : variants)
    {
        const auto& s = st[v];
        o << "| " << v << " | " << s.runs << " | "
          << mrpt::format("%.0f%%", s.runs ? 100.0 * static_cast<double>(s.converged) /
                                                 static_cast<double>(s.runs)
                                           : 0.0)
          << " | " << cell("%.1f", mean(s.convTime)) << " | " << cell("%.3f", mean(s.errAfter))
          << " | " << cell("%.3f", mean(s.var)) << " | " << cell("%.3f", mean(s.filter)) << " | "
          << cell("%.3f", mean(s.perParticle)) << " | " << cell("%.3f", mean(s.wall)) << " | "
          << cell("%.2f", mean(s.filter) / refFilter) << " |\n";
    }
    return o.str();
}

}  // namespace semloc

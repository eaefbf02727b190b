/* semloc — Benchmark's sweep: a key the variants' runs read and that changes them, refused
 * otherwise with the reason. */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ErrorMessage.h>

#include <string>
#include <vector>

#include "experiment/LocalizationConfig.h"

namespace semloc
{
namespace
{
const std::string kRunSection = "LocalizationExperiment";
}  // namespace

std::string Benchmark::keySetByBenchmark(const std::string& section, const std::string& key) const
{
    const bool run = section == kRunSection;
    const std::string scenario = "the scenario '" + m_scenario.name + "' sets ";
    if (run && key == "seed")
    {
        return "each run seeds every filter with its own number (the runs 1..runs are the "
               "benchmark's seeds)";
    }
    if (section == "PF_options" && key == "threads")
    {
        return "[Benchmark] filter_threads sets every filter's threads, and a filter's results "
               "do not depend on its threads";
    }
    if (run && key == "variant")
    {
        return "it names the variant, which a sweep names <name>@KEY=<value>";
    }
    if (run && key == "particles_count" && (m_scenario.particles > 0 || m_options.particles > 0))
    {
        return m_scenario.particles > 0
                   ? scenario + "particles = " + std::to_string(m_scenario.particles) +
                         " for every variant"
                   : "[Benchmark] particles = " + std::to_string(m_options.particles) +
                         " sets every variant's particles_count";
    }
    if (run && key == "map_file" && mapFromWorld())
    {
        return "map_from_world = true: every variant localizes against the simulated world (the "
               "simulation's [Simulation] world_file), not its map_file";
    }
    if (run && key == "init_PDF_mode" && m_scenario.init_PDF_mode >= 0)
    {
        return scenario + "init_PDF_mode = " + std::to_string(m_scenario.init_PDF_mode) +
               " for every variant";
    }
    if (section == "Recovery" && m_scenario.recovery &&
        (key == "trigger" || key == "alpha_slow" || key == "alpha_fast"))
    {
        return scenario +
               "recovery = true: every variant's [Recovery] trigger = amcl with the "
               "scenario's recovery_alpha_slow and recovery_alpha_fast";
    }
    return {};
}

void Benchmark::checkSweepKey() const
{
    const auto& w = m_options.sweep;
    if (w.key.empty())
    {
        return;
    }
    if (w.section == "Benchmark")
    {
        THROW_EXCEPTION(w.error(
            "[Benchmark] is the benchmark's own section: a sweep sets a key of the variants' "
            "inis (one the runs of semloc-localize read)"));
    }
    try
    {
        detail::checkLocalizeSection(w.section);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION(w.error("no variant's run reads it: " + errorMessage(e)));
    }
    if (const std::string why = keySetByBenchmark(w.section, w.key); !why.empty())
    {
        THROW_EXCEPTION(w.error("the benchmark sets [" + w.section + "] " + w.key +
                                " itself, whatever the variants' inis say: " + why));
    }
}

std::string Benchmark::runConfiguration(const TVariant& v)
{
    // What runOne() reads of the variant; what it does not keeps its default.
    LocalizationExperiment::TOptions o;
    o.filter = v.options.filter;
    o.filter.seed = 0;     // each run's
    o.filter.threads = 1;  // [Benchmark] filter_threads, which changes no result
    o.filter.pf.sampleSize = Localizer::TOptions().pf.sampleSize;  // ignored: particles_count
    o.filter.warnings.clear();
    o.convergence = v.options.convergence;
    o.map_file = v.options.map_file;
    mrpt::config::CConfigFileMemory c;
    o.saveToConfigFile(c, kRunSection);
    return c.getContent() + v.mapsConfig;
}

void Benchmark::checkSweepValuesDiffer() const
{
    const auto& w = m_options.sweep;
    if (w.key.empty())
    {
        return;
    }
    // m_variants: each variant of [Benchmark] variants once per value, in the values' order.
    const size_t n = w.values.size();
    std::vector<std::string> configs;
    configs.reserve(m_variants.size());
    for (const auto& v : m_variants)
    {
        configs.push_back(runConfiguration(v));
    }
    for (size_t k = 0; k < m_variants.size(); k++)
    {
        const size_t first = k - k % n;  // the same variant's first value
        for (size_t j = first; j < k; j++)
        {
            if (configs[j] == configs[k])
            {
                const std::string& name = m_variants[k].name();
                THROW_EXCEPTION(w.error(
                    "the values '" + w.values[j - first] + "' and '" + w.values[k - first] +
                    "' run the variant '" + name.substr(0, name.rfind('@')) +
                    "' alike (the same filter, convergence criterion and maps as the benchmark "
                    "runs them: its runs do not read [" +
                    w.section + "] " + w.key + ", or the benchmark sets it)"));
            }
        }
    }
}

}  // namespace semloc

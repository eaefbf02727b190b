/* semloc — Benchmark's configuration: [Benchmark], the scenario files and the variants, read
 * strictly before any output is written. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/filesystem.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <sstream>
#include <thread>

#include "experiment/BenchmarkLists.h"
#include "experiment/ClosedLoop.h"
#include "io/ExactConfigWrite.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
using detail::joinList;
using detail::readList;
using detail::splitList;
using detail::trim;
const std::string kSection = "Benchmark";
const std::string kScenarioSection = "Scenario";
const std::vector<std::string> kScenarioKeys = {"name",
                                                "description",
                                                "variants",
                                                "particles",
                                                "recovery",
                                                "recovery_alpha_slow",
                                                "recovery_alpha_fast",
                                                "recovery_max_steps",
                                                "map_from_world",
                                                "init_PDF_mode",
                                                "world_shift_sigma_m",
                                                "world_removed_share",
                                                "world_added",
                                                "world_changes_seed"};

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

/** The sections of a scenario file that overlay the simulation; every other section but
 *  [Scenario] overlays the variants' inis. */
const std::vector<std::string> kSimulationSections = {
    "Simulation", "Odometry", "Sonar", "SemanticDetector", "Kidnapping", "BeaconRanging"};

/** Reads scenario file `path` (resolved) into `scenario`, its simulation overlay into
 *  `simulation` (whose max_steps `maxSteps` > 0 replaces) and its variants' overlay (section,
 *  key, value) into `variantOverlay`; throws naming the file. */
void readScenarioFile(const std::string& path, int maxSteps, Benchmark::TScenario& scenario,
                      TSimulatorOptions& simulation,
                      std::vector<std::array<std::string, 3>>& variantOverlay)
{
    try
    {
        config::checkIniFile(path, "scenario file");
        const config::IniFileInMemory sini(path, "scenario file");
        if (!sini.sectionExists(kScenarioSection))
        {
            THROW_EXCEPTION("no [" + kScenarioSection + "] section");
        }
        scenario.loadFromConfigFile(sini, kScenarioSection);
        std::vector<std::string> sections;
        sini.getAllSections(sections);
        for (const auto& sec : sections)
        {
            if (sec == kScenarioSection ||
                std::find(kSimulationSections.begin(), kSimulationSections.end(), sec) !=
                    kSimulationSections.end())
            {
                continue;
            }
            std::vector<std::string> keys;
            sini.getAllKeys(sec, keys);
            for (const auto& k : keys)
            {
                variantOverlay.push_back({sec, trim(k), sini.read_string(sec, trim(k), "")});
            }
        }
        // The overlay: its keys replace the base simulation's.
        simulation.loadFromConfigFile(sini);
        if (maxSteps > 0)
        {
            simulation.simulation.max_steps = maxSteps;
        }
        (void)Simulator(simulation);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("scenario '" + path + "': " + errorMessage(e));
    }
    if (scenario.name.empty())
    {
        scenario.name = std::filesystem::path(path).stem().string();
    }
}

/** The ini of the variant `name` of [Benchmark] variants: `<name>.ini` in `dir`, or a path
 *  ending in .ini, resolved next to `ini`; throws naming [Benchmark] variants. */
std::string variantIniPath(const mrpt::config::CConfigFileBase& ini, const std::string& iniPath,
                           const std::string& dir, const std::string& name)
{
    const bool isFile = name.size() > 4 && name.substr(name.size() - 4) == ".ini";
    const std::string file = isFile || dir.empty() ? name : dir + "/" + name;
    return resolveFile(ini, iniPath, kSection, "variants", isFile ? file : file + ".ini");
}

/** The variant of ini file `path` with the (section, key, value) of `overlay` replacing its
 *  own, and its maps (of `mapFile` instead of its map_file when given); throws the readers'
 *  errors. */
Benchmark::TVariant loadVariant(const std::string& path, const std::string& mapFile,
                                const std::vector<std::array<std::string, 3>>& overlay)
{
    Benchmark::TVariant v;
    v.iniPath = path;
    config::checkIniFile(v.iniPath);
    // The scenario's keys replace the variant's (in memory: the file stays as it is).
    config::IniFileInMemory vini(v.iniPath);
    for (const auto& [section, key, value] : overlay)
    {
        vini.write(section, key, value);
    }
    v.options.loadFromConfigFile(vini, "LocalizationExperiment");
    auto& warnings = v.options.filter.warnings;
    warnings.insert(warnings.begin(), vini.warnings().begin(), vini.warnings().end());
    if (!mapFile.empty())
    {
        v.options.map_file = mapFile;  // the simulated world (map_from_world)
    }
    v.maps = LocalizationMap::FromConfig(vini, v.options.map_file);
    v.mapsConfig = v.maps.effectiveConfig(vini);
    if (v.options.variant.empty())
    {
        v.options.variant = v.maps.variant();
    }
    return v;
}

/** loadVariant() of the variant `name` (its ini `path`); throws naming the variant. */
Benchmark::TVariant readVariant(const std::string& name, const std::string& path,
                                const std::string& mapFile,
                                const std::vector<std::array<std::string, 3>>& overlay)
{
    try
    {
        return loadVariant(path, mapFile, overlay);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("variant '" + name + "' (" + path + "): " + errorMessage(e));
    }
}

/** readVariant() with the sweep's `value` on the overlay, as the variant
 *  `<name>@KEY=<value>`; an error (the variant's file read without the sweep is fine) is
 *  the sweep line's, naming the value. */
Benchmark::TVariant readSweptVariant(const std::string& name, const std::string& path,
                                     const std::string& mapFile,
                                     std::vector<std::array<std::string, 3>> overlay,
                                     const Benchmark::TOptions::TSweep& sweep,
                                     const std::string& value)
{
    overlay.push_back({sweep.section, sweep.key, value});
    Benchmark::TVariant v;
    try
    {
        v = loadVariant(path, mapFile, overlay);
    }
    catch (const std::exception& e)
    {
        // "ini 'PATH': [SECTION] KEY: ..." or "ini [SECTION] KEY: ...": of the swept key.
        std::string m = errorMessage(e);
        const std::string ofFile = "ini '" + path + "': ";
        m = m.rfind(ofFile, 0) == 0    ? m.substr(ofFile.size())
            : m.rfind("ini [", 0) == 0 ? m.substr(4)
                                       : m;
        THROW_EXCEPTION(sweep.error("the value '" + value + "' (variant '" + name + "'): " + m));
    }
    v.options.variant += "@" + sweep.key + "=" + value;
    return v;
}

}  // namespace

// ------------------------------------------------------------------ options

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
    if (c.keyExists(s, "map_from_world") && !trim(c.read_string(s, "map_from_world", "")).empty())
    {
        bool fromWorld = true;
        readBool(c, s, "map_from_world", fromWorld);
        map_from_world = fromWorld;
    }
    readInt(c, s, "init_PDF_mode", init_PDF_mode, -1, 3);
    readDouble(c, s, "world_shift_sigma_m", world_changes.shift_sigma_m, 0, 1e3);
    readDouble(c, s, "world_removed_share", world_changes.removed_share, 0, 1);
    readInt(c, s, "world_added", world_changes.added, 0, 100000);
    int seed = static_cast<int>(world_changes.seed);
    readInt(c, s, "world_changes_seed", seed, 0, std::numeric_limits<int>::max());
    world_changes.seed = static_cast<uint32_t>(seed);
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
    // Unset (an empty value, written without a comment): [Benchmark]'s.
    c.write(s, "map_from_world",
            map_from_world ? std::string(*map_from_world ? "true" : "false") : std::string());
    c.write(s, "init_PDF_mode", init_PDF_mode);
    detail::writeExact(c, s, "world_shift_sigma_m", world_changes.shift_sigma_m,
                       "simulated world: objects moved by N(0, this) along x, y [m]");
    detail::writeExact(c, s, "world_removed_share", world_changes.removed_share,
                       "simulated world: share of the map's objects gone");
    c.write(s, "world_added", world_changes.added, 24, 24,
            "simulated world: objects the map does not have");
    c.write(s, "world_changes_seed", static_cast<int>(world_changes.seed), 24, 24,
            "seed of those changes (the maps stay the file's)");
}

// ------------------------------------------------------------------ setup

namespace
{
/** With same_filter: `v` runs the filter of `reference` (the first variant's options). */
template <typename Options, typename Variant>
void takeFilterOf(const Options& reference, Variant& v)
{
    v.options.filter = reference.filter;
    v.options.convergence = reference.convergence;
    // Mode 3 is mode 0 until a detection the semantic map places: without that map, the
    // filter's start is the uniform one it would come to.
    if (v.options.filter.init_PDF_mode == Localizer::InitMode::FromDetections &&
        !v.maps.map->template mapByClass<CSemanticMap>())
    {
        v.options.filter.init_PDF_mode = Localizer::InitMode::FreeSpace;
    }
    // The evidence trigger weighs the detections alone: a variant with other maps runs
    // without recovery (as the shipped sonar and grid variants do).
    if (v.options.filter.recovery.trigger == RecoveryTrigger::Evidence &&
        !weighsWithoutMaps(*v.maps.map))
    {
        v.options.filter.recovery.trigger = RecoveryTrigger::Off;
    }
}
}  // namespace

Benchmark Benchmark::FromConfigFile(const std::string& iniPath, const std::string& outputDir,
                                    int runs)
{
    ASSERTMSG_(runs >= 0 && runs <= TOptions::kMaxRuns,
               "runs must be in [0, " + std::to_string(TOptions::kMaxRuns) + "] (0: the ini's)");
    config::checkIniFile(iniPath);
    const config::IniFileInMemory ini(iniPath);
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
    }
    for (const auto& file : o.scenarios)
    {
        Benchmark sc = b;
        const std::string path = resolveFile(ini, iniPath, kSection, "scenarios", file);
        readScenarioFile(path, o.max_steps, sc.m_scenario, sc.m_simulation, sc.m_variantOverlay);
        const auto& s = sc.m_scenario;
        if (s.world_changes.any())
        {
            // One changed world for every run of the scenario; the maps stay the file's.
            sc.m_changedWorld = std::make_shared<const World>(changeWorld(
                World::FromFile(sc.m_simulation.simulation.world_file), s.world_changes));
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

std::vector<std::string> Benchmark::seriesNames() const
{
    std::vector<std::string> names;
    for (const auto& v : m_variants)
    {
        for (const auto& c : m_options.controls)
        {
            names.push_back(seriesName(v.name(), c));
        }
    }
    return names;
}

std::vector<std::string> Benchmark::inputFiles() const
{
    std::vector<std::string> files = {m_simulation.simulation.world_file};
    for (const auto& ini : {m_iniPath, m_options.simulate_ini})
    {
        const auto chain = config::iniFileAndBases(ini);
        files.insert(files.end(), chain.begin(), chain.end());
    }
    for (const auto& v : m_variants)
    {
        const auto chain = config::iniFileAndBases(v.iniPath);
        files.insert(files.end(), chain.begin(), chain.end());
        files.push_back(v.options.map_file);
    }
    for (const auto& sc : m_scenarios)
    {
        const auto more = sc.inputFiles();
        files.insert(files.end(), more.begin(), more.end());
    }
    return files;
}

std::vector<size_t> Benchmark::readVariants(const mrpt::config::CConfigFileBase& ini)
{
    const auto& o = m_options;
    checkSweepKey();
    // A sweep: each variant once per value, the value overlaid on its ini.
    const bool swept = !o.sweep.key.empty();
    const auto values = swept ? o.sweep.values : std::vector<std::string>{std::string()};
    const std::string mapFile = mapFromWorld() ? m_simulation.simulation.world_file : std::string();
    std::vector<size_t> reference;  // per variant: the first one of its sweep value
    const bool closedLoop = o.controls.size() > 1 || o.controls.front() != "route";
    for (const auto& name : o.variants)
    {
        const std::string path = variantIniPath(ini, m_iniPath, o.variants_dir, name);
        if (swept)
        {
            (void)readVariant(name, path, mapFile, m_variantOverlay);  // errors of its file
        }
        for (size_t i = 0; i < values.size(); i++)
        {
            TVariant v =
                swept ? readSweptVariant(name, path, mapFile, m_variantOverlay, o.sweep, values[i])
                      : readVariant(name, path, mapFile, m_variantOverlay);
            for (const auto& w : m_variants)
            {
                if (w.name() == v.name())
                {
                    THROW_EXCEPTION("ini [" + kSection + "] variants: '" + v.name() +
                                    "' appears twice");
                }
            }
            if (closedLoop && !v.maps.map->mapByClass<CSemanticMap>())
            {
                THROW_EXCEPTION("ini [" + kSection + "] controls: the variant '" + v.name() +
                                "' has no semantic map for the active and random controls to "
                                "plan in (keep them to variants with a semanticMap)");
            }
            reference.push_back(i);  // the first variant's of value i
            m_variants.push_back(std::move(v));
        }
    }
    if (m_variants.empty())
    {
        THROW_EXCEPTION("ini [" + kSection + "] variants: empty");
    }
    return reference;
}

void Benchmark::loadVariants(const mrpt::config::CConfigFileBase& ini)
{
    const auto& o = m_options;
    const auto referenceOf = readVariants(ini);
    checkMaps();

    // Only the likelihood differs between variants: the first one's filter for all (with a
    // sweep, the first one's of the same value: a swept filter key stays swept).
    std::vector<LocalizationExperiment::TOptions> references;
    references.reserve(referenceOf.size());
    for (const size_t r : referenceOf)
    {
        references.push_back(m_variants[r].options);
    }
    // The keys set below for every variant are keySetByBenchmark()'s: a sweep of one is refused.
    for (size_t k = 0; k < m_variants.size(); k++)
    {
        auto& v = m_variants[k];
        if (o.same_filter)
        {
            takeFilterOf(references[k], v);
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
            v.options.filter.recovery.trigger = RecoveryTrigger::Amcl;
            v.options.filter.recovery.alpha_slow = m_scenario.recovery_alpha_slow;
            v.options.filter.recovery.alpha_fast = m_scenario.recovery_alpha_fast;
        }
        if (m_scenario.init_PDF_mode >= 0)
        {
            v.options.filter.init_PDF_mode =
                static_cast<Localizer::InitMode>(m_scenario.init_PDF_mode);
        }
        const auto& f = v.options.filter;
        if (f.init_PDF_mode == Localizer::InitMode::Box &&
            !(f.init_PDF_min_x < f.init_PDF_max_x && f.init_PDF_min_y < f.init_PDF_max_y))
        {
            THROW_EXCEPTION("variant '" + v.name() +
                            "': init_PDF_mode = 1 (uniform in a box) needs a non-empty "
                            "init_PDF box");
        }
        if (v.options.filter.init_PDF_mode == Localizer::InitMode::FromDetections &&
            !v.maps.map->mapByClass<CSemanticMap>())
        {
            THROW_EXCEPTION("variant '" + v.name() +
                            "': init_PDF_mode = 3 (from the first detections) needs a "
                            "semanticMap in its [MetricMap]");
        }
    }
    checkSweepValuesDiffer();
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

}  // namespace semloc

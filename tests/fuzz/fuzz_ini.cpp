/* semloc — libFuzzer target: ini text -> semloc's ini check (config::checkIniText) and option
 * loaders (docs/testing.md, "Fuzzing"): [LocalizationExperiment] with the filter's sections,
 * [MetricMap] and its map sections (semanticMap, structureMap and MRPT's own maps),
 * semloc-simulate's sections and [Benchmark]. Each loader must accept or throw; what it accepted
 * must be written out as an effective configuration that loads again to the same text (what the
 * tools' config.ini promises). The maps are filled from the shipped paper world (read once); run
 * from config/ so that the seeds' relative paths (../maps/...) resolve as they do next to the ini
 * files. */
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/simulator/Simulator.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <unordered_set>

namespace
{
/** Runs `load` on `ini`; if it succeeds, `save` then `load` again on the saved text must
 *  succeed and save the same text. */
template <class OPTIONS>
void loadAndRoundTrip(
    const mrpt::config::CConfigFileBase& ini,
    const std::function<void(OPTIONS&, const mrpt::config::CConfigFileBase&)>& load,
    const std::function<void(const OPTIONS&, mrpt::config::CConfigFileBase&)>& save)
{
    OPTIONS o;
    try
    {
        load(o, ini);
    }
    catch (const std::exception&)
    {
        return;  // rejected with a message
    }
    mrpt::config::CConfigFileMemory saved;
    save(o, saved);
    const std::string text = saved.getContent();
    // An effective configuration already round-tripped needs it no more: many inputs load to
    // the same options (a mutated comment, a key another section's loader ignores). The cache
    // is bounded (cleared when full), per options class.
    static std::unordered_set<std::string> verified;
    if (verified.count(text) != 0)
    {
        return;
    }
    // Reloaded from the text, as a user reruns a tool's config.ini (MRPT's CConfigFileMemory
    // does not read back keys it wrote with a comment until its text is parsed again).
    OPTIONS again;
    load(again, mrpt::config::CConfigFileMemory(text));  // a throw is a finding
    mrpt::config::CConfigFileMemory savedAgain;
    save(again, savedAgain);
    if (const std::string textAgain = savedAgain.getContent(); textAgain != text)
    {
        std::cerr << "effective configuration changed on reloading:\n"
                  << text << "\n---- reloaded:\n"
                  << textAgain << "\n";
        std::abort();
    }
    if (verified.size() >= 2000)
    {
        verified.clear();
    }
    verified.insert(text);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    // The tools' check of an ini file's lines (blank, comment, section, key = value, each key
    // once, a leading byte-order mark): it must accept or throw. The loaders below run either
    // way, as they do on ini text that did not come from a file.
    bool checked = true;
    try
    {
        semloc::config::checkIniText(text, "fuzz.ini");
    }
    catch (const std::exception&)
    {
        checked = false;
    }
    // MRPT's own reader may refuse the text (an unclosed ${...}): only text the check refused.
    std::optional<mrpt::config::CConfigFileMemory> parsed;
    try
    {
        parsed.emplace(text);
    }
    catch (const std::exception& e)
    {
        if (checked)
        {
            std::cerr << "accepted by checkIniText, refused by MRPT's reader: " << e.what() << "\n";
            std::abort();
        }
        return 0;
    }
    const mrpt::config::CConfigFileMemory& ini = *parsed;
    using Experiment = semloc::LocalizationExperiment::TOptions;
    loadAndRoundTrip<Experiment>(
        ini,
        [](Experiment& o, const auto& c) { o.loadFromConfigFile(c, "LocalizationExperiment"); },
        [](const Experiment& o, auto& c) { o.saveToConfigFile(c, "LocalizationExperiment"); });
    using Simulation = semloc::TSimulatorOptions;
    loadAndRoundTrip<Simulation>(
        ini, [](Simulation& o, const auto& c) { o.loadFromConfigFile(c); },
        [](const Simulation& o, auto& c) { o.saveToConfigFile(c); });
    using Bench = semloc::Benchmark::TOptions;
    loadAndRoundTrip<Bench>(
        ini, [](Bench& o, const auto& c) { o.loadFromConfigFile(c, "Benchmark"); },
        [](const Bench& o, auto& c) { o.saveToConfigFile(c, "Benchmark"); });
    // The map file, loaded once: the maps of each input are built on this world.
    static const std::string mapFile = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
    static const semloc::World world = semloc::World::FromFile(mapFile);
    try
    {
        (void)semloc::LocalizationMap::FromConfig(ini, world, mapFile);
    }
    catch (const std::exception&)
    {
    }
    return 0;
}

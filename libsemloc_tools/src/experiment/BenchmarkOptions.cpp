/* semloc — Benchmark's [Benchmark] section: its keys read strictly, the sweep, the controls. */
#include <mrpt/core/exceptions.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ConfigHelpers.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <optional>

#include "experiment/BenchmarkLists.h"
#include "experiment/ClosedLoop.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
using detail::joinList;
using detail::readList;
using detail::splitList;
using detail::trim;
const std::vector<std::string> kKeys = {
    "runs",      "variants",       "variants_dir", "simulate_ini", "output_dir",
    "jobs",      "filter_threads", "max_steps",    "particles",    "same_filter",
    "scenarios", "map_from_world", "controls",     "sweep"};

const std::string kActiveSection = "ActiveLocalization";

/** `v` as a number when the whole of it reads as one (strtod: 0.5, 0.50 and 5e-1 alike). */
std::optional<double> asNumber(const std::string& v)
{
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    return !v.empty() && *end == '\0' ? std::optional<double>(d) : std::nullopt;
}

/** Throws `bad` when the i-th value is an earlier one again, as text or as a number. */
template <typename Bad>
void checkNotTwice(const std::vector<std::string>& values, size_t i, const Bad& bad)
{
    const auto& v = values[i];
    for (size_t j = 0; j < i; j++)
    {
        if (values[j] == v)
        {
            bad("the value '" + v + "' appears twice");
        }
        const auto a = asNumber(values[j]), b = asNumber(v);
        if (a && b && *a == *b)
        {
            bad("the values '" + values[j] + "' and '" + v + "' are one number");
        }
    }
}

/** [Benchmark] sweep: "SECTION.KEY: v1, v2, ..." (values without blanks, none twice). */
Benchmark::TOptions::TSweep readSweep(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    const std::string text = trim(c.read_string(s, "sweep", ""));
    Benchmark::TOptions::TSweep w;
    if (text.empty())
    {
        return w;
    }
    const auto colon = text.find(':');
    const std::string target = trim(text.substr(0, colon));
    const auto dot = target.rfind('.');
    const auto bad = [&](const std::string& why)
    {
        THROW_EXCEPTION("ini [" + s + "] sweep: '" + text + "': " + why +
                        " (SECTION.KEY: value, value, ...)");
    };
    if (colon == std::string::npos || dot == std::string::npos || dot == 0 ||
        dot + 1 == target.size() || target.find_first_of(" \t[]") != std::string::npos)
    {
        bad("not a section and key followed by values");
    }
    w.section = target.substr(0, dot);
    w.key = target.substr(dot + 1);
    w.values = splitList(text.substr(colon + 1));
    for (size_t i = 0; i < w.values.size(); i++)
    {
        const auto& v = w.values[i];
        if (v.empty() || v.find_first_of(" \t") != std::string::npos)
        {
            bad("a value is empty or holds a blank");
        }
        checkNotTwice(w.values, i, bad);
    }
    return w;
}

}  // namespace

std::string Benchmark::TOptions::TSweep::text() const
{
    std::string s = section + "." + key + ":";
    for (size_t i = 0; i < values.size(); i++)
    {
        s += (i == 0 ? " " : ", ") + values[i];
    }
    return s;
}

std::string Benchmark::TOptions::TSweep::error(const std::string& why) const
{
    return "ini [Benchmark] sweep: '" + text() + "': " + why;
}

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
    variants_dir = trim(c.read_string(s, "variants_dir", variants_dir));
    simulate_ini = trim(c.read_string(s, "simulate_ini", simulate_ini));
    output_dir = trim(c.read_string(s, "output_dir", output_dir));
    readInt(c, s, "jobs", jobs, 0, 4096);
    readInt(c, s, "filter_threads", filter_threads, 0, 4096);
    readInt(c, s, "max_steps", max_steps, 0, std::numeric_limits<int>::max());
    readInt(c, s, "particles", particles, 0, 100000000);
    readBool(c, s, "same_filter", same_filter);
    readBool(c, s, "map_from_world", map_from_world);
    if (c.keyExists(s, "controls"))
    {
        controls = readList(c, s, "controls");
        if (controls.empty())
        {
            THROW_EXCEPTION("ini [" + s + "] controls: empty (route, active, random)");
        }
        const auto& known = detail::controlNames();
        for (size_t i = 0; i < controls.size(); i++)
        {
            if (std::find(known.begin(), known.end(), controls[i]) == known.end())
            {
                THROW_EXCEPTION("ini [" + s + "] controls: '" + controls[i] +
                                "' is not one of route, active, random");
            }
            if (std::find(controls.begin(), controls.begin() + static_cast<long>(i), controls[i]) !=
                controls.begin() + static_cast<long>(i))
            {
                THROW_EXCEPTION("ini [" + s + "] controls: '" + controls[i] + "' appears twice");
            }
        }
    }
    sweep = readSweep(c, s);
    if (c.sectionExists(kActiveSection))
    {
        active.loadFromConfigFile(c, kActiveSection);
    }
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
    c.write(s, "variants_dir", variants_dir);
    c.write(s, "simulate_ini", simulate_ini);
    c.write(s, "output_dir", output_dir);
    c.write(s, "jobs", jobs);
    c.write(s, "filter_threads", filter_threads);
    c.write(s, "max_steps", max_steps);
    c.write(s, "particles", particles);
    c.write(s, "same_filter", same_filter ? "true" : "false");
    c.write(s, "scenarios", joinList(scenarios));
    c.write(s, "map_from_world", map_from_world ? "true" : "false");
    c.write(s, "controls", joinList(controls));
    c.write(s, "sweep",
            sweep.key.empty() ? std::string()
                              : sweep.section + "." + sweep.key + ": " + joinList(sweep.values));
    active.saveToConfigFile(c, kActiveSection);
}

}  // namespace semloc

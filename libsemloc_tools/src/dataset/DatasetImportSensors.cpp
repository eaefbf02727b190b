/* semloc — DatasetImport: semloc-import's options (docs/tools.md, "semloc-import"), the
 * detectors' coverage and mount by sensor among them. */
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/Text.h"

namespace semloc
{
namespace
{
/** The numbers of `text`, separated by commas (each trimmed; finite), or none if one is not
 *  a number. */
std::vector<double> numbers(const std::string& text)
{
    std::vector<double> out;
    size_t b = 0;
    for (;;)
    {
        const size_t e = text.find(',', b);
        const std::string cell =
            detail::trim(text.substr(b, e == std::string::npos ? std::string::npos : e - b));
        char* end = nullptr;
        const double v = std::strtod(cell.c_str(), &end);
        if (cell.empty() || *end != '\0' || !std::isfinite(v))
        {
            return {};
        }
        out.push_back(v);
        if (e == std::string::npos)
        {
            return out;
        }
        b = e + 1;
    }
}

/** The form an option's value takes, for its messages. */
std::string optionForm(const std::string& option)
{
    if (option == "--sensor-pose")
    {
        return "[NAME=]x,y,yaw_deg[,z_m] (three or four numbers)";
    }
    return option == "--fov-deg" ? "[NAME=]F, F a number [deg]" : "[NAME=]R, R a number [m]";
}

/** One value of `--max-range-m`, `--fov-deg` or `--sensor-pose`: its sensor (none: every
 *  sensor) and its numbers. */
struct SensorValue
{
    std::optional<std::string> name;
    std::vector<double> numbers;
};

/** The value `text` of `option` ("[NAME=]NUMBERS"); throws naming both when malformed. */
SensorValue sensorValue(const std::string& option, const std::string& text)
{
    const std::string quoted = option + " '" + shownValue(text) + "': ";
    const size_t eq = text.find('=');
    SensorValue v;
    if (eq != std::string::npos)
    {
        v.name = detail::trim(text.substr(0, eq));
        if (const std::string p = labelProblem(*v.name); !p.empty())
        {
            THROW_EXCEPTION(quoted + "sensor " + p);
        }
    }
    v.numbers = numbers(eq == std::string::npos ? text : text.substr(eq + 1));
    const size_t n = v.numbers.size();
    if (option == "--sensor-pose" ? n != 3 && n != 4 : n != 1)
    {
        THROW_EXCEPTION(quoted + "expected " + optionForm(option));
    }
    return v;
}

/** Throws: `text`, a value of `option`, names a sensor (or every sensor) a previous one did. */
[[noreturn]] void givenTwice(const std::string& option, const std::string& text,
                             const std::optional<std::string>& name)
{
    THROW_EXCEPTION(option + " '" + shownValue(text) + "': given twice for " +
                    (name ? "sensor " + *name : "every sensor (the form without NAME=)"));
}

/** The warning of a sensor `name` the options `o` name and no detection row has (`list`: the
 *  detections' sensors). */
std::string unusedSensorWarning(const std::string& name, const TImportSensorOverride& o,
                                const std::string& list)
{
    std::string given;
    for (const auto& [opt, set] : {std::pair{"--max-range-m", o.maxRange_m.has_value()},
                                   {"--fov-deg", o.fov_deg.has_value()},
                                   {"--sensor-pose", o.pose.has_value()}})
    {
        if (set)
        {
            given += given.empty() ? "" : ", ";
            given.append(opt).append(" ").append(name).append("=");
        }
    }
    return given + ": no detection row is of sensor '" + name +
           "' (the detections' sensors: " + list + "): not used";
}

/** Throws "OPTION WHO: must be WHAT" unless `ok`. */
void require(bool ok, const std::string& option, const std::string& who, const std::string& what)
{
    if (!ok)
    {
        THROW_EXCEPTION(option + " " + who + ": must be " + what);
    }
}

/** Checks a sensor's coverage and mount; `prefix` is "" (the defaults) or "NAME=". */
void checkSensor(const std::string& prefix, const std::optional<double>& maxRange,
                 const std::optional<double>& fov, const std::optional<mrpt::math::TPose2D>& pose,
                 double z)
{
    if (maxRange)
    {
        require(*maxRange > 0 && *maxRange <= kMaxWorldCoordinate_m, "--max-range-m",
                prefix + detail::shortestText(*maxRange), "a finite number in (0, 1e7] [m]");
    }
    if (fov)
    {
        require(*fov > 0 && *fov <= 360, "--fov-deg", prefix + detail::shortestText(*fov),
                "in (0, 360] [deg]");
    }
    const std::string who = prefix.empty() ? "" : " " + prefix.substr(0, prefix.size() - 1);
    if (pose &&
        !(std::abs(pose->x) <= 1000 && std::abs(pose->y) <= 1000 && std::isfinite(pose->phi)))
    {
        THROW_EXCEPTION("--sensor-pose" + who +
                        ": x and y must be finite and within 1000 m of the vehicle");
    }
    if (pose && !(std::abs(z) <= 1000))
    {
        THROW_EXCEPTION("--sensor-pose" + who +
                        ": z must be finite and within 1000 m of the vehicle");
    }
}
}  // namespace

void TDatasetImportOptions::check() const
{
    auto bad = [](const std::string& opt, double v, const std::string& what)
    { THROW_EXCEPTION(opt + " " + detail::shortestText(v) + ": must be " + what); };
    checkSensor("", maxRange_m, fov_deg, std::nullopt, 0);
    if (!(maxStep_s > 0 && maxStep_s <= 1e6))
    {
        bad("--max-step-s", maxStep_s, "in (0, 1e6] [s]");
    }
    if (!(margin_m >= 0 && margin_m <= kMaxWorldCoordinate_m))
    {
        bad("--margin-m", margin_m, "a finite number in [0, 1e7] [m]");
    }
    if (!(scanWindow_s >= 0 && scanWindow_s <= 1))
    {
        bad("--scan-window-s", scanWindow_s, "in [0, 1] [s]");
    }
    if (!(gtMaxGap_s >= 0 && gtMaxGap_s <= 1e6))
    {
        bad("--gt-max-gap-s", gtMaxGap_s, "in [0, 1e6] [s] (0: the default)");
    }
    checkSensor("", std::nullopt, std::nullopt, sensorPose, sensorZ_m);
    for (const auto& [name, o] : sensors)
    {
        if (const std::string p = labelProblem(name); !p.empty())
        {
            THROW_EXCEPTION("sensor '" + shownValue(name) + "' of the options: " + p);
        }
        checkSensor(name + "=", o.maxRange_m, o.fov_deg, o.pose, o.z_m);
    }
}

TImportSensor TDatasetImportOptions::sensor(const std::string& label) const
{
    TImportSensor s{maxRange_m, fov_deg, sensorPose, sensorZ_m};
    const auto it = sensors.find(label);
    if (it != sensors.end())
    {
        const auto& o = it->second;
        s.maxRange_m = o.maxRange_m.value_or(s.maxRange_m);
        s.fov_deg = o.fov_deg.value_or(s.fov_deg);
        if (o.pose)
        {
            s.pose = *o.pose;
            s.z_m = o.z_m;
        }
    }
    return s;
}

void TDatasetImportOptions::setSensorOption(const std::string& option,
                                            const std::vector<std::string>& values)
{
    ASSERT_(option == "--max-range-m" || option == "--fov-deg" || option == "--sensor-pose");
    bool unnamed = false;
    std::set<std::string> named;
    for (const auto& text : values)
    {
        const SensorValue v = sensorValue(option, text);
        if (v.name ? !named.insert(*v.name).second : std::exchange(unnamed, true))
        {
            givenTwice(option, text, v.name);
        }
        const auto& n = v.numbers;
        TImportSensorOverride* o = v.name ? &sensors[*v.name] : nullptr;
        if (option == "--max-range-m")
        {
            (o ? o->maxRange_m.emplace() : maxRange_m) = n[0];
        }
        else if (option == "--fov-deg")
        {
            (o ? o->fov_deg.emplace() : fov_deg) = n[0];
        }
        else
        {
            (o ? o->pose.emplace() : sensorPose) = {n[0], n[1], mrpt::DEG2RAD(n[2])};
            (o ? o->z_m : sensorZ_m) = n.size() > 3 ? n[3] : 0.0;
        }
    }
}

void DatasetImport::checkSensors(const std::vector<DetectionScan>& scans,
                                 const TDatasetImportOptions& options, TDatasetImportStats& stats)
{
    std::set<std::string> seen;
    for (const auto& s : scans)
    {
        seen.insert(s.sensor);
    }
    std::string list;
    for (const auto& s : seen)
    {
        list += (list.empty() ? "" : ", ") + s;
    }
    for (const auto& [name, o] : options.sensors)
    {
        if (seen.count(name) > 0)
        {
            continue;
        }
        stats.warnings.push_back(unusedSensorWarning(name, o, list));
    }
}

}  // namespace semloc

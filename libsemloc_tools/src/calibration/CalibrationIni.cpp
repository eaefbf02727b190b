/* semloc — semloc-calibrate's output ini: the base configuration with the fitted values in
 * place, each with a comment giving its fit. */
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "calibration/IniText.h"
#include "io/Text.h"

namespace semloc
{
namespace detail
{
std::string fitComment(const TCalibrationFit& f)
{
    if (f.widenedBy != 1)
    {
        TCalibrationFit fitted = f;
        fitted.widenedBy = 1;
        fitted.value = f.value / f.widenedBy;
        return "calibrated: widened x" + number(f.widenedBy) +
               " by the consistency stage (fitted " + number(fitted.value) + "); " +
               fitComment(fitted).substr(std::string("calibrated: ").size());
    }
    if (f.status == TCalibrationFit::Status::Clamped)
    {
        const bool low = f.fitted < f.value;
        return "calibrated: fitted " + number(f.fitted) + " (" + f.why + "), clamped to the " +
               (low ? "smallest" : "largest") +
               " value the filter takes; n = " + std::to_string(f.n) + ", " + f.method;
    }
    if (f.value == 0 && f.ci95 == 0 && f.method.rfind("least squares (>= 0)", 0) == 0)
    {
        return "calibrated: n = " + std::to_string(f.n) + ", 0: left out of the best fit (its " +
               "regressor does not vary or its coefficient would be negative), " + f.method;
    }
    return "calibrated: n = " + std::to_string(f.n) + ", +/- " + number(f.ci95) + " (95 %), " +
           f.method;
}
}  // namespace detail

namespace
{
using detail::fitComment;
using detail::IniText;
using detail::keyLine;
using detail::keyOf;
using detail::lower;
using detail::number;
using detail::sectionOf;
using detail::trim;

const char* const kLikelihood = "MetricMap_semanticMap_00_likelihoodOpts";

std::string rangeBiasText(const TCalibrationResult& r)
{
    std::string t;
    for (const double c : r.rangeBias_m)
    {
        t += (t.empty() ? "" : ", ") + number(c);
    }
    return t.empty() ? "0" : t;
}

std::string rangeBiasComment(const TCalibrationResult& r)
{
    const std::string n = std::to_string(r.samples.rangeResiduals_m.size());
    if (r.rangeBias_m.empty())
    {
        return "calibrated: n = " + n + ", no range bias by bearing found";
    }
    std::string ci;
    for (const double c : r.rangeBiasCi95_m)
    {
        ci += (ci.empty() ? "" : ", ") + number(c);
    }
    const auto& c = r.rangeBias_m;
    return "calibrated: n = " + n + ", +/- " + ci +
           " (95 %), robust least squares of the range residuals against 1, u, u^2, u^3 (u: "
           "the bearing over half the view): " +
           number(c[0]) + " m on the axis, " + number(c[0] - c[1] + c[2] - c[3]) +
           " m at bearing -fov/2, " + number(c[0] + c[1] + c[2] + c[3]) + " m at +fov/2";
}

/** The base ini's values, and the defaults of the keys it does not set. */
class BaseValues
{
public:
    explicit BaseValues(const std::string& baseIni) : m_base(baseIni)
    {
        mrpt::config::CConfigFileMemory written;
        CSemanticMap::TLikelihoodOptions().saveToConfigFile(written, kLikelihood);
        MotionModelConfig::TOptions().saveToConfigFile(written, MotionModelConfig::kSection);
        // As text and back: MRPT reads a value written with a comment back as empty from the
        // object it was written to.
        std::string text;
        written.getContent(text);
        m_defaults.setContent(text);
    }
    /** The value of `key` and "the base ini's" or "the default" for where it comes from. */
    std::pair<std::string, std::string> of(const std::string& section, const std::string& key) const
    {
        if (m_base.keyExists(section, key))
        {
            return {trim(m_base.read_string(section, key, "")), "the base ini's value kept"};
        }
        return {trim(m_defaults.read_string(section, key, "")),
                "the default kept (the base ini does not set it)"};
    }

private:
    mrpt::config::CConfigFileMemory m_base, m_defaults;
};

void setFit(IniText& ini, const BaseValues& base, const char* section, const char* key,
            const TCalibrationFit& f)
{
    if (f.status == TCalibrationFit::Status::TooLittleData)
    {
        const auto [value, whence] = base.of(section, key);
        ini.set(section, key, value,
                "calibrated: not fitted, too little data (" + f.why + "): " + whence);
        return;
    }
    // 4 digits, unless they round out of the range the filter takes (0.99996 to 1): then
    // all of them.
    const auto range = std::string(section) == kLikelihood
                           ? CSemanticMap::TLikelihoodOptions::range(key)
                           : MotionModelConfig::TOptions::range(key);
    std::string text = number(f.value);
    if (const double back = std::stod(text); back < range.lo || back > range.hi)
    {
        text = detail::shortestText(f.value);
    }
    ini.set(section, key, text, fitComment(f));
}

/** Throws naming the file and [MetricMap] semanticMap_count when `baseIni` has no semantic
 *  map whose noise the fits could fill. */
void requireSemanticMap(const std::string& baseIni, const std::string& baseName)
{
    mrpt::config::CConfigFileMemory mem(baseIni);
    if (mem.read_int("MetricMap", "semanticMap_count", 0) < 1)
    {
        throw std::runtime_error("ini '" + baseName +
                                 "': [MetricMap] semanticMap_count: the base configuration has "
                                 "no semantic map to calibrate (needs >= 1) and no model of an "
                                 "AUV's sensors (a sideScanMap, forwardSonarMap, "
                                 "bearingCameraMap, compassMap, poseFixMap, or [MotionModel] "
                                 "kind = dvl)");
    }
}
/** The comment of `key` in `section` of the ini text `ini` ("" when it has none). */
std::string commentOf(const std::string& ini, const std::string& section, const std::string& key)
{
    std::istringstream in(ini);
    bool inSection = false;
    for (std::string line; std::getline(in, line);)
    {
        if (const std::string s = sectionOf(line); !s.empty())
        {
            inSection = lower(s) == lower(section);
        }
        else if (inSection && lower(keyOf(line)) == lower(key))
        {
            const auto c = line.find(" // ");
            return c == std::string::npos ? std::string() : trim(line.substr(c + 4));
        }
    }
    return "";
}

/** `key`'s value in the written ini `ini`, and why it is not the fit as made when it is not:
 *  its comment, less the fit's count and method. */
std::string writtenText(const std::string& ini, const mrpt::config::CConfigFileMemory& written,
                        const char* key)
{
    std::string text = trim(written.read_string(kLikelihood, key, ""));
    std::string why = commentOf(ini, kLikelihood, key);
    const std::string calibrated = "calibrated: ";
    why = why.rfind(calibrated, 0) == 0 ? why.substr(calibrated.size()) : std::string();
    why = why.substr(0, why.find("; n = "));
    if (!why.empty() && why.rfind("n = ", 0) != 0)
    {
        text += " (" + why + ")";
    }
    return text;
}
}  // namespace

std::string SensorCalibration::SummaryText(const TCalibrationResult& r, const std::string& ini)
{
    const mrpt::config::CConfigFileMemory written(ini);
    const auto value = [&](const char* key) { return writtenText(ini, written, key); };
    std::string t = std::to_string(r.scans) + " scans, " + std::to_string(r.increments) +
                    " odometry increments: sigma_range_m " + value("sigma_range_m") +
                    ", sigma_bearing_deg " + value("sigma_bearing_deg") + ", p_detect " +
                    value("p_detect_near") + " .. " + value("p_detect_far") +
                    ", clutter_per_scan " + value("clutter_per_scan") + ", p_confusion " +
                    value("p_confusion") + ", p_range_outlier " + value("p_range_outlier");
    if (r.a1.status == TCalibrationFit::Status::TooLittleData)
    {
        t += ", [MotionModel] the base ini's (not fitted, too little data (" + r.a1.why + "))";
    }
    return t;
}

void SensorCalibration::ReadBaseOptions(const std::string& baseIni, TOptions& o)
{
    const mrpt::config::CConfigFileMemory base(baseIni);
    const CSemanticMap::TLikelihoodOptions defaults;
    o.lookAlikeSpeed_mps = base.read_double(kLikelihood, "lookalike_speed_mps",
                                            defaults.lookalike.lookalike_speed_mps);
    o.lookAlikeWindow_s =
        base.read_double(kLikelihood, "lookalike_window_s", defaults.lookalike.lookalike_window_s);
}

void SensorCalibration::CheckBase(const std::string& basePath, const std::string& worldPath)
{
    LocalizationExperiment::CheckConfig(basePath, worldPath);
    requireSemanticMap(config::readIniText(basePath), basePath);
}

std::string SensorCalibration::ApplyToIni(const std::string& baseIni, const std::string& baseName,
                                          const TCalibrationResult& r, const std::string& worldPath)
{
    requireSemanticMap(baseIni, baseName);
    IniText ini(baseIni, baseName);
    const BaseValues base(baseIni);
    const std::string header = std::string(kIniHeader) + "the fits written into " + baseName + "\n";
    if (!worldPath.empty())
    {
        ini.set("LocalizationExperiment", "map_file",
                std::filesystem::absolute(worldPath).lexically_normal().string(),
                "calibrated: the world the fits were made in");
    }
    ini.set(kLikelihood, "model", "probabilistic", "calibrated: the model the fits are for");
    using Fit = std::pair<const char*, const TCalibrationFit*>;
    for (const auto& [key, fit] :
         {Fit{"sigma_range_m", &r.sigma_range_m}, Fit{"sigma_bearing_deg", &r.sigma_bearing_deg},
          Fit{"p_detect_near", &r.p_detect_near}, Fit{"p_detect_far", &r.p_detect_far},
          Fit{"p_detect_edge_ratio", &r.p_detect_edge_ratio},
          Fit{"clutter_per_scan", &r.clutter_per_scan}, Fit{"p_confusion", &r.p_confusion},
          Fit{"p_range_outlier", &r.p_range_outlier},
          Fit{"lookalike_persistence", &r.lookalike_persistence}})
    {
        setFit(ini, base, kLikelihood, key, *fit);
    }
    ini.set(kLikelihood, "range_bias_m", rangeBiasText(r), rangeBiasComment(r));
    if (r.temper != 1)
    {
        const double basePow =
            mrpt::config::CConfigFileMemory(baseIni).read_double("PF_options", "powFactor", 1.0);
        ini.set("PF_options", "powFactor", number(basePow * r.temper),
                "calibrated: the likelihood tempered x" + number(r.temper) +
                    " by the consistency stage (the base's " + number(basePow) + ")");
    }
    const char* mm = MotionModelConfig::kSection;
    if (mrpt::config::CConfigFileMemory(baseIni).read_string(mm, "kind", "") == "dvl")
    {
        // The DVL's model is not MRPT's Gaussian one: SensorModelCalibration fits it.
        return header + ini.text();
    }
    if (r.a1.status == TCalibrationFit::Status::TooLittleData)
    {
        const std::string why = "semloc-calibrate: not fitted, too little data (" + r.a1.why +
                                "): the base ini's [" + std::string(mm) + "] kept";
        const bool noted = ini.note(mm, why);  // else in the header
        return header + (noted ? "" : "// " + why + "\n") + ini.text();
    }
    ini.set(mm, "source", "gaussian", "calibrated: the model below, from the odometry's errors");
    for (const auto& [key, fit] :
         {Fit{"a1", &r.a1}, Fit{"a2", &r.a2}, Fit{"a3", &r.a3}, Fit{"a4", &r.a4},
          Fit{"minStdXY", &r.minStdXY}, Fit{"minStdPHI", &r.minStdPHI}})
    {
        setFit(ini, base, mm, key, *fit);
    }
    // A drift is the run's own (a gyro's bias changes from one power-up to the next): what
    // carries over to another run is that it drifts, so the drift state is turned on with
    // semantic.ini's walk, not set to the rate measured here.
    const auto& d = r.heading_drift_deg_per_min;
    const std::string measured = number(d.value) + " +/- " + number(d.ci95) + " deg/min";
    ini.set(mm, "heading_drift_std_deg_per_min", "0",
            "calibrated: each particle's drift rate starts at 0");
    ini.set(
        mm, "heading_drift_walk_deg_per_min",
        r.headingDrifts ? number(MotionModelConfig::TOptions::kCalibratedDriftWalkDegPerMin) : "0",
        r.headingDrifts ? "calibrated: the heading drifts " + measured + ": the drift state on"
                        : "calibrated: no heading drift (" + measured + "): the drift state off");
    const auto& delay = r.odometry_delay_s;
    const std::string rms = number(r.odomHeadingRms_deg) + " deg RMS per increment";
    ini.set(mm, "odometry_delay_s", number(delay.value),
            delay.value > 0
                ? "calibrated: n = " + std::to_string(delay.n) + ", +/- " + number(delay.ci95) +
                      " (95 %), heading errors " + rms + " as they come, " +
                      number(r.odomHeadingRmsDelayed_deg) + " re-cut; " + delay.method
                : "calibrated: no delay found (heading errors " + rms + "); " + delay.method);
    return header + ini.text();
}

}  // namespace semloc

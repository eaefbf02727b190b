/* semloc — SensorModelCalibration's output: the fits in the calibrated ini, the summary and
 * the warnings. */
#include <semloc/calibration/SensorModelCalibration.h>

#include <semloc/io/StagedDirectory.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "calibration/IniText.h"
#include "io/Text.h"

namespace semloc
{
std::string SensorModelCalibration::ApplyToIni(const std::string& ini, const std::string& name,
                                               const std::vector<TModelFits>& fits,
                                               const std::string& worldPath)
{
    detail::IniText text(ini, name);
    if (!worldPath.empty())
    {
        text.set("LocalizationExperiment", "map_file",
                 std::filesystem::absolute(worldPath).lexically_normal().string(),
                 "calibrated: the world the fits were made in");
    }
    std::string unplaced;  // notes of sections the text does not have
    for (const auto& m : fits)
    {
        for (const auto& [key, f] : m.keys)
        {
            if (f.status == TCalibrationFit::Status::TooLittleData)
            {
                const std::string why = "semloc-calibrate: [" + m.section + "] " + key +
                                        " not fitted, too little data (" + f.why +
                                        "): the base ini's value kept";
                if (!text.note(m.section, why))
                {
                    unplaced += "// " + why + "\n";
                }
                continue;
            }
            // 4 digits, unless they round to 0 (a rate of 1e-5): then all of them.
            std::string value = detail::number(f.value);
            if (std::stod(value) == 0 && f.value != 0)
            {
                value = detail::shortestText(f.value);
            }
            text.set(m.section, key, value, detail::fitComment(f));
        }
    }
    return unplaced + text.text();
}

std::string SensorModelCalibration::SummaryText(const std::vector<TModelFits>& fits)
{
    std::string t;
    for (const auto& m : fits)
    {
        t += m.name + ": " + std::to_string(m.samples) + " " + m.unit + ":";
        const char* sep = " ";
        for (const auto& [key, f] : m.keys)
        {
            t += sep + key + " " +
                 (f.status == TCalibrationFit::Status::TooLittleData ? "(not fitted)"
                                                                     : detail::number(f.value));
            if (f.status == TCalibrationFit::Status::Clamped)
            {
                t += " (clamped from " + detail::number(f.fitted) + ")";
            }
            sep = ", ";
        }
        t += "\n";
    }
    return t;
}

std::vector<std::string> SensorModelCalibration::Warnings(const std::vector<TModelFits>& fits)
{
    std::vector<std::string> w;
    for (const auto& m : fits)
    {
        for (const auto& [key, f] : m.keys)
        {
            if (f.status == TCalibrationFit::Status::TooLittleData)
            {
                w.push_back(m.name + " " + key + ": not fitted, too little data (" + f.why +
                            "): the base ini's value kept");
            }
            else if (f.status == TCalibrationFit::Status::Clamped)
            {
                w.push_back(m.name + " " + key + ": fitted " + detail::number(f.fitted) + " (" +
                            f.why + "), clamped to " + detail::number(f.value));
            }
        }
    }
    return w;
}

std::vector<TFigureWarning> SensorModelCalibration::WriteReport(const std::vector<TModelFits>& fits,
                                                                StagedDirectory& out)
{
    std::ofstream f(out.path("report.md"), std::ios::binary);
    f << "# semloc-calibrate: the sensor models' fits\n\n";
    for (const auto& m : fits)
    {
        f << "## " << m.name << " ([" << m.section << "], " << m.samples << " " << m.unit
          << ")\n\n| key | value | fit |\n| --- | --- | --- |\n";
        for (const auto& [key, fit] : m.keys)
        {
            const bool made = fit.status != TCalibrationFit::Status::TooLittleData;
            f << "| `" << key << "` | " << (made ? detail::number(fit.value) : "not fitted")
              << " | " << (made ? detail::fitComment(fit) : fit.why) << " |\n";
        }
        f << "\n";
    }
    if (!f.flush())
    {
        throw std::runtime_error("cannot write '" + out.path("report.md") + "'");
    }
    return {};
}

}  // namespace semloc

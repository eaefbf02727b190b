/* semloc — libFuzzer target: semloc-import's ground-truth CSV (DatasetImport::readGroundTruth:
 * t,x,y,phi) (docs/testing.md, "Fuzzing"). Any input must either be read or throw naming the
 * file; accepted rows are at least one, at finite times strictly increasing, with finite
 * positions and wrapped headings, and interpolate (DatasetImport::groundTruthAtSteps, as
 * semloc-import does at its step times) to finite poses at their times and between them. */
#include <semloc/dataset/DatasetImport.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "FuzzImport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using semloc::fuzz::require;
    const auto rows =
        semloc::fuzz::readCsv(data, size,
                              [](std::istream& in, const std::string& name)
                              { return semloc::DatasetImport::readGroundTruth(in, name); });
    if (!rows)
    {
        return 0;
    }
    require(!rows->empty(), "no row");
    std::vector<double> times;
    for (const auto& r : *rows)
    {
        times.push_back(r.t);
        require(std::isfinite(r.x) && std::isfinite(r.y), "a position not finite");
        require(semloc::fuzz::wrapped(r.phi), "a heading not in [-pi, pi]");
    }
    require(semloc::fuzz::increasing(times), "times not finite and strictly increasing");
    std::vector<semloc::ImportStep> steps;
    for (size_t i = 0; i < times.size(); i++)
    {
        if (i > 0)
        {
            steps.push_back({0.5 * (times[i - 1] + times[i]), -1});
        }
        steps.push_back({times[i], -1});
    }
    for (const auto& r : semloc::DatasetImport::groundTruthAtSteps(*rows, steps, "fuzz.csv"))
    {
        require(std::isfinite(r.x) && std::isfinite(r.y) && semloc::fuzz::wrapped(r.phi),
                "the ground truth interpolated at a step is not finite");
    }
    return 0;
}

/* semloc — libFuzzer target: semloc-import's detections CSV (DatasetImport::readDetections:
 * t,label,range_m,bearing_rad, optional id, confidence) (docs/testing.md, "Fuzzing"). Any input
 * must either be read or throw naming the file; accepted scans are at least one, at finite
 * nonzero times strictly increasing (rows of one time form one scan), and every detection has
 * a valid label, a finite range >= 0, a bearing within +-4 pi, a confidence in [0, 1] and an
 * id that is -1 or positive. */
#include <semloc/dataset/DatasetImport.h>
#include <semloc/observation/Labels.h>

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
    const auto scans =
        semloc::fuzz::readCsv(data, size,
                              [](std::istream& in, const std::string& name)
                              { return semloc::DatasetImport::readDetections(in, name); });
    if (!scans)
    {
        return 0;
    }
    require(!scans->empty(), "no scan");
    std::vector<double> times;
    for (const auto& s : *scans)
    {
        require(s.t != 0, "a scan at time 0 (MRPT's 'no timestamp')");
        times.push_back(s.t);
        for (const auto& d : s.detections)
        {
            require(semloc::labelProblem(d.label).empty(), "an invalid label");
            require(std::isfinite(d.range_m) && d.range_m >= 0, "a range not finite and >= 0");
            require(std::abs(d.bearing_rad) <= 4 * M_PI, "a bearing beyond +-4 pi");
            require(d.confidence >= 0 && d.confidence <= 1, "a confidence not in [0, 1]");
            require(d.object_id == -1 || d.object_id > 0, "an id neither -1 nor positive");
        }
    }
    require(semloc::fuzz::increasing(times), "scan times not finite and strictly increasing");
    return 0;
}

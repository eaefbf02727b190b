/* semloc tests — one localization run of a test: an ini on a rawlog into an output directory,
 * with the test's particle count (semloc-localize's -n, -t, --trace-detections). */
#pragma once

#include <semloc/experiment/LocalizationExperiment.h>

#include <optional>
#include <string>

namespace semloc::test
{
/** Runs `ini` on `rawlog` into `outDir` with `particles` particles, on `threads` threads and
 *  with the detections trace when given (the ini's otherwise). */
inline LocalizationExperiment::TResult localizeRun(
    const std::string& ini, const std::string& rawlog, const std::string& outDir, int particles,
    std::optional<int> threads = std::nullopt, std::optional<bool> detectionsTrace = std::nullopt)
{
    LocalizationExperiment::TOverrides ov;
    ov.rawlog_file = rawlog;
    ov.logOutput_dir = outDir;
    ov.particles_count = particles;
    ov.threads = threads;
    ov.detections_trace = detectionsTrace;
    return LocalizationExperiment::FromConfigFile(ini, ov).run();
}
}  // namespace semloc::test

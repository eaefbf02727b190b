/* semloc-localize: MRPT pf-localization's configuration, our particle filter, docs/design.md's
 * outputs. semloc-localize config/localize/semantic.ini [dataset.rawlog] [--threads N] [--seed S]
 * [-o DIR]
 *                   [--allow-truncated] */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>

#include <unistd.h>
#include <cstdio>
#include <iostream>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-localize", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argIni("config", "pf-localization style ini file", true, "",
                                             "config.ini", cmd);
TCLAP::UnlabeledValueArg<std::string> argRawlog(
    "rawlog", "Dataset; overrides [LocalizationExperiment] rawlog_file", false, "",
    "dataset.rawlog", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output-dir", "Overrides logOutput_dir", false, "", "dir",
                                    cmd);
TCLAP::ValueArg<int> argThreads("t", "threads", "Overrides [PF_options] threads (0: all cores)",
                                false, 0, "N", cmd);
TCLAP::ValueArg<int> argParticles("n", "particles", "Overrides particles_count", false, 0, "N",
                                  cmd);
TCLAP::ValueArg<long long> argSeed("s", "seed", "Overrides seed", false, 1, "S", cmd);
TCLAP::ValueArg<int> argSaveParticles(
    "", "save-particles",
    "Write the particles of every N-th step and of the last to particles.csv "
    "(overrides particles_save_every; 0: none)",
    false, 0, "N", cmd);
TCLAP::SwitchArg argTraceDetections(
    "", "trace-detections",
    "Write detections.csv: what each semantic detection adds to the weight at the estimate "
    "and at the true pose (sets detections_trace)",
    cmd);
TCLAP::SwitchArg argQuiet("q", "quiet", "No progress bar and no summary", cmd);
TCLAP::SwitchArg argAllowTruncated(
    "", "allow-truncated",
    "Localize with the intact entries before a truncated or corrupted one (else an error)", cmd);

/** A one-line progress bar on a terminal, nothing in a pipe. */
void showProgress(size_t done, size_t total)
{
    static int last = -1;
    const int pct = total ? static_cast<int>(100 * done / total) : 100;
    if (pct == last)
    {
        return;
    }
    last = pct;
    const int width = 40, filled = pct * width / 100;
    std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), pct);
    if (done == total)
    {
        std::fprintf(stderr, "\n");
    }
    std::fflush(stderr);
}

void run()
{
    semloc::LocalizationExperiment::TOverrides ov;
    ov.rawlog_file = argRawlog.getValue();
    ov.logOutput_dir = argOut.getValue();
    if (argThreads.isSet())
    {
        ov.threads = argThreads.getValue();
    }
    if (argParticles.isSet())
    {
        ov.particles_count = argParticles.getValue();
    }
    if (argSeed.isSet())
    {
        ov.seed = semloc::apps::seedOption(argSeed.getValue());
    }
    if (argSaveParticles.isSet())
    {
        ov.particles_save_every = argSaveParticles.getValue();
    }
    if (argTraceDetections.isSet())
    {
        ov.detections_trace = true;
    }
    ov.allow_truncated = argAllowTruncated.isSet();
    const auto experiment = semloc::LocalizationExperiment::FromConfigFile(argIni.getValue(), ov);
    for (const auto& w : experiment.warnings())
    {
        std::cerr << "semloc-localize: warning: " << w << "\n";
    }
    const bool bar = !argQuiet.isSet() && ::isatty(::fileno(stderr));
    semloc::installInterruptHandlers();  // Ctrl-C: exit 130, no output directory
    semloc::LocalizationExperiment::TResult result;
    try
    {
        // The steps are streamed to steps.csv: memory does not grow with the rawlog's length.
        result = experiment.run(bar ? showProgress : std::function<void(size_t, size_t)>(),
                                semloc::LocalizationExperiment::Records::Stream);
    }
    catch (const semloc::Interrupted&)
    {
        if (bar)
        {
            std::cerr << "\n";  // end the progress bar's line before the message
        }
        throw;
    }
    if (!argQuiet.isSet())
    {
        std::cout << result.summaryParagraph() << "\n";
    }
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-localize", run);
}

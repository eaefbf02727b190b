/* semloc-plot-run: the figures of one semloc-localize run (world, true path, estimate,
 * particle clouds, error and spread over time, an animated GIF of the particles).
 *   semloc-plot-run out/semantic -o out/semantic_figures [--steps 0,50,430] */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/exceptions.h>
#include <semloc/experiment/RunPlot.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-plot-run", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argRun("run", "A semloc-localize output directory", true, "",
                                             "run_dir", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output-dir", "Directory of the figures to write", true,
                                    "", "dir", cmd);
TCLAP::ValueArg<std::string> argWorld("w", "world",
                                      "World YAML to draw (default: the run's map_file)", false, "",
                                      "world.yaml", cmd);
TCLAP::ValueArg<std::string> argSteps(
    "", "steps", "Steps whose particle clouds run.png shows, comma-separated (saved steps)", false,
    "", "a,b,c", cmd);
TCLAP::ValueArg<int> argSize("s", "size", "Width of run.png and error.png [px]", false, 900, "px",
                             cmd);
TCLAP::ValueArg<int> argGifSize("", "gif-size", "Width of run.gif [px]", false, 600, "px", cmd);
TCLAP::ValueArg<int> argFrames("", "gif-frames", "Most frames of run.gif", false, 200, "N", cmd);
TCLAP::SwitchArg argNoGif("", "no-gif", "Do not draw run.gif", cmd);

std::vector<size_t> parseSteps(const std::string& text)
{
    std::vector<size_t> steps;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
    {
        char* end = nullptr;
        const long long v = std::strtoll(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || v < 0)
        {
            THROW_EXCEPTION("--steps: '" + item + "' is not a step (a whole number from 0)");
        }
        steps.push_back(static_cast<size_t>(v));
    }
    return steps;
}

void run()
{
    semloc::RunPlot::TOptions o;
    o.cloudSteps = parseSteps(argSteps.getValue());
    o.gif = !argNoGif.isSet();
    o.widthPx = argSize.getValue();
    o.gifWidthPx = argGifSize.getValue();
    if (argFrames.getValue() < 2 || argFrames.getValue() > 2000)
    {
        THROW_EXCEPTION("--gif-frames must be in [2, 2000]");
    }
    o.maxGifFrames = static_cast<size_t>(argFrames.getValue());
    // The output is checked before any input is read (the run's files are inputs).
    semloc::checkOutputDirectory(argOut.getValue(), {argRun.getValue(), argWorld.getValue()});
    const auto plot = semloc::RunPlot::FromDirectory(argRun.getValue(), argWorld.getValue());
    semloc::installInterruptHandlers("semloc-plot-run");
    const auto warnings = plot.save(argOut.getValue(), o);
    std::string drawn;
    for (const std::string f : {"run.png", "error.png", "run.gif"})
    {
        const bool wanted = f != "run.gif" || (o.gif && !plot.clouds().empty());
        const bool failed =
            std::any_of(warnings.begin(), warnings.end(),
                        [&](const semloc::TFigureWarning& w) { return w.figure == f; });
        if (wanted && !failed)
        {
            drawn += (drawn.empty() ? "" : ", ") + f;
        }
    }
    for (const auto& w : warnings)
    {
        std::cerr << "semloc-plot-run: warning: " << w.text() << "\n";
    }
    std::cout << "Wrote " << argOut.getValue() << ": " << (drawn.empty() ? "run.gp" : drawn)
              << (plot.clouds().empty() ? " (no particles.csv: semloc-localize --save-particles N "
                                          "adds the clouds and the GIF)"
                                        : "")
              << "\n";
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-plot-run", run);
}

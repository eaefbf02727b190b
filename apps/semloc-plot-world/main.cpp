/* semloc-plot-world: draws a world file (outlines, labels, trajectory) to PNG with gnuplot.
 *   semloc-plot-world maps/paper_50x50.yaml -o maps/paper_50x50.png */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/plot/WorldPlot.h>

#include <algorithm>
#include <iostream>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-plot-world", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argWorld("world", "World YAML file", true, "", "world.yaml",
                                               cmd);
TCLAP::ValueArg<std::string> argOut("o", "output", "PNG to write", true, "", "out.png", cmd);
TCLAP::ValueArg<int> argSize("s", "size", "Width in pixels (height follows the world's aspect)",
                             false, 900, "px", cmd);
TCLAP::SwitchArg argKeep("k", "keep-script", "Keep the gnuplot script and data beside the PNG",
                         cmd);

void run()
{
    if (argSize.getValue() < 100 || argSize.getValue() > 10000)
    {
        THROW_EXCEPTION("--size must be in [100, 10000]");
    }
    semloc::WorldPlot::checkPngOutputs(argOut.getValue(), {argWorld.getValue()},
                                       argKeep.getValue());
    // Ctrl-C (or SIGTERM): gnuplot ended, exit 130, no PNG and no temporary file left.
    semloc::installInterruptHandlers("semloc-plot-world");
    const auto world = semloc::World::FromFile(argWorld.getValue());
    const auto& b = world.bounds;
    const int w = argSize.getValue();
    const int h = static_cast<int>(w * (b.y_max - b.y_min) / (b.x_max - b.x_min)) + 80;  // + legend
    semloc::WorldPlot plot(world);
    plot.addWorldTrajectory();
    plot.savePng(argOut.getValue(), w, std::clamp(h, 100, 10000), argKeep.getValue());
    std::cout << "Wrote " << argOut.getValue() << "\n";
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-plot-world", run);
}

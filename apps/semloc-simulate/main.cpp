/* semloc-simulate: a dataset for the paper's experiment (rawlog + ground truth + effective ini).
 *   semloc-simulate config/simulate/simulate.ini -o dataset.rawlog --seed 7 [--csv dataset_csv] */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/simulator/Simulator.h>

#include <iostream>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-simulate", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argIni("config",
                                             "Simulation ini (see config/simulate/simulate.ini)",
                                             true, "", "simulate.ini", cmd);
TCLAP::ValueArg<std::string> argOut(
    "o", "output",
    "Output rawlog (default: [Simulation] output_rawlog); also writes <stem>_gt.txt and <stem>.ini",
    false, "", "dataset.rawlog", cmd);
TCLAP::ValueArg<std::string> argCsv(
    "", "csv", "Also write the dataset as semloc-import's CSV files into this directory", false, "",
    "dir", cmd);
TCLAP::ValueArg<long long> argSeed("", "seed", "Random seed (default: [Simulation] seed)", false,
                                   -1, "N", cmd);

void run()
{
    auto options = semloc::TSimulatorOptions::FromConfigFile(argIni.getValue());
    if (argSeed.isSet())
    {
        options.simulation.seed = semloc::apps::seedOption(argSeed.getValue());
    }
    if (argOut.isSet())
    {
        options.simulation.output_rawlog = argOut.getValue();
    }
    // Before any work: the outputs replace neither an input nor a file of the user's.
    // Every base of the ini's chain is an input too.
    std::vector<std::string> inputs = semloc::config::iniFileAndBases(argIni.getValue());
    inputs.push_back(options.simulation.world_file);
    semloc::Simulator::checkDatasetPaths(options.simulation.output_rawlog, inputs);
    if (argCsv.isSet())
    {
        auto csvInputs = inputs;
        csvInputs.push_back(options.simulation.output_rawlog);
        semloc::checkOutputDirectory(argCsv.getValue(), csvInputs);
    }
    semloc::installInterruptHandlers();  // Ctrl-C: exit 130, no file written or half-written
    const semloc::Simulator simulator(options);
    const auto result = simulator.run();
    simulator.writeDataset(result, options.simulation.output_rawlog);
    if (argCsv.isSet())
    {
        simulator.writeCsvDataset(
            result, argCsv.getValue(),
            {argIni.getValue(), options.simulation.world_file, options.simulation.output_rawlog});
    }
    std::cout << "semloc-simulate: " << options.simulation.output_rawlog << ": " << result.summary()
              << "\n";
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-simulate", run);
}

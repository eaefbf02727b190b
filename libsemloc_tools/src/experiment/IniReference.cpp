/* semloc — iniReference(): generated from the options structs. */
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/IniReference.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/models/SensorModelRegistry.h>
#include <semloc/simulator/Simulator.h>

namespace semloc
{
std::string iniReference()
{
    mrpt::config::CConfigFileMemory c;
    // The map kinds' sections ([MetricMap] <name>_count = 1), semloc's first.
    for (const auto& kind : SensorModelRegistry::kinds())
    {
        kind->writeReference(c, "MetricMap_" + kind->name() + "_00");
    }
    // semloc-localize: [LocalizationExperiment], [PF_options], [KLD_options],
    // [DummyOdometryParams], [MotionModel]; the maps are the [MetricMap_*] sections above
    LocalizationExperiment::TOptions loc;
    loc.rawlog_file = "dataset.rawlog";
    loc.map_file = "../maps/paper_50x50.yaml";
    loc.logOutput_dir = "results/semantic";
    loc.saveToConfigFile(c, "LocalizationExperiment");
    // semloc-benchmark
    Benchmark::TOptions().saveToConfigFile(c, "Benchmark");
    // semloc-benchmark scenario files (config/benchmark/faults/*.ini): [Scenario] + simulate.ini
    // keys
    Benchmark::TScenario().saveToConfigFile(c, "Scenario");
    // semloc-simulate
    TSimulatorOptions sim;
    sim.simulation.world_file = "../maps/paper_50x50.yaml";
    sim.saveToConfigFile(c);
    return c.getContent();
}

}  // namespace semloc

/* semloc — iniReference(): generated from the options structs. */
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/experiment/IniReference.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/structure/CStructureMap.h>
#include <semloc/simulator/Simulator.h>

#include "io/ExactConfigWrite.h"

namespace semloc
{
std::string iniReference()
{
    mrpt::config::CConfigFileMemory c;
    const std::string sm = "MetricMap_semanticMap_00";
    c.write(sm + "_creationOpts", "world_file", std::string("maps/paper_50x50.yaml"), 24, 24,
            "world YAML (relative to the cwd, else to the ini)");
    CSemanticMap::TLikelihoodOptions().saveToConfigFile(c, sm + "_likelihoodOpts");
    CSemanticMap::TInsertionOptions().saveToConfigFile(c, sm + "_insertOpts");
    const std::string st = "MetricMap_structureMap_00";
    const CStructureMap::TMapDefinition sdef;
    c.write(st + "_creationOpts", "world_file", std::string("maps/paper_50x50.yaml"), 24, 24,
            "world YAML whose outlines are loaded");
    detail::writeExact(c, st + "_creationOpts", "cylinder_tolerance_m", sdef.cylinder_tolerance_m,
                       "max gap between a cylinder and its polygon [m]");
    detail::writeExact(c, st + "_creationOpts", "raycast_cell_m", sdef.raycast_cell_m,
                       "ray-casting grid cell [m] (>= 0.01), 0 = automatic");
    CStructureMap::TLikelihoodOptions().saveToConfigFile(c, st + "_likelihoodOpts");
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

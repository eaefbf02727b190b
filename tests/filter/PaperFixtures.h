/* semloc tests — the filter tests' fixtures: the simulated paper dataset and a semantic map of
 * its world. */
#pragma once

#include <mrpt/maps/CMultiMetricMap.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

namespace semloc::test
{
/** The paper trajectory's first `steps` steps, simulated with config/simulate/simulate.ini. */
inline SimulationResult simulate(int steps)
{
    auto o = TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini");
    o.simulation.max_steps = steps;
    return Simulator(o).run();
}

/** A semantic map (probabilistic model) over the world `w`. */
inline mrpt::maps::CMultiMetricMap::Ptr semanticMap(const World& w)
{
    auto sem = CSemanticMap::Create();
    sem->loadFromWorld(w);
    sem->likelihoodOptions.model = CSemanticMap::Model::Probabilistic;
    auto mm = mrpt::maps::CMultiMetricMap::Create();
    mm->maps.push_back(sem);
    return mm;
}
}  // namespace semloc::test

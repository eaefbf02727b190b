/* semloc benchmarks — semloc-simulate's engine on the paper scenario
 * (config/simulate/simulate.ini): the whole trajectory (431 steps of 61 sonar beams and one
 * detection scan) in memory, and writing the dataset (gz rawlog, ground truth, effective ini). Run:
 * build/bench/bench_Simulator Counter `per_step`: seconds per simulated step. */
#include <benchmark/benchmark.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/simulator/Simulator.h>

#include <cstdio>
#include <string>

namespace
{
const semloc::Simulator& paperSimulator()
{
    static const semloc::Simulator sim(semloc::TSimulatorOptions::FromConfigFile(
        SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini"));
    return sim;
}

void BM_SimulatePaperTrajectory(benchmark::State& state)
{
    const auto& sim = paperSimulator();
    size_t steps = 0;
    for (auto _ : state)
    {
        const auto res = sim.run();
        steps = res.steps;
        benchmark::DoNotOptimize(res.rawlog.size());
    }
    state.counters["steps"] = static_cast<double>(steps);
    state.counters["per_step"] = benchmark::Counter(
        static_cast<double>(steps),
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SimulatePaperTrajectory)->Unit(benchmark::kMillisecond);

void BM_WritePaperDataset(benchmark::State& state)
{
    const auto& sim = paperSimulator();
    const auto res = sim.run();
    const std::string path = "/tmp/semloc_bench_simulator.rawlog";
    for (auto _ : state)
    {
        sim.writeDataset(res, path);
    }
    for (const auto& f :
         {path, semloc::GroundTruthFile::PathFor(path), semloc::Simulator::configPath(path)})
    {
        std::remove(f.c_str());
    }
}
BENCHMARK(BM_WritePaperDataset)->Unit(benchmark::kMillisecond);

}  // namespace

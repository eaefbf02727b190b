/* semloc benchmarks — sonar-scan likelihood per particle: CStructureMap (exact ray casting,
 * beam model) vs MRPT's COccupancyGridMap2D (likelihood field, ray tracing) on the grid that
 * World::makeOccupancyGrid(0.1) rasterizes from the same world.
 * Run: build/bench/bench_StructureLikelihood
 * Counter `per_beam`: seconds per scan beam (60 per particle; every method uses all 60). */
#include <benchmark/benchmark.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/structure/CStructureMap.h>

#include <vector>

#include "ScanSimulation.h"

using mrpt::math::TPose2D;

namespace
{
constexpr size_t kBeams = 60;
constexpr double kMaxRange_m = 20;

/** Everything built once: the maps, the scan, the particles. */
struct Setup
{
    semloc::CStructureMap structure;
    mrpt::maps::COccupancyGridMap2D gridLF, gridRT;
    mrpt::obs::CObservation2DRangeScan scan;
    std::vector<mrpt::poses::CPose3D> particles3D;
    std::vector<TPose2D> particles;

    Setup()
    {
        const auto world = semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
        structure.loadFromWorld(world);
        gridLF = world.makeOccupancyGrid(0.1);
        gridLF.likelihoodOptions.likelihoodMethod =
            mrpt::maps::COccupancyGridMap2D::lmLikelihoodField_Thrun;
        gridLF.likelihoodOptions.LF_decimation = 1;
        gridLF.likelihoodOptions.LF_maxRange = static_cast<float>(kMaxRange_m);
        gridRT = world.makeOccupancyGrid(0.1);
        gridRT.likelihoodOptions.likelihoodMethod = mrpt::maps::COccupancyGridMap2D::lmRayTracing;
        gridRT.likelihoodOptions.rayTracing_decimation = 1;
        // A pose on the trajectory (first leg), looking at the manifold cluster.
        scan = semloc::test::simulateScan(structure.rayCaster(), TPose2D(12.5, 4.0, M_PI / 2),
                                          kBeams, kMaxRange_m, M_PI);
        mrpt::random::CRandomGenerator rng(2024);
        for (int i = 0; i < 4096; i++)
        {
            particles.push_back(world.sampleFreePose(rng));
            particles3D.emplace_back(mrpt::poses::CPose2D(particles.back()));
        }
        // Warm MRPT's caches (likelihood field, the scan's points map) outside the timing.
        for (const auto& p : particles3D)
        {
            gridLF.computeObservationLikelihood(scan, p);
        }
    }
};

const Setup& setup()
{
    static const Setup s;
    return s;
}

void finish(benchmark::State& state, double sink)
{
    benchmark::DoNotOptimize(sink);
    state.counters["per_beam"] = benchmark::Counter(
        static_cast<double>(kBeams),
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/** CStructureMap through its fast entry (what a custom filter would call). */
void BM_StructureMap_fast(benchmark::State& state)
{
    const Setup& s = setup();
    size_t i = 0;
    double sink = 0;
    for (auto _ : state)
    {
        sink += s.structure.computeLogLikelihood(s.scan, s.particles[i++ & 4095]);
    }
    finish(state, sink);
}

/** The three maps through CMetricMap::computeObservationLikelihood (what MRPT's PF calls). */
void runMetricMap(benchmark::State& state, const mrpt::maps::CMetricMap& map)
{
    const Setup& s = setup();
    size_t i = 0;
    double sink = 0;
    for (auto _ : state)
    {
        sink += map.computeObservationLikelihood(s.scan, s.particles3D[i++ & 4095]);
    }
    finish(state, sink);
}

void BM_StructureMap(benchmark::State& state)
{
    runMetricMap(state, setup().structure);
}
void BM_Grid_LikelihoodField(benchmark::State& state)
{
    runMetricMap(state, setup().gridLF);
}
void BM_Grid_RayTracing(benchmark::State& state)
{
    runMetricMap(state, setup().gridRT);
}

/** CStructureMap's cost vs the number of beams (same 20 m, 180 deg sonar). */
void BM_StructureMap_beams(benchmark::State& state)
{
    const Setup& s = setup();
    const auto beams = static_cast<size_t>(state.range(0));
    const auto scan = semloc::test::simulateScan(
        s.structure.rayCaster(), TPose2D(12.5, 4.0, M_PI / 2), beams, kMaxRange_m, M_PI);
    size_t i = 0;
    double sink = 0;
    for (auto _ : state)
    {
        sink += s.structure.computeLogLikelihood(scan, s.particles[i++ & 4095]);
    }
    benchmark::DoNotOptimize(sink);
    state.counters["per_beam"] = benchmark::Counter(
        static_cast<double>(beams),
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_StructureMap_beams)->ArgName("beams")->Arg(15)->Arg(30)->Arg(60)->Arg(120)->Arg(240);
BENCHMARK(BM_StructureMap_fast);
BENCHMARK(BM_StructureMap);
BENCHMARK(BM_Grid_LikelihoodField);
BENCHMARK(BM_Grid_RayTracing);

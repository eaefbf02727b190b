/* semloc benchmarks — the cost of one active-localization decision (ActivePolicy::decide,
 * [ActiveLocalization]'s defaults, and with the look-arounds) against ten particle-filter
 * steps, both for 2 000 particles spread over the paper's harbour (a global start: every
 * representative in use), with the detector of config/benchmark/active/paper.ini (8 m, 90
 * degrees), on 1 and 2 threads. The budget of a decision is ten filter steps on 2 cores.
 * Run: build/bench/bench_ActiveDecision --benchmark_enable_random_interleaving=true */
#include <benchmark/benchmark.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <memory>

namespace
{
constexpr size_t kParticles = 2000;
/** A step of the first leg where the detector sees an object. */
constexpr size_t kStep = 12;

/** The paper dataset with the 8 m, 90 degree detector, simulated once. */
const semloc::SimulationResult& dataset()
{
    static const semloc::SimulationResult sim = []
    {
        auto o = semloc::TSimulatorOptions::FromConfigFile(SEMLOC_SOURCE_DIR
                                                           "/config/simulate/simulate.ini");
        o.detector.max_range_m = 8;
        o.detector.fov_deg = 90;
        o.simulation.max_steps = 40;
        return semloc::Simulator(o).run();
    }();
    return sim;
}

/** config/localize/semantic.ini's maps over the paper's world, built once. */
const semloc::LocalizationMap& maps()
{
    static const semloc::LocalizationMap lm = semloc::LocalizationMap::FromConfig(
        semloc::config::IniFileInMemory(SEMLOC_SOURCE_DIR "/config/localize/semantic.ini"),
        SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    return lm;
}

/** 2 000 particles uniform over the free space (the same every time). */
void spread(semloc::CParallelMonteCarloLocalization2D& pdf)
{
    const auto sampler = semloc::FreeSpaceSampler::FromWorld(*maps().world);
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1);
    pdf.m_particles.resize(kParticles);
    for (auto& p : pdf.m_particles)
    {
        p.d = sampler.draw(rng);
        p.log_w = 0;
    }
}

/** Ten CParticleFilter::executeOn of steps kStep..kStep+9, from the same spread cloud. */
void BM_TenFilterSteps(benchmark::State& state)
{
    const auto& sim = dataset();
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = maps().map;
    pdf.setFreeSpaceSampler(std::make_shared<semloc::FreeSpaceSampler>(
        semloc::FreeSpaceSampler::FromWorld(*maps().world)));
    pdf.setFreeSpacePrior(true);
    pdf.setExecutor(
        std::make_shared<semloc::ParallelExecutor>(static_cast<size_t>(state.range(0))));
    spread(pdf);
    const auto cloud = pdf.m_particles;
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    pf.m_options.BETA = 1.0;  // resample every step
    for (auto _ : state)
    {
        state.PauseTiming();
        pdf.m_particles = cloud;
        state.ResumeTiming();
        for (size_t k = kStep; k < kStep + 10; k++)
        {
            pf.executeOn(pdf, sim.rawlog.getAsAction(2 * k).get(),
                         sim.rawlog.getAsObservations(2 * k + 1).get());
        }
    }
    state.counters["threads"] = static_cast<double>(state.range(0));
}

/** One ActivePolicy::decide over the same spread cloud, on range(0) threads, with the
 *  look-arounds when range(1) is 1 (config/benchmark/active.ini's choice). */
void BM_Decision(benchmark::State& state)
{
    const auto& sim = dataset();
    semloc::CParallelMonteCarloLocalization2D pdf;
    spread(pdf);
    const auto sensor = sim.rawlog.getAsObservations(2 * kStep + 1)
                            ->getObservationByClass<semloc::CObservationSemantic>();
    semloc::ActivePolicy::TOptions o;
    o.threads = static_cast<int>(state.range(0));
    o.look_around = state.range(1) != 0;
    semloc::ActivePolicy policy(o, *maps().map->mapByClass<semloc::CSemanticMap>(), &*maps().world);
    size_t candidates = 0;
    double evaluations = 0;
    for (auto _ : state)
    {
        const auto d = policy.decide(pdf, *sensor);
        candidates = d.candidates.size();
        evaluations = 0;
        for (const auto& c : d.candidates)
        {
            evaluations += c.evaluations;
        }
        benchmark::DoNotOptimize(d.chosen);
    }
    state.counters["evaluations"] = evaluations;
    state.counters["threads"] = static_cast<double>(state.range(0));
    state.counters["candidates"] = static_cast<double>(candidates);
    state.counters["look_around"] = static_cast<double>(state.range(1));
}
}  // namespace

BENCHMARK(BM_TenFilterSteps)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Decision)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

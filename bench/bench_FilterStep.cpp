/* semloc benchmarks — one particle-filter step (prediction + likelihood + resampling) of
 * semloc-localize on the paper scenario, 10 000 particles, per variant, on 1 and 2 threads;
 * and the per-step estimate (mean and covariance) semloc-localize writes after each step,
 * MRPT's implementation beside ours.
 * Run: build/bench/bench_FilterStep [--benchmark_filter=semantic] */
#include <benchmark/benchmark.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/poses/CPosePDFParticles.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <map>
#include <memory>
#include <string>

namespace
{
/** A step in the middle of the first leg, where the detector sees objects (2 of them). */
constexpr size_t kStep = 20;
/** A busy step (semantic_busy): the detector reports 6 objects, several of one label, and
 *  ~5 objects are in view of each particle (1.2 detection-object pairs per particle at kStep,
 *  ~5 here). The semantic likelihood's cost grows with those counts. */
constexpr size_t kBusyStep = 270;

/** True for the AUV survey's variants, "auv_<name>": config/localize/auv/<name>.ini. */
bool auvVariant(const std::string& variant)
{
    return variant.rfind("auv_", 0) == 0;
}

/** The paper dataset (config/simulate/simulate.ini), or for an AUV variant the seabed survey
 *  (config/simulate/simulate_auv.ini), simulated once. */
const semloc::SimulationResult& dataset(const std::string& variant)
{
    static const semloc::SimulationResult paper =
        semloc::Simulator(semloc::TSimulatorOptions::FromConfigFile(
                              SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini"))
            .run();
    static const semloc::SimulationResult auv =
        semloc::Simulator(semloc::TSimulatorOptions::FromConfigFile(
                              SEMLOC_SOURCE_DIR "/config/simulate/simulate_auv.ini"))
            .run();
    return auvVariant(variant) ? auv : paper;
}

/** The first step from `from` on whose side-scan reports 2 objects or more. */
size_t sideScanStep(const semloc::SimulationResult& sim, size_t from)
{
    for (size_t k = from; 2 * k + 1 < sim.rawlog.size(); k++)
    {
        for (const auto& o : *sim.rawlog.getAsObservations(2 * k + 1))
        {
            const auto* scan = dynamic_cast<const semloc::CObservationSemantic*>(o.get());
            if (scan && scan->sensorLabel == "sidescan" && scan->detections.size() >= 2)
            {
                return k;
            }
        }
    }
    return from;
}

/** The maps of config/<variant>.ini, built once; "semantic_paper" is semantic.ini with the
 *  paper's likelihood model (§III) instead of the probabilistic one. */
const semloc::LocalizationMap& maps(const std::string& variant)
{
    static std::map<std::string, semloc::LocalizationMap> cache;
    auto it = cache.find(variant);
    if (it == cache.end())
    {
        const bool paper = variant == "semantic_paper";
        const std::string file = paper                 ? std::string("semantic")
                                 : auvVariant(variant) ? "auv/" + variant.substr(4)
                                                       : variant;
        const semloc::config::IniFileInMemory ini(SEMLOC_SOURCE_DIR "/config/localize/" + file +
                                                  ".ini");
        const std::string world = auvVariant(variant) ? SEMLOC_SOURCE_DIR
                                      "/maps/seabed_200x200.yaml"
                                                      : SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
        it = cache.emplace(variant, semloc::LocalizationMap::FromConfig(ini, world)).first;
        if (paper)
        {
            it->second.map->mapByClass<semloc::CSemanticMap>()->likelihoodOptions.model =
                semloc::CSemanticMap::Model::Paper;
        }
    }
    return it->second;
}

/** One CParticleFilter::executeOn with the action and frame of step `step`, from the same
 *  cloud every time: 10 000 particles around the true pose (1 m, 6 deg), resampled at each
 *  step (BETA = 1), with the free-space prior on as in config/localize/<variant>.ini (off for
 *  the AUV, which flies over its objects). Time =
 *  wall time of the step. */
void BM_FilterStep(benchmark::State& state, const std::string& variant, size_t step)
{
    const auto& sim = dataset(variant);
    const auto& lm = maps(variant);
    if (auvVariant(variant))
    {
        step = sideScanStep(sim, step);
    }
    const auto action = sim.rawlog.getAsAction(2 * step);
    const auto frame = sim.rawlog.getAsObservations(2 * step + 1);
    const auto truth = sim.groundTruth[step - 1].pose();

    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = lm.map;
    // As semloc-localize with the variant's ini: free_space_prior = 1 (config/localize/*.ini;
    // 0 in config/localize/auv/).
    pdf.setFreeSpaceSampler(
        std::make_shared<semloc::FreeSpaceSampler>(semloc::FreeSpaceSampler::FromWorld(*lm.world)));
    pdf.setFreeSpacePrior(!auvVariant(variant));  // the AUV flies over its objects
    pdf.setExecutor(
        std::make_shared<semloc::ParallelExecutor>(static_cast<size_t>(state.range(0))));
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1);
    const auto nParticles = static_cast<size_t>(state.range(1));
    pdf.m_particles.resize(nParticles);
    for (auto& p : pdf.m_particles)
    {
        p.d = mrpt::math::TPose2D(truth.x + rng.drawGaussian1D(0, 1.0),
                                  truth.y + rng.drawGaussian1D(0, 1.0),
                                  truth.phi + rng.drawGaussian1D(0, 0.1));
        p.log_w = 0;
    }
    const auto cloud = pdf.m_particles;

    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    pf.m_options.BETA = 1.0;                       // resample every step: the full step is measured
    pf.executeOn(pdf, action.get(), frame.get());  // warm-up: caches, buffers

    for (auto _ : state)
    {
        state.PauseTiming();
        pdf.m_particles = cloud;
        state.ResumeTiming();
        pf.executeOn(pdf, action.get(), frame.get());
    }
    state.counters["particles"] = static_cast<double>(nParticles);
    size_t detections = 0;
    for (const auto& o : *frame)
    {
        if (const auto* scan = dynamic_cast<const semloc::CObservationSemantic*>(o.get());
            scan && scan->sensorLabel != (auvVariant(variant) ? "SEMANTIC" : ""))
        {
            detections += scan->detections.size();  // the AUV's: its side-scan's
        }
    }
    state.counters["detections"] = static_cast<double>(detections);
    state.counters["us_per_particle"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(nParticles) * 1e-6,
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// threads x particles: the reference point is 10 000 particles.
#define SEMLOC_FILTER_STEP_AT(name, variant, step)          \
    BENCHMARK_CAPTURE(BM_FilterStep, name, #variant, step)  \
        ->ArgNames({"threads", "particles"})                \
        ->ArgsProduct({{1, 2}, {100, 1000, 10000, 100000}}) \
        ->UseRealTime()                                     \
        ->Unit(benchmark::kMillisecond)
#define SEMLOC_FILTER_STEP(variant) SEMLOC_FILTER_STEP_AT(variant, variant, kStep)

SEMLOC_FILTER_STEP(semantic);
SEMLOC_FILTER_STEP(semantic_paper);
SEMLOC_FILTER_STEP(geometric);
SEMLOC_FILTER_STEP(grid_lf);
SEMLOC_FILTER_STEP(grid_rt);
SEMLOC_FILTER_STEP(fused);
SEMLOC_FILTER_STEP_AT(semantic_busy, semantic, kBusyStep);
/** The side-scan survey (config/localize/auv/sidescan.ini) at the first step from 40 on where
 *  the side-scan reports 2 objects or more. */
constexpr size_t kSideScanStep = 40;
SEMLOC_FILTER_STEP_AT(sidescan, auv_sidescan, kSideScanStep);

/** getCovarianceAndMean() of 10 000 particles around the true pose of step kStep (as
 *  BM_FilterStep's cloud), by MRPT's CPosePDFParticles or by CParallelMonteCarloLocalization2D
 *  (the same bits, tested); weights equal (log-weights 0, as after a resampling: every step
 *  of BM_FilterStep) or not (random log-weights, as after an update without resampling). */
template <typename Pdf>
void BM_Estimate(benchmark::State& state, bool equalWeights, Pdf& pdf)
{
    const auto truth = dataset("semantic").groundTruth[kStep - 1].pose();
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1);
    pdf.m_particles.resize(10000);
    for (auto& p : pdf.m_particles)
    {
        p.d = mrpt::math::TPose2D(truth.x + rng.drawGaussian1D(0, 1.0),
                                  truth.y + rng.drawGaussian1D(0, 1.0),
                                  truth.phi + rng.drawGaussian1D(0, 0.1));
        p.log_w = equalWeights ? 0 : rng.drawGaussian1D(0, 2);
    }
    double sink = 0;
    for (auto _ : state)
    {
        const auto [cov, mean] = pdf.getCovarianceAndMean();
        sink += cov(0, 0) + mean.x();
        benchmark::DoNotOptimize(sink);
    }
    state.counters["particles"] = static_cast<double>(pdf.m_particles.size());
}

void BM_EstimateMrpt(benchmark::State& state, bool equalWeights)
{
    mrpt::poses::CPosePDFParticles pdf;
    BM_Estimate(state, equalWeights, pdf);
}
/** Ours on `threads` threads (the executor of the filter). */
void BM_EstimateSemloc(benchmark::State& state, bool equalWeights)
{
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.setExecutor(
        std::make_shared<semloc::ParallelExecutor>(static_cast<size_t>(state.range(0))));
    BM_Estimate(state, equalWeights, pdf);
}
BENCHMARK_CAPTURE(BM_EstimateMrpt, equal_weights, true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_EstimateSemloc, equal_weights, true)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_EstimateMrpt, weighted, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_EstimateSemloc, weighted, false)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

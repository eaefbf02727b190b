/* semloc benchmarks — CSemanticMap likelihood per particle.
 * Run: build/bench/bench_SemanticLikelihood [--benchmark_filter=...] */
#include <benchmark/benchmark.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <vector>

using mrpt::math::TPose2D;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;

namespace
{
/** n objects in 6 labels at a fixed density of 50 objects per 50 x 50 m. */
CSemanticMap makeMap(int n, CSemanticMap::Model model, mrpt::random::CRandomGenerator& rng)
{
    static const char* labels[] = {"wellhead", "manifold", "pillar", "pipeline", "anchor", "wreck"};
    const double side = 50.0 * std::sqrt(n / 50.0);
    CSemanticMap m;
    m.likelihoodOptions.model = model;
    for (int i = 1; i <= n; i++)
    {
        m.addObject(
            {i, labels[i % 6], rng.drawUniform(0.0, side), rng.drawUniform(0.0, side), 0, 0.5, 1});
    }
    return m;
}

/** The nd nearest objects in front of `pose`, as detections. */
CObservationSemantic makeObs(const CSemanticMap& m, const TPose2D& pose, size_t nd)
{
    CObservationSemantic obs;
    obs.maxRange_m = 20;
    obs.fov_rad = 2 * M_PI / 3;
    std::vector<std::pair<double, semloc::TSemanticDetection>> cand;
    for (const auto& o : m.objects())
    {
        const double r = std::hypot(o.x - pose.x, o.y - pose.y);
        const double b = mrpt::math::wrapToPi(std::atan2(o.y - pose.y, o.x - pose.x) - pose.phi);
        if (r <= obs.maxRange_m && std::abs(b) <= obs.fov_rad / 2)
        {
            cand.push_back({r, {o.label, r + 0.1, b + 0.01, 1.0, -1}});
        }
    }
    std::sort(cand.begin(), cand.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (size_t i = 0; i < nd && i < cand.size(); i++)
    {
        obs.detections.push_back(cand[i].second);
    }
    return obs;
}

/** A map of nObjects, an observation with nDet detections from a pose, and 4096
 *  particles spread around that pose (as in a filter that is converging). */
struct Setup
{
    CSemanticMap map;
    CObservationSemantic obs;
    std::vector<TPose2D> particles;
};

Setup makeSetup(int nObjects, size_t nDet, CSemanticMap::Model model, size_t nParticles = 4096)
{
    mrpt::random::CRandomGenerator rng(1);
    Setup s{makeMap(nObjects, model, rng), {}, {}};
    const double side = 50.0 * std::sqrt(nObjects / 50.0);
    TPose2D truth;
    for (int tries = 0; tries < 1000 && s.obs.detections.size() < nDet; tries++)
    {
        truth = TPose2D(rng.drawUniform(0.2 * side, 0.8 * side),
                        rng.drawUniform(0.2 * side, 0.8 * side), rng.drawUniform(-M_PI, M_PI));
        s.obs = makeObs(s.map, truth, nDet);
    }
    s.particles.resize(nParticles);
    for (auto& p : s.particles)
    {
        p = TPose2D(truth.x + rng.drawGaussian1D(0, 2.0), truth.y + rng.drawGaussian1D(0, 2.0),
                    truth.phi + rng.drawGaussian1D(0, 0.2));
    }
    return s;
}

/** One particle per call: the path MRPT's CParticleFilter takes (per-particle virtual
 *  call through CMultiMetricMap). Time column = ns per particle. */
void runSingle(benchmark::State& state, CSemanticMap::Model model)
{
    const Setup s =
        makeSetup(static_cast<int>(state.range(0)), static_cast<size_t>(state.range(1)), model);
    size_t i = 0;
    double sink = 0;
    for (auto _ : state)
    {
        sink += s.map.computeLogLikelihood(s.obs, s.particles[i]);
        i = (i + 1) & (s.particles.size() - 1);
    }
    benchmark::DoNotOptimize(sink);
    state.counters["detections"] = static_cast<double>(s.obs.detections.size());
}

/** All 4096 particles per call (computeLogLikelihoods, the localizer's path).
 *  Counter per_particle = time of one call / 4096. */
void runBatch(benchmark::State& state, CSemanticMap::Model model,
              CSemanticMap::Association association = CSemanticMap::Association::Greedy,
              double pRangeOutlier = 0)
{
    Setup s =
        makeSetup(static_cast<int>(state.range(0)), static_cast<size_t>(state.range(1)), model);
    s.map.likelihoodOptions.probabilistic.association = association;
    s.map.likelihoodOptions.detector.p_range_outlier = pRangeOutlier;
    std::vector<double> out(s.particles.size());
    for (auto _ : state)
    {
        s.map.computeLogLikelihoods(s.obs, s.particles.data(), s.particles.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["detections"] = static_cast<double>(s.obs.detections.size());
    // Seconds per particle, printed with an SI prefix (e.g. 228n = 228 ns).
    state.counters["per_particle"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(s.particles.size()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/** Batch cost per particle vs the number of particles (50 objects, 5 detections). */
void BM_PaperBatchParticles(benchmark::State& state)
{
    const Setup s =
        makeSetup(50, 5, CSemanticMap::Model::Paper, static_cast<size_t>(state.range(0)));
    std::vector<double> out(s.particles.size());
    for (auto _ : state)
    {
        s.map.computeLogLikelihoods(s.obs, s.particles.data(), s.particles.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["per_particle"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(s.particles.size()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_PaperSingle(benchmark::State& s)
{
    runSingle(s, CSemanticMap::Model::Paper);
}
void BM_PaperBatch(benchmark::State& s)
{
    runBatch(s, CSemanticMap::Model::Paper);
}
void BM_ProbabilisticSingle(benchmark::State& s)
{
    runSingle(s, CSemanticMap::Model::Probabilistic);
}
void BM_ProbabilisticBatch(benchmark::State& s)
{
    runBatch(s, CSemanticMap::Model::Probabilistic);
}
/** The probabilistic model summed over every association (association = marginal): compare
 *  with BM_ProbabilisticBatch of the same arguments in the same run
 *  (--benchmark_enable_random_interleaving=true). */
void BM_MarginalBatch(benchmark::State& s)
{
    runBatch(s, CSemanticMap::Model::Probabilistic, CSemanticMap::Association::Marginal);
}

/** A map of uncertain objects (every object sigma_m = 0.5 m, p_exist = 0.8, every third with a
 *  class distribution): compare with BM_ProbabilisticBatch of the same arguments in the same
 *  run. */
void BM_ProbabilisticUncertainBatch(benchmark::State& state)
{
    Setup s = makeSetup(static_cast<int>(state.range(0)), static_cast<size_t>(state.range(1)),
                        CSemanticMap::Model::Probabilistic);
    CSemanticMap uncertain;
    uncertain.likelihoodOptions = s.map.likelihoodOptions;
    for (auto o : s.map.objects())
    {
        o.sigma_m = 0.5;
        o.p_exist = 0.8;
        if (o.id % 3 == 0 && o.label != "wreck")
        {
            o.classes = {{o.label, 0.7}, {"wreck", 0.3}};
            std::sort(o.classes.begin(), o.classes.end());
        }
        uncertain.addObject(o);
    }
    std::vector<double> out(s.particles.size());
    for (auto _ : state)
    {
        uncertain.computeLogLikelihoods(s.obs, s.particles.data(), s.particles.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["per_particle"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(s.particles.size()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/** Misread ranges (p_range_outlier = 0.05: every range passes the range gate, each pair's
 *  range term a mixture): compare with BM_PaperBatch / BM_ProbabilisticBatch of the same
 *  arguments in the same run (--benchmark_enable_random_interleaving=true). */
void BM_PaperMisreadBatch(benchmark::State& s)
{
    runBatch(s, CSemanticMap::Model::Paper, CSemanticMap::Association::Greedy, 0.05);
}
void BM_ProbabilisticMisreadBatch(benchmark::State& s)
{
    runBatch(s, CSemanticMap::Model::Probabilistic, CSemanticMap::Association::Greedy, 0.05);
}

// The reference point: 50 objects, 5 detections.
BENCHMARK(BM_PaperSingle)->Args({50, 5});
BENCHMARK(BM_PaperBatch)->Args({50, 5});
BENCHMARK(BM_ProbabilisticSingle)->Args({50, 5});
BENCHMARK(BM_ProbabilisticBatch)->Args({50, 5});
// The marginal association against the greedy one, 5 and 10 detections.
BENCHMARK(BM_MarginalBatch)->Args({50, 5})->Args({50, 10});
BENCHMARK(BM_ProbabilisticBatch)->Args({50, 10});
// Misread ranges against the Gaussian range model.
BENCHMARK(BM_PaperMisreadBatch)->Args({50, 5});
BENCHMARK(BM_ProbabilisticMisreadBatch)->Args({50, 5});
// A map of uncertain objects against the exact one.
BENCHMARK(BM_ProbabilisticUncertainBatch)->Args({50, 5});
// Particles per call (10^2 .. 10^5).
BENCHMARK(BM_PaperBatchParticles)
    ->ArgName("particles")
    ->Arg(100)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000);
// Detections per scan.
BENCHMARK(BM_PaperBatch)->Args({50, 0})->Args({50, 1})->Args({50, 10});
// Map size at fixed density: cost must stay flat (grid index).
BENCHMARK(BM_PaperBatch)
    ->Args({10, 0})
    ->Args({10, 5})
    ->Args({500, 5})
    ->Args({5000, 5})
    ->Args({10000, 5});

}  // namespace

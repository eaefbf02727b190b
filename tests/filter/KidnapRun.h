/* semloc tests — the semantic-only filter over a world's objects, and a kidnapping on the
 * paper world: the filter with recovery tracks the first leg, is moved to the third, the
 * odometry unaware. */
#pragma once

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/AugmentedMCL.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <functional>
#include <memory>

#include "TestHelpers.h"

namespace semloc::test
{
/** A semantic-only filter (the probabilistic model) over the objects of `world`, on `threads`
 *  threads, with recovery `recovery` drawing from `world`'s free space. */
inline std::unique_ptr<CParallelMonteCarloLocalization2D> semanticOnlyFilter(
    const World& world, size_t threads, const AugmentedMCL::TOptions& recovery)
{
    auto sem = CSemanticMap::Create();
    sem->likelihoodOptions.model = CSemanticMap::Model::Probabilistic;
    sem->loadFromWorld(world);
    auto map = mrpt::maps::CMultiMetricMap::Create();
    map->maps.push_back(sem);
    auto pdf = std::make_unique<CParallelMonteCarloLocalization2D>();
    pdf->options.metricMap = map;
    pdf->setExecutor(std::make_shared<ParallelExecutor>(threads));
    pdf->setFreeSpaceSampler(
        std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromWorld(world)));
    pdf->setRecoveryOptions(recovery);
    return pdf;
}

/** What kidnapOnPaperWorld() saw. */
struct KidnapRun
{
    std::unique_ptr<CParallelMonteCarloLocalization2D> pdf;
    double errorTracking = 0;       ///< of the estimate before the kidnapping [m]
    double error = 0;               ///< of the estimate at the end [m]
    size_t injectionsTracking = 0;  ///< injection steps (or sets drawn) before the kidnapping
    bool cloudSizeKept = true;      ///< the cloud kept its 2000 particles at every step
};

/** 2000 particles of a semantic-only filter (probabilistic model) on `threads` threads, with
 *  recovery `recovery` and systematic resampling, seeded with 3, track 60 steps of 0.5 m along
 *  the paper world's first leg; the vehicle is then kidnapped to its third leg (45, 30, pi)
 *  and drives 60 more steps, the odometry unaware. `afterStep(pdf, k)` is called after step k
 *  (0..119; the kidnapping comes before step 60). */
inline KidnapRun kidnapOnPaperWorld(
    size_t threads, const AugmentedMCL::TOptions& recovery,
    const std::function<void(CParallelMonteCarloLocalization2D&, int)>& afterStep = {})
{
    const auto world = World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    KidnapRun r;
    r.pdf = semanticOnlyFilter(world, threads, recovery);
    auto& pdf = *r.pdf;
    mrpt::random::getRandomGenerator().randomize(3);
    pdf.resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 2000);
    mrpt::math::TPose2D truth(5, 4, 0);
    const auto errorNow = [&]
    { return std::hypot(pdf.getMeanVal().x() - truth.x, pdf.getMeanVal().y() - truth.y); };
    for (int k = 0; k < 120; k++)
    {
        if (k == 60)
        {
            r.errorTracking = errorNow();
            r.injectionsTracking = pdf.recoveryStats().injection_steps;
            truth = mrpt::math::TPose2D(45, 30, M_PI);
        }
        truth.x += k < 60 ? 0.5 : -0.5;
        const auto acts = gaussianOdometry(mrpt::poses::CPose2D(0.5, 0, 0));
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<CObservationSemantic>(observe(world, truth)));
        pf.executeOn(pdf, &acts, &sf);
        r.cloudSizeKept = r.cloudSizeKept && pdf.size() == 2000;
        if (afterStep)
        {
            afterStep(pdf, k);
        }
    }
    r.error = errorNow();
    return r;
}
}  // namespace semloc::test

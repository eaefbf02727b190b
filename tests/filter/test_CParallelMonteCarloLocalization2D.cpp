/* semloc tests — CParallelMonteCarloLocalization2D: MRPT's numbers, the same bits for any
 * thread count, never NaN or empty, augmented-MCL recovery. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFParticles.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/structure/CStructureMap.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <tuple>

#include "KidnapRun.h"
#include "ScanSimulation.h"
#include "TestHelpers.h"
#include "filter/KldResampling.h"

using mrpt::math::TPose2D;
using semloc::CParallelMonteCarloLocalization2D;
using semloc::ParallelExecutor;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

/** semantic + structure + likelihood-field grid over the paper world. */
struct Maps
{
    semloc::World world = semloc::World::FromFile(kPaperWorld);
    mrpt::maps::CMultiMetricMap::Ptr multi = mrpt::maps::CMultiMetricMap::Create();
    semloc::CStructureMap::Ptr structure = semloc::CStructureMap::Create();

    explicit Maps(bool withGrid = true)
    {
        auto sem = semloc::CSemanticMap::Create();
        sem->loadFromWorld(world);
        structure->loadFromWorld(world);
        multi->maps.push_back(sem);
        multi->maps.push_back(structure);
        if (withGrid)
        {
            auto grid = mrpt::maps::COccupancyGridMap2D::Create();
            *grid = world.makeOccupancyGrid(0.1);
            grid->likelihoodOptions.likelihoodMethod =
                mrpt::maps::COccupancyGridMap2D::lmLikelihoodField_Thrun;
            multi->maps.push_back(grid);
        }
    }

    mrpt::obs::CSensoryFrame frame(const TPose2D& truth) const
    {
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<mrpt::obs::CObservation2DRangeScan>(
            semloc::test::simulateScan(structure->rayCaster(), truth, 61, 20, M_PI)));
        sf.insert(
            std::make_shared<semloc::CObservationSemantic>(semloc::test::observe(world, truth)));
        return sf;
    }
};

mrpt::obs::CActionCollection odometry(const mrpt::poses::CPose2D& u)
{
    return semloc::test::gaussianOdometry(u);
}

/** Runs `steps` filter steps along a straight leg of the paper trajectory (y = 4). */
void runSteps(CParallelMonteCarloLocalization2D& pdf, const Maps& maps, int steps,
              const mrpt::bayes::CParticleFilter& pf)
{
    TPose2D truth(5, 4, 0);
    for (int k = 0; k < steps; k++)
    {
        truth.x += 0.5;
        const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
        const auto sf = maps.frame(truth);
        pf.executeOn(pdf, &acts, &sf);
    }
}

/** The bits of v (a comparison that tells -0 from 0). */
uint64_t bitsOf(double v)
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

/** A map whose likelihood is NaN for every pose: the filter must survive it. */
class CNanMap : public semloc::CStructureMap
{
    // Both interfaces, as BatchLikelihood's contract asks of a subclass that changes one.
    double internal_computeObservationLikelihood(const mrpt::obs::CObservation&,
                                                 const mrpt::poses::CPose3D&) const override
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    void logLikelihoods(const mrpt::obs::CObservation&, const TPose2D*, size_t n,
                        double* out) const override
    {
        std::fill_n(out, n, std::numeric_limits<double>::quiet_NaN());
    }
};
}  // namespace

TEST(CParallelMonteCarloLocalization2D, PredictionSamplesMrptsOdometryGaussian)
{
    // Every particle at one pose: the moved particles are samples of the action's Gaussian.
    // Ours draws its own numbers (per-particle streams), so compare distributions with
    // MRPT's sampler: sample means and covariances, 20000 samples each.
    const size_t M = 20000;
    const TPose2D start(3, 4, 0.5);
    const auto acts = odometry(mrpt::poses::CPose2D(0.7, -0.1, 0.3));
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    mrpt::slam::CMonteCarloLocalization2D stock;
    CParallelMonteCarloLocalization2D ours;
    ours.setExecutor(std::make_shared<ParallelExecutor>(2));
    stock.resetDeterministic(start, M);
    ours.resetDeterministic(start, M);
    mrpt::random::getRandomGenerator().randomize(11);
    stock.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    mrpt::random::getRandomGenerator().randomize(11);
    ours.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    ASSERT_EQ(stock.size(), ours.size());
    const auto [covStock, meanStock] = stock.getCovarianceAndMean();
    const auto [covOurs, meanOurs] = ours.getCovarianceAndMean();
    for (int d = 0; d < 3; d++)
    {
        // Means agree within 5 standard errors of the difference of two sample means.
        const double se = std::sqrt(2 * covStock(d, d) / M);
        EXPECT_NEAR(meanOurs[d], meanStock[d], 5 * se) << d;
        for (int e = 0; e < 3; e++)
        {
            // Covariances within 5 % of the larger variance (sampling error ~1 %).
            const double scale = std::sqrt(covStock(d, d) * covStock(e, e));
            EXPECT_NEAR(covOurs(d, e), covStock(d, e), 0.05 * scale) << d << "," << e;
        }
    }
    // The particles did move (the check above is not comparing two unmoved clouds).
    EXPECT_NEAR(meanOurs.x(), 3 + 0.7 * std::cos(0.5) + 0.1 * std::sin(0.5), 0.01);

    // The seed decides the draws; the thread count does not.
    CParallelMonteCarloLocalization2D one, again, other;
    for (auto* p : {&one, &again, &other})
    {
        p->resetDeterministic(start, 1000);
    }
    again.setExecutor(std::make_shared<ParallelExecutor>(3));
    mrpt::random::getRandomGenerator().randomize(11);
    one.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    mrpt::random::getRandomGenerator().randomize(11);
    again.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    mrpt::random::getRandomGenerator().randomize(12);
    other.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    size_t differ = 0;
    for (size_t i = 0; i < one.size(); i++)
    {
        ASSERT_EQ(one.m_particles[i].d.x, again.m_particles[i].d.x) << i;
        ASSERT_EQ(one.m_particles[i].d.y, again.m_particles[i].d.y) << i;
        ASSERT_EQ(one.m_particles[i].d.phi, again.m_particles[i].d.phi) << i;
        differ += one.m_particles[i].d.x != other.m_particles[i].d.x;
    }
    EXPECT_EQ(differ, one.size());
}

namespace
{
/** Odometry that stands still without noise, stamped `t` seconds. */
mrpt::obs::CActionCollection stillAt(double t)
{
    mrpt::obs::CActionRobotMovement2D act;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions mo;
    mo.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    mo.gaussianModel = {0, 0, 0, 0, 0, 0};
    act.computeFromOdometry(mrpt::poses::CPose2D(0, 0, 0), mo);
    act.timestamp = mrpt::Clock::fromDouble(t);
    mrpt::obs::CActionCollection acts;
    acts.insert(act);
    return acts;
}

/** Standard deviation of the particles' headings (small angles). */
double headingStd(const CParallelMonteCarloLocalization2D& pdf)
{
    double s = 0, s2 = 0;
    for (const auto& p : pdf.m_particles)
    {
        s += p.d.phi;
        s2 += p.d.phi * p.d.phi;
    }
    const double n = static_cast<double>(pdf.size());
    return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)));
}
}  // namespace

TEST(CParallelMonteCarloLocalization2D, HeadingDriftTurnsEachParticleByItsOwnRate)
{
    // Odometry standing still, one step a minute: each particle turns by -rate * 60 s, its
    // rate drawn from N(0, 10 deg/min) (the headings' spread); a substitution carries the
    // rates with their particles; a walk spreads rates that started equal.
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    const size_t M = 4000;
    const double perMin = mrpt::DEG2RAD(1.0) / 60;  // 1 deg/min in rad/s
    CParallelMonteCarloLocalization2D pdf;
    pdf.setExecutor(std::make_shared<ParallelExecutor>(2));
    pdf.resetDeterministic(TPose2D(1, 2, 0), M);
    mrpt::random::getRandomGenerator().randomize(5);
    pdf.setHeadingDrift(10 * perMin, 0);
    for (double t : {100.0, 160.0})
    {
        const auto acts = stillAt(t);
        pdf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    }
    // One minute of drift: the headings spread as the rates, 10 deg (sampling error ~1 %).
    EXPECT_NEAR(headingStd(pdf), mrpt::DEG2RAD(10.0), mrpt::DEG2RAD(0.5));
    EXPECT_NEAR(pdf.headingDriftRate() * 60, -pdf.getMeanVal().phi(), 1e-3);

    // Every particle becomes particle 7: its rate with it, so the next minute turns every
    // particle by that particle's turn again.
    const double turn = pdf.m_particles[7].d.phi;
    ASSERT_GT(std::abs(turn), 0);
    pdf.performSubstitution(std::vector<size_t>(M, 7));
    EXPECT_NEAR(pdf.headingDriftRate() * 60, -turn, 1e-12);
    const auto next = stillAt(220);
    pdf.prediction_and_update_pfStandardProposal(&next, nullptr, o);
    for (const auto& p : pdf.m_particles)
    {
        ASSERT_NEAR(p.d.phi, 2 * turn, 1e-12);
    }

    // A walk of 2 deg/min over a minute, from rates all 0: after the first minute the rates
    // spread by 2 deg/min, so the second minute spreads the headings by 2 deg.
    CParallelMonteCarloLocalization2D walk;
    walk.resetDeterministic(TPose2D(1, 2, 0), M);
    walk.setHeadingDrift(0, 2 * perMin / std::sqrt(60.0));
    for (double t : {0.0, 60.0})
    {
        const auto acts = stillAt(t);
        walk.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    }
    EXPECT_EQ(headingStd(walk), 0);
    const auto last = stillAt(120);
    walk.prediction_and_update_pfStandardProposal(&last, nullptr, o);
    EXPECT_NEAR(headingStd(walk), mrpt::DEG2RAD(2.0), mrpt::DEG2RAD(0.1));

    // Off: nothing turns, and the rate is 0.
    CParallelMonteCarloLocalization2D off;
    off.resetDeterministic(TPose2D(1, 2, 0), 100);
    const auto a0 = stillAt(0), a1 = stillAt(60);
    off.prediction_and_update_pfStandardProposal(&a0, nullptr, o);
    off.prediction_and_update_pfStandardProposal(&a1, nullptr, o);
    EXPECT_EQ(headingStd(off), 0);
    EXPECT_EQ(off.headingDriftRate(), 0);
}

TEST(CParallelMonteCarloLocalization2D, UpdateEqualsMrptsLikelihoodOnEveryThreadCount)
{
    const Maps maps;
    const TPose2D truth(20, 17, 0.3);
    const auto sf = maps.frame(truth);
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    o.powFactor = 0.7;
    o.BETA = 0;  // ours resamples at the end of the step when ESS < BETA: not here

    mrpt::slam::CMonteCarloLocalization2D stock;
    stock.options.metricMap = maps.multi;
    mrpt::random::getRandomGenerator().randomize(3);
    stock.resetUniform(15, 25, 12, 22, -M_PI, M_PI, 3000);
    stock.prediction_and_update_pfStandardProposal(nullptr, &sf, o);

    for (size_t threads : {1, 2, 3})
    {
        CParallelMonteCarloLocalization2D ours;
        ours.options.metricMap = maps.multi;
        ours.setExecutor(std::make_shared<ParallelExecutor>(threads));
        mrpt::random::getRandomGenerator().randomize(3);
        ours.resetUniform(15, 25, 12, 22, -M_PI, M_PI, 3000);
        ours.prediction_and_update_pfStandardProposal(nullptr, &sf, o);
        for (size_t i = 0; i < stock.size(); i++)
        {
            const double a = stock.m_particles[i].log_w, b = ours.m_particles[i].log_w;
            ASSERT_NEAR(a, b, 1e-9 * std::max(1.0, std::abs(a)))
                << "particle " << i << ", " << threads << " threads";
        }
        EXPECT_EQ(ours.likelihoodStats().observations_used, 2u);
    }
}

TEST(CParallelMonteCarloLocalization2D, StepResamplesSystematicallyWhenEssIsBelowBeta)
{
    // Weights 0, 1, 2, ..., 9 (relative), 1000 particles each: systematic resampling gives
    // particle i floor or ceil of M w_i / sum(w) copies, never one of weight zero, in order.
    constexpr size_t kGroups = 10, kEach = 1000, M = kGroups * kEach;
    CParallelMonteCarloLocalization2D pdf(M);
    double sumW = 0, sumW2 = 0;
    for (size_t i = 0; i < M; i++)
    {
        const double w = static_cast<double>(i % kGroups);
        pdf.m_particles[i].d = TPose2D(static_cast<double>(i), 0, 0);
        pdf.m_particles[i].log_w =
            w > 0 ? std::log(w) - 7 : -std::numeric_limits<double>::infinity();
        sumW += w;
        sumW2 += w * w;
    }
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    o.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    o.BETA = 1.0;
    mrpt::random::getRandomGenerator().randomize(5);
    pdf.prediction_and_update_pfStandardProposal(nullptr, nullptr, o);

    EXPECT_NEAR(pdf.essBeforeResampling(), sumW * sumW / (M * sumW2), 1e-12);
    ASSERT_EQ(pdf.size(), M);
    std::vector<size_t> copies(M, 0);
    double prev = -1;
    for (const auto& p : pdf.m_particles)
    {
        EXPECT_EQ(p.log_w, 0);
        EXPECT_GE(p.d.x, prev);  // sorted
        prev = p.d.x;
        copies[static_cast<size_t>(p.d.x)]++;
    }
    for (size_t i = 0; i < M; i++)
    {
        const double expected = static_cast<double>(M) * static_cast<double>(i % kGroups) / sumW;
        EXPECT_GE(static_cast<double>(copies[i]), std::floor(expected) - 1e-9) << i;
        EXPECT_LE(static_cast<double>(copies[i]), std::ceil(expected) + 1e-9) << i;
    }
    // Equal weights afterwards: CParticleFilter::executeOn's own test finds nothing to do.
    EXPECT_EQ(pdf.ESS(), 1.0);

    // ESS above BETA: no resampling, the weights stay.
    CParallelMonteCarloLocalization2D keep(M);
    for (size_t i = 0; i < M; i++)
    {
        keep.m_particles[i].d = TPose2D(static_cast<double>(i), 0, 0);
        keep.m_particles[i].log_w = i % 2 ? 0.0 : -0.1;
    }
    o.BETA = 0.5;
    keep.prediction_and_update_pfStandardProposal(nullptr, nullptr, o);
    EXPECT_GT(keep.essBeforeResampling(), 0.99);
    EXPECT_EQ(keep.m_particles[0].log_w, -0.1);
    EXPECT_EQ(keep.m_particles[M - 1].d.x, static_cast<double>(M - 1));
}

TEST(CParallelMonteCarloLocalization2D, SameBitsOnOneTwoAndThreeThreads)
{
    const Maps maps;
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    auto run = [&](size_t threads)
    {
        auto pdf = std::make_unique<CParallelMonteCarloLocalization2D>();
        pdf->options.metricMap = maps.multi;
        pdf->setExecutor(std::make_shared<ParallelExecutor>(threads));
        mrpt::random::getRandomGenerator().randomize(5);
        pdf->resetUniform(0, 20, 0, 10, -M_PI, M_PI, 4000);
        runSteps(*pdf, maps, 12, pf);
        return pdf;
    };
    const auto a = run(1);
    for (size_t threads : {2, 3})
    {
        const auto b = run(threads);
        ASSERT_EQ(a->size(), b->size());
        for (size_t i = 0; i < a->size(); i++)
        {
            ASSERT_EQ(a->m_particles[i].d.x, b->m_particles[i].d.x) << i;
            ASSERT_EQ(a->m_particles[i].d.y, b->m_particles[i].d.y) << i;
            ASSERT_EQ(a->m_particles[i].d.phi, b->m_particles[i].d.phi) << i;
            ASSERT_EQ(a->m_particles[i].log_w, b->m_particles[i].log_w) << i;
        }
        EXPECT_EQ(a->ESS(), b->ESS());
    }
    // It localized, too: the leg at y = 4 has look-alikes only far away.
    EXPECT_LT(std::hypot(a->getMeanVal().x() - 11, a->getMeanVal().y() - 4), 1.0);
}

TEST(CParallelMonteCarloLocalization2D, KldAdaptiveSampleSizeRunsThroughMrpt)
{
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.adaptiveSampleSize = true;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prMultinomial;
    CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = maps.multi;
    pdf.options.KLD_params.KLD_minSampleSize = 300;
    pdf.options.KLD_params.KLD_maxSampleSize = 5000;
    pdf.setExecutor(std::make_shared<ParallelExecutor>(2));
    mrpt::random::getRandomGenerator().randomize(9);
    pdf.resetUniform(3, 9, 2, 6, -0.3, 0.3, 5000);
    runSteps(pdf, maps, 10, pf);
    EXPECT_GE(pdf.size(), 300u);
    EXPECT_LT(pdf.size(), 5000u) << "KLD shrinks a converged cloud";
    EXPECT_LT(std::hypot(pdf.getMeanVal().x() - 10, pdf.getMeanVal().y() - 4), 1.0);
}

TEST(CParallelMonteCarloLocalization2D, KldBoundIsFoxs)
{
    mrpt::slam::TKLDParams p;
    p.KLD_epsilon = 0.02;
    p.KLD_delta = 0.01;
    EXPECT_EQ(semloc::detail::kldBound(1, p), 0u);
    // Fox (IJRR 2003), eq. 8 with the Wilson-Hilferty approximation of chi2inv(0.99, k - 1):
    // (k - 1) / (2 eps) (1 - 2 / (9 (k - 1)) + sqrt(2 / (9 (k - 1))) z_0.99)^3.
    for (size_t k : {10u, 100u, 1000u})
    {
        const double km1 = static_cast<double>(k - 1), z = 2.326347874;
        const double a = 2.0 / (9.0 * km1);
        const double fox = km1 / (2 * p.KLD_epsilon) * std::pow(1 - a + std::sqrt(a) * z, 3);
        EXPECT_NEAR(static_cast<double>(semloc::detail::kldBound(k, p)), fox, 0.01 * fox) << k;
    }
}

TEST(CParallelMonteCarloLocalization2D, KldResamplingSizesTheSetBySpread)
{
    mrpt::slam::TKLDParams p;
    p.KLD_binSize_XY = 0.25;
    p.KLD_binSize_PHI = mrpt::DEG2RAD(10.0);
    p.KLD_minSampleSize = 200;
    p.KLD_maxSampleSize = 20000;
    semloc::detail::ParticleList cloud(5000);
    std::vector<double> w(cloud.size(), 1.0);
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(3);
    // Every particle in one bin: the floor.
    for (auto& q : cloud)
    {
        q.d = TPose2D(rng.drawUniform(10.0, 10.2), rng.drawUniform(4.0, 4.2), 0.01);
    }
    std::vector<size_t> idx;
    semloc::detail::kldResample(w, cloud, p, 0.5, rng, idx);
    EXPECT_EQ(idx.size(), 200u);
    // Spread over 10 x 10 m and every heading: more bins than Fox's bound can cover below
    // the cap, so the cap.
    for (auto& q : cloud)
    {
        q.d = TPose2D(rng.drawUniform(0.0, 10.0), rng.drawUniform(0.0, 10.0),
                      rng.drawUniform(-M_PI, M_PI));
    }
    semloc::detail::kldResample(w, cloud, p, 0.5, rng, idx);
    EXPECT_EQ(idx.size(), 20000u);
    // In between (2 m x 2 m, +-20 deg): Fox's bound of the bins the taken particles occupy.
    for (auto& q : cloud)
    {
        q.d = TPose2D(rng.drawUniform(0.0, 2.0), rng.drawUniform(0.0, 2.0),
                      rng.drawUniform(-0.35, 0.35));
    }
    semloc::detail::kldResample(w, cloud, p, 0.5, rng, idx);
    std::set<std::tuple<long, long, long>> bins;
    for (const size_t i : idx)
    {
        const auto& d = cloud[i].d;
        bins.emplace(std::lround(std::floor(d.x / 0.25)), std::lround(std::floor(d.y / 0.25)),
                     std::lround(std::floor(d.phi / p.KLD_binSize_PHI)));
    }
    EXPECT_GT(idx.size(), 200u);
    EXPECT_LT(idx.size(), 20000u);
    EXPECT_EQ(idx.size(), semloc::detail::kldBound(bins.size(), p));
    // Only particles of positive weight are taken, in proportion to their weights.
    for (size_t i = 0; i < w.size(); i++)
    {
        w[i] = i % 2 ? 3.0 : (i % 4 ? 0.0 : 1.0);
    }
    semloc::detail::kldResample(w, cloud, p, 0.5, rng, idx);
    size_t heavy = 0;
    for (const size_t i : idx)
    {
        ASSERT_NE(i % 4, 2u) << "a particle of weight zero was taken";
        heavy += i % 2;
    }
    EXPECT_NEAR(static_cast<double>(heavy) / static_cast<double>(idx.size()), 6.0 / 7.0, 0.03);
}

TEST(CParallelMonteCarloLocalization2D, KldAtResamplingKeepsTheSetBetweenResamplings)
{
    const Maps maps(false);
    auto run = [&](size_t threads, bool measure)
    {
        mrpt::bayes::CParticleFilter pf;
        pf.m_options.adaptiveSampleSize = true;
        pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
        auto pdf = std::make_unique<CParallelMonteCarloLocalization2D>();
        pdf->options.metricMap = maps.multi;
        pdf->options.KLD_params.KLD_minSampleSize = 300;
        pdf->options.KLD_params.KLD_maxSampleSize = 5000;
        pdf->setKldAtResampling(true);
        pdf->setExecutor(std::make_shared<ParallelExecutor>(threads));
        mrpt::random::getRandomGenerator().randomize(9);
        pdf->resetUniform(3, 9, 2, 6, -0.3, 0.3, 5000);
        if (measure)
        {
            runSteps(*pdf, maps, 10, pf);
        }
        else
        {
            // Odometry only: nothing degenerates the weights, nothing is resampled.
            for (int k = 0; k < 10; k++)
            {
                const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
                pf.executeOn(*pdf, &acts, nullptr);
            }
        }
        return pdf;
    };
    EXPECT_EQ(run(1, false)->size(), 5000u) << "no resampling, no change of size";
    const auto a = run(1, true);
    EXPECT_GE(a->size(), 300u);
    EXPECT_LT(a->size(), 5000u) << "KLD shrinks a converged cloud";
    EXPECT_LT(std::hypot(a->getMeanVal().x() - 10, a->getMeanVal().y() - 4), 1.0);
    const auto b = run(2, true);
    ASSERT_EQ(a->size(), b->size());
    for (size_t i = 0; i < a->size(); i++)
    {
        ASSERT_EQ(a->m_particles[i].d.x, b->m_particles[i].d.x) << i;
        ASSERT_EQ(a->m_particles[i].log_w, b->m_particles[i].log_w) << i;
    }
}

TEST(CParallelMonteCarloLocalization2D, AllWeightsZeroReinitializesInsteadOfNaN)
{
    const semloc::World world = semloc::World::FromFile(kPaperWorld);
    auto mm = mrpt::maps::CMultiMetricMap::Create();
    mm->maps.push_back(std::make_shared<CNanMap>());
    CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = mm;
    pdf.setExecutor(std::make_shared<ParallelExecutor>(2));
    pdf.setFreeSpaceSampler(
        std::make_shared<semloc::FreeSpaceSampler>(semloc::FreeSpaceSampler::FromWorld(world)));
    mrpt::random::getRandomGenerator().randomize(1);
    pdf.resetUniform(10, 11, 10, 11, 0, 0.1, 500);

    mrpt::bayes::CParticleFilter pf;
    const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
    mrpt::obs::CSensoryFrame sf;
    sf.insert(std::make_shared<mrpt::obs::CObservation2DRangeScan>());
    pf.executeOn(pdf, &acts, &sf);

    EXPECT_EQ(pdf.recoveryStats().reinitializations, 1u);
    EXPECT_EQ(pdf.likelihoodStats().nonfinite_likelihoods, 500u);
    ASSERT_EQ(pdf.size(), 500u);
    double xMin = 1e9, xMax = -1e9;
    for (const auto& p : pdf.m_particles)
    {
        ASSERT_TRUE(std::isfinite(p.log_w) && std::isfinite(p.d.x) && std::isfinite(p.d.y));
        ASSERT_TRUE(world.isFree(p.d.x, p.d.y));
        xMin = std::min(xMin, p.d.x);
        xMax = std::max(xMax, p.d.x);
    }
    EXPECT_GT(xMax - xMin, 30) << "re-initialized over the whole free space";
    EXPECT_TRUE(std::isfinite(pdf.getMeanVal().x()));
}

namespace
{
/** `pdf` over the semantic and structure maps of `maps`, on two threads, with a free-space
 *  sampler of its world (where recovery draws from). */
void withFreeSpace(CParallelMonteCarloLocalization2D& pdf, const Maps& maps)
{
    pdf.options.metricMap = maps.multi;
    pdf.setExecutor(std::make_shared<ParallelExecutor>(2));
    pdf.setFreeSpaceSampler(std::make_shared<semloc::FreeSpaceSampler>(
        semloc::FreeSpaceSampler::FromWorld(maps.world)));
}
}  // namespace

TEST(CParallelMonteCarloLocalization2D, AugmentedMclInjectsWhenTheLikelihoodCollapses)
{
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    CParallelMonteCarloLocalization2D pdf;
    withFreeSpace(pdf, maps);
    // AMCL's usual rates. w_slow starts at 0 (Table 8.3), so it needs a few 1 / alpha_slow
    // steps before an ordinary dip of the likelihood can bring w_fast below it.
    pdf.setRecoveryOptions({0.001, 0.1});
    mrpt::random::getRandomGenerator().randomize(2);
    pdf.resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 3000);

    auto step = [&](TPose2D& truth, double dx)
    {
        truth.x += dx;
        const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
        const auto sf = maps.frame(truth);
        pf.executeOn(pdf, &acts, &sf);
    };
    TPose2D truth(5, 4, 0);
    for (int k = 0; k < 60; k++)
    {
        step(truth, 0.5);  // tracking along the first leg: the likelihood stays high
    }
    EXPECT_EQ(pdf.recoveryStats().injected_particles, 0u);
    EXPECT_LT(std::hypot(pdf.getMeanVal().x() - truth.x, pdf.getMeanVal().y() - truth.y), 0.2);

    truth = TPose2D(45, 30, M_PI);  // kidnapped to the third leg, the odometry unaware
    for (int k = 0; k < 40; k++)
    {
        step(truth, -0.5);
    }
    EXPECT_GT(pdf.recoveryStats().injection_steps, 0u);
    EXPECT_GT(pdf.recoveryStats().injected_particles, 0u);
    EXPECT_EQ(pdf.recoveryStats().reinitializations, 0u);
}

TEST(CParallelMonteCarloLocalization2D, FramesThatMeasureNothingLeaveTheRecoveryAlone)
{
    // An imported log has odometry-only steps between scans. Such a frame scores nothing, so
    // augmented MCL must not average it in (as a perfect fit it would hold w_fast above w_slow
    // and no kidnapping would ever be noticed): the same run with an empty frame after every
    // scan injects exactly as without.
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    auto run = [&](bool emptyFrames)
    {
        CParallelMonteCarloLocalization2D pdf;
        withFreeSpace(pdf, maps);
        pdf.setRecoveryOptions({0.001, 0.1});
        mrpt::random::getRandomGenerator().randomize(2);
        pdf.resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 3000);
        const mrpt::obs::CSensoryFrame nothing;
        TPose2D truth(5, 4, 0);
        for (int k = 0; k < 100; k++)
        {
            if (k == 60)
            {
                truth = TPose2D(45, 30, M_PI);  // kidnapped to the third leg
            }
            truth.x += k < 60 ? 0.5 : -0.5;
            const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
            const auto sf = maps.frame(truth);
            pf.executeOn(pdf, &acts, &sf);
            if (emptyFrames)
            {
                pf.executeOn(pdf, nullptr, &nothing);
            }
        }
        return std::make_pair(pdf.recoveryStats(), pdf.getMeanVal().asTPose());
    };
    const auto [plain, plainMean] = run(false);
    const auto [interleaved, interleavedMean] = run(true);
    EXPECT_GT(plain.injection_steps, 0u);
    EXPECT_EQ(interleaved.injection_steps, plain.injection_steps);
    EXPECT_EQ(interleaved.injected_particles, plain.injected_particles);
    EXPECT_EQ(interleavedMean, plainMean);
}

TEST(CParallelMonteCarloLocalization2D, HeadingDriftRatesOutliveInjectionAndReinitialization)
{
    // The drift rates are the odometry's, not the poses': a re-initialization keeps every
    // particle's rate, and an injected particle keeps the rate of the resampled particle it
    // replaces, so with no walk every rate after a step is one of the rates before it.
    const double perMin = mrpt::DEG2RAD(1.0) / 60;
    auto stamped = [](const mrpt::poses::CPose2D& u, double t)
    {
        auto acts = odometry(u);
        acts.get(0)->timestamp = mrpt::Clock::fromDouble(t);
        return acts;
    };
    {
        const semloc::World world = semloc::World::FromFile(kPaperWorld);
        auto mm = mrpt::maps::CMultiMetricMap::Create();
        mm->maps.push_back(std::make_shared<CNanMap>());
        CParallelMonteCarloLocalization2D pdf;
        pdf.options.metricMap = mm;
        pdf.setFreeSpaceSampler(
            std::make_shared<semloc::FreeSpaceSampler>(semloc::FreeSpaceSampler::FromWorld(world)));
        mrpt::random::getRandomGenerator().randomize(1);
        pdf.resetUniform(10, 11, 10, 11, 0, 0.1, 500);
        pdf.setHeadingDrift(10 * perMin, 0);
        const std::vector<double> before = pdf.headingDriftRates();
        ASSERT_EQ(before.size(), 500u);
        mrpt::bayes::CParticleFilter pf;
        const auto acts = stamped(mrpt::poses::CPose2D(0.5, 0, 0), 100);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<mrpt::obs::CObservation2DRangeScan>());
        pf.executeOn(pdf, &acts, &sf);
        ASSERT_EQ(pdf.recoveryStats().reinitializations, 1u);
        EXPECT_EQ(pdf.headingDriftRates(), before);
    }
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    CParallelMonteCarloLocalization2D pdf;
    withFreeSpace(pdf, maps);
    pdf.setRecoveryOptions(semloc::AugmentedMCL::TOptions{0.001, 0.1});
    mrpt::random::getRandomGenerator().randomize(2);
    pdf.resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 2000);
    pdf.setHeadingDrift(5 * perMin, 0);
    TPose2D truth(5, 4, 0);
    double t = 0;
    for (int k = 0; k < 80; k++)
    {
        if (k == 40)
        {
            truth = TPose2D(45, 30, M_PI);  // kidnapped: the injections start
        }
        truth.x += k < 40 ? 0.5 : -0.5;
        const std::vector<double> before = pdf.headingDriftRates();
        const auto acts = stamped(mrpt::poses::CPose2D(0.5, 0, 0), t += 1);
        const auto sf = maps.frame(truth);
        pf.executeOn(pdf, &acts, &sf);
        const auto& after = pdf.headingDriftRates();
        ASSERT_EQ(after.size(), pdf.size());
        for (const double r : after)
        {
            ASSERT_NE(std::find(before.begin(), before.end(), r), before.end())
                << "step " << k << ": a rate that no particle had";
        }
    }
    EXPECT_GT(pdf.recoveryStats().injected_particles, 0u);
}

TEST(CParallelMonteCarloLocalization2D, InjectedParticlesEarnTheirWeightAndStillRecover)
{
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    CParallelMonteCarloLocalization2D pdf;
    withFreeSpace(pdf, maps);
    semloc::AugmentedMCL::TOptions rec{0.001, 0.1};
    rec.injected_weight = 1e-4;
    pdf.setRecoveryOptions(rec);
    mrpt::random::getRandomGenerator().randomize(2);
    pdf.resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 3000);

    size_t checkedSteps = 0;
    auto step = [&](TPose2D& truth, double dx)
    {
        truth.x += dx;
        const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
        const auto sf = maps.frame(truth);
        const size_t before = pdf.recoveryStats().injected_particles;
        pf.executeOn(pdf, &acts, &sf);
        const size_t injected = pdf.recoveryStats().injected_particles - before;
        if (injected == 0 || pdf.ESS() == 1.0)
        {
            return;  // no injection, or CParticleFilter resampled the set afterwards
        }
        // Right after the injection: the injected particles hold 1e-4 of a resampled one's
        // weight, whatever their number.
        double maxW = -std::numeric_limits<double>::infinity();
        for (const auto& p : pdf.m_particles)
        {
            maxW = std::max(maxW, p.log_w);
        }
        size_t light = 0;
        double lightW = 0, sumW = 0;
        for (const auto& p : pdf.m_particles)
        {
            const double w = std::exp(p.log_w - maxW);
            sumW += w;
            if (w < 2e-4)
            {
                light++;
                lightW += w;
                EXPECT_NEAR(w, 1e-4, 1e-12);
            }
        }
        EXPECT_EQ(light, injected);
        EXPECT_LE(lightW / sumW, 1e-4 * static_cast<double>(injected) /
                                     static_cast<double>(pdf.size() - injected));
        checkedSteps++;
    };
    TPose2D truth(5, 4, 0);
    for (int k = 0; k < 60; k++)
    {
        step(truth, 0.5);
    }
    truth = TPose2D(45, 30, M_PI);  // kidnapped to the third leg, the odometry unaware
    for (int k = 0; k < 60; k++)
    {
        step(truth, -0.5);
    }
    EXPECT_GT(checkedSteps, 0u);
    // The injected particles earned their weight where the vehicle is.
    EXPECT_LT(std::hypot(pdf.getMeanVal().x() - truth.x, pdf.getMeanVal().y() - truth.y), 1.0);
}

TEST(CParallelMonteCarloLocalization2D, EvidenceTriggerInjectsOnlyAfterTheKidnapping)
{
    // Tracking: the detections are explained far better than by clutter, nothing is
    // injected. Kidnapped: the shortfall builds up within a few frames, particles are injected
    // until the cloud explains the detections again, where the vehicle is.
    semloc::AugmentedMCL::TOptions ro;
    ro.trigger = semloc::RecoveryTrigger::Evidence;
    ro.injected_weight = 3e-6;
    size_t firstInjection = 0;  // steps after the kidnapping
    const auto r = semloc::test::kidnapOnPaperWorld(
        1, ro,
        [&](CParallelMonteCarloLocalization2D& pdf, int k)
        {
            if (k >= 60 && firstInjection == 0 && pdf.recoveryStats().injection_steps > 0)
            {
                firstInjection = static_cast<size_t>(k - 59);
            }
        });
    EXPECT_EQ(r.injectionsTracking, 0u);
    EXPECT_LT(r.errorTracking, 1.0);
    EXPECT_GE(firstInjection, 2u);  // one frame alone cannot trigger
    EXPECT_LE(firstInjection, 30u);
    EXPECT_LT(r.error, 1.0);
}

TEST(CParallelMonteCarloLocalization2D, SensorResettingInjectsTheSameOnOneAndTwoThreads)
{
    // Kidnapped after tracking (w_slow starts at 0, Table 8.3: the first injections come
    // some 40 steps after the kidnapping here): with from_detections part of the injected
    // particles come from the frame's detections (test_Robustness measures the recovery
    // itself), and every draw (injection, detection, uniform fallback) is on the calling
    // thread: the same bits on 1 and 2.
    const Maps maps(false);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    auto run = [&](size_t threads, double fromDetections)
    {
        auto pdf = std::make_unique<CParallelMonteCarloLocalization2D>();
        pdf->options.metricMap = maps.multi;
        pdf->setExecutor(std::make_shared<ParallelExecutor>(threads));
        pdf->setFreeSpaceSampler(std::make_shared<semloc::FreeSpaceSampler>(
            semloc::FreeSpaceSampler::FromWorld(maps.world)));
        semloc::AugmentedMCL::TOptions ro;
        ro.alpha_slow = 0.001;
        ro.alpha_fast = 0.1;
        ro.from_detections = fromDetections;
        pdf->setRecoveryOptions(ro);
        mrpt::random::getRandomGenerator().randomize(2);
        pdf->resetUniform(4.5, 5.5, 3.5, 4.5, -0.05, 0.05, 2000);
        TPose2D truth(5, 4, 0);
        auto step = [&](double dx)
        {
            truth.x += dx;
            const auto acts = odometry(mrpt::poses::CPose2D(0.5, 0, 0));
            const auto sf = maps.frame(truth);
            pf.executeOn(*pdf, &acts, &sf);
        };
        for (int k = 0; k < 60; k++)
        {
            step(0.5);
        }
        truth = TPose2D(45, 30, M_PI);
        for (int k = 0; k < 60; k++)
        {
            step(-0.5);
        }
        const double err =
            std::hypot(pdf->getMeanVal().x() - truth.x, pdf->getMeanVal().y() - truth.y);
        return std::make_pair(std::move(pdf), err);
    };
    const auto [a, errA] = run(1, 0.8);
    const auto [b, errB] = run(2, 0.8);
    ASSERT_EQ(a->size(), b->size());
    for (size_t i = 0; i < a->size(); i++)
    {
        ASSERT_EQ(a->m_particles[i].d.x, b->m_particles[i].d.x) << i;
        ASSERT_EQ(a->m_particles[i].d.phi, b->m_particles[i].d.phi) << i;
        ASSERT_EQ(a->m_particles[i].log_w, b->m_particles[i].log_w) << i;
    }
    EXPECT_EQ(errA, errB);
    EXPECT_GT(a->recoveryStats().injected_from_detections, 0u);
    EXPECT_LT(a->recoveryStats().injected_from_detections,
              a->recoveryStats().injected_particles);  // the rest uniform
    const auto [u, errU] = run(1, 0.0);
    EXPECT_EQ(u->recoveryStats().injected_from_detections, 0u);
}

TEST(CParallelMonteCarloLocalization2D, MeanAndCovarianceAreMrptsBitForBit)
{
    // The same particles in MRPT's CPosePDFParticles and in ours: getMean and
    // getCovarianceAndMean must give the same bits. Kinds: 0 equal weights (as after a
    // resampling), 1 random log-weights, 2 some zero weights (-inf), 3 headings at and
    // around +-pi and far outside [-pi, pi], 4 every weight zero (both throw).
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(7);
    size_t values = 0, throwing = 0;
    for (int trial = 0; trial < 500; trial++)
    {
        const int kind = trial % 5;
        const size_t n = trial < 15 ? static_cast<size_t>(trial / 5)  // 0, 1, 2 particles
                                    : 1 + rng.drawUniform32bit() % 3000;
        CParallelMonteCarloLocalization2D ours(n);
        for (auto& p : ours.m_particles)
        {
            p.d = TPose2D(rng.drawGaussian1D(25, 5), rng.drawGaussian1D(25, 5),
                          rng.drawUniform(-M_PI, M_PI));
            p.log_w = 0;
            if (kind == 1 || kind == 2)
            {
                p.log_w = rng.drawGaussian1D(0, 3) - 2;
            }
            if (kind == 2 && rng.drawUniform(0.0, 1.0) < 0.3)
            {
                p.log_w = -std::numeric_limits<double>::infinity();
            }
            if (kind == 3)
            {
                const double u = rng.drawUniform(0.0, 1.0);
                p.d.phi = u < 0.2   ? M_PI
                          : u < 0.4 ? -M_PI
                          : u < 0.7 ? M_PI - rng.drawUniform(0.0, 1e-6)
                                    : rng.drawUniform(-1e5, 1e5);
            }
            if (kind == 4)
            {
                p.log_w = -std::numeric_limits<double>::infinity();
            }
        }
        mrpt::poses::CPosePDFParticles mrpts(n);
        mrpts.m_particles = ours.m_particles;
        if (kind == 4 && n > 0)
        {
            EXPECT_ANY_THROW(mrpts.getCovarianceAndMean());
            EXPECT_ANY_THROW(ours.getCovarianceAndMean());
            EXPECT_ANY_THROW(ours.getMeanVal());
            throwing++;
            continue;
        }
        const auto [covOurs, meanOurs] = ours.getCovarianceAndMean();
        const auto [covMrpt, meanMrpt] = mrpts.getCovarianceAndMean();
        const mrpt::poses::CPose2D meanOnly = ours.getMeanVal();
        for (int k = 0; k < 3; k++)
        {
            ASSERT_EQ(bitsOf(meanOurs[k]), bitsOf(meanMrpt[k])) << "trial " << trial << " k " << k;
            ASSERT_EQ(bitsOf(meanOnly[k]), bitsOf(meanMrpt[k])) << "trial " << trial << " k " << k;
            for (int l = 0; l < 3; l++)
            {
                ASSERT_EQ(bitsOf(covOurs(k, l)), bitsOf(covMrpt(k, l)))
                    << "trial " << trial << " (" << k << ", " << l << ")";
                values++;
            }
        }
    }
    EXPECT_EQ(values, 9u * 401u);  // kinds 0-3, and kind 4 with no particle (trial 4)
    EXPECT_EQ(throwing, 99u);      // kind 4 with particles
}

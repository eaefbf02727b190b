/* semloc tests — Localizer: its options, the step API in both rawlog formats, the initial
 * clouds, a new run's recovery trigger, very uncertain odometry, observations that cannot
 * be scored. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <semloc/filter/Localizer.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "TestHelpers.h"
#include "filter/PaperFixtures.h"

using semloc::test::errorOf;

using mrpt::math::TPose2D;
using semloc::Localizer;

using semloc::test::iniText;
using semloc::test::semanticMap;
using semloc::test::simulate;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

/** A filter started near the simulated dataset's first pose: Gaussian at (4, 5), 1.5 m. */
Localizer::TOptions gaussianStart(int particles)
{
    Localizer::TOptions o;
    o.particles_count = particles;
    o.init_PDF_mode = Localizer::InitMode::Gaussian;
    o.init_PDF_mean_x = 4;
    o.init_PDF_mean_y = 5;
    o.init_PDF_std_xy = 1.5;
    return o;
}

}  // namespace

TEST(LocalizerOptions, ReadWriteEveryKeyAndRejectMistakes)
{
    Localizer::TOptions o;
    const auto c = iniText(R"(
[LocalizationExperiment]
particles_count = 1234
init_PDF_mode = 2
init_PDF_mean_x = 3.25
init_PDF_std_yaw_deg = 7.5
seed = 42
[PF_options]
PF_algorithm = pfStandardProposal
resamplingMethod = 3
BETA = 0.25
threads = 3
free_space_prior = true
[Recovery]
trigger = amcl
alpha_slow = 0.001
alpha_fast = 0.1
from_detections = 0.5
[KLD_options]
KLD_binSize_PHI_deg = 5
[DummyOdometryParams]
minStdXY = 0.2
minStdPHI = 3   // degrees
)");
    o.loadFromConfigFile(c, "LocalizationExperiment");
    EXPECT_EQ(o.particles_count, 1234);
    EXPECT_EQ(o.init_PDF_mode, Localizer::InitMode::Gaussian);
    EXPECT_EQ(o.init_PDF_mean_x, 3.25);
    EXPECT_EQ(o.seed, 42u);
    EXPECT_EQ(o.pf.resamplingMethod, mrpt::bayes::CParticleFilter::prSystematic);
    EXPECT_EQ(o.threads, 3);
    EXPECT_EQ(o.effectiveThreads(), 3u);
    EXPECT_TRUE(o.recovery.enabled());
    EXPECT_EQ(o.recovery.from_detections, 0.5);
    EXPECT_EQ(Localizer::TOptions().recovery.from_detections, 0.8);
    EXPECT_TRUE(o.free_space_prior);
    EXPECT_NEAR(o.kld.KLD_binSize_PHI, mrpt::DEG2RAD(5.0), 1e-12);
    EXPECT_EQ(o.odometry_min_std_phi_deg, 3);

    // Every key written, read back (from the text, as from config.ini) to the same values.
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "LocalizationExperiment");
    Localizer::TOptions back;
    back.loadFromConfigFile(iniText(out.getContent()), "LocalizationExperiment");
    mrpt::config::CConfigFileMemory out2;
    back.saveToConfigFile(out2, "LocalizationExperiment");
    EXPECT_EQ(out.getContent(), out2.getContent());

    auto fails = [](const std::string& text)
    {
        return errorOf(
            [&]
            {
                Localizer::TOptions x;
                x.loadFromConfigFile(iniText(text), "LocalizationExperiment");
            });
    };
    // (ini text, what the error message must name)
    const std::pair<const char*, const char*> bad[] = {
        {"[PF_options]\nBETTA = 0.5\n", "[PF_options] BETTA"},
        {"[PF_options]\nBETA = 1.5\n", "[PF_options] BETA"},
        {"[PF_options]\nPF_algorithm = 7\n", "PF_algorithm"},
        {"[PF_options]\nPF_algorithm = 2\n", "pfOptimalProposal"},
        {"[PF_options]\nadaptiveSampleSize = 1\nresamplingMethod = 3\n",
         "[PF_options] adaptiveSampleSize"},
        {"[Recovery]\nalpha_slow = 0.2\nalpha_fast = 0.1\n", "[Recovery] alpha_fast"},
        {"[Recovery]\nfrom_detections = 1.5\n", "[Recovery] from_detections"},
        {"[Recovery]\nfrom_detections = -0.1\n", "[Recovery] from_detections"},
        {"[Recovery]\nrecovery_trigger = off\n", "[Recovery] recovery_trigger"},
        // The deprecated names: their errors name them; both names at once is an error.
        {"[PF_options]\nrecovery_alpha_slow = 0.2\nrecovery_alpha_fast = 0.1\n",
         "[PF_options] recovery_alpha_fast"},
        {"[PF_options]\nrecovery_from_detections = 1.5\n", "[PF_options] recovery_from_detections"},
        {"[PF_options]\nrecovery_trigger = off\n[Recovery]\ntrigger = off\n",
         "the same setting twice"},
        {"[LocalizationExperiment]\nparticles_count = lots\n",
         "[LocalizationExperiment] particles_count"},
        {"[LocalizationExperiment]\nparticles_count = 100 200\n", "one number"},
        {"[LocalizationExperiment]\ninit_PDF_mode = 1\n", "init_PDF_mode"},
        {"[KLD_options]\nKLD_minSampleSize = 10\nKLD_maxSampleSize = 5\n", "KLD_maxSampleSize"},
        {"[DummyOdometryParams]\nminStdXYZ = 1\n", "minStdXYZ"},
    };
    for (const auto& [text, needle] : bad)
    {
        EXPECT_NE(fails(text).find(needle), std::string::npos) << text;
    }
}

TEST(LocalizerOptions, RecoveryKeysUnderTheirOldNamesStillReadWithAWarning)
{
    // [PF_options] recovery_<key> was the keys' place: read as [Recovery] <key>, each with
    // a warning naming both; written back under [Recovery].
    Localizer::TOptions old, now;
    old.loadFromConfigFile(iniText("[PF_options]\nrecovery_trigger = amcl\n"
                                   "recovery_alpha_slow = 0.002\nrecovery_alpha_fast = 0.2\n"
                                   "recovery_injected_weight = 0.5\n"),
                           "LocalizationExperiment");
    now.loadFromConfigFile(iniText("[Recovery]\ntrigger = amcl\nalpha_slow = 0.002\n"
                                   "alpha_fast = 0.2\ninjected_weight = 0.5\n"),
                           "LocalizationExperiment");
    EXPECT_TRUE(now.warnings.empty());
    ASSERT_EQ(old.warnings.size(), 4u);
    EXPECT_NE(old.warnings[0].find("[PF_options] recovery_trigger is deprecated"),
              std::string::npos)
        << old.warnings[0];
    EXPECT_NE(old.warnings[0].find("[Recovery] trigger"), std::string::npos);
    mrpt::config::CConfigFileMemory a, b;
    old.saveToConfigFile(a, "LocalizationExperiment");
    now.saveToConfigFile(b, "LocalizationExperiment");
    EXPECT_EQ(a.getContent(), b.getContent());
    const auto written = iniText(a.getContent());
    EXPECT_TRUE(written.keyExists("Recovery", "trigger"));
    EXPECT_FALSE(written.keyExists("PF_options", "recovery_trigger"));
    EXPECT_EQ(old.recovery.alpha_fast, 0.2);
}

TEST(Localizer, StepApiLocalizesInBothRawlogFormats)
{
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(40);
    Localizer::TOptions o = gaussianStart(1500);
    o.threads = 2;

    // Action / sensory-frame pairs.
    Localizer pairs(o, semanticMap(world), &world);
    EXPECT_EQ(pairs.threads(), 2u);
    EXPECT_EQ(pairs.pdf().size(), 1500u);
    size_t k = 0;
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2, k++)
    {
        pairs.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
    }
    const auto truth = sim.groundTruth.back().pose();
    EXPECT_EQ(pairs.steps(), sim.steps);
    EXPECT_LT(std::hypot(pairs.mean().x() - truth.x, pairs.mean().y() - truth.y), 0.5);
    EXPECT_LT(pairs.varianceXY(), 0.5);
    EXPECT_GT(pairs.lastStep().update_us, 0);
    EXPECT_GT(pairs.likelihoodStats().observations_used, 0u);

    // Observations only: odometry readings (the increments summed up) and the frames.
    Localizer obsOnly(o, semanticMap(world), &world);
    mrpt::poses::CPose2D odo(100, -20, 1.0);  // any reference: only increments matter
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        const auto mov = sim.rawlog.getAsAction(i)->getBestMovementEstimation();
        odo = odo + mov->poseChange->getMeanVal();
        mrpt::obs::CObservationOdometry reading;
        reading.odometry = odo;
        obsOnly.setOdometry(reading);
        obsOnly.step(*sim.rawlog.getAsObservations(i + 1));
    }
    EXPECT_LT(std::hypot(obsOnly.mean().x() - truth.x, obsOnly.mean().y() - truth.y), 0.5);
}

TEST(Localizer, InitialCloudsFollowInitPdfMode)
{
    const auto world = semloc::World::FromFile(kPaperWorld);
    Localizer::TOptions o;
    o.particles_count = 3000;
    o.threads = 1;
    {
        Localizer free(o, semanticMap(world), &world);  // whole free space
        double xMin = 1e9, xMax = -1e9;
        for (const auto& p : free.pdf().m_particles)
        {
            ASSERT_TRUE(world.isFree(p.d.x, p.d.y));
            xMin = std::min(xMin, p.d.x);
            xMax = std::max(xMax, p.d.x);
        }
        EXPECT_LT(xMin, 1);
        EXPECT_GT(xMax, 49);
    }
    o.init_PDF_min_x = 10;
    o.init_PDF_max_x = 15;
    o.init_PDF_min_y = 8;
    o.init_PDF_max_y = 12;
    for (auto mode : {Localizer::InitMode::FreeSpace, Localizer::InitMode::Box})
    {
        o.init_PDF_mode = mode;
        Localizer boxed(o, semanticMap(world), &world);
        for (const auto& p : boxed.pdf().m_particles)
        {
            ASSERT_TRUE(p.d.x >= 10 && p.d.x <= 15 && p.d.y >= 8 && p.d.y <= 12);
            if (mode == Localizer::InitMode::FreeSpace)
            {
                ASSERT_TRUE(world.isFree(p.d.x, p.d.y)) << "the manifold is in the box";
            }
        }
    }
    o.init_PDF_mode = Localizer::InitMode::Gaussian;
    o.init_PDF_mean_x = 20;
    o.init_PDF_mean_y = 30;
    o.init_PDF_std_xy = 0.5;
    Localizer gauss(o, semanticMap(world), &world);
    EXPECT_NEAR(gauss.mean().x(), 20, 0.05);
    EXPECT_NEAR(gauss.mean().y(), 30, 0.05);
    EXPECT_NEAR(gauss.varianceXY(), 2 * 0.25, 0.05);

    // Same seed, same cloud; no world, no grid, no box: mode 0 is an error.
    Localizer again(o, semanticMap(world), &world);
    EXPECT_EQ(again.pdf().m_particles[17].d.x, gauss.pdf().m_particles[17].d.x);
    o.init_PDF_mode = Localizer::InitMode::FreeSpace;
    o.init_PDF_min_x = o.init_PDF_max_x = 0;
    EXPECT_NE(errorOf([&] { Localizer none(o, semanticMap(world)); }).find("init_PDF_mode = 0"),
              std::string::npos);
}

TEST(Localizer, EssBeforeResamplingIsReportedForEveryAlgorithm)
{
    // pfStandardProposal resamples inside its own step (CParallelMonteCarloLocalization2D
    // keeps the ESS before it); pfAuxiliaryPFStandard runs MRPT's step (the ESS comes from
    // executeOn's stats). Either way the steps.csv `ess` column must be the weights' ESS
    // before resampling: in (0, 1], and below 1 once the observations weigh the particles.
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(10);
    for (const auto alg : {mrpt::bayes::CParticleFilter::pfStandardProposal,
                           mrpt::bayes::CParticleFilter::pfAuxiliaryPFStandard})
    {
        Localizer::TOptions o = gaussianStart(500);
        o.pf.PF_algorithm = alg;
        o.free_space_prior = false;
        Localizer loc(o, semanticMap(world), &world);
        double minEss = 1;
        for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
        {
            loc.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
            const double ess = loc.lastStep().ess_before_resampling;
            EXPECT_GT(ess, 0) << "PF_algorithm " << alg;
            EXPECT_LE(ess, 1) << "PF_algorithm " << alg;
            minEss = std::min(minEss, ess);
        }
        EXPECT_LT(minEss, 0.9) << "PF_algorithm " << alg;
    }
}

TEST(LocalizerOptions, ParticleMemoryCountsTheCloudAndTheKldMaximum)
{
    Localizer::TOptions o;
    o.particles_count = 1000000;
    EXPECT_EQ(o.particleMemoryBytes(), 1000000 * Localizer::kBytesPerParticle);
    o.pf.adaptiveSampleSize = true;
    o.kld.KLD_maxSampleSize = 3000000;
    EXPECT_EQ(o.particleMemoryBytes(),
              1000000 * Localizer::kBytesPerParticle + 3000000 * Localizer::kBytesPerKLDParticle);
    o.particles_count = Localizer::TOptions::kMaxParticles;
    o.kld.KLD_maxSampleSize = 100000000;
    EXPECT_GT(o.particleMemoryBytes(), uint64_t{30000000000}) << "no overflow";
}

TEST(Localizer, VeryUncertainOdometryStillMovesTheParticles)
{
    // MRPT's CActionCollection::getBestMovementEstimation() ignores a 2D movement whose
    // covariance determinant is 1e3 or more: the step must use it all the same.
    const auto world = semloc::World::FromFile(kPaperWorld);
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;
    model.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    model.gaussianModel.minStdXY = 5;
    model.gaussianModel.minStdPHI = mrpt::DEG2RAD(60.0);
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(10, 0, 0), model);
    mrpt::obs::CActionCollection acts;
    acts.insert(move);
    ASSERT_GT(move.poseChange->getCovariance().det(), 1e3);
    ASSERT_FALSE(acts.getBestMovementEstimation()) << "MRPT's rule changed: the test is moot";

    for (const bool kld : {false, true})
    {
        Localizer::TOptions o = gaussianStart(4000);
        o.init_PDF_std_xy = 0.1;
        o.free_space_prior = false;
        o.pf.adaptiveSampleSize = kld;
        o.kld.KLD_minSampleSize = 4000;
        Localizer loc(o, semanticMap(world), &world);
        const auto before = loc.mean();
        loc.step(acts, mrpt::obs::CSensoryFrame());
        EXPECT_NEAR(loc.mean().x() - before.x(), 10, 1) << "KLD " << kld;
        EXPECT_GT(loc.varianceXY(), 10) << "KLD " << kld << ": the noise is applied";
    }

    // Observations only: [DummyOdometryParams] noise as large.
    Localizer::TOptions o = gaussianStart(4000);
    o.init_PDF_std_xy = 0.1;
    o.free_space_prior = false;
    o.odometry_min_std_xy = 5;
    o.odometry_min_std_phi_deg = 60;
    Localizer loc(o, semanticMap(world), &world);
    mrpt::obs::CObservationOdometry odo;
    loc.setOdometry(odo);
    odo.odometry = mrpt::poses::CPose2D(10, 0, 0);
    loc.setOdometry(odo);
    const auto before = loc.mean();
    loc.step(mrpt::obs::CSensoryFrame());
    EXPECT_NEAR(loc.mean().x() - before.x(), 10, 1);
}

TEST(Localizer, ResetStartsTheRecoveryTriggerAfresh)
{
    // A filter sure of a wrong place accumulates the evidence trigger's shortfall until it
    // injects; reset() (a new run) starts the trigger from zero.
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(80);
    Localizer::TOptions o = gaussianStart(500);
    o.init_PDF_mean_x = 40;
    o.init_PDF_mean_y = 40;
    o.init_PDF_std_xy = 0.3;
    o.threads = 1;
    o.recovery.trigger = semloc::RecoveryTrigger::Evidence;
    Localizer loc(o, semanticMap(world), &world);
    const auto step = [&](size_t i)
    { loc.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1)); };
    size_t i = 0;
    for (; i + 1 < sim.rawlog.size() && loc.pdf().lastInjectionProbability() == 0; i += 2)
    {
        step(i);
    }
    ASSERT_GT(loc.pdf().lastInjectionProbability(), 0) << "the wrong start never triggered";
    ASSERT_GE(loc.pdf().recoveryShortfall(), o.recovery.evidence_threshold);
    const size_t injected = loc.recoveryStats().injection_steps;

    loc.reset();
    EXPECT_EQ(loc.pdf().recoveryShortfall(), 0);
    EXPECT_EQ(loc.recoveryStats().injection_steps, injected) << "the counters keep counting";
    ASSERT_LT(i + 1, sim.rawlog.size());
    step(i);  // one frame alone cannot reach a fresh trigger's threshold
    EXPECT_LE(loc.pdf().recoveryShortfall(), o.recovery.evidence_threshold / 2);
    EXPECT_EQ(loc.pdf().lastInjectionProbability(), 0);
}

TEST(Localizer, ObservationsThatCannotBeScoredAreLeftOutAndCounted)
{
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(3);
    const auto map = semanticMap(world);
    auto gridMap = mrpt::maps::CMultiMetricMap::Create();
    gridMap->maps.push_back(mrpt::maps::COccupancyGridMap2D::Create(world.makeOccupancyGrid(0.5)));
    const auto frame = sim.rawlog.getAsObservations(1);
    const auto sem = frame->getObservationByClass<semloc::CObservationSemantic>();
    const auto scan = frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
    ASSERT_TRUE(sem && scan);
    EXPECT_EQ(Localizer::invalidObservation(*sem, *map), "");
    EXPECT_EQ(Localizer::invalidObservation(*scan, *gridMap), "");

    auto semWith = [&](const std::function<void(semloc::CObservationSemantic&)>& edit)
    {
        auto o = std::make_shared<semloc::CObservationSemantic>(*sem);
        edit(*o);
        return o;
    };
    auto scanWith = [&](const std::function<void(mrpt::obs::CObservation2DRangeScan&)>& edit)
    {
        auto o = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*scan);
        edit(*o);
        return o;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<std::pair<mrpt::obs::CObservation::Ptr, std::string>> bad = {
        {semWith([&](auto& o) { o.sensorPose.x(nan); }), "sensorPose is not finite"},
        {semWith([&](auto& o) { o.sensorPose.setYawPitchRoll(nan, 0, 0); }),
         "sensorPose is not finite"},
        {semWith([](auto& o) { o.sensorPose.y(1e300); }), "more than 1000 m from the vehicle"},
        {semWith([](auto& o) { o.maxRange_m = std::numeric_limits<double>::infinity(); }),
         "maxRange_m inf is not a finite range"},
        {semWith([&](auto& o) { o.fov_rad = nan; }), "fov_rad nan is not a finite angle"},
        {scanWith([&](auto& o) { o.sensorPose.z(nan); }), "sensorPose is not finite"},
        {scanWith([](auto& o) { o.aperture = std::numeric_limits<float>::quiet_NaN(); }),
         "aperture nan is not a finite angle"},
        {scanWith([](auto& o) { o.resizeScan(0); }), "it has no beam"},
    };
    for (const auto& [obs, why] : bad)
    {
        EXPECT_NE(Localizer::invalidObservation(*obs, *map).find(why), std::string::npos)
            << why << ": " << Localizer::invalidObservation(*obs, *map);
    }
    const auto oneBeam = scanWith([](auto& o) { o.resizeScan(1); });
    EXPECT_EQ(Localizer::invalidObservation(*oneBeam, *map), "") << "no grid: usable";
    EXPECT_NE(Localizer::invalidObservation(*oneBeam, *gridMap).find("needs at least 2"),
              std::string::npos);

    // The same steps with and without the invalid observations: the same particles (one
    // localizer after the other: each seeds MRPT's global generator).
    const Localizer::TOptions o = gaussianStart(500);
    auto run = [&](bool withBad)
    {
        auto loc = std::make_unique<Localizer>(o, map, &world);
        for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
        {
            mrpt::obs::CSensoryFrame sf;
            for (const auto& [obs, why] : bad)
            {
                if (withBad)
                {
                    sf.insert(obs);
                }
            }
            for (const auto& obs : *sim.rawlog.getAsObservations(i + 1))
            {
                sf.insert(obs);
            }
            loc->step(*sim.rawlog.getAsAction(i), sf);
        }
        return loc;
    };
    const auto clean = run(false);
    const auto dirty = run(true);
    EXPECT_EQ(dirty->likelihoodStats().observations_invalid, bad.size() * sim.steps);
    EXPECT_EQ(clean->likelihoodStats().observations_invalid, 0u);
    EXPECT_EQ(dirty->likelihoodStats().observations_used,
              clean->likelihoodStats().observations_used);
    EXPECT_EQ(dirty->mean().x(), clean->mean().x());
    EXPECT_EQ(dirty->mean().y(), clean->mean().y());
    EXPECT_EQ(dirty->mean().phi(), clean->mean().phi());
}

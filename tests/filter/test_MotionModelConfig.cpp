/* semloc tests — MotionModelConfig ([MotionModel]): its keys, the re-derived odometry against
 * MRPT's computeFromOdometry, the Localizer's use of it in both rawlog formats, the spread it
 * gives. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <semloc/filter/Localizer.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/filter/OdometryDelay.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"
#include "filter/PaperFixtures.h"

using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using semloc::Localizer;
using semloc::MotionModelConfig;
using semloc::test::errorOf;

using semloc::test::iniText;
using semloc::test::semanticMap;
using semloc::test::simulate;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

/** A re-derivation with noise far from the simulator's. */
MotionModelConfig::TOptions wideModel()
{
    MotionModelConfig::TOptions m;
    m.source = MotionModelConfig::Source::Gaussian;
    m.a1 = 0.2;
    m.a2 = 0.01;
    m.a3 = 3;
    m.a4 = 0.3;
    m.minStdXY = 0.05;
    m.minStdPHI = 1.5;
    return m;
}

/** MRPT's own options for wideModel(), in TOptions_GaussianModel's units (radians). */
CActionRobotMovement2D::TMotionModelOptions wideModelMrpt()
{
    CActionRobotMovement2D::TMotionModelOptions m;
    m.modelSelection = CActionRobotMovement2D::mmGaussian;
    m.gaussianModel = {0.2, 0.01 * 180 / M_PI, 3 * M_PI / 180, 0.3, 0.05, 1.5 * M_PI / 180};
    return m;
}

/** The particles of two localizers are the same, bit for bit. */
void expectSameParticles(const Localizer& a, const Localizer& b)
{
    ASSERT_EQ(a.pdf().size(), b.pdf().size());
    for (size_t i = 0; i < a.pdf().size(); i++)
    {
        const auto& p = a.pdf().m_particles[i];
        const auto& q = b.pdf().m_particles[i];
        ASSERT_EQ(p.d.x, q.d.x) << i;
        ASSERT_EQ(p.d.y, q.d.y) << i;
        ASSERT_EQ(p.d.phi, q.d.phi) << i;
        ASSERT_EQ(p.log_w, q.log_w) << i;
    }
}

Localizer::TOptions gaussianStart(int particles, double stdXY)
{
    Localizer::TOptions o;
    o.particles_count = particles;
    o.init_PDF_mode = Localizer::InitMode::Gaussian;
    o.init_PDF_mean_x = 4;
    o.init_PDF_mean_y = 5;
    o.init_PDF_std_xy = stdXY;
    o.init_PDF_std_yaw_deg = stdXY > 0 ? 10 : 0;
    o.threads = 2;
    return o;
}
}  // namespace

TEST(MotionModelConfig, ReadWriteEveryKeyAndRejectMistakes)
{
    MotionModelConfig::TOptions o;
    EXPECT_EQ(o.source, MotionModelConfig::Source::Rawlog);
    o.loadFromConfigFile(iniText("[MotionModel]\nsource = gaussian\na1 = 0.2\na2 = 0.01\na3 = 3\n"
                                 "a4 = 0.3\nminStdXY = 0.05\nminStdPHI = 1.5 // deg\n"),
                         "MotionModel");
    EXPECT_EQ(o.source, MotionModelConfig::Source::Gaussian);
    EXPECT_EQ(o.odometry_delay_s, 0);
    EXPECT_EQ(o.a3, 3);
    EXPECT_EQ(o.minStdPHI, 1.5);

    mrpt::config::CConfigFileMemory out, out2;
    o.saveToConfigFile(out, "MotionModel");
    MotionModelConfig::TOptions back;
    back.loadFromConfigFile(iniText(out.getContent()), "MotionModel");
    back.saveToConfigFile(out2, "MotionModel");
    EXPECT_EQ(out.getContent(), out2.getContent());
    EXPECT_EQ(back.source, MotionModelConfig::Source::Gaussian);
    EXPECT_EQ(back.a2, 0.01);
    o.loadFromConfigFile(iniText("[MotionModel]\nodometry_delay_s = 0.25\n"), "MotionModel");
    EXPECT_EQ(o.odometry_delay_s, 0.25);

    // Through Localizer::TOptions, whose config.ini carries the section.
    Localizer::TOptions lo;
    lo.loadFromConfigFile(iniText("[MotionModel]\nsource = gaussian\na1 = 0.5\n"),
                          "LocalizationExperiment");
    EXPECT_EQ(lo.motion_model.a1, 0.5);
    mrpt::config::CConfigFileMemory eff;
    lo.saveToConfigFile(eff, "LocalizationExperiment");
    EXPECT_NE(eff.getContent().find("[MotionModel]"), std::string::npos);

    const std::pair<const char*, const char*> bad[] = {
        {"source = recompute", "[MotionModel] source: 'recompute' is not one of: rawlog, gaussian"},
        {"a5 = 1", "[MotionModel] a5: unknown key"},
        {"a1 = -0.1", "[MotionModel] a1: value -0.1 is out of range"},
        {"a4 = nan", "[MotionModel] a4: 'nan' is not a finite number"},
        {"minStdPHI = 400", "[MotionModel] minStdPHI: value 400 is out of range [0, 360]"},
        {"minStdXY = wide", "[MotionModel] minStdXY: 'wide' is not a number"},
        {"odometry_delay_s = 6", "[MotionModel] odometry_delay_s: value 6 is out of range [0, 5]"},
        {"odometry_delay_s = -0.1", "[MotionModel] odometry_delay_s: value -0.1 is out of range"},
    };
    for (const auto& [line, needle] : bad)
    {
        const std::string text = std::string("[MotionModel]\n") + line + "\n";
        const std::string err = errorOf(
            [&text]
            {
                MotionModelConfig::TOptions x;
                x.loadFromConfigFile(iniText(text), "MotionModel");
            });
        EXPECT_NE(err.find(needle), std::string::npos) << line << ": " << err;
    }
}

TEST(MotionModelConfig, DefaultsAreMrptsAndUnitsFollowMrpt)
{
    const auto m = MotionModelConfig(MotionModelConfig::TOptions()).gaussian();
    const CActionRobotMovement2D::TMotionModelOptions mrpt;
    EXPECT_EQ(m.modelSelection, CActionRobotMovement2D::mmGaussian);
    EXPECT_EQ(m.gaussianModel.a1, mrpt.gaussianModel.a1);
    EXPECT_EQ(m.gaussianModel.a2, mrpt.gaussianModel.a2);
    EXPECT_EQ(m.gaussianModel.a3, mrpt.gaussianModel.a3);
    EXPECT_EQ(m.gaussianModel.a4, mrpt.gaussianModel.a4);
    EXPECT_EQ(m.gaussianModel.minStdXY, mrpt.gaussianModel.minStdXY);
    EXPECT_EQ(m.gaussianModel.minStdPHI, mrpt.gaussianModel.minStdPHI);
}

TEST(MotionModelConfig, EveryActionGetsMrptsCovarianceOfItsIncrement)
{
    const auto sim = simulate(30);
    const MotionModelConfig model(wideModel());
    const auto mrptModel = wideModelMrpt();
    size_t checked = 0;
    for (size_t i = 0; i < sim.rawlog.size(); i += 2)
    {
        const auto& acts = *sim.rawlog.getAsAction(i);
        ASSERT_EQ(model.problem(acts), "");
        CActionCollection copy;
        const auto& out = model.apply(acts, copy);
        ASSERT_EQ(&out, &copy);
        const auto* src = acts.getActionByClass<CActionRobotMovement2D>().get();
        const auto* got = copy.getActionByClass<CActionRobotMovement2D>().get();
        ASSERT_TRUE(src && got);
        CActionRobotMovement2D ref;  // MRPT itself, from the raw increment
        ref.computeFromOdometry(src->rawOdometryIncrementReading, mrptModel);
        const auto [cov, mean] = got->poseChange->getCovarianceAndMean();
        const auto [refCov, refMean] = ref.poseChange->getCovarianceAndMean();
        EXPECT_EQ(mean, refMean);
        for (int r = 0; r < 3; r++)
        {
            for (int c = 0; c < 3; c++)
            {
                EXPECT_NEAR(cov(r, c), refCov(r, c), 1e-15 + 1e-12 * std::abs(refCov(r, c)));
            }
        }
        // ... and not the rawlog's own: the model is wider.
        EXPECT_GT(cov(0, 0), src->poseChange->getCovariance()(0, 0));
        EXPECT_EQ(got->timestamp, src->timestamp);
        checked++;
    }
    EXPECT_EQ(checked, sim.steps);
    // source = rawlog: the actions as they are.
    CActionCollection copy;
    EXPECT_EQ(
        &MotionModelConfig(MotionModelConfig::TOptions()).apply(*sim.rawlog.getAsAction(0), copy),
        sim.rawlog.getAsAction(0).get());
}

TEST(MotionModelConfig, ActionsItCannotRederiveAreNamed)
{
    const MotionModelConfig model(wideModel());
    CActionRobotMovement2D scan;
    scan.computeFromOdometry(mrpt::poses::CPose2D(1, 0, 0), {});
    scan.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
    CActionCollection a;
    a.insert(scan);
    EXPECT_NE(model.problem(a).find("scan-matching"), std::string::npos);
    EXPECT_EQ(MotionModelConfig(MotionModelConfig::TOptions()).problem(a), "");  // source = rawlog
    CActionCollection copy;
    EXPECT_NE(errorOf([&] { model.apply(a, copy); }).find("[MotionModel] source = gaussian"),
              std::string::npos);

    CActionRobotMovement2D noRaw;  // the pose change set directly, no raw increment
    mrpt::math::CMatrixDouble33 cov;
    cov.setIdentity();
    noRaw.poseChange = mrpt::poses::CPosePDFGaussian::Create(mrpt::poses::CPose2D(1, 0, 0), cov);
    CActionCollection b;
    b.insert(noRaw);
    EXPECT_NE(model.problem(b).find("holds no raw odometry increment"), std::string::npos);

    CActionCollection c;
    c.insert(mrpt::obs::CActionRobotMovement3D());
    EXPECT_NE(model.problem(c).find("CActionRobotMovement3D"), std::string::npos);

    CActionRobotMovement2D still;  // a zero increment with a zero raw reading is fine
    still.computeFromOdometry(mrpt::poses::CPose2D(0, 0, 0), {});
    CActionCollection d;
    d.insert(still);
    EXPECT_EQ(model.problem(d), "");
}

TEST(MotionModelConfig, LocalizerUsesTheRederivedOdometryInBothFormats)
{
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(12);
    Localizer::TOptions o = gaussianStart(800, 1.5);

    // Action pairs: re-derived by the Localizer = the rawlog's actions recomputed by MRPT.
    Localizer::TOptions og = o;
    og.motion_model = wideModel();
    // (One filter after the other: each seeds MRPT's global generator.)
    Localizer rederived(og, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        rederived.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
    }
    Localizer byHand(o, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        const auto& acts = *sim.rawlog.getAsAction(i);
        CActionRobotMovement2D mv(*acts.getActionByClass<CActionRobotMovement2D>());
        mv.computeFromOdometry(mv.rawOdometryIncrementReading, wideModelMrpt());
        CActionCollection recomputed;
        recomputed.insert(mv);
        byHand.step(recomputed, *sim.rawlog.getAsObservations(i + 1));
    }
    expectSameParticles(rederived, byHand);

    // Observations only: [MotionModel] gives the noise of each reading's increment (the
    // [DummyOdometryParams] noise is not used): the same as the pairs of those increments.
    Localizer::TOptions od = og;
    od.odometry_min_std_xy = 7;  // would make a different filter if it were used
    std::vector<mrpt::poses::CPose2D> readings;
    mrpt::poses::CPose2D odo(100, -20, 1.0);
    Localizer obsOnly(od, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        odo =
            odo + sim.rawlog.getAsAction(i)->getBestMovementEstimation()->poseChange->getMeanVal();
        readings.push_back(odo);
        mrpt::obs::CObservationOdometry reading;
        reading.odometry = odo;
        obsOnly.setOdometry(reading);
        obsOnly.step(*sim.rawlog.getAsObservations(i + 1));
    }
    Localizer pairs(o, semanticMap(world), &world);
    mrpt::poses::CPose2D last;
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        odo = readings[i / 2];
        CActionRobotMovement2D mv;
        // As the Localizer does: the first reading is the reference (a zero increment).
        mv.computeFromOdometry(i == 0 ? odo - odo : odo - last, wideModelMrpt());
        last = odo;
        CActionCollection acts;
        acts.insert(mv);
        pairs.step(acts, *sim.rawlog.getAsObservations(i + 1));
    }
    expectSameParticles(obsOnly, pairs);
}

TEST(MotionModelConfig, LocalizerMovesByTheIncrementsReCutForTheDelay)
{
    // odometry_delay_s: the Localizer moves the particles by each action's increment re-cut
    // by OdometryDelay at the action's time, its covariance kept: the same particles as a
    // filter without the delay fed those increments by hand.
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(12);
    Localizer::TOptions o = gaussianStart(500, 1.5);
    Localizer::TOptions od = o;
    od.motion_model.odometry_delay_s = 0.7;
    Localizer delayed(od, semanticMap(world), &world);
    semloc::OdometryDelay cut(0.7);
    std::vector<CActionCollection> byHandActions;
    size_t changed = 0;
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        const auto& acts = *sim.rawlog.getAsAction(i);
        delayed.step(acts, *sim.rawlog.getAsObservations(i + 1));
        const auto move = acts.getBestMovementEstimation();
        const auto* g = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(move->poseChange.get());
        ASSERT_NE(g, nullptr);
        const mrpt::poses::CPose2D u(
            cut.step(mrpt::Clock::toDouble(move->timestamp), g->mean.asTPose()));
        ASSERT_NE(delayed.lastMovement(), nullptr);
        const auto got = delayed.lastMovement()->poseChange->getMeanVal();
        EXPECT_EQ(got.x(), u.x());
        EXPECT_EQ(got.y(), u.y());
        EXPECT_EQ(got.phi(), u.phi());
        changed += std::abs(u.x() - g->mean.x()) > 1e-6 ? 1 : 0;
        CActionRobotMovement2D mv(*move);
        mv.poseChange =
            mrpt::poses::CPosePDF::Ptr(std::make_shared<mrpt::poses::CPosePDFGaussian>(u, g->cov));
        byHandActions.emplace_back();
        byHandActions.back().insert(mv);
    }
    EXPECT_GT(changed, 10U);  // the re-cut increments are not the rawlog's
    Localizer byHand(o, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        byHand.step(byHandActions[i / 2], *sim.rawlog.getAsObservations(i + 1));
    }
    expectSameParticles(delayed, byHand);

    // A step without any timestamp cannot be re-cut: an error that says why.
    Localizer noTime(od, semanticMap(world), &world);
    CActionRobotMovement2D mv;
    mv.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0), wideModelMrpt());
    mv.timestamp = INVALID_TIMESTAMP;
    CActionCollection acts;
    acts.insert(mv);
    const std::string err = errorOf([&] { noTime.step(acts, mrpt::obs::CSensoryFrame()); });
    EXPECT_NE(err.find("odometry_delay_s > 0 needs timestamped steps"), std::string::npos) << err;
}

TEST(MotionModelConfig, SimulatorsModelRederivedChangesNothing)
{
    // config/localize/semantic.ini's [MotionModel] values are config/simulate/simulate.ini's
    // [Odometry]: with source = gaussian the filter runs exactly as with the rawlog's own noise.
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto sim = simulate(12);
    mrpt::config::CConfigFileMemory c;
    c.setContent(semloc::test::resolvedIni(SEMLOC_SOURCE_DIR "/config/localize/semantic.ini"));
    Localizer::TOptions o = gaussianStart(800, 1.5);
    o.motion_model.loadFromConfigFile(c, "MotionModel");
    EXPECT_EQ(o.motion_model.source, MotionModelConfig::Source::Rawlog);
    Localizer own(o, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        own.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
    }
    o.motion_model.source = MotionModelConfig::Source::Gaussian;
    Localizer rederived(o, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        rederived.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
    }
    expectSameParticles(own, rederived);
    // A different model does change the filter (the comparison can fail).
    o.motion_model.a1 = 0.06;
    Localizer other(o, semanticMap(world), &world);
    for (size_t i = 0; i + 1 < sim.rawlog.size(); i += 2)
    {
        other.step(*sim.rawlog.getAsAction(i), *sim.rawlog.getAsObservations(i + 1));
    }
    EXPECT_NE(own.pdf().m_particles[0].d.x, other.pdf().m_particles[0].d.x);
}

TEST(MotionModelConfig, LargerCoefficientsSpreadTheParticlesMore)
{
    // Every particle at one pose, one step of 2 m turning 20 deg, no observation: the spread
    // after it is the motion model's alone, and grows with a1..a4.
    const auto world = semloc::World::FromFile(kPaperWorld);
    CActionRobotMovement2D mv;
    mv.computeFromOdometry(mrpt::poses::CPose2D(2, 0, mrpt::DEG2RAD(20.0)), {});
    CActionCollection acts;
    acts.insert(mv);
    const mrpt::obs::CSensoryFrame empty;
    double previous = 0;
    for (const double scale : {0.5, 1.0, 2.0, 4.0})
    {
        Localizer::TOptions o = gaussianStart(4000, 0);
        o.motion_model.source = MotionModelConfig::Source::Gaussian;
        o.motion_model.a1 = 0.05 * scale;
        o.motion_model.a2 = 0.002 * scale;
        o.motion_model.a3 = 1 * scale;
        o.motion_model.a4 = 0.05 * scale;
        o.motion_model.minStdXY = 0.001;
        o.motion_model.minStdPHI = 0.01;
        Localizer loc(o, semanticMap(world), &world);
        loc.step(acts, empty);
        const double spread = loc.varianceXY();
        // The model's own x-y variance (MRPT's covariance at this increment), within 10 %.
        CActionRobotMovement2D ref;
        ref.computeFromOdometry(mv.rawOdometryIncrementReading,
                                MotionModelConfig(o.motion_model).gaussian());
        const auto cov = ref.poseChange->getCovariance();
        EXPECT_NEAR(spread, cov(0, 0) + cov(1, 1), 0.1 * (cov(0, 0) + cov(1, 1))) << scale;
        EXPECT_GT(spread, 1.5 * previous) << scale;
        previous = spread;
    }
}

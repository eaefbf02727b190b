/* semloc tests — the detector outage model: the two-state chain and the mixture against their
 * closed forms, the options refused, and a silence that no longer drags the filter to poses
 * that see nothing. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <string>
#include <vector>

#include "TestHelpers.h"
#include "filter/DetectorOutage.h"

using mrpt::math::TPose2D;
using semloc::CParallelMonteCarloLocalization2D;
using semloc::CSemanticMap;
using semloc::detail::DetectorOutage;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

semloc::SensoryFrameLikelihood::TOutageTerms terms(double t_s, bool silent = true)
{
    semloc::SensoryFrameLikelihood::TOutageTerms o;
    o.present = true;
    o.silent = silent;
    o.t = mrpt::Clock::fromDouble(1000 + t_s);
    o.every_s = 300;
    o.mean_s = 60;
    return o;
}

/** A semantic observation of the paper world from `truth` at time t_s; none of the map's
 *  objects detected in a silence, only (with `unknownInSilence`) a diver close ahead, a label
 *  the map does not know. */
std::shared_ptr<semloc::CObservationSemantic> frameObs(const semloc::World& w, const TPose2D& truth,
                                                       double t_s, bool silent,
                                                       bool unknownInSilence = false)
{
    auto obs = std::make_shared<semloc::CObservationSemantic>(semloc::test::observe(w, truth));
    obs->timestamp = mrpt::Clock::fromDouble(1000 + t_s);
    if (silent)
    {
        obs->detections.clear();
        if (unknownInSilence)
        {
            semloc::TSemanticDetection d;
            d.label = "diver";
            d.range_m = 2;
            d.bearing_rad = 0.1;
            obs->detections.push_back(d);
        }
    }
    return obs;
}

mrpt::obs::CActionCollection odometry(double dx)
{
    return semloc::test::gaussianOdometry(mrpt::poses::CPose2D(dx, 0, 0));
}

struct SilenceRun
{
    double maxErrorInSilence = 0;
    double errorAfter = 0;
    double outageAtSilenceEnd = 0;
    double outageAfter = 0;
};

/** Tracks along the leg y = 4 of the paper world from a cloud around the truth: 10 frames
 *  with detections, 60 silent ones (objects in view), 10 with detections again. */
SilenceRun runSilence(double outageEvery_s, size_t threads, bool unknownInSilence = false)
{
    const auto world = semloc::World::FromFile(kPaperWorld);
    auto sem = CSemanticMap::Create();
    sem->loadFromWorld(world);
    sem->likelihoodOptions.model = CSemanticMap::Model::Probabilistic;
    sem->likelihoodOptions.outage.outage_every_s = outageEvery_s;
    sem->likelihoodOptions.outage.outage_mean_s = 60;
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(sem);

    CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    pdf.setExecutor(std::make_shared<semloc::ParallelExecutor>(threads));
    mrpt::random::getRandomGenerator().randomize(3);
    pdf.resetUniform(4, 6, 3, 5, -0.1, 0.1, 2000);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;

    SilenceRun r;
    TPose2D truth(5, 4, 0);
    for (int k = 0; k < 80; k++)
    {
        truth.x += 0.25;
        const bool silent = k >= 10 && k < 70;
        const auto acts = odometry(0.25);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(frameObs(world, truth, k, silent, unknownInSilence));
        pf.executeOn(pdf, &acts, &sf);
        const auto mean = pdf.getMeanVal();
        const double err = std::hypot(mean.x() - truth.x, mean.y() - truth.y);
        if (silent)
        {
            r.maxErrorInSilence = std::max(r.maxErrorInSilence, err);
        }
        if (k == 69)
        {
            r.outageAtSilenceEnd = pdf.detectorOutageProbability();
        }
        r.errorAfter = err;
        r.outageAfter = pdf.detectorOutageProbability();
    }
    return r;
}
/** The filter held through the silence (within 0.5 m in it and after), found the outage and
 *  its end. */
void expectHeldThroughTheSilence(const SilenceRun& on)
{
    EXPECT_LT(on.maxErrorInSilence, 0.5);
    EXPECT_LT(on.errorAfter, 0.5);
    EXPECT_GT(on.outageAtSilenceEnd, 0.9);
    EXPECT_LT(on.outageAfter, 0.1);
}

/** Two runs gave the same numbers. */
void expectSameRun(const SilenceRun& a, const SilenceRun& b)
{
    EXPECT_EQ(a.maxErrorInSilence, b.maxErrorInSilence);
    EXPECT_EQ(a.outageAtSilenceEnd, b.outageAtSilenceEnd);
}
}  // namespace

TEST(DetectorOutage, ObjectsUnknownToTheMapLeaveAFrameSilent)
{
    // A silence in which the detector reports only something the map does not know (a diver
    // close ahead): for the map's objects it is a silence, found as one, and the filter holds.
    const SilenceRun on = runSilence(300, 1, true);
    expectHeldThroughTheSilence(on);
    // The same as a silence with nothing reported at all: unknown detections weigh every pose
    // alike.
    expectSameRun(on, runSilence(300, 1));
}

TEST(DetectorOutage, ChainRelaxesToItsStationaryProbability)
{
    DetectorOutage d;
    const double a = 1.0 / 300, b = 1.0 / 60, s = a / (a + b);
    ASSERT_TRUE(d.predict(terms(0)));
    EXPECT_NEAR(d.probability(), s, 1e-15);  // the first frame: stationary
    EXPECT_NEAR(d.mix()->logOut, std::log(s), 1e-12);
    EXPECT_NEAR(d.mix()->logOn, std::log(1 - s), 1e-12);

    // A posterior of 0.9, then 30 s: s + (0.9 - s) e^{-(a + b) 30}.
    const double logW = 0, logPost = std::log(0.9);
    d.update(&logW, &logPost, 1);
    EXPECT_NEAR(d.probability(), 0.9, 1e-15);
    EXPECT_TRUE(d.predict(terms(30)));
    EXPECT_NEAR(d.probability(), s + (0.9 - s) * std::exp(-(a + b) * 30), 1e-12);
    // Time going back is no time.
    const double before = d.probability();
    d.predict(terms(10));
    EXPECT_EQ(d.probability(), before);
    // A detection: the detector is on, no mixture.
    EXPECT_FALSE(d.predict(terms(11, false)));
    EXPECT_EQ(d.probability(), 0);
    EXPECT_TRUE(d.predict(terms(21)));
    EXPECT_NEAR(d.probability(), s * (1 - std::exp(-(a + b) * 10)), 1e-12);

    semloc::SensoryFrameLikelihood::TOutageTerms untimed = terms(0);
    untimed.t = INVALID_TIMESTAMP;
    EXPECT_THROW(d.predict(untimed), std::exception);
}

TEST(DetectorOutage, MixtureAndPosteriorAreTheClosedForms)
{
    const double pi = 0.3;
    const semloc::detail::OutageMix mix{std::log(pi), std::log(1 - pi)};
    // Three particles: the outage terms s_i are part of logLik_i (with another map's 0.4).
    std::vector<double> s = {-0.5, -12.0, -0.2}, logLik(3);
    for (size_t i = 0; i < 3; i++)
    {
        logLik[i] = s[i] + 0.4;
    }
    std::vector<double> post = s;
    DetectorOutage::apply(mix, logLik.data(), post.data(), 3);
    std::vector<double> want(3);
    for (size_t i = 0; i < 3; i++)
    {
        const double p = pi + (1 - pi) * std::exp(s[i]);
        EXPECT_NEAR(logLik[i], std::log(p) + 0.4, 1e-12) << i;
        want[i] = pi / p;
        EXPECT_NEAR(std::exp(post[i]), want[i], 1e-12) << i;
    }
    // A particle with no weight stays without.
    double dead = -INFINITY, deadPost = -3;
    DetectorOutage::apply(mix, &dead, &deadPost, 1);
    EXPECT_EQ(dead, -INFINITY);

    // The posterior: the weighted mean of the particles' P(out | z, x_i).
    const double w[3] = {0.5, 0.2, 0.3};
    double logW[3];
    for (size_t i = 0; i < 3; i++)
    {
        logW[i] = std::log(w[i]) - 40;  // any common offset
    }
    DetectorOutage d;
    d.update(logW, post.data(), 3);
    EXPECT_NEAR(d.probability(), w[0] * want[0] + w[1] * want[1] + w[2] * want[2], 1e-12);
}

TEST(DetectorOutage, OptionsAreReadAndBadValuesRefused)
{
    auto load = [](const std::string& extra)
    {
        mrpt::config::CConfigFileMemory c("[s]\nmodel = probabilistic\n" + extra);
        CSemanticMap::TLikelihoodOptions o;
        o.loadFromConfigFile(c, "s");
        return o;
    };
    const auto o = load("outage_every_s = 240\noutage_mean_s = 30\n");
    EXPECT_EQ(o.outage.outage_every_s, 240);
    EXPECT_EQ(o.outage.outage_mean_s, 30);
    EXPECT_EQ(load("").outage.outage_every_s, 0);  // off by default
    for (const std::string bad :
         {"outage_every_s = -1\n", "outage_mean_s = 0\n", "outage_every_s = nan\n"})
    {
        EXPECT_THROW(load(bad), std::exception) << bad;
    }
    mrpt::config::CConfigFileMemory paper("[s]\nmodel = paper\noutage_every_s = 60\n");
    CSemanticMap::TLikelihoodOptions p;
    try
    {
        p.loadFromConfigFile(paper, "s");
        FAIL() << "the paper model took the outage model";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("outage_every_s"), std::string::npos) << e.what();
    }
}

TEST(DetectorOutage, ASilenceNoLongerDragsTheFilterAway)
{
    const SilenceRun off = runSilence(0, 1);
    const SilenceRun on = runSilence(300, 1);
    // Without the model every silent frame pays (1 - P_D) per object in view: the cloud moves
    // to poses that see fewer objects.
    EXPECT_GT(off.maxErrorInSilence, 1.0);
    // The model found the outage and its end.
    expectHeldThroughTheSilence(on);
    // The same numbers on two threads.
    expectSameRun(on, runSilence(300, 2));
}

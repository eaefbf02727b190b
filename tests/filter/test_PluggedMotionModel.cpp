/* semloc tests — a motion model defined here only, plugged into the filter through
 * ParticleMotionModel (docs/design.md, "Adding a motion model"): the water current as a state
 * of every particle, estimated by the filter with no line of the filter changed. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/Localizer.h>
#include <semloc/filter/MotionModelRegistry.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "TestHelpers.h"
#include "filter/PositionFixModel.h"

namespace
{
using mrpt::math::TPose2D;
using semloc::test::forward;

/** Normal draws of one particle from (step key, particle index) alone: splitmix64 and
 *  Box–Muller, so any thread may move any particle. */
class Stream
{
public:
    Stream(uint64_t key, size_t i) : m_s(key ^ (static_cast<uint64_t>(i) * 0xD1B54A32D192ED03ull))
    {
    }
    double normal()
    {
        const double u1 = (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53;
        const double u2 = static_cast<double>(next() >> 11) * 0x1.0p-53;
        return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
    }

private:
    uint64_t next()
    {
        uint64_t z = (m_s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint64_t m_s;
};

/** The water current (cx, cy) [m/s] as every particle's state: the vehicle moves by its
 *  odometry through the water (the mean of the step's CActionRobotMovement2D) plus the
 *  current times the step's `dt` seconds, with a little noise; the current starts from
 *  N(0, 0.3²) per axis and walks by N(0, 0.01²) per step. */
class WaterCurrentModel : public semloc::ParticleMotionModel
{
public:
    static constexpr double kDt = 1, kPriorStd = 0.3, kWalkStd = 0.01, kMoveStd = 0.05;
    /** Particle states drawn (from the prior). */
    mutable std::atomic<size_t> drawn{0};

    size_t stateSize() const override { return 2; }
    void drawState(double* state, mrpt::random::CRandomGenerator& rng) const override
    {
        drawn++;
        state[0] = kPriorStd * rng.drawGaussian1D_normalized();
        state[1] = kPriorStd * rng.drawGaussian1D_normalized();
    }
    void prepare(const semloc::TMotionStep& step, mrpt::random::CRandomGenerator& rng) override
    {
        const auto mov = step.actions.getBestMovementEstimation();
        ASSERT_(mov && mov->poseChange);
        m_odometry = mov->poseChange->getMeanVal().asTPose();
        m_key = (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
    }
    void move(size_t i0, size_t n, TPose2D* poses, double* states) const override
    {
        for (size_t k = 0; k < n; k++)
        {
            Stream z(m_key, i0 + k);
            TPose2D& p = poses[k];
            double* current = states + 2 * k;
            const double c = std::cos(p.phi), s = std::sin(p.phi);
            const TPose2D& u = m_odometry;
            p.x += c * u.x - s * u.y + current[0] * kDt + kMoveStd * z.normal();
            p.y += s * u.x + c * u.y + current[1] * kDt + kMoveStd * z.normal();
            p.phi = mrpt::math::wrapToPi(p.phi + u.phi + 0.01 * z.normal());
            current[0] += kWalkStd * z.normal();
            current[1] += kWalkStd * z.normal();
        }
    }

private:
    TPose2D m_odometry;
    uint64_t m_key = 0;
};

constexpr double kCurrentX = 0.25, kCurrentY = -0.15;  // the truth's [m/s]

struct CurrentRun
{
    std::vector<TPose2D> particles;
    std::vector<double> states;
    /** Mean position error over the last 20 of 60 steps [m]. */
    double error = 0;
    /** The weighted mean current of the particles at the end [m/s]. */
    double cx = 0, cy = 0;
};

/** 60 steps of 1 s: the vehicle makes 0.4 m/s east through the water, which carries it by
 *  (kCurrentX, kCurrentY); a position fix (0.5 m) each step. With `model`, the current is
 *  every particle's state; without, the odometry's model (no current). */
CurrentRun track(size_t threads, const std::shared_ptr<WaterCurrentModel>& model)
{
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(std::make_shared<semloc::test::PositionFixModel>());
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    pdf.setExecutor(std::make_shared<semloc::ParallelExecutor>(threads));
    mrpt::random::getRandomGenerator().randomize(7);
    pdf.resetUniform(1, 3, 4, 6, -0.05, 0.05, 2000);
    if (model)
    {
        pdf.setMotionModel(model);
    }
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    mrpt::random::CRandomGenerator noise(11);
    TPose2D truth(2, 5, 0);
    CurrentRun r;
    for (int k = 0; k < 60; k++)
    {
        truth.x += 0.4 + kCurrentX;
        truth.y += kCurrentY;
        const auto acts = forward(0.4);
        auto sf = semloc::test::fixFrame(truth.x + 0.5 * noise.drawGaussian1D_normalized(),
                                         truth.y + 0.5 * noise.drawGaussian1D_normalized(), 0.5);
        pf.executeOn(pdf, &acts, &sf);
        if (k >= 40)
        {
            const auto mean = pdf.getMeanVal();
            r.error += std::hypot(mean.x() - truth.x, mean.y() - truth.y) / 20;
        }
    }
    for (size_t i = 0; i < pdf.size(); i++)
    {
        r.particles.push_back(pdf.m_particles[i].d);
    }
    r.states = pdf.motionStates();
    if (model)
    {
        const auto current = pdf.meanMotionState();
        r.cx = current.at(0);
        r.cy = current.at(1);
    }
    return r;
}
}  // namespace

TEST(PluggedMotionModel, TheFilterEstimatesTheStateOfAModelItDoesNotKnow)
{
    auto model = std::make_shared<WaterCurrentModel>();
    const CurrentRun current = track(1, model);
    const CurrentRun odometry = track(1, nullptr);
    // The current, carried by every particle through the resamplings, is found...
    EXPECT_NEAR(current.cx, kCurrentX, 0.05);
    EXPECT_NEAR(current.cy, kCurrentY, 0.05);
    // ...and the track holds where the odometry alone lags behind the drifting vehicle.
    EXPECT_LT(current.error, 0.5 * odometry.error);
    ASSERT_EQ(current.states.size(), 2 * current.particles.size());
    EXPECT_TRUE(odometry.states.empty());  // the odometry's model keeps no state

    // Deterministic for any number of threads: the poses and the states.
    const CurrentRun two = track(2, std::make_shared<WaterCurrentModel>());
    ASSERT_EQ(current.particles.size(), two.particles.size());
    for (size_t i = 0; i < current.particles.size(); i++)
    {
        ASSERT_EQ(current.particles[i], two.particles[i]) << i;
    }
    EXPECT_EQ(current.states, two.states);
}

TEST(PluggedMotionModel, AParticlePlacedFromOutsideGetsAStateFromThePrior)
{
    auto model = std::make_shared<WaterCurrentModel>();
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(std::make_shared<semloc::test::PositionFixModel>());
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    mrpt::random::getRandomGenerator().randomize(3);
    pdf.resetUniform(0, 1, 0, 1, 0, 0.1, 100);
    pdf.setMotionModel(model);
    EXPECT_EQ(model->drawn.load(), 100u);  // every particle's state drawn
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    const auto acts = forward(0.1);
    pdf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    EXPECT_EQ(model->drawn.load(), 100u);  // the filter's own step keeps them
    const std::vector<double> before = pdf.motionStates();

    // One particle moved by hand: only it gets a new state.
    pdf.m_particles[7].d = TPose2D(50, 50, 0);
    pdf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    EXPECT_EQ(model->drawn.load(), 101u);
    // Moved by hand and adopted: it keeps its state.
    pdf.m_particles[8].d = TPose2D(60, 50, 0);
    pdf.adoptParticles();
    pdf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    EXPECT_EQ(model->drawn.load(), 101u);
    // A new set of another size: every particle new.
    pdf.resetUniform(0, 1, 0, 1, 0, 0.1, 40);
    pdf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
    EXPECT_EQ(model->drawn.load(), 141u);
    EXPECT_EQ(pdf.motionStates().size(), 80u);
    EXPECT_NE(before.size(), pdf.motionStates().size());

    // A substitution carries each particle's state with it.
    const std::vector<double> states = pdf.motionStates();
    pdf.performSubstitution(std::vector<size_t>(40, 9));
    const std::vector<double> after = pdf.motionStates();
    for (size_t i = 0; i < 40; i++)
    {
        ASSERT_EQ(after[2 * i], states[18]);  // particle 9's
        ASSERT_EQ(after[2 * i + 1], states[19]);
    }
}

TEST(PluggedMotionModel, CreatedByNameFromTheMotionModelSection)
{
    semloc::MotionModelRegistry::add("water_current", [](const semloc::MotionModelConfig::TOptions&)
                                     { return std::make_shared<WaterCurrentModel>(); });
    semloc::Localizer::TOptions o;
    o.particles_count = 200;
    o.init_PDF_mode = semloc::Localizer::InitMode::Gaussian;
    o.motion_model.loadFromConfigFile(
        semloc::test::iniText("[MotionModel]\nkind = water_current\n"), "MotionModel");
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    multi->maps.push_back(std::make_shared<semloc::test::PositionFixModel>());
    const semloc::Localizer byName(o, multi);
    EXPECT_NE(dynamic_cast<const WaterCurrentModel*>(&byName.pdf().motionModel()), nullptr);
    EXPECT_EQ(byName.pdf().motionStates().size(), 2u * 200u);  // its state, drawn per particle

    // The default is semloc's odometry model; a name nobody registered is refused, by key.
    o.motion_model = semloc::MotionModelConfig::TOptions();
    const semloc::Localizer odometry(o, multi);
    EXPECT_NE(dynamic_cast<const semloc::OdometryMotionModel*>(&odometry.pdf().motionModel()),
              nullptr);
    semloc::MotionModelConfig::TOptions bad;
    try
    {
        bad.loadFromConfigFile(semloc::test::iniText("[MotionModel]\nkind = tide\n"),
                               "MotionModel");
        FAIL() << "an unknown motion model was accepted";
    }
    catch (const std::exception& e)
    {
        const std::string what = e.what();
        EXPECT_NE(what.find("ini [MotionModel] kind: unknown motion model 'tide' (registered: "
                            "odometry, dvl, water_current)"),
                  std::string::npos)
            << what;
    }
}

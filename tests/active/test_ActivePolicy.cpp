/* Tests of ActivePolicy: the motion that tells two look-alike places apart, determinism over
 * threads, free-space safety and the stop rule. */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cmath>
#include <cstdint>
#include <cstring>

using semloc::ActivePolicy;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;
using semloc::World;

namespace
{
/** Two places that look alike from where the vehicle stands (a buoy 3 m ahead of each),
 *  told apart by a wreck 4 m to the left of the first only; optionally a wall right ahead
 *  of both. */
World twoPlaces(bool wall)
{
    std::string text = R"(
name: two_places
bounds: {x_min: 0, x_max: 40, y_min: 0, y_max: 30}
objects:
  - {id: 1, label: buoy, shape: point, center: [13.5, 10.5]}
  - {id: 2, label: buoy, shape: point, center: [33.5, 10.5]}
  - {id: 3, label: wreck, shape: point, center: [10.5, 14.5]}
)";
    if (wall)
    {
        text +=
            "  - {id: 4, label: quay, shape: box, center: [12, 10.5], size: [0.5, 8]}\n"
            "  - {id: 5, label: quay, shape: box, center: [32, 10.5], size: [0.5, 8]}\n";
    }
    return World::FromText(text, "two_places");
}

CSemanticMap mapOf(const World& w)
{
    CSemanticMap m;
    m.likelihoodOptions.model = CSemanticMap::Model::Probabilistic;
    m.likelihoodOptions.detector.sigma_range_m = 0.3;
    m.likelihoodOptions.detector.sigma_bearing_deg = 3;
    m.likelihoodOptions.probabilistic.p_detect_near = 0.95;
    m.likelihoodOptions.probabilistic.p_detect_far = 0.8;
    m.likelihoodOptions.probabilistic.clutter_per_scan = 0.1;
    m.loadFromWorld(w);
    return m;
}

/** A detector of 5 m and 90 degrees, straight ahead. */
CObservationSemantic sensor()
{
    CObservationSemantic s;
    s.maxRange_m = 5;
    s.fov_rad = M_PI / 2;
    return s;
}

/** Particles split evenly over the poses `at`, each spread by +-`spread` m in a fixed
 *  pattern, heading 0. */
mrpt::poses::CPosePDFParticles cloud(const std::vector<mrpt::math::TPoint2D>& at, double spread)
{
    mrpt::poses::CPosePDFParticles pdf(100 * at.size());
    for (size_t i = 0; i < pdf.m_particles.size(); i++)
    {
        const auto& c = at[i % at.size()];
        const size_t k = i / at.size();  // the particle's place in a 10 x 10 pattern
        const size_t column = k % 10, row = k / 10;
        const double u = static_cast<double>(column) / 9 - 0.5,
                     v = static_cast<double>(row) / 9 - 0.5;
        pdf.m_particles[i].d = mrpt::math::TPose2D(c.x + spread * u, c.y + spread * v, 0.0);
        pdf.m_particles[i].log_w = 0;
    }
    return pdf;
}

/** The bits of `v` (the same bits, not merely equal values). */
uint64_t bits(double v)
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

ActivePolicy::TOptions options(int threads = 1)
{
    ActivePolicy::TOptions o;
    o.threads = threads;
    o.outcomes = 4;
    return o;
}
}  // namespace

TEST(ActivePolicy, TurnsToWhereOnlyOnePlaceHasSomethingToSee)
{
    const World w = twoPlaces(false);
    const CSemanticMap map = mapOf(w);
    ActivePolicy policy(options(), map, &w);
    const auto d = policy.decide(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4), sensor());
    ASSERT_FALSE(d.converged);
    EXPECT_NEAR(d.entropy, std::log(2.0), 0.05);  // two equal places
    // Left, towards the wreck: only the first place would see it (or miss it: negative
    // information), so the posterior tells them apart.
    EXPECT_GT(d.motion.turn_rad, 0.1);
    EXPECT_LT(d.motion.turn_rad, M_PI - 0.1);
    const auto& chosen = d.candidates[static_cast<size_t>(d.chosen)];
    EXPECT_LT(chosen.expected_entropy, 0.5 * d.entropy);
    // Straight on, both see the same buoy: nothing learnt.
    for (const auto& c : d.candidates)
    {
        if (c.motion.turn_rad == 0 && c.admissible)
        {
            EXPECT_GT(c.expected_entropy, 0.8 * d.entropy);
        }
    }
}

TEST(ActivePolicy, PerMetreALookAroundThatTellsThePlacesApartBeatsAJourney)
{
    const World w = twoPlaces(false);
    const CSemanticMap map = mapOf(w);
    auto o = options();
    o.look_around = true;
    o.objective = ActivePolicy::TObjective::GainPerMetre;
    ActivePolicy policy(o, map, &w);
    const auto d = policy.decide(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4), sensor());
    ASSERT_GE(d.chosen, 0);
    // Turning left on the spot shows the wreck (4 m away) from the first place only: as much
    // learnt as by driving there, for no distance.
    EXPECT_EQ(d.motion.distance_m, 0);
    EXPECT_GT(d.motion.turn_rad, 0.1);
    EXPECT_LT(d.motion.turn_rad, M_PI - 0.1);
    size_t scored = 0;
    for (const auto& c : d.candidates)
    {
        if (c.admissible)
        {
            EXPECT_DOUBLE_EQ(
                c.score, -(d.entropy - c.expected_entropy) / (c.motion.distance_m + o.overhead_m));
            scored++;
        }
    }
    EXPECT_GT(scored, o.distances_m.size());
    // Summed with a travel cost instead, the scores are E[H] + c d; free travel buys the
    // journey's extra scans.
    o.objective = ActivePolicy::TObjective::EntropyPlusCost;
    o.travel_cost_per_m = 0;
    ActivePolicy summed(o, map, &w);
    const auto e = summed.decide(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4), sensor());
    EXPECT_GT(e.motion.distance_m, 0);
    for (const auto& c : e.candidates)
    {
        if (c.admissible)
        {
            EXPECT_DOUBLE_EQ(c.score,
                             c.expected_entropy + o.travel_cost_per_m * c.motion.distance_m);
        }
    }
}

TEST(ActivePolicy, SameChoiceForOneAndTwoThreadsAndForTheSameSeed)
{
    const World w = twoPlaces(false);
    const CSemanticMap map = mapOf(w);
    const auto pdf = cloud({{10.5, 10.5}, {30.5, 10.5}, {20.5, 20.5}}, 2.0);
    ActivePolicy one(options(1), map, &w), two(options(2), map, &w), again(options(1), map, &w);
    for (int k = 0; k < 3; k++)  // decisions 0, 1, 2 draw differently but alike in each
    {
        const auto a = one.decide(pdf, sensor()), b = two.decide(pdf, sensor()),
                   c = again.decide(pdf, sensor());
        ASSERT_EQ(a.candidates.size(), b.candidates.size());
        EXPECT_EQ(a.chosen, b.chosen);
        EXPECT_EQ(a.chosen, c.chosen);
        for (size_t i = 0; i < a.candidates.size(); i++)
        {
            const double sa = a.candidates[i].score, sb = b.candidates[i].score,
                         sc = c.candidates[i].score;
            EXPECT_EQ(bits(sa), bits(sb)) << "candidate " << i;
            EXPECT_EQ(bits(sa), bits(sc)) << "candidate " << i;
        }
    }
}

TEST(ActivePolicy, NeverChoosesAPathThroughAnObject)
{
    const World w = twoPlaces(true);  // a quay 1.5 m ahead of both places
    const CSemanticMap map = mapOf(w);
    auto o = options();
    o.min_free_share = 1;
    ActivePolicy policy(o, map, &w);
    const auto d = policy.decide(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4), sensor());
    ASSERT_GE(d.chosen, 0);
    size_t blocked = 0;
    for (const auto& c : d.candidates)
    {
        if (c.motion.turn_rad == 0 && c.motion.distance_m > 0)
        {
            EXPECT_FALSE(c.admissible);  // into the quay
            EXPECT_LT(c.free_share, 1.0);
            blocked++;
        }
    }
    EXPECT_EQ(blocked, o.distances_m.size());
    const auto& chosen = d.candidates[static_cast<size_t>(d.chosen)];
    EXPECT_TRUE(chosen.admissible);
    for (const auto& r : policy.representatives(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4)))
    {
        const double h = r.pose.phi + chosen.motion.turn_rad;
        const mrpt::math::TPoint2D a(r.pose.x, r.pose.y),
            b(a.x + chosen.motion.distance_m * std::cos(h),
              a.y + chosen.motion.distance_m * std::sin(h));
        EXPECT_TRUE(w.isFree(b.x, b.y));
        EXPECT_LT(w.firstObjectOnSegment(a, b), 0);
    }
}

TEST(ActivePolicy, HandsBackAtOnceWhenConverged)
{
    const World w = twoPlaces(false);
    const CSemanticMap map = mapOf(w);
    ActivePolicy policy(options(), map, &w);
    const auto d = policy.decide(cloud({{10.5, 10.5}}, 0.4), sensor());
    EXPECT_TRUE(d.converged);
    EXPECT_LT(d.var_xy_m2, 1.0);
    EXPECT_TRUE(d.candidates.empty());
    EXPECT_EQ(d.chosen, -1);
    EXPECT_EQ(d.motion.distance_m, 0);
    EXPECT_EQ(d.motion.turn_rad, 0);
    // Spread over both places it is not converged.
    EXPECT_FALSE(policy.decide(cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4), sensor()).converged);
}

TEST(ActivePolicy, OptionsReadStrictlyAndWrittenBack)
{
    mrpt::config::CConfigFileMemory ini;
    ini.write("ActiveLocalization", "headings", 6);
    ini.write("ActiveLocalization", "distances_m", "1, 3");
    ActivePolicy::TOptions o;
    o.loadFromConfigFile(ini, "ActiveLocalization");
    EXPECT_EQ(o.headings, 6);
    EXPECT_EQ(o.distances_m, (std::vector<double>{1, 3}));
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "ActiveLocalization");
    ActivePolicy::TOptions back;
    back.loadFromConfigFile(mrpt::config::CConfigFileMemory(out.getContent()),
                            "ActiveLocalization");
    EXPECT_EQ(back.distances_m, o.distances_m);
    EXPECT_EQ(back.headings, 6);
    ini.write("ActiveLocalization", "heading", 6);
    EXPECT_THROW(o.loadFromConfigFile(ini, "ActiveLocalization"), std::exception);
    mrpt::config::CConfigFileMemory bad;
    bad.write("ActiveLocalization", "distances_m", "2, -1");
    EXPECT_THROW(o.loadFromConfigFile(bad, "ActiveLocalization"), std::exception);
}

TEST(ActivePolicy, TheObjectiveIsReadByNameAndWrittenBack)
{
    mrpt::config::CConfigFileMemory ini;
    ini.write("ActiveLocalization", "objective", "gain_per_metre");
    ini.write("ActiveLocalization", "overhead_m", "4");
    ActivePolicy::TOptions o;
    o.loadFromConfigFile(ini, "ActiveLocalization");
    EXPECT_EQ(o.objective, ActivePolicy::TObjective::GainPerMetre);
    EXPECT_EQ(o.overhead_m, 4.0);
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "ActiveLocalization");
    EXPECT_NE(out.getContent().find("gain_per_metre"), std::string::npos);
    ActivePolicy::TOptions back;
    back.loadFromConfigFile(mrpt::config::CConfigFileMemory(out.getContent()),
                            "ActiveLocalization");
    EXPECT_EQ(back.objective, ActivePolicy::TObjective::GainPerMetre);
    EXPECT_EQ(back.overhead_m, 4.0);
    const auto errorOf = [](const char* key, const char* value)
    {
        mrpt::config::CConfigFileMemory bad;
        bad.write("ActiveLocalization", key, value);
        ActivePolicy::TOptions p;
        try
        {
            p.loadFromConfigFile(bad, "ActiveLocalization");
        }
        catch (const std::exception& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(errorOf("objective", "rate").find("objective"), std::string::npos);
    EXPECT_NE(errorOf("overhead_m", "0").find("overhead_m"), std::string::npos);
    EXPECT_EQ(errorOf("objective", "entropy_plus_cost"), "");
}

TEST(ActivePolicy, ADecisionCountsItsLikelihoodEvaluationsAndTellsThemBeforeDrawing)
{
    // Two places 20 m apart, 0.4 m spreads: representatives of 1 m bins. The wall in front
    // of both makes the straight moves inadmissible (no evaluation), the turns evaluate
    // representatives^2 x outcomes x path points each; the observer sees the total before
    // any scan is drawn (no expected entropy yet) and the decision ends with the same.
    const World w = twoPlaces(true);
    const CSemanticMap map = mapOf(w);
    auto o = options();
    o.look_around = true;
    ActivePolicy policy(o, map, &w);
    std::vector<ActivePolicy::TDecision> told;
    policy.setCostObserver([&](const ActivePolicy::TDecision& d) { told.push_back(d); });
    const auto pdf = cloud({{10.5, 10.5}, {30.5, 10.5}}, 0.4);
    const auto d = policy.decide(pdf, sensor());
    ASSERT_EQ(told.size(), 1u);
    const auto K = static_cast<double>(d.representatives);
    double expected = 0;
    size_t inadmissible = 0;
    for (const auto& c : d.candidates)
    {
        const double points =
            c.motion.distance_m > 0 ? std::ceil(c.motion.distance_m / o.scan_every_m) : 1;
        EXPECT_EQ(c.evaluations, c.admissible ? K * K * o.outcomes * points : 0.0);
        expected += c.evaluations;
        inadmissible += c.admissible ? 0 : 1;
    }
    EXPECT_GT(inadmissible, 0u) << "the wall";
    EXPECT_GT(expected, 0.0);
    EXPECT_EQ(d.evaluations, expected);
    EXPECT_EQ(told[0].evaluations, expected);
    for (const auto& c : told[0].candidates)
    {
        EXPECT_TRUE(std::isnan(c.expected_entropy)) << "told before any scan is drawn";
    }
    // In filter steps of the cloud's 200 particles.
    EXPECT_DOUBLE_EQ(ActivePolicy::filterSteps(d.evaluations, pdf.size()), expected / 200);
    EXPECT_TRUE(std::isinf(ActivePolicy::filterSteps(1, 0)));
    // Converged: nothing evaluated, nothing told.
    o.converged_var_xy_m2 = 1e6;
    ActivePolicy converged(o, map, &w);
    converged.setCostObserver([&](const ActivePolicy::TDecision& x) { told.push_back(x); });
    EXPECT_EQ(converged.decide(pdf, sensor()).evaluations, 0.0);
    EXPECT_EQ(told.size(), 1u);
}

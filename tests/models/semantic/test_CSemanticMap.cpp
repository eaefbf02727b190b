/* semloc tests — CSemanticMap: creation, both likelihood models, robustness, insertion. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionProbability.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <set>
#include <thread>
#include <utility>

#include "TestHelpers.h"
#include "models/semantic/VisibilityTable.h"

using mrpt::math::TPose2D;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;
using semloc::TSemanticDetection;
using semloc::World;
using namespace semloc::test;

namespace
{
CSemanticMap smallMap(CSemanticMap::Model model = CSemanticMap::Model::Paper)
{
    CSemanticMap m;
    m.likelihoodOptions.model = model;
    m.loadFromWorld(smallWorld());
    return m;
}

std::string writeWorldFile(const std::string& name)
{
    std::string path = std::string(SEMLOC_TEST_OUT) + "/" + name;
    smallWorld().saveToFile(path);
    return path;
}

mrpt::maps::CMultiMetricMap mapFromIni(const std::string& ini)
{
    mrpt::config::CConfigFileMemory cfg(ini);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "MetricMap");
    mrpt::maps::CMultiMetricMap mm;
    mm.setListOfMaps(inits);
    return mm;
}

const TPose2D kTrue(10, 10, 0.3);

/** Inserts into `map` 40 scans of `w` from known poses on a circle of 8 m around (15, 15),
 *  the detector's full circle, noise sigmaRange [m] and sigmaBearing [rad]. */
void surveyCircle(CSemanticMap& map, const World& w, double sigmaRange, double sigmaBearing,
                  uint32_t seed)
{
    mrpt::random::CRandomGenerator rng(seed);
    DetectorSim ds;
    ds.sigma_range_m = sigmaRange;
    ds.sigma_bearing_rad = sigmaBearing;
    ds.fov_rad = 2 * M_PI;
    for (int k = 0; k < 40; k++)
    {
        const double a = 2 * M_PI * k / 40;
        const TPose2D p(15 + 8 * std::cos(a), 15 + 8 * std::sin(a), a + M_PI / 2);
        map.insertObservation(observe(w, p, ds, &rng),
                              mrpt::poses::CPose3D(mrpt::poses::CPose2D(p)));
    }
}

/** A pillar at (x, y) known to sigma [m], there with probability pExist, an anchor with
 *  probability pAnchor. */
CSemanticMap::TObject uncertainPillar(int32_t id, double x, double y, double sigma, double pExist,
                                      double pAnchor)
{
    CSemanticMap::TObject ob;
    ob.id = id;
    ob.label = "pillar";
    ob.x = x;
    ob.y = y;
    ob.sigma_m = sigma;
    ob.p_exist = pExist;
    ob.classes = {{"anchor", pAnchor}, {"pillar", 1 - pAnchor}};
    return ob;
}
}  // namespace

TEST(CSemanticMap, CreatedFromIniThroughMultiMetricMap)
{
    const std::string world = writeWorldFile("semantic_ini_world.yaml");
    const auto mm = mapFromIni(
        "[MetricMap]\nsemanticMap_count=1\n"
        "[MetricMap_semanticMap_00_creationOpts]\nworld_file=" +
        world +
        "\n[MetricMap_semanticMap_00_likelihoodOpts]\n"
        "model=probabilistic\nsigma_range_m=0.3\nsigma_bearing_deg=2\n");
    const auto sm = mm.mapByClass<CSemanticMap>();
    ASSERT_TRUE(sm);
    EXPECT_EQ(sm->objects().size(), 12u);
    EXPECT_EQ(sm->labelCount(), 4u);
    EXPECT_EQ(sm->likelihoodOptions.model, CSemanticMap::Model::Probabilistic);
    EXPECT_DOUBLE_EQ(sm->likelihoodOptions.detector.sigma_range_m, 0.3);
    // The multi-map sums the semantic log-likelihood like any MRPT map's.
    const auto obs = observe(smallWorld(), kTrue);
    const double viaMulti =
        mm.computeObservationLikelihood(obs, mrpt::poses::CPose3D(mrpt::poses::CPose2D(kTrue)));
    EXPECT_DOUBLE_EQ(viaMulti, sm->computeLogLikelihood(obs, kTrue));
}

TEST(CSemanticMap, IniErrorsNameSectionAndKey)
{
    const std::string world = writeWorldFile("semantic_ini_world2.yaml");
    const std::string head =
        "[MetricMap]\nsemanticMap_count=1\n[MetricMap_semanticMap_00_creationOpts]\nworld_file=" +
        world + "\n[MetricMap_semanticMap_00_likelihoodOpts]\n";
    std::string e = errorOf([&] { mapFromIni(head + "sigma_rnage_m=0.3\n"); });
    EXPECT_NE(e.find("MetricMap_semanticMap_00_likelihoodOpts"), std::string::npos) << e;
    EXPECT_NE(e.find("sigma_rnage_m"), std::string::npos) << e;
    e = errorOf([&] { mapFromIni(head + "model=magic\n"); });
    EXPECT_NE(e.find("model"), std::string::npos) << e;
    EXPECT_NE(e.find("magic"), std::string::npos) << e;
    e = errorOf([&] { mapFromIni(head + "sigma_range_m=-1\n"); });
    EXPECT_NE(e.find("sigma_range_m"), std::string::npos) << e;
    e = errorOf([&] { mapFromIni(head + "sigma_range_m=nan\n"); });
    EXPECT_NE(e.find("sigma_range_m"), std::string::npos) << e;
    for (const char* bad : {"1", "-0.1", "nan"})
    {
        e = errorOf([&] { mapFromIni(head + "p_range_outlier=" + bad + "\n"); });
        EXPECT_NE(e.find("p_range_outlier"), std::string::npos) << bad << ": " << e;
    }
    for (const auto& [value, needle] :
         {std::pair{"0.1, x", "'x' is not a number"}, std::pair{"1, 2, 3, 4, 5", "at most 4"},
          std::pair{"0.1,", "is not a list of numbers"}, std::pair{"nan", "not a finite number"},
          std::pair{"2000", "out of range"}})
    {
        const std::string bad = value;  // a lambda may not capture a structured binding
        e = errorOf([&] { mapFromIni(head + "range_bias_m=" + bad + "\n"); });
        EXPECT_NE(e.find("range_bias_m"), std::string::npos) << bad << ": " << e;
        EXPECT_NE(e.find(needle), std::string::npos) << bad << ": " << e;
    }
    e = errorOf(
        [&]
        {
            mapFromIni(
                "[MetricMap]\nsemanticMap_count=1\n[MetricMap_semanticMap_00_creationOpts]\n"
                "world_file=/no/such/world.yaml\n");
        });
    EXPECT_NE(e.find("/no/such/world.yaml"), std::string::npos) << e;
}

TEST(CSemanticMap, OptionsWrittenToIniReadBackToTheBit)
{
    // The apps' config.ini must reproduce the run: MRPT's write() of a double keeps 6 decimals.
    CSemanticMap::TLikelihoodOptions a;
    a.model = CSemanticMap::Model::Paper;
    a.detector.sigma_range_m = 0.123456789012345;
    a.detector.sigma_bearing_deg = 2.718281828459045;
    a.probabilistic.p_confusion = 1.2345678901234567e-7;
    a.detector.p_range_outlier = 0.031415926535897934;
    a.probabilistic.clutter_per_scan = 1.0 / 3.0;
    a.detector.range_bias_m = {0.1234567890123, -1.0 / 3.0, 0, 2.5e-7};
    CSemanticMap::TInsertionOptions ia;
    ia.merge_distance_m = 2.0 / 3.0;
    mrpt::config::CConfigFileMemory out;
    a.saveToConfigFile(out, "l");
    ia.saveToConfigFile(out, "i");
    const mrpt::config::CConfigFileMemory in(out.getContent());
    CSemanticMap::TLikelihoodOptions b;
    CSemanticMap::TInsertionOptions ib;
    b.loadFromConfigFile(in, "l");
    ib.loadFromConfigFile(in, "i");
    EXPECT_EQ(b.model, a.model);
    EXPECT_EQ(b.detector.sigma_range_m, a.detector.sigma_range_m);
    EXPECT_EQ(b.detector.sigma_bearing_deg, a.detector.sigma_bearing_deg);
    EXPECT_EQ(b.probabilistic.p_confusion, a.probabilistic.p_confusion);
    EXPECT_EQ(b.detector.p_range_outlier, a.detector.p_range_outlier);
    EXPECT_EQ(b.probabilistic.clutter_per_scan, a.probabilistic.clutter_per_scan);
    EXPECT_EQ(b.probabilistic.p_detect_near, a.probabilistic.p_detect_near);
    EXPECT_EQ(b.detector.range_bias_m, a.detector.range_bias_m);
    EXPECT_EQ(ib.merge_distance_m, ia.merge_distance_m);
    // No bias is written as 0 and read back as none.
    mrpt::config::CConfigFileMemory none;
    CSemanticMap::TLikelihoodOptions().saveToConfigFile(none, "l");
    b.loadFromConfigFile(mrpt::config::CConfigFileMemory(none.getContent()), "l");
    EXPECT_TRUE(b.detector.range_bias_m.empty());
}

class BothModels : public ::testing::TestWithParam<CSemanticMap::Model>
{
};

TEST_P(BothModels, PrefersTruePoseOverDisplacedAndRotated)
{
    const CSemanticMap m = smallMap(GetParam());
    const World w = smallWorld();
    mrpt::random::CRandomGenerator rng(7);
    DetectorSim ds;
    ds.sigma_range_m = 0.1;
    ds.sigma_bearing_rad = 0.01;
    int checked = 0;
    for (const TPose2D truth : {TPose2D(10, 10, 0.3), TPose2D(20, 18, 2.0), TPose2D(6, 20, -1.2)})
    {
        const auto obs = observe(w, truth, ds, &rng);
        ASSERT_GE(obs.detections.size(), 2u);
        const double lTrue = m.computeLogLikelihood(obs, truth);
        for (const double d : {0.5, 1.0, 2.0, 4.0})
        {
            for (const double a : {0.0, M_PI / 2, M_PI, -M_PI / 2})
            {
                const TPose2D moved(truth.x + d * std::cos(a), truth.y + d * std::sin(a),
                                    truth.phi);
                EXPECT_GT(lTrue, m.computeLogLikelihood(obs, moved)) << "displaced by " << d;
                checked++;
            }
        }
        for (const double dphi : {-0.3, -0.1, 0.1, 0.3})
        {
            const TPose2D rot(truth.x, truth.y, truth.phi + dphi);
            EXPECT_GT(lTrue, m.computeLogLikelihood(obs, rot)) << "rotated by " << dphi;
            checked++;
        }
    }
    EXPECT_EQ(checked, 60);
}

TEST_P(BothModels, UnmatchedObjectsLowerTheLikelihoodMonotonically)
{
    const CSemanticMap m = smallMap(GetParam());
    auto obs = observe(smallWorld(), kTrue);
    ASSERT_GE(obs.detections.size(), 3u);
    // Extra detections where the map has nothing (false positives).
    double prev = m.computeLogLikelihood(obs, kTrue);
    for (int k = 0; k < 4; k++)
    {
        obs.detections.push_back(detection("wellhead", 2.0 + k, -0.5 + 0.2 * k));
        const double l = m.computeLogLikelihood(obs, kTrue);
        EXPECT_LT(l, prev) << "after adding unmatched detection " << k;
        prev = l;
    }
    // Missed detections of predicted objects.
    auto obs2 = observe(smallWorld(), kTrue);
    prev = m.computeLogLikelihood(obs2, kTrue);
    while (!obs2.detections.empty())
    {
        obs2.detections.pop_back();
        const double l = m.computeLogLikelihood(obs2, kTrue);
        EXPECT_LT(l, prev) << "after dropping to " << obs2.detections.size();
        prev = l;
    }
}

TEST_P(BothModels, AMisreadRangeCostsAtMostTheUniformsShare)
{
    CSemanticMap m = smallMap(GetParam());
    m.likelihoodOptions.detector.sigma_range_m = 0.2;
    const World w = smallWorld();
    mrpt::random::CRandomGenerator rng(11);
    DetectorSim ds;
    ds.sigma_range_m = 0.1;
    ds.sigma_bearing_rad = 0.01;
    const auto clean = observe(w, kTrue, ds, &rng);
    ASSERT_GE(clean.detections.size(), 3u);
    const double R = clean.maxRange_m, sr = m.likelihoodOptions.detector.sigma_range_m;
    int checked = 0;
    for (const double eps : {0.01, 0.1, 0.3})
    {
        m.likelihoodOptions.detector.p_range_outlier = eps;
        const double lClean = m.computeLogLikelihood(clean, kTrue);
        // Whatever range a detection reports, matching it as a misread costs at most the
        // Gaussian's peak over the uniform's density: (1 - eps) N(0) + eps / R over eps / R.
        const double bound = std::log1p((1 - eps) * R / (eps * std::sqrt(2 * M_PI) * sr));
        for (size_t j = 0; j < clean.detections.size(); j++)
        {
            for (const double range : {0.3, 4.0, 11.9})
            {
                auto misread = clean;
                misread.detections[j].range_m = range;
                const double l = m.computeLogLikelihood(misread, kTrue);
                EXPECT_GE(l, lClean - bound - 1e-9) << "eps " << eps << " detection " << j;
                // ... and one misread range leaves the true pose ahead of displaced ones.
                for (const double d : {1.0, 2.0, 4.0})
                {
                    const TPose2D moved(kTrue.x + d, kTrue.y - d, kTrue.phi);
                    EXPECT_GT(l, m.computeLogLikelihood(misread, moved)) << "eps " << eps;
                }
                checked++;
            }
        }
    }
    EXPECT_EQ(checked, 9 * static_cast<int>(clean.detections.size()));
}

INSTANTIATE_TEST_SUITE_P(
    Models, BothModels,
    ::testing::Values(CSemanticMap::Model::Paper, CSemanticMap::Model::Probabilistic),
    [](const auto& param_info)
    { return param_info.param == CSemanticMap::Model::Paper ? "Paper" : "Probabilistic"; });

TEST(CSemanticMap, PaperFormulaExactly)
{
    // One object straight ahead at 5 m; one detection off by d_rho, d_theta.
    CSemanticMap m;
    m.addObject({1, "pillar", 5, 0, 0, 0.3, 1});
    const auto& o = m.likelihoodOptions;
    CObservationSemantic obs;
    obs.maxRange_m = 10;
    obs.fov_rad = M_PI;
    const double dr = 0.3, db = 2.0 * M_PI / 180;
    obs.detections.push_back(detection("pillar", 5 + dr, db));
    const double sb = o.detector.sigma_bearing_deg * M_PI / 180;
    const double expected =
        -0.5 * std::pow(dr / o.detector.sigma_range_m, 2) - 0.5 * std::pow(db / sb, 2);
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), expected, 1e-6);
    // d = q + l - 2m: one more unseen object ahead adds one log(p_u).
    m.addObject({2, "anchor", 7, 1, 0, 0.3, 1});
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)),
                expected + std::log(o.paper.unmatched_penalty), 1e-6);
    // A detection too far off to be worth matching counts as two unmatched objects.
    obs.detections[0].range_m = 9.5;
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)),
                3 * std::log(o.paper.unmatched_penalty), 1e-9);
}

TEST(CSemanticMap, MisreadRangeMixtureExactly)
{
    // One object straight ahead at 5 m; one detection off by d_rho, d_theta.
    for (const auto model : {CSemanticMap::Model::Paper, CSemanticMap::Model::Probabilistic})
    {
        CSemanticMap m;
        m.addObject({1, "pillar", 5, 0, 0, 0.3, 1});
        auto& o = m.likelihoodOptions;
        o.model = model;
        o.detector.p_range_outlier = 0.2;
        o.paper.unmatched_penalty =
            0.05;  // the misread (d_rho = 4 m) is matched, not left unmatched
        CObservationSemantic obs;
        obs.maxRange_m = 10;
        obs.fov_rad = M_PI;
        const double R = obs.maxRange_m, sr = o.detector.sigma_range_m,
                     eps = o.detector.p_range_outlier;
        const double sb = o.detector.sigma_bearing_deg * M_PI / 180, db = 2.0 * M_PI / 180;
        const double logNr = -std::log(std::sqrt(2 * M_PI) * sr);
        for (const double dr : {0.3, 4.0})
        {
            obs.detections = {detection("pillar", 5 + dr, db)};
            const double gauss = -0.5 * std::pow(dr / sr, 2);
            double expected = 0;
            if (model == CSemanticMap::Model::Paper)
            {
                // (1 - eps) N0 + eps sqrt(2 pi) sigma / R, the bearing's N0.
                expected = std::log((1 - eps) * std::exp(gauss) + eps / R / std::exp(logNr)) -
                           0.5 * std::pow(db / sb, 2);
            }
            else
            {
                // -lambda + log P_D + log C + log((1 - eps) N + eps / R) + log N.
                const double pd =
                    o.probabilistic.p_detect_near +
                    (o.probabilistic.p_detect_far - o.probabilistic.p_detect_near) * 5 / R;
                expected = -o.probabilistic.clutter_per_scan + std::log(pd) +
                           std::log(1 - o.probabilistic.p_confusion) +
                           std::log((1 - eps) * std::exp(gauss + logNr) + eps / R) -
                           std::log(std::sqrt(2 * M_PI) * sb) - 0.5 * std::pow(db / sb, 2);
            }
            EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), expected, 1e-6)
                << (model == CSemanticMap::Model::Paper ? "paper" : "probabilistic") << " d_rho "
                << dr;
        }
    }
}

TEST(CSemanticMap, UncertainObjectFormulaExactly)
{
    // One object straight ahead at 5 m, known to +-0.4 m, there with probability 0.6, a pillar
    // with 0.7 and an anchor with 0.3; the map's labels: pillar and anchor (K = 2).
    CSemanticMap m;
    m.addObject(uncertainPillar(1, 5, 0, 0.4, 0.6, 0.3));
    auto& o = m.likelihoodOptions;
    o.model = CSemanticMap::Model::Probabilistic;
    CObservationSemantic obs;
    obs.maxRange_m = 10;
    obs.fov_rad = M_PI;
    const double R = 10, pc = o.probabilistic.p_confusion,
                 lambda = o.probabilistic.clutter_per_scan;
    const double pd =
        0.6 * (o.probabilistic.p_detect_near +
               (o.probabilistic.p_detect_far - o.probabilistic.p_detect_near) * 5 / R);
    auto logN = [](double d, double var)
    { return -0.5 * d * d / var - 0.5 * std::log(2 * M_PI * var); };
    const double sr = o.detector.sigma_range_m, sb = o.detector.sigma_bearing_deg * M_PI / 180;
    const double vr = sr * sr + 0.16, vb = sb * sb + 0.16 / 25;  // sigma_m / rho, rho = 5 m
    const double dr = 0.3, db = 2.0 * M_PI / 180;
    // Seen as an anchor: C = 0.3 (1 - p_c) + 0.7 p_c / (K - 1).
    obs.detections = {detection("anchor", 5 + dr, db)};
    const double matched =
        -lambda + std::log(pd) + std::log(0.3 * (1 - pc) + 0.7 * pc) + logN(dr, vr) + logN(db, vb);
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), matched, 1e-6);
    // Not seen: a miss of probability 1 - p_exist P_D.
    obs.detections.clear();
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), -lambda + std::log(1 - pd), 1e-9);
    // A label it cannot be is clutter, unless p_c lets any label be any other.
    m.addObject({2, "wreck", 40, 40, 0, 0.3, 1});
    o.probabilistic.p_confusion = 0;
    obs.detections = {detection("wreck", 5 + dr, db)};
    const double kappa = lambda / (R * M_PI * 3);  // K = 3 labels now
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)),
                -lambda + std::log(kappa) + std::log(1 - pd), 1e-9);
}

TEST(CSemanticMap, DetectionProbabilityFallsTowardsTheEdgeOfTheView)
{
    // One object at 5 m and bearing b in a 90-degree view; an empty scan costs
    // -lambda + log(1 - P_D(5, b)), a detection of it -lambda + log P_D(5, b) + ...: P_D on the
    // axis times 1 - (1 - p_detect_edge_ratio) |b| / 45 deg.
    CSemanticMap m;
    auto& o = m.likelihoodOptions;
    o.model = CSemanticMap::Model::Probabilistic;
    o.probabilistic.p_detect_near = 0.9;
    o.probabilistic.p_detect_far = 0.5;
    o.probabilistic.p_detect_edge_ratio = 0.2;
    m.addObject({1, "pillar", 5, 0, 0, 0.3, 1});
    CObservationSemantic obs;
    obs.maxRange_m = 10;
    obs.fov_rad = M_PI / 2;
    const double onAxis = 0.9 - 0.4 * 5 / 10;
    for (const double deg : {0.0, 10.0, -30.0, 44.0})
    {
        const double b = mrpt::DEG2RAD(deg);
        const double pd = onAxis * (1 - 0.8 * std::abs(deg) / 45);
        EXPECT_NEAR(o.detectionProbability(5, 10, b, M_PI / 2), pd, 1e-15) << deg;
        obs.detections.clear();
        const TPose2D pose(0, 0, -b);  // the object at bearing b
        EXPECT_NEAR(m.computeLogLikelihood(obs, pose),
                    -o.probabilistic.clutter_per_scan + std::log(1 - pd), 1e-6)
            << deg;
        obs.detections = {detection("pillar", 5, 0)};
        obs.detections[0].bearing_rad = b;
        const double sb = mrpt::DEG2RAD(o.detector.sigma_bearing_deg);
        const double expected = -o.probabilistic.clutter_per_scan + std::log(pd) +
                                std::log(1 - o.probabilistic.p_confusion) -
                                std::log(2 * M_PI * o.detector.sigma_range_m * sb);
        EXPECT_NEAR(m.computeLogLikelihood(obs, pose), expected, 1e-6) << deg;
    }
    // 1: the same across the view; a full circle has no edge.
    o.probabilistic.p_detect_edge_ratio = 1;
    EXPECT_NEAR(o.detectionProbability(5, 10, 0.7, M_PI / 2), onAxis, 1e-15);
    o.probabilistic.p_detect_edge_ratio = 0.2;
    EXPECT_NEAR(o.detectionProbability(5, 10, 3.0, 2 * M_PI), onAxis, 1e-15);
}

TEST(CSemanticMap, RangeBiasIsTakenOffEachDetection)
{
    // A detector whose ranges read c0 + c1 u + c2 u^2 + c3 u^3 long (u: the bearing over half
    // its 90-degree view): with range_bias_m set, a detection of the object at 5 m read that
    // much long scores as a detection at 5 m does without it, in both models.
    for (const auto model : {CSemanticMap::Model::Paper, CSemanticMap::Model::Probabilistic})
    {
        CSemanticMap biased, plain;
        for (CSemanticMap* m : {&biased, &plain})
        {
            m->likelihoodOptions.model = model;
            m->addObject({1, "pillar", 5, 0, 0, 0.3, 1});
        }
        biased.likelihoodOptions.detector.range_bias_m = {0.2, 0.1, -0.5, 0.05};
        CObservationSemantic obs;
        obs.maxRange_m = 10;
        obs.fov_rad = M_PI / 2;
        for (const double deg : {0.0, 20.0, -30.0, 44.0})
        {
            const double b = mrpt::DEG2RAD(deg), u = deg / 45;
            const double bias = 0.2 + 0.1 * u - 0.5 * u * u + 0.05 * u * u * u;
            EXPECT_NEAR(
                semloc::rangeBias(biased.likelihoodOptions.detector.range_bias_m, b, M_PI / 2),
                bias, 1e-15);
            const TPose2D pose(0, 0, -b);  // the object at bearing b
            obs.detections = {detection("pillar", 5 + bias, 0)};
            obs.detections[0].bearing_rad = b;
            const double withBias = biased.computeLogLikelihood(obs, pose);
            obs.detections[0].range_m = 5;
            EXPECT_NEAR(withBias, plain.computeLogLikelihood(obs, pose), 1e-9) << deg;
            // And the bias matters: read as it came, the detection scores lower.
            obs.detections[0].range_m = 5 + bias;
            EXPECT_LT(plain.computeLogLikelihood(obs, pose), withBias - 1e-3) << deg;
        }
    }
}

TEST(CSemanticMap, AFullCircleSeesAnObjectStraightBehind)
{
    // fov = 2 pi sees every direction: an object straight behind the sensor, where the
    // sensor-frame test lx^2 <= d2 may fail by a rounding, is predicted at every pose.
    mrpt::random::CRandomGenerator rng(7);
    CObservationSemantic obs;
    obs.maxRange_m = 20;
    obs.fov_rad = 2 * M_PI;
    size_t counted = 0;
    for (int k = 0; k < 2000; k++)
    {
        const TPose2D pose(rng.drawUniform(-50.0, 50.0), rng.drawUniform(-50.0, 50.0),
                           rng.drawUniform(-M_PI, M_PI));
        const double r = rng.drawUniform(1.0, 19.0);
        CSemanticMap m;  // paper model: an empty scan costs log(p_u) per predicted object
        m.addObject({1, "pillar", pose.x - r * std::cos(pose.phi), pose.y - r * std::sin(pose.phi),
                     0, 0.3, 1});
        const double ll = m.computeLogLikelihood(obs, pose);
        EXPECT_NEAR(ll, std::log(m.likelihoodOptions.paper.unmatched_penalty), 1e-12) << k;
        counted += ll < 0 ? 1 : 0;
    }
    EXPECT_EQ(counted, 2000u);
}

TEST(CSemanticMap, PaperMissedObjectPenaltySplitsTheUnmatchedTerms)
{
    // The scene of PaperFormulaExactly with p_o for the objects no detection matched.
    CSemanticMap m;
    m.addObject({1, "pillar", 5, 0, 0, 0.3, 1});
    m.addObject({2, "anchor", 7, 1, 0, 0.3, 1});
    auto& o = m.likelihoodOptions;
    o.paper.missed_object_penalty = 0.9;
    CObservationSemantic obs;
    obs.maxRange_m = 10;
    obs.fov_rad = M_PI;
    const double dr = 0.3, db = 2.0 * M_PI / 180;
    obs.detections.push_back(detection("pillar", 5 + dr, db));
    const double sb = o.detector.sigma_bearing_deg * M_PI / 180;
    const double matched =
        -0.5 * std::pow(dr / o.detector.sigma_range_m, 2) - 0.5 * std::pow(db / sb, 2);
    const double logPu = std::log(o.paper.unmatched_penalty), logPo = std::log(0.9);
    // One pair, the anchor missed: (l - m) log p_u + (q - m) log p_o = log p_o.
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), matched + logPo, 1e-6);
    // Too far off to match: the detection unmatched, both objects missed.
    obs.detections[0].range_m = 9.5;
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), logPu + 2 * logPo, 1e-9);
    // A pose that predicts nothing no longer beats the true one on an empty scan by p_u per
    // object: with p_o = 1 missing objects costs nothing.
    obs.detections.clear();
    o.paper.missed_object_penalty = 1;
    EXPECT_EQ(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)),
              m.computeLogLikelihood(obs, TPose2D(0, 0, M_PI)));
    // 0: §III's single p_u.
    o.paper.missed_object_penalty = 0;
    EXPECT_NEAR(m.computeLogLikelihood(obs, TPose2D(0, 0, 0)), 2 * logPu, 1e-9);
}

/** The probabilistic model written out pair by pair as the class documentation states it:
 *  every pair's gain over leaving both unmatched, log P_D - log(1 - P_D) + log C + log N(d_rho)
 *  + log N(d_theta) - log kappa, the pairs that gain, the greedy one-to-one association (best
 *  pair first, ties by detection then object), libm's trig and logs. No shortcut of the
 *  library's (range bins, folded products, skipped logs). Sensor at the vehicle's origin. */
double probabilisticByHand(const CSemanticMap& m, const CObservationSemantic& obs,
                           const TPose2D& pose)
{
    const auto& o = m.likelihoodOptions;
    const double R = obs.maxRange_m, fov = obs.fov_rad;
    std::set<std::string> labels;
    for (const auto& ob : m.objects())
    {
        labels.insert(ob.label);
    }
    const double K = static_cast<double>(labels.size());
    const double sr = o.detector.sigma_range_m, sb = o.detector.sigma_bearing_deg * M_PI / 180;
    const double logKappa = std::log(o.probabilistic.clutter_per_scan / (R * fov * K));
    auto wrap = [](double a) { return std::remainder(a, 2 * M_PI); };
    struct Visible
    {
        double range, bearing, pd;
        std::string label;
    };
    std::vector<Visible> vis;
    for (const auto& ob : m.objects())
    {
        const double d = std::hypot(ob.x - pose.x, ob.y - pose.y);
        const double b = wrap(std::atan2(ob.y - pose.y, ob.x - pose.x) - pose.phi);
        if (d <= R && std::abs(b) <= fov / 2)
        {
            const double pd = std::clamp(
                o.probabilistic.p_detect_near +
                    (o.probabilistic.p_detect_far - o.probabilistic.p_detect_near) * d / R,
                1e-6, 1 - 1e-6);
            vis.push_back({d, b, pd, ob.label});
        }
    }
    double total =
        -o.probabilistic.clutter_per_scan + static_cast<double>(obs.detections.size()) * logKappa;
    for (const auto& v : vis)
    {
        total += std::log(1 - v.pd);
    }
    struct Pair
    {
        double gain;
        size_t j, v;
    };
    std::vector<Pair> pairs;
    for (size_t j = 0; j < obs.detections.size(); j++)
    {
        const auto& d = obs.detections[j];
        for (size_t v = 0; v < vis.size(); v++)
        {
            const double dr = d.range_m - vis[v].range, db = wrap(d.bearing_rad - vis[v].bearing);
            const double logC = d.label == vis[v].label
                                    ? std::log(1 - o.probabilistic.p_confusion)
                                    : std::log(o.probabilistic.p_confusion / (K - 1));
            const double gain = std::log(vis[v].pd / (1 - vis[v].pd)) + logC -
                                std::log(2 * M_PI * sr * sb) - 0.5 * (dr / sr) * (dr / sr) -
                                0.5 * (db / sb) * (db / sb) - logKappa;
            if (gain > 0)
            {
                pairs.push_back({gain, j, v});
            }
        }
    }
    std::sort(pairs.begin(), pairs.end(),
              [](const Pair& a, const Pair& b) {
                  return a.gain != b.gain ? a.gain > b.gain : a.j != b.j ? a.j < b.j : a.v < b.v;
              });
    std::set<size_t> usedJ, usedV;
    for (const auto& p : pairs)
    {
        if (!usedJ.count(p.j) && !usedV.count(p.v))
        {
            usedJ.insert(p.j);
            usedV.insert(p.v);
            total += p.gain;
        }
    }
    return total;
}

TEST(CSemanticMap, ProbabilisticEqualsItsFormulaPairByPair)
{
    // Random scenes of 3 labels: most visible objects detected, some twice (two detections
    // competing for one object), some relabelled, some clutter; particles around the pose.
    // Tolerance: the library's atan2 is within 1e-7 rad, a few 1e-6 in the Gaussian term.
    mrpt::random::CRandomGenerator rng(5);
    const std::vector<std::string> labels = {"pillar", "anchor", "wreck"};
    size_t pairsSeen = 0, scenes = 0;
    for (int scene = 0; scene < 60; scene++)
    {
        CSemanticMap m;
        m.likelihoodOptions.model = CSemanticMap::Model::Probabilistic;
        m.likelihoodOptions.probabilistic.p_confusion = 0.1;
        for (int i = 1; i <= 12; i++)
        {
            m.addObject({i, labels[static_cast<size_t>(i) % 3], rng.drawUniform(0.0, 20.0),
                         rng.drawUniform(0.0, 20.0), 0, 0.3, 1});
        }
        CObservationSemantic obs;
        obs.maxRange_m = 10;
        obs.fov_rad = rng.drawUniform(1.0, 2 * M_PI);
        const TPose2D truth(rng.drawUniform(5.0, 15.0), rng.drawUniform(5.0, 15.0),
                            rng.drawUniform(-M_PI, M_PI));
        for (const auto& ob : m.objects())
        {
            const double d = std::hypot(ob.x - truth.x, ob.y - truth.y);
            const double b =
                std::remainder(std::atan2(ob.y - truth.y, ob.x - truth.x) - truth.phi, 2 * M_PI);
            if (d > obs.maxRange_m || std::abs(b) > obs.fov_rad / 2)
            {
                continue;
            }
            const int copies = rng.drawUniform(0.0, 1.0) < 0.2   ? 0
                               : rng.drawUniform(0.0, 1.0) < 0.2 ? 2
                                                                 : 1;
            for (int c = 0; c < copies; c++)
            {
                const std::string label = rng.drawUniform(0.0, 1.0) < 0.1
                                              ? labels[static_cast<size_t>(ob.id + 1) % 3]
                                              : ob.label;
                // Inside the sensor's range and FOV (the library ignores others).
                obs.detections.push_back(detection(
                    label, std::clamp(d + rng.drawGaussian1D(0, 0.3), 0.1, obs.maxRange_m - 0.01),
                    std::clamp(b + rng.drawGaussian1D(0, 0.03), -0.99 * obs.fov_rad / 2,
                               0.99 * obs.fov_rad / 2)));
            }
        }
        if (rng.drawUniform(0.0, 1.0) < 0.5)
        {
            obs.detections.push_back(detection(labels[0], rng.drawUniform(0.5, 9.5),
                                               rng.drawUniform(-0.4, 0.4)));  // clutter
        }
        std::vector<TPose2D> poses(40, truth);
        for (size_t i = 1; i < poses.size(); i++)
        {
            poses[i] =
                TPose2D(truth.x + rng.drawGaussian1D(0, 0.5), truth.y + rng.drawGaussian1D(0, 0.5),
                        truth.phi + rng.drawGaussian1D(0, 0.05));
        }
        std::vector<double> got(poses.size());
        m.computeLogLikelihoods(obs, poses.data(), poses.size(), got.data());
        for (size_t i = 0; i < poses.size(); i++)
        {
            const double want = probabilisticByHand(m, obs, poses[i]);
            EXPECT_NEAR(got[i], want, 1e-4 * std::max(1.0, std::abs(want)))
                << "scene " << scene << " particle " << i;
        }
        pairsSeen += obs.detections.size();
        scenes += obs.detections.size() >= 3 ? 1 : 0;
    }
    EXPECT_GT(scenes, 30u);  // most scenes have several detections to associate
    EXPECT_GT(pairsSeen, 150u);
}

TEST(CSemanticMap, SameLabelAmbiguityIsOneToOne)
{
    CSemanticMap m;
    m.addObject({1, "pillar", 5, 1, 0, 0.3, 1});
    m.addObject({2, "pillar", 5, -1, 0, 0.3, 1});
    const double logPu = std::log(m.likelihoodOptions.paper.unmatched_penalty);
    CObservationSemantic obs;
    obs.maxRange_m = 10;
    obs.fov_rad = M_PI;
    const double r = std::hypot(5, 1), b = std::atan2(1, 5);
    obs.detections = {detection("pillar", r, b), detection("pillar", r, -b)};
    const TPose2D origin(0, 0, 0);
    const double both = m.computeLogLikelihood(obs, origin);
    EXPECT_NEAR(both, 0, 1e-9);  // both matched perfectly
    std::swap(obs.detections[0], obs.detections[1]);
    EXPECT_NEAR(m.computeLogLikelihood(obs, origin), both, 1e-12);  // order does not matter
    // Two detections on the same pillar: only one may take it.
    obs.detections = {detection("pillar", r, b), detection("pillar", r, b)};
    const double oneToOne = m.computeLogLikelihood(obs, origin);
    // Best: one perfect match, the other detection matched to the other pillar (far in
    // bearing, so cheaper unmatched): l=2, q=2, m=1 -> 2 log p_u.
    EXPECT_NEAR(oneToOne, 2 * logPu, 1e-6);
    // With ids the detector says which is which: a swapped id costs.
    obs.detections = {detection("pillar", r, b, 1), detection("pillar", r, -b, 2)};
    EXPECT_NEAR(m.computeLogLikelihood(obs, origin), 0, 1e-9);
    obs.detections = {detection("pillar", r, b, 2), detection("pillar", r, -b, 1)};
    EXPECT_LT(m.computeLogLikelihood(obs, origin), both - 1);
}

TEST(CSemanticMap, FiniteOnEveryBadInput)
{
    for (const auto model : {CSemanticMap::Model::Paper, CSemanticMap::Model::Probabilistic})
    {
        const CSemanticMap m = smallMap(model);
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const double inf = std::numeric_limits<double>::infinity();
        CObservationSemantic obs;
        obs.maxRange_m = 12;
        EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(obs, kTrue))) << "empty";
        obs.detections = {detection("kraken", 3, 0),
                          detection("pillar", nan, 0),
                          detection("pillar", -1, 0),
                          detection("pillar", inf, 0),
                          detection("pillar", 3, nan),
                          detection("pillar", 3, inf),
                          detection("pillar", 30, 0),
                          detection("pillar", 3, 2.5),
                          detection("", 3, 0),
                          detection("pillar", 3, 1e300),
                          detection("pillar", 3, 0, 99999)};
        obs.detections.back().confidence = nan;
        const auto c = m.check(obs);
        EXPECT_EQ(c.used, 0u);
        EXPECT_EQ(c.unknown, 1u);  // "kraken"
        EXPECT_EQ(c.invalid, obs.detections.size() - 1);
        EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(obs, kTrue)));
        for (const auto& p : {TPose2D(nan, 0, 0), TPose2D(0, inf, 0), TPose2D(1e12, -1e12, 1e9)})
        {
            EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(obs, p)));
        }
        for (const double R : {0.0, -1.0, nan, inf})
        {
            obs.maxRange_m = R;
            EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(obs, kTrue))) << "maxRange " << R;
        }
        obs.maxRange_m = 12;
        obs.fov_rad = nan;
        EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(obs, kTrue)));
        // Many valid detections at once must not overflow.
        CObservationSemantic many = observe(smallWorld(), kTrue);
        for (int i = 0; i < 5000; i++)
        {
            many.detections.push_back(detection("pillar", 1 + (i % 10), 0.01 * (i % 50) - 0.25));
        }
        EXPECT_TRUE(std::isfinite(m.computeLogLikelihood(many, kTrue)));
        const CSemanticMap empty;
        EXPECT_TRUE(std::isfinite(empty.computeLogLikelihood(many, kTrue)));
    }
}

TEST(CSemanticMap, ScoresMrptBearingRangeObservations)
{
    const CSemanticMap m = smallMap();
    const World w = smallWorld();
    for (const bool withIds : {true, false})
    {
        mrpt::obs::CObservationBearingRange br;
        br.maxSensorDistance = 12;
        br.fieldOfView_yaw = static_cast<float>(2 * M_PI / 3);
        const auto sem = observe(w, kTrue);
        for (const auto& d : sem.detections)
        {
            mrpt::obs::CObservationBearingRange::TMeasurement meas;
            meas.range = static_cast<float>(d.range_m);
            meas.yaw = static_cast<float>(d.bearing_rad);
            meas.pitch = 0;
            const int idx = [&]
            {
                for (const auto& o : w.objects)
                {
                    if (std::abs(std::hypot(o.center.x - kTrue.x, o.center.y - kTrue.y) -
                                 d.range_m) < 1e-9)
                    {
                        return o.id;
                    }
                }
                return -1;
            }();
            meas.landmarkID = withIds ? idx : -1;
            br.sensedData.push_back(meas);
        }
        ASSERT_GE(br.sensedData.size(), 2u);
        const double lTrue = m.computeLogLikelihood(br, kTrue);
        EXPECT_TRUE(std::isfinite(lTrue));
        EXPECT_GT(lTrue, m.computeLogLikelihood(br, TPose2D(11, 10, 0.3)));
        EXPECT_GT(lTrue, m.computeLogLikelihood(br, TPose2D(10, 10, 0.5)));
        // Through the CMetricMap interface too.
        EXPECT_TRUE(m.canComputeObservationLikelihood(br));
        EXPECT_DOUBLE_EQ(
            m.computeObservationLikelihood(br, mrpt::poses::CPose3D(mrpt::poses::CPose2D(kTrue))),
            lTrue);
    }
}

TEST(CSemanticMap, GridIndexEqualsBruteForceOnLargeMaps)
{
    // 2000 objects over 400 x 400 m; a single huge cell is a brute-force scan.
    mrpt::random::CRandomGenerator rng(3);
    CSemanticMap indexed, brute;
    indexed.likelihoodOptions.index_cell_m = 10;
    brute.likelihoodOptions.index_cell_m = 1e5;
    const char* labels[] = {"a", "b", "c", "d", "e"};
    for (int i = 1; i <= 2000; i++)
    {
        const CSemanticMap::TObject o{
            i, labels[i % 5], rng.drawUniform(0.0, 400.0), rng.drawUniform(0.0, 400.0), 0, 0.5, 1};
        indexed.addObject(o);
        brute.addObject(o);
    }
    World w;
    w.bounds = {0, 400, 0, 400};
    for (const auto& o : indexed.objects())
    {
        semloc::WorldObject wo;
        wo.id = o.id;
        wo.label = o.label;
        wo.center = {o.x, o.y};
        w.objects.push_back(wo);
    }
    for (int k = 0; k < 200; k++)
    {
        const TPose2D truth(rng.drawUniform(0.0, 400.0), rng.drawUniform(0.0, 400.0),
                            rng.drawUniform(-M_PI, M_PI));
        const auto obs = observe(w, truth);
        const TPose2D probe(truth.x + rng.drawUniform(-2.0, 2.0),
                            truth.y + rng.drawUniform(-2.0, 2.0), truth.phi);
        EXPECT_EQ(indexed.computeLogLikelihood(obs, probe), brute.computeLogLikelihood(obs, probe));
    }
}

TEST(CSemanticMap, VisibilityTableKeepsEveryVisibleObject)
{
    // The likelihoods with the visibility candidate table must equal, to the bit, those of
    // the grid scan (table off): a dropped visible object changes q and the pairs. Objects
    // and poses on the table's cell edges (R / 10 = 2 m) and headings on its bin edges.
    mrpt::random::CRandomGenerator rng(29);
    const char* labels[] = {"a", "b", "c"};
    std::vector<CSemanticMap::TObject> objs;
    for (int i = 1; i <= 40; i++)  // a table of < 1 MB (larger maps keep the grid scan)
    {
        const bool onEdge = i % 3 == 0;
        const double x =
            onEdge ? 2 * std::floor(rng.drawUniform(0.0, 20.0)) : rng.drawUniform(0.0, 40.0);
        const double y = onEdge ? 2.0 * (i % 21) : rng.drawUniform(0.0, 40.0);
        objs.push_back({i, labels[i % 3], x, y, 0, 0.5, 1});
    }
    std::vector<TPose2D> poses;
    for (int k = 0; k < 2000; k++)
    {
        TPose2D p(rng.drawUniform(-25.0, 65.0), rng.drawUniform(-25.0, 65.0),
                  rng.drawUniform(-4.0, 4.0));
        if (k % 4 == 1)
        {
            p.x = 2.0 * std::floor(p.x / 2);  // a cell edge
        }
        if (k % 3 == 2)
        {
            // A bin edge: bins are uniform in s / (|c| + |s|), 8 per quadrant.
            const double a = (k % 32) / 8.0 - 1;
            p.phi = a <= 1 ? std::atan2(a, 1 - std::abs(a))
                           : M_PI - std::atan2(2 - a, 1 - std::abs(2 - a));
        }
        poses.push_back(p);
    }
    for (const auto model : {CSemanticMap::Model::Paper, CSemanticMap::Model::Probabilistic})
    {
        CSemanticMap m;
        m.likelihoodOptions.model = model;
        for (const auto& o : objs)
        {
            m.addObject(o);
        }
        for (const double fovDeg : {120.0, 30.0, 200.0, 360.0})
        {
            CObservationSemantic obs;
            obs.maxRange_m = 20;
            obs.fov_rad = fovDeg * M_PI / 180;
            obs.sensorPose = mrpt::poses::CPose3D(0.5, -0.2, 0, 0.3, 0, 0);
            for (int j = 0; j < 4; j++)
            {
                TSemanticDetection d;
                d.label = labels[j % 3];
                d.range_m = 3 + 4 * j;
                d.bearing_rad = 0.1 * (j - 2);
                obs.detections.push_back(d);
            }
            std::vector<double> withTable(poses.size()), gridScan(poses.size());
            semloc::detail::setVisibilityTableEnabled(true);
            m.computeLogLikelihoods(obs, poses.data(), poses.size(), withTable.data());
            EXPECT_GT(semloc::detail::lastVisibilityTableBytes(), 0u);
            semloc::detail::setVisibilityTableEnabled(false);
            m.computeLogLikelihoods(obs, poses.data(), poses.size(), gridScan.data());
            semloc::detail::setVisibilityTableEnabled(true);
            size_t differ = 0;
            for (size_t k = 0; k < poses.size(); k++)
            {
                differ += withTable[k] != gridScan[k];
            }
            EXPECT_EQ(differ, 0u) << "fov " << fovDeg << " deg";
            // The one-particle path uses the table too.
            for (size_t k = 0; k < poses.size(); k += 37)
            {
                EXPECT_EQ(m.computeLogLikelihood(obs, poses[k]), gridScan[k]);
            }
        }
    }
}

TEST(CSemanticMap, ConstLikelihoodIsThreadSafe)
{
    const CSemanticMap m = smallMap();
    mrpt::random::CRandomGenerator rng(11);
    std::vector<TPose2D> poses;
    std::vector<CObservationSemantic> obs;
    for (int i = 0; i < 3000; i++)
    {
        poses.emplace_back(rng.drawUniform(0.0, 30.0), rng.drawUniform(0.0, 30.0),
                           rng.drawUniform(-M_PI, M_PI));
        obs.push_back(observe(smallWorld(), poses.back()));
    }
    std::vector<double> ref(poses.size());
    for (size_t i = 0; i < poses.size(); i++)
    {
        ref[i] = m.computeLogLikelihood(obs[(i * 7) % obs.size()], poses[i]);
    }
    std::vector<std::vector<double>> out(4, std::vector<double>(poses.size()));
    std::vector<std::thread> th;
    for (size_t t = 0; t < 4; t++)
    {
        th.emplace_back(
            [&, t]
            {
                for (int rep = 0; rep < 3; rep++)
                {
                    for (size_t i = 0; i < poses.size(); i++)
                    {
                        const size_t k = (i + t * 131) % poses.size();
                        out[t][k] = m.computeLogLikelihood(obs[(k * 7) % obs.size()], poses[k]);
                    }
                }
            });
    }
    for (auto& x : th)
    {
        x.join();
    }
    for (size_t t = 0; t < 4; t++)
    {
        EXPECT_EQ(out[t], ref) << "thread " << t;
    }
}

TEST(CSemanticMap, InsertingObservationsWithKnownPosesBuildsTheMap)
{
    const World w = smallWorld();
    CSemanticMap built;
    built.insertionOptions.merge_distance_m = 1.5;
    surveyCircle(built, w, 0.05, 0.005, 5);
    ASSERT_EQ(built.objects().size(), w.objects.size());
    for (const auto& wo : w.objects)
    {
        double best = 1e9;
        std::string label;
        for (const auto& o : built.objects())
        {
            const double d = std::hypot(o.x - wo.center.x, o.y - wo.center.y);
            if (d < best)
            {
                best = d;
                label = o.label;
            }
        }
        EXPECT_LT(best, 0.3) << "object " << wo.id;
        EXPECT_EQ(label, wo.label);
    }
}

TEST(CSemanticMap, InsertionEstimatesPositionSigmaAndExistence)
{
    // An earlier map (the world's objects, exactly placed, and a ghost that has gone), then a
    // survey with known poses around the middle.
    const World w = smallWorld();
    CSemanticMap built;
    built.loadFromWorld(w);
    built.addObject({99, "anchor", 18, 18, 0, 0, 1});
    surveyCircle(built, w, 0.2, 0.02, 9);
    ASSERT_EQ(built.objects().size(), w.objects.size() + 1);
    size_t detected = 0;
    for (const auto& o : built.objects())
    {
        if (o.id == 99)
        {
            // Never detected in many views: hardly there.
            EXPECT_GT(o.n_in_view, 10u);
            EXPECT_EQ(o.n_detected, 0u);
            EXPECT_LT(o.p_exist, 0.1);
            EXPECT_EQ(o.sigma_m, 0.0);  // no detection: the map's own sigma, untouched
            continue;
        }
        if (o.n_detected == 0)
        {
            continue;
        }
        detected++;
        const auto& wo = w.objects[static_cast<size_t>(w.indexOfId(o.id))];
        // Detected whenever in view: surely there; its mean within a few of its sigmas.
        EXPECT_EQ(o.p_exist, 1.0) << o.id;
        EXPECT_GT(o.sigma_m, 0.0) << o.id;
        EXPECT_LT(o.sigma_m, 0.15) << o.id;
        EXPECT_LT(std::hypot(o.x - wo.center.x, o.y - wo.center.y), 5 * o.sigma_m) << o.id;
    }
    EXPECT_GE(detected, 8u);
    // Saved as a world file that loads, with what the insertions estimated.
    const std::string prefix = std::string(SEMLOC_TEST_OUT) + "/surety";
    built.saveMetricMapRepresentationToFile(prefix);
    const World back = World::FromFile(prefix + "_semantic.yaml");
    ASSERT_EQ(back.objects.size(), built.objects().size());
    for (size_t i = 0; i < back.objects.size(); i++)
    {
        EXPECT_EQ(back.objects[i].sigma_m, built.objects()[i].sigma_m);
        EXPECT_EQ(back.objects[i].p_exist, built.objects()[i].p_exist);
    }
}

TEST(CSemanticMap, SerializationAndSavedYamlRoundTrip)
{
    const CSemanticMap m = smallMap();
    mrpt::io::CMemoryStream mem;
    auto ar = mrpt::serialization::archiveFrom(mem);
    ar << m;
    mem.Seek(0);
    CSemanticMap back;
    ar >> back;
    ASSERT_EQ(back.objects().size(), m.objects().size());
    const auto obs = observe(smallWorld(), kTrue);
    EXPECT_EQ(back.computeLogLikelihood(obs, kTrue), m.computeLogLikelihood(obs, kTrue));

    const std::string prefix = std::string(SEMLOC_TEST_OUT) + "/saved_map";
    m.saveMetricMapRepresentationToFile(prefix);
    CSemanticMap reloaded;
    reloaded.loadFromWorldFile(prefix + "_semantic.yaml");
    ASSERT_EQ(reloaded.objects().size(), m.objects().size());
    for (size_t i = 0; i < m.objects().size(); i++)
    {
        EXPECT_EQ(reloaded.objects()[i].label, m.objects()[i].label);
        EXPECT_NEAR(reloaded.objects()[i].x, m.objects()[i].x, 1e-12);
        EXPECT_NEAR(reloaded.objects()[i].extent_m, m.objects()[i].extent_m, 1e-12);
    }
    EXPECT_NE(m.asString().find("12 objects"), std::string::npos);
}

TEST(CSemanticMap, SerializationKeepsHowSureTheMapIs)
{
    CSemanticMap a;
    CSemanticMap::TObject ob = uncertainPillar(3, 2, 7, 0.25, 0.5, 0.125);
    ob.n_detected = 4;
    ob.scatter_m2 = 0.75;
    ob.n_in_view = 9;
    ob.expected_detections = 6.5;
    a.addObject(ob);
    CSemanticMap b;
    ASSERT_EQ(readArchiveInto(archiveBytes(a), b), "");
    ASSERT_EQ(b.objects().size(), 1u);
    const auto& c = b.objects()[0];
    EXPECT_EQ(c.sigma_m, 0.25);
    EXPECT_EQ(c.p_exist, 0.5);
    EXPECT_EQ(c.classes, ob.classes);
    EXPECT_EQ(c.n_detected, 4u);
    EXPECT_EQ(c.scatter_m2, 0.75);
    EXPECT_EQ(c.n_in_view, 9u);
    EXPECT_EQ(c.expected_detections, 6.5);
    // A class probability spoiled in the bytes is refused, the map left as it was.
    std::string bytes = archiveBytes(a);
    const double bad = 7.0, good = 0.875;
    const size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&good), sizeof good));
    ASSERT_NE(at, std::string::npos);
    bytes.replace(at, sizeof bad, std::string(reinterpret_cast<const char*>(&bad), sizeof bad));
    EXPECT_NE(readArchiveInto(bytes, b), "");
    EXPECT_EQ(b.objects()[0].classes, ob.classes);
}

TEST(CSemanticMap, FlagBytesOtherThanZeroOrOneAreRejected)
{
    // MRPT writes a bool as one byte and reads it back as is: a corrupted byte must be refused,
    // not copied into a bool. Layout: ... "mrpt::maps::TMapGenericParams", version, three
    // flags, end-of-object marker, then the map's bounds flag.
    const CSemanticMap m = smallMap();
    const std::string bytes = archiveBytes(m);
    const size_t firstFlag = genericMapFlagsAt(bytes);
    ASSERT_NE(firstFlag, std::string::npos);
    const size_t boundsFlag = firstFlag + 4;
    ASSERT_LT(boundsFlag, bytes.size());
    ASSERT_LE(static_cast<unsigned char>(bytes[boundsFlag]), 1);
    for (const size_t i : {firstFlag, firstFlag + 2, boundsFlag})
    {
        std::string spoiled = bytes;
        spoiled[i] = 2;
        CSemanticMap target = smallMap();
        const std::string e = readArchiveInto(spoiled, target);
        EXPECT_NE(e.find("corrupted data"), std::string::npos) << "byte " << i << ": " << e;
        EXPECT_EQ(target.objects().size(), m.objects().size());
    }
    // The unspoiled bytes still read.
    CSemanticMap back;
    EXPECT_EQ(readArchiveInto(bytes, back), "");
    EXPECT_EQ(back.objects().size(), m.objects().size());
}

TEST(CSemanticMap, AcceptsMrptGenericMapKeysInCreationOpts)
{
    // MRPT reads enableObservationLikelihood & co. from the creationOpts section.
    const std::string world = writeWorldFile("semantic_ini_world3.yaml");
    const auto mm = mapFromIni(
        "[MetricMap]\nsemanticMap_count=1\n"
        "[MetricMap_semanticMap_00_creationOpts]\nworld_file=" +
        world + "\nenableObservationLikelihood=false\n");
    const auto sm = mm.mapByClass<CSemanticMap>();
    ASSERT_TRUE(sm);
    EXPECT_FALSE(sm->genericMapParams.enableObservationLikelihood);
    const auto obs = observe(smallWorld(), kTrue);
    const auto p = mrpt::poses::CPose3D(mrpt::poses::CPose2D(kTrue));
    EXPECT_EQ(mm.computeObservationLikelihood(obs, p), 0.0);
}

TEST(CSemanticMap, WorldFileIsFoundNextToTheIni)
{
    // An ini in its own directory names its world relatively; it is read from elsewhere.
    const std::string dir = std::string(SEMLOC_TEST_OUT) + "/ini_dir_test";
    std::system(("mkdir -p '" + dir + "/maps'").c_str());
    smallWorld().saveToFile(dir + "/maps/w.yaml");
    std::ofstream(dir + "/m.ini")
        << "[MetricMap]\nsemanticMap_count=1\n"
           "[MetricMap_semanticMap_00_creationOpts]\nworld_file=maps/w.yaml\n";
    mrpt::config::CConfigFile cfg(dir + "/m.ini");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "MetricMap");
    mrpt::maps::CMultiMetricMap mm;
    mm.setListOfMaps(inits);
    const auto sm = mm.mapByClass<CSemanticMap>();
    ASSERT_TRUE(sm);
    EXPECT_EQ(sm->objects().size(), 12u);
}

TEST(CSemanticMap, ModelsTakeTurnsOnOneThread)
{
    // The models share a thread's scratch buffers: the probabilistic model first, on a new
    // thread, then the paper model, each with a full block, then again (each sizes what it
    // uses, whatever the other sized before).
    std::vector<double> batch[4], single[4];
    std::thread worker(
        [&]
        {
            mrpt::random::CRandomGenerator rng(8);
            const auto obs = observe(smallWorld(), kTrue, DetectorSim{}, &rng);
            std::vector<TPose2D> poses(600);
            for (auto& p : poses)
            {
                p = TPose2D(rng.drawUniform(0.0, 30.0), rng.drawUniform(0.0, 30.0),
                            rng.drawUniform(-M_PI, M_PI));
            }
            for (int run = 0; run < 4; run++)
            {
                const CSemanticMap m = smallMap(run % 2 == 0 ? CSemanticMap::Model::Probabilistic
                                                             : CSemanticMap::Model::Paper);
                batch[run].resize(poses.size());
                m.computeLogLikelihoods(obs, poses.data(), poses.size(), batch[run].data());
                for (const auto& p : poses)
                {
                    single[run].push_back(m.computeLogLikelihood(obs, p));
                }
            }
        });
    worker.join();
    for (int run = 0; run < 4; run++)
    {
        EXPECT_EQ(batch[run], single[run]) << "run " << run;
        EXPECT_EQ(batch[run], batch[run % 2]) << "run " << run;
    }
    EXPECT_NE(batch[0], batch[1]);  // two models
}

TEST(CSemanticMap, BatchEqualsSingleCalls)
{
    // Both models, detections with and without object ids (the paper model's gates differ).
    for (const auto& [model, ids] :
         {std::pair{CSemanticMap::Model::Paper, false}, std::pair{CSemanticMap::Model::Paper, true},
          std::pair{CSemanticMap::Model::Probabilistic, false},
          std::pair{CSemanticMap::Model::Probabilistic, true}})
    {
        const CSemanticMap m = smallMap(model);
        mrpt::random::CRandomGenerator rng(21);
        DetectorSim ds;
        ds.sigma_range_m = 0.2;
        ds.sigma_bearing_rad = 0.02;
        ds.reportIds = ids;
        auto obs = observe(smallWorld(), kTrue, ds, &rng);
        obs.sensorPose = mrpt::poses::CPose3D(0.4, -0.2, 0, 0.3, 0, 0);  // off-centre, yawed
        std::vector<TPose2D> poses(1000);
        for (auto& p : poses)
        {
            p = TPose2D(rng.drawUniform(0.0, 30.0), rng.drawUniform(0.0, 30.0),
                        rng.drawUniform(-M_PI, M_PI));
        }
        poses[17] = TPose2D(std::nan(""), 0, 0);
        std::vector<double> batch(poses.size());
        m.computeLogLikelihoods(obs, poses.data(), poses.size(), batch.data());
        for (size_t i = 0; i < poses.size(); i++)
        {
            EXPECT_EQ(batch[i], m.computeLogLikelihood(obs, poses[i])) << "particle " << i;
        }
    }
}

TEST(CSemanticMap, LikelihoodWithoutObjectsIsEveryDetectionClutter)
{
    CObservationSemantic obs;
    obs.maxRange_m = 20;
    obs.fov_rad = M_PI / 2;
    obs.detections = {detection("pillar", 6, 0.2), detection("anchor", 12, -0.5),
                      detection("wreck", 3, 0.1), detection("pillar", 25, 0.0),
                      detection("submarine", 5, 0.0)};  // too far; unknown
    const TPose2D nothingInView(-500, -500, M_PI);      // outside the world, facing away
    for (const auto model : {CSemanticMap::Model::Probabilistic, CSemanticMap::Model::Paper})
    {
        const CSemanticMap m = smallMap(model);
        size_t used = 99;
        const double ref = m.logLikelihoodWithoutObjects(obs, &used);
        EXPECT_EQ(used, 3u);
        const auto& lo = m.likelihoodOptions;
        const double expected =
            model == CSemanticMap::Model::Paper
                ? 3 * std::log(lo.paper.unmatched_penalty)
                : -lo.probabilistic.clutter_per_scan +
                      3 * std::log(lo.probabilistic.clutter_per_scan /
                                   (20 * (M_PI / 2) * static_cast<double>(m.labelCount())));
        EXPECT_NEAR(ref, expected, 1e-12);
        EXPECT_NEAR(ref, m.computeLogLikelihood(obs, nothingInView), 1e-12);
        // Where objects are in view and match, the frame is explained better than that.
        CObservationSemantic seen;
        seen.maxRange_m = 5;  // only the pillar at (12, 4) in view
        seen.fov_rad = 0.5;
        seen.detections = {detection("pillar", std::hypot(2, 0.5), std::atan2(-0.5, 2))};
        const TPose2D atPillar(10, 4.5, 0);
        EXPECT_GT(m.computeLogLikelihood(seen, atPillar), m.logLikelihoodWithoutObjects(seen));
    }
    CObservationSemantic blind;
    blind.maxRange_m = 0;  // an unusable sensor
    blind.detections = {detection("pillar", 6, 0.2)};
    size_t used = 99;
    EXPECT_EQ(smallMap().logLikelihoodWithoutObjects(blind, &used), 0.0);
    EXPECT_EQ(used, 0u);
}

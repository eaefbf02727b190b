/* semloc tests — CSemanticMap's fast likelihood against the reference written to be read
 * (models/semantic/SemanticLikelihoodReference.h), on random scenes of both models. */
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "models/semantic/SemanticLikelihoodReference.h"
#include "models/semantic/VisibilityTable.h"

using mrpt::math::TPose2D;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;
using semloc::TSemanticDetection;
namespace ref = semloc::reference;

namespace
{
// Scenes (drawn in the same order by every compiler: no two draws in one call's arguments):
// kMaps maps (options drawn per map), kObsPerMap observations each, kPoses particle
// poses per observation: a scene is one (map, observation, pose).
constexpr int kMaps = 320;
constexpr int kObsPerMap = 40;
constexpr size_t kPoses = 10;

/** |fast - reference| allowed per matched pair where the fast path approximates: its atan2 is
 *  within 1e-7 rad of libm's, so a pair's bearing term -1/2 (dtheta / sigma_theta)^2 may differ
 *  by |dtheta| 1e-7 / sigma_theta^2, and the gates bound |dtheta| by sigma_theta sqrt(budget)
 *  (the bearing budget, no larger with misread ranges): at most sqrt(budget) 1e-7 /
 *  sigma_theta, 3.4e-5 for the options drawn here (sigma_theta >= 1 deg; budget <= 36, the
 *  probabilistic model's at sigma_rho = 0.2 m, P_D = 0.99, lambda = 0.05, R = 30 m, 4 labels).
 *  Everything else (sin/cos to 1e-15, the order of sums and logs) is ~1e-12. The test prints
 *  the largest difference and the largest per matched pair it measured (4.9e-5 and 5.9e-6
 *  with this seed); the tolerance, m 1e-4 for m matched pairs, keeps a margin of ~3 over the
 *  bound and ~17 over the measure (wider sigmas of uncertain objects only lower the bound). */
constexpr double kTolerancePerPair = 1e-4;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
const std::vector<std::string> kLabels = {"pillar", "anchor", "wreck", "wellhead"};

struct Rng
{
    mrpt::random::CRandomGenerator g;
    explicit Rng(uint32_t seed) : g(seed) {}
    double uniform(double a, double b) { return g.drawUniform(a, b); }
    bool chance(double p) { return g.drawUniform(0.0, 1.0) < p; }
    size_t index(size_t n)
    {
        return std::min(n - 1, static_cast<size_t>(uniform(0.0, static_cast<double>(n))));
    }
    template <typename T>
    T pick(const std::vector<T>& v)
    {
        return v[index(v.size())];
    }
    double gauss(double sigma) { return g.drawGaussian1D(0.0, sigma); }
};

/** A position sigma, a p_exist and a class distribution over the first nLabels labels (its
 *  own among them), each drawn or left at its default. */
void makeUncertain(Rng& rng, size_t nLabels, CSemanticMap::TObject& ob)
{
    ob.sigma_m = rng.pick<double>({0.0, 0.3, 2.0});
    ob.p_exist = rng.pick<double>({1.0, 0.7, 0.2});
    if (nLabels > 1 && rng.chance(0.5))
    {
        const double own = rng.uniform(0.4, 0.9);
        const std::string& other = kLabels[rng.index(nLabels)];
        ob.classes = {{ob.label, own}};
        if (other != ob.label)
        {
            ob.classes.emplace_back(other, 1 - own);
        }
        else
        {
            ob.classes[0].second = 1;
        }
        std::sort(ob.classes.begin(), ob.classes.end());
    }
}

/** A map of 0..40 objects over up to 80 x 80 m in 1..4 labels, options drawn at random; in
 *  one map of three, half the objects uncertain (makeUncertain). */
CSemanticMap randomMap(Rng& rng, size_t& nLabels)
{
    CSemanticMap m;
    auto& o = m.likelihoodOptions;
    o.model = rng.chance(0.5) ? CSemanticMap::Model::Paper : CSemanticMap::Model::Probabilistic;
    o.detector.sigma_range_m = rng.uniform(0.2, 2.0);
    o.detector.sigma_bearing_deg = rng.uniform(1.0, 10.0);
    o.paper.unmatched_penalty = rng.uniform(0.02, 0.6);
    o.paper.missed_object_penalty = rng.pick<double>({0.0, 0.0, 0.3, 0.9, 1.0});
    o.probabilistic.p_detect_near = rng.uniform(0.3, 0.99);
    o.probabilistic.p_detect_far = rng.uniform(0.1, 0.99);
    o.probabilistic.clutter_per_scan = rng.uniform(0.05, 3.0);
    o.probabilistic.p_confusion = rng.pick<double>({0.0, 0.05, 0.3});
    o.detector.p_range_outlier = rng.pick<double>({0.0, 0.0, 0.02, 0.3});
    o.detector.min_confidence = rng.pick<double>({0.0, 0.0, 0.5});
    o.detector.max_range_m = rng.chance(0.2) ? rng.uniform(5.0, 25.0) : 0.0;
    o.detector.fov_deg = rng.chance(0.2) ? rng.uniform(20.0, 360.0) : 0.0;
    o.index_cell_m = rng.pick<double>({2.0, 5.0, 3.7});
    nLabels = 1 + rng.index(4);
    const bool uncertain = rng.chance(0.33);
    const size_t n = rng.pick<size_t>({0, 1, 3, 8, 20, 40, 40});
    const double w = rng.uniform(20.0, 80.0), h = rng.uniform(20.0, 80.0);
    for (size_t i = 0; i < n; i++)
    {
        CSemanticMap::TObject ob;
        ob.id = static_cast<int32_t>(3 * i + 1);
        ob.label = kLabels[rng.index(nLabels)];
        ob.x = rng.uniform(0.0, w);
        ob.y = rng.uniform(0.0, h);
        if (i > 0 && rng.chance(0.03))  // a twin: same place, same label
        {
            const auto& prev = m.objects().back();
            ob.x = prev.x;
            ob.y = prev.y;
            ob.label = prev.label;
        }
        if (uncertain && rng.chance(0.5))
        {
            makeUncertain(rng, nLabels, ob);
        }
        m.addObject(ob);
    }
    // In turn, not drawn: the scenes' random streams stay those the coverage counts are for.
    static size_t turn = 0;
    const size_t k = turn++;
    o.probabilistic.p_detect_edge_ratio = std::array<double, 4>{1.0, 0.3, 1.0, 0.0}[k % 4];
    // Every third scene's detector reads its ranges with a bias by bearing.
    o.detector.range_bias_m =
        k % 3 == 1 ? std::vector<double>{0.4, -0.3, -1.2, 0.5} : std::vector<double>{};
    return m;
}

/** The sensor's effective range and field of view for the map's options. */
struct Sensor
{
    double R, fov;
    mrpt::poses::CPose3D onVehicle;
};

Sensor randomSensor(Rng& rng)
{
    Sensor s;
    s.R = rng.uniform(5.0, 30.0);
    s.fov = rng.pick<double>({2 * M_PI, M_PI, 2 * M_PI / 3, 7.0, rng.uniform(0.3, 2 * M_PI)});
    switch (rng.index(4))
    {
        case 0:
            break;  // at the vehicle's origin
        case 1:
            s.onVehicle = mrpt::poses::CPose3D{rng.uniform(-2, 2), rng.uniform(-1, 1), 0, 0, 0, 0};
            break;
        case 2:
            s.onVehicle = mrpt::poses::CPose3D{0, 0, 0, rng.uniform(-M_PI, M_PI), 0, 0};
            break;
        default:
            s.onVehicle = mrpt::poses::CPose3D{
                rng.uniform(-2, 2), rng.uniform(-1, 1), 0.3, rng.uniform(-M_PI, M_PI), 0, 0};
            break;
    }
    return s;
}

/** A detection as a simulated detector reports it from `truth`: the map's objects in range
 *  and FOV, with noise, misses, doubles, wrong/unknown labels and ids, clutter and garbage. */
struct Simulated
{
    std::string label;
    double r, b, confidence;
    int32_t id;
};

std::vector<Simulated> simulate(Rng& rng, const CSemanticMap& m, const Sensor& s,
                                const TPose2D& truth, size_t nLabels)
{
    const double sr = rng.uniform(0.02, 1.0), sb = rng.uniform(0.002, 0.1);
    const bool ids = rng.chance(0.4);
    const mrpt::poses::CPose3D sensor =
        mrpt::poses::CPose3D(truth.x, truth.y, 0, truth.phi, 0, 0) + s.onVehicle;
    std::vector<Simulated> out;
    auto idOf = [&](int32_t own) -> int32_t
    {
        if (!ids)
        {
            return -1;
        }
        const double u = rng.uniform(0.0, 1.0);
        return u < 0.8 ? own : u < 0.9 ? 99999 : 3 * static_cast<int32_t>(rng.index(40)) + 1;
    };
    for (const auto& ob : m.objects())
    {
        const double dx = ob.x - sensor.x(), dy = ob.y - sensor.y();
        const double r = std::hypot(dx, dy);
        const double b = std::remainder(std::atan2(dy, dx) - sensor.yaw(), 2 * M_PI);
        if (r > s.R || std::abs(b) > 0.5 * std::min(s.fov, 2 * M_PI) || rng.chance(0.15))
        {
            continue;
        }
        const int copies = rng.chance(0.1) ? 2 : 1;
        for (int c = 0; c < copies; c++)
        {
            std::string label = ob.label;
            if (rng.chance(0.1))
            {
                label = rng.chance(0.5) ? kLabels[rng.index(nLabels)] : "kraken";
            }
            out.push_back({label, std::clamp(r + rng.gauss(sr), 0.0, s.R),
                           std::clamp(b + rng.gauss(sb), -0.5 * s.fov, 0.5 * s.fov),
                           rng.chance(0.3) ? rng.uniform(0.0, 1.0) : 1.0, idOf(ob.id)});
        }
    }
    for (size_t k = rng.index(4); k > 0; k--)  // clutter
    {
        out.push_back({kLabels[rng.index(nLabels)], rng.uniform(0.0, s.R),
                       rng.uniform(-0.5, 0.5) * std::min(s.fov, 2 * M_PI), 1.0, idOf(1)});
    }
    if (rng.chance(0.2))  // garbage the likelihood must skip (or take, as its rules say)
    {
        const std::vector<Simulated> bad = {
            {"pillar", kNaN, 0, 1, -1},     {"pillar", kInf, 0, 1, -1},
            {"pillar", -1, 0, 1, -1},       {"pillar", s.R * 1.5, 0, 1, -1},
            {"pillar", 3, kNaN, 1, -1},     {"pillar", 3, kInf, 1, -1},
            {"pillar", 3, 3 * M_PI, 1, -1}, {"pillar", 3, 5 * M_PI, 1, -1},
            {"pillar", 3, 3.0, 1, -1},      {"", 3, 0, 1, 1},
            {"pillar", 3, 0, kNaN, -1},     {"anchor", 3, 0, 1.5, -1},
            {"anchor", s.R, 0, 0.2, -1},    {"pillar", 0, 0, 1, 1}};
        for (size_t k = 1 + rng.index(3); k > 0; k--)
        {
            const auto at = static_cast<ptrdiff_t>(rng.index(out.size() + 1));
            out.insert(out.begin() + at, rng.pick(bad));
        }
    }
    return out;
}

/** Angles that are edges of the visibility tables' 32 heading bins (uniform in the "diamond
 *  angle"), and multiples of 45 degrees. */
double binEdgeAngle(Rng& rng)
{
    const double a = 4.0 * static_cast<double>(rng.index(33)) / 32 - 1;  // [-1, 3]
    if (rng.chance(0.3))
    {
        return M_PI / 4 * static_cast<double>(static_cast<int>(rng.index(9)) - 4);
    }
    if (a <= 1)
    {
        return std::atan2(a, 1 - std::abs(a));
    }
    return M_PI - std::atan2(2 - a, 1 - std::abs(2 - a));
}

/** kPoses particle poses around `truth`: itself, nearby, anywhere on the map, on the edges of
 *  the index cells and of the visibility tables' cells and heading bins, far off the map, not
 *  finite. */
std::vector<TPose2D> poses(Rng& rng, const CSemanticMap& m, const Sensor& s, const TPose2D& truth)
{
    double x0 = 0, y0 = 0;
    if (!m.objects().empty())
    {
        x0 = m.objects()[0].x;
        y0 = m.objects()[0].y;
        for (const auto& o : m.objects())
        {
            x0 = std::min(x0, o.x);
            y0 = std::min(y0, o.y);
        }
    }
    const double cell = m.likelihoodOptions.index_cell_m;
    const double R = m.likelihoodOptions.detector.max_range_m > 0
                         ? m.likelihoodOptions.detector.max_range_m
                         : s.R;
    const double side = R / 10;
    std::vector<TPose2D> p;
    p.push_back(truth);
    for (int k = 0; k < 3; k++)
    {
        p.push_back(TPose2D{truth.x + rng.gauss(0.5), truth.y + rng.gauss(0.5),
                            truth.phi + rng.gauss(0.05)});
    }
    p.push_back(TPose2D{rng.uniform(-5, 85), rng.uniform(-5, 85), rng.uniform(-M_PI, M_PI)});
    // The index's cell edges x0 + k cell (and y).
    p.push_back(TPose2D{
        x0 + cell * static_cast<double>(rng.index(16)),
        rng.chance(0.5) ? y0 + cell * static_cast<double>(rng.index(16)) : rng.uniform(0, 80),
        rng.uniform(-M_PI, M_PI)});
    // The visibility table's cell edges (it starts R + 2 cells of R / 10 before the objects),
    // with a heading on a bin edge.
    const double yaw = s.onVehicle.yaw();
    p.push_back(TPose2D{x0 - R - 2 * side + side * static_cast<double>(rng.index(40)),
                        y0 - R - 2 * side + side * static_cast<double>(rng.index(40)),
                        binEdgeAngle(rng) - yaw});
    p.push_back(
        TPose2D{truth.x + rng.gauss(1.0), truth.y + rng.gauss(1.0), binEdgeAngle(rng) - yaw});
    // Far off the map (finite).
    p.push_back(TPose2D{rng.pick<double>({1e5, -1e7, 1e12, 1e300}),
                        rng.pick<double>({-1e5, 1e9, 3.0, -1e300}),
                        rng.pick<double>({0.0, 1e7, -1e300, truth.phi})});
    // Not finite, or one more near the truth.
    if (rng.chance(0.5))
    {
        TPose2D bad = truth;
        (rng.chance(0.33)  ? bad.x
         : rng.chance(0.5) ? bad.y
                           : bad.phi) = rng.pick<double>({kNaN, kInf, -kInf});
        p.push_back(bad);
    }
    else
    {
        p.push_back(TPose2D{truth.x + rng.gauss(0.2), truth.y + rng.gauss(0.2),
                            truth.phi + rng.gauss(0.02)});
    }
    EXPECT_EQ(p.size(), kPoses);
    return p;
}

CObservationSemantic semanticObservation(const Sensor& s, const std::vector<Simulated>& dets)
{
    CObservationSemantic obs;
    obs.maxRange_m = s.R;
    obs.fov_rad = s.fov;
    obs.sensorPose = s.onVehicle;
    for (const auto& d : dets)
    {
        TSemanticDetection t;
        t.label = d.label;
        t.range_m = d.r;
        t.bearing_rad = d.b;
        t.confidence = d.confidence;
        t.object_id = d.id;
        obs.detections.push_back(t);
    }
    return obs;
}

mrpt::obs::CObservationBearingRange landmarkObservation(Rng& rng, const Sensor& s,
                                                        const std::vector<Simulated>& dets)
{
    mrpt::obs::CObservationBearingRange obs;
    obs.maxSensorDistance = static_cast<float>(s.R);
    obs.fieldOfView_yaw = rng.chance(0.3) ? 0.0f : static_cast<float>(s.fov);
    obs.sensorLocationOnRobot = s.onVehicle;
    for (const auto& d : dets)
    {
        mrpt::obs::CObservationBearingRange::TMeasurement t;
        t.range = static_cast<float>(d.r);
        t.yaw = static_cast<float>(d.b);
        t.pitch = 0;
        t.landmarkID = d.id;
        obs.sensedData.push_back(t);
    }
    return obs;
}

/** What the scenes covered, to check they exercise what they claim. */
struct Coverage
{
    size_t scenes = 0, landmark = 0, paper = 0, probabilistic = 0, exact = 0, floor = 0,
           unusable = 0, onEdge = 0, matched = 0, severalMatched = 0, contested = 0, withIds = 0,
           misreadModel = 0, uncertainMap = 0;
    double maxDiff = 0, maxPerPair = 0;
    size_t failures = 0;
};

bool uncertainMap(const CSemanticMap& m)
{
    return std::any_of(m.objects().begin(), m.objects().end(),
                       [](const CSemanticMap::TObject& o)
                       { return o.sigma_m > 0 || o.p_exist < 1 || !o.classes.empty(); });
}

template <typename OBS>
void compare(const CSemanticMap& m, const OBS& obs, const std::vector<TPose2D>& p, Coverage& cov,
             const std::string& where)
{
    const size_t n = p.size();
    // The filter's call (SensoryFrameLikelihood): one batch per observation.
    std::vector<double> fast(n), noTable(n);
    m.computeLogLikelihoods(obs, p.data(), n, fast.data());
    // The same without visibility tables (every particle scans the grid): the same bits.
    semloc::detail::setVisibilityTableEnabled(false);
    m.computeLogLikelihoods(obs, p.data(), n, noTable.data());
    semloc::detail::setVisibilityTableEnabled(true);
    for (size_t i = 0; i < n; i++)
    {
        ref::SemanticTerms t;
        const double want = ref::semanticLogLikelihood(m, obs, p[i], &t);
        const double single = m.computeLogLikelihood(obs, p[i]);
        // Bit for bit where the fast path approximates nothing: a pose that is not finite
        // (the floor), an unusable sensor (0), and the paper model without a matched pair
        // ((q + l) log p_u, no Gaussian term); elsewhere within kTolerancePerPair per matched pair.
        const bool paper = m.likelihoodOptions.model == CSemanticMap::Model::Paper;
        const bool exact = want == -1e300 || want == 0.0 || (paper && t.m == 0);
        // An object on the edge of the coverage (constructed here: poses on cell edges may
        // put one exactly at the range limit, the FOV's edge or the sensor): whether it is in
        // z^k is rounding, decided by each implementation its own way. Only the fast path's
        // own equalities are checked there.
        if (t.onEdge > 0)
        {
            cov.onEdge++;
            cov.failures += fast[i] == noTable[i] && fast[i] == single ? 0 : 1;
            EXPECT_TRUE(fast[i] == noTable[i] && fast[i] == single) << where << " pose " << i;
            cov.scenes++;
            continue;
        }
        const double diff = std::abs(fast[i] - want);
        const double perPair = diff / static_cast<double>(std::max<size_t>(1, t.m));
        const bool ok = fast[i] == noTable[i] && fast[i] == single &&
                        (exact ? fast[i] == want : perPair <= kTolerancePerPair);
        if (!exact && std::isfinite(diff))
        {
            cov.maxDiff = std::max(cov.maxDiff, diff);
            cov.maxPerPair = std::max(cov.maxPerPair, perPair);
        }
        if (!ok && ++cov.failures <= 10)
        {
            ADD_FAILURE() << where << " pose " << i << " (" << p[i].x << ", " << p[i].y << ", "
                          << p[i].phi << "): fast " << fast[i] << " (grid scan " << noTable[i]
                          << ", single call " << single << "), reference " << want << " (l=" << t.l
                          << " q=" << t.q << " m=" << t.m << "), difference " << diff
                          << (exact ? " (bit-for-bit expected)" : "");
        }
        cov.scenes++;
        cov.exact += exact ? 1 : 0;
        cov.floor += want == -1e300 ? 1 : 0;
        cov.matched += t.m > 0 ? 1 : 0;
        cov.severalMatched += t.m >= 2 ? 1 : 0;
        cov.contested += t.l > t.m && t.q > t.m && t.m > 0 ? 1 : 0;
        cov.misreadModel += m.likelihoodOptions.detector.p_range_outlier > 0 && t.m > 0 ? 1 : 0;
        cov.uncertainMap += !paper && uncertainMap(m) && t.m > 0 ? 1 : 0;
        (paper ? cov.paper : cov.probabilistic)++;
    }
}
}  // namespace

TEST(SemanticLikelihoodReference, FastPathEqualsReferenceOnRandomScenes)
{
    Rng rng(20240613);
    Coverage cov;
    for (int map = 0; map < kMaps; map++)
    {
        size_t nLabels = 1;
        const CSemanticMap m = randomMap(rng, nLabels);
        // A few sensors per map (each builds its visibility table once).
        const std::vector<Sensor> sensors = {randomSensor(rng), randomSensor(rng),
                                             randomSensor(rng)};
        for (int o = 0; o < kObsPerMap; o++)
        {
            Sensor s = sensors[rng.index(sensors.size())];
            const bool unusable = rng.chance(0.02);
            if (unusable)
            {
                (rng.chance(0.5) ? s.R : s.fov) = rng.pick<double>({kNaN, 0.0, -1.0, kInf});
            }
            const TPose2D truth{rng.uniform(-5, 85), rng.uniform(-5, 85), rng.uniform(-M_PI, M_PI)};
            const std::vector<Simulated> dets = simulate(rng, m, s, truth, nLabels);
            const std::vector<TPose2D> p = poses(rng, m, s, truth);
            const std::string where = "map " + std::to_string(map) + " obs " + std::to_string(o);
            const bool ids =
                std::any_of(dets.begin(), dets.end(), [](const Simulated& d) { return d.id >= 0; });
            cov.withIds += ids ? p.size() : 0;
            if (rng.chance(0.3))
            {
                compare(m, landmarkObservation(rng, s, dets), p, cov, where + " (landmarks)");
                cov.landmark += p.size();
            }
            else
            {
                compare(m, semanticObservation(s, dets), p, cov, where);
            }
            cov.unusable += unusable ? p.size() : 0;
        }
    }
    std::cout << "scenes " << cov.scenes << " (paper " << cov.paper << ", probabilistic "
              << cov.probabilistic << ", landmark observations " << cov.landmark << ", with ids "
              << cov.withIds << ", unusable sensor " << cov.unusable << ", non-finite pose "
              << cov.floor << ", object on the coverage's edge " << cov.onEdge << "); bit-for-bit "
              << cov.exact << "; with a match " << cov.matched << ", >= 2 matches "
              << cov.severalMatched << ", unmatched on both sides " << cov.contested
              << ", with a match under misread ranges " << cov.misreadModel
              << ", probabilistic with a match in a map of uncertain objects " << cov.uncertainMap
              << "; largest |fast - reference| " << cov.maxDiff << ", per matched pair "
              << cov.maxPerPair << " (tolerance " << kTolerancePerPair << " per pair)\n";
    EXPECT_EQ(cov.failures, 0u);
    EXPECT_GE(cov.scenes, 100000u);
    // The scenes exercise what they claim.
    EXPECT_GT(cov.paper, 40000u);
    EXPECT_GT(cov.probabilistic, 40000u);
    EXPECT_GT(cov.landmark, 20000u);
    EXPECT_GT(cov.withIds, 20000u);
    EXPECT_GT(cov.unusable, 1500u);
    EXPECT_GT(cov.misreadModel, 3000u);
    EXPECT_GT(cov.uncertainMap, 2000u);
    EXPECT_GT(cov.floor, 4000u);
    EXPECT_GT(cov.matched, 10000u);
    EXPECT_GT(cov.severalMatched, 6000u);
    EXPECT_GT(cov.contested, 6000u);
    EXPECT_GT(cov.onEdge, 0u);  // the edge poses reach the edges, rarely
    EXPECT_LT(cov.onEdge, 500u);
    EXPECT_GT(cov.maxDiff, 0.0);  // the approximations are there: the tolerance is needed
}

namespace
{
/** A small map for the marginal association: 2..5 objects within 12 x 12 m in 1..2 labels
 *  (objects of one label close together: pairs compete), the probabilistic model with
 *  `association` and options drawn at random. */
CSemanticMap smallMap(Rng& rng, size_t& nLabels, CSemanticMap::Association association)
{
    CSemanticMap m;
    auto& o = m.likelihoodOptions;
    o.model = CSemanticMap::Model::Probabilistic;
    o.probabilistic.association = association;
    o.detector.sigma_range_m = rng.uniform(0.2, 2.0);
    o.detector.sigma_bearing_deg = rng.uniform(1.0, 15.0);
    o.probabilistic.p_detect_near = rng.uniform(0.3, 0.99);
    o.probabilistic.p_detect_far = rng.uniform(0.1, 0.99);
    o.probabilistic.p_detect_edge_ratio = rng.pick<double>({1.0, 1.0, 0.3, 0.0});
    o.probabilistic.clutter_per_scan = rng.uniform(0.05, 3.0);
    o.probabilistic.p_confusion = rng.pick<double>({0.0, 0.05, 0.3});
    o.detector.p_range_outlier = rng.pick<double>({0.0, 0.0, 0.02, 0.3});
    nLabels = 1 + rng.index(2);
    const size_t n = 2 + rng.index(4);
    for (size_t i = 0; i < n; i++)
    {
        CSemanticMap::TObject ob;
        ob.id = static_cast<int32_t>(i + 1);
        ob.label = kLabels[rng.index(nLabels)];
        ob.x = rng.uniform(0.0, 12.0);
        ob.y = rng.uniform(0.0, 12.0);
        if (rng.chance(0.3))
        {
            makeUncertain(rng, nLabels, ob);
        }
        m.addObject(ob);
    }
    return m;
}

/** Detections of up to 6 rows of `dets` (the reference enumerates every association). */
std::vector<Simulated> fewDetections(std::vector<Simulated> dets)
{
    if (dets.size() > 6)
    {
        dets.resize(6);
    }
    return dets;
}
}  // namespace

TEST(SemanticLikelihoodReference, MarginalAssociationEqualsPlainEnumeration)
{
    Rng rng(20261124);
    size_t scenes = 0, contested = 0, failures = 0, aboveGreedy = 0;
    double maxDiff = 0;
    for (int map = 0; map < 400; map++)
    {
        size_t nLabels = 1;
        const uint32_t seed = static_cast<uint32_t>(rng.index(1u << 30));
        Rng mapRng(seed), greedyRng(seed);
        const CSemanticMap m = smallMap(mapRng, nLabels, CSemanticMap::Association::Marginal);
        const CSemanticMap greedy =
            smallMap(greedyRng, nLabels, CSemanticMap::Association::Greedy);  // the same map
        for (int o = 0; o < 10; o++)
        {
            Sensor s = randomSensor(rng);
            const TPose2D truth{rng.uniform(-5, 17), rng.uniform(-5, 17), rng.uniform(-M_PI, M_PI)};
            const auto obs =
                semanticObservation(s, fewDetections(simulate(rng, m, s, truth, nLabels)));
            const std::vector<TPose2D> p = poses(rng, m, s, truth);
            std::vector<double> fast(p.size()), greedyFast(p.size());
            m.computeLogLikelihoods(obs, p.data(), p.size(), fast.data());
            greedy.computeLogLikelihoods(obs, p.data(), p.size(), greedyFast.data());
            for (size_t i = 0; i < p.size(); i++)
            {
                ref::SemanticTerms t;
                const double want = ref::semanticLogLikelihood(m, obs, p[i], &t);
                if (t.onEdge > 0)
                {
                    continue;  // in z^k or not by rounding (see the random-scenes test)
                }
                const double diff = std::abs(fast[i] - want);
                const bool ok = (want == -1e300 || want == 0.0)
                                    ? fast[i] == want
                                    : diff <= kTolerancePerPair * std::max<double>(1, t.m);
                if (!ok && ++failures <= 10)
                {
                    ADD_FAILURE() << "map " << map << " obs " << o << " pose " << i << ": fast "
                                  << fast[i] << ", enumeration " << want << " (l=" << t.l
                                  << " q=" << t.q << ", " << t.m << " pairs)";
                }
                maxDiff = std::isfinite(diff) ? std::max(maxDiff, diff) : maxDiff;
                // The greedy association's product is one term of the sum.
                EXPECT_GE(fast[i], greedyFast[i] - 1e-9) << "map " << map << " pose " << i;
                aboveGreedy += fast[i] > greedyFast[i] + 1e-6 ? 1 : 0;
                contested += t.m > std::min(t.l, t.q) ? 1 : 0;
                scenes++;
            }
        }
        EXPECT_EQ(m.associationsApproximated(), 0u);  // small scenes: exact
    }
    std::cout << "scenes " << scenes << ", with more pairs than a one-to-one association holds "
              << contested << ", marginal above greedy " << aboveGreedy
              << "; largest |fast - enumeration| " << maxDiff << "\n";
    EXPECT_EQ(failures, 0u);
    EXPECT_GT(scenes, 30000u);
    EXPECT_GT(contested, 3000u);
    EXPECT_GT(aboveGreedy, 10000u);
}

/** log of the sum over every association of a dense scene's pairs by a plain subset DP over
 *  the objects (independent of the library's): dp[S] sums the associations of the first
 *  detections that use exactly the objects of S. */
double denseLogSum(const std::vector<std::vector<double>>& logW)
{
    const size_t objs = logW.empty() ? 0 : logW[0].size();
    std::vector<double> dp(size_t{1} << objs, 0.0);
    dp[0] = 1.0;
    double scale = 0;  // dp holds exp(log - scale) to stay in range
    for (const auto& row : logW)
    {
        const double rowMax = *std::max_element(row.begin(), row.end());
        const double shift = std::max(0.0, rowMax);
        std::vector<double> next(dp.size(), 0.0);
        for (size_t S = 0; S < dp.size(); S++)
        {
            next[S] += dp[S] * std::exp(-shift);
            for (size_t o = 0; o < objs; o++)
            {
                if ((S & (size_t{1} << o)) == 0)
                {
                    next[S | (size_t{1} << o)] += dp[S] * std::exp(row[o] - shift);
                }
            }
        }
        dp.swap(next);
        scale += shift;
    }
    double sum = 0;
    for (const double v : dp)
    {
        sum += v;
    }
    return std::log(sum) + scale;
}

TEST(SemanticLikelihoodReference, MarginalAssociationBeyondItsBudgetIsALowerBoundAndCounted)
{
    // Fourteen objects of one label close together, fourteen detections among them: one group
    // of 196 pairs, 2^14 x 196 work, beyond the budget.
    CSemanticMap m;
    auto& o = m.likelihoodOptions;
    o.model = CSemanticMap::Model::Probabilistic;
    o.probabilistic.association = CSemanticMap::Association::Marginal;
    o.detector.sigma_range_m = 3.0;
    o.detector.sigma_bearing_deg = 30.0;
    o.probabilistic.p_confusion = 0;
    const size_t n = 14;
    for (size_t i = 0; i < n; i++)
    {
        CSemanticMap::TObject ob;
        ob.id = static_cast<int32_t>(i + 1);
        ob.label = "buoy";
        ob.x = 10.0 + 0.3 * static_cast<double>(i);
        ob.y = 0.2 * static_cast<double>(i % 3);
        m.addObject(ob);
    }
    CObservationSemantic obs;
    obs.maxRange_m = 30;
    obs.fov_rad = M_PI;
    for (size_t j = 0; j < n; j++)
    {
        TSemanticDetection d;
        d.label = "buoy";
        d.range_m = 10.1 + 0.31 * static_cast<double>(j);
        d.bearing_rad = 0.005 * static_cast<double>(j);
        obs.detections.push_back(d);
    }
    const TPose2D pose{0, 0, 0};
    // The exact value: the model's terms as the reference writes them, summed by denseLogSum.
    const double R = 30, fov = M_PI;
    const double logKappa = std::log(o.probabilistic.clutter_per_scan / (R * fov));
    const double sr = o.detector.sigma_range_m, sb = o.detector.sigma_bearing_deg * M_PI / 180;
    double base = -o.probabilistic.clutter_per_scan + static_cast<double>(n) * logKappa;
    std::vector<std::vector<double>> logW(n, std::vector<double>(n));
    for (size_t v = 0; v < n; v++)
    {
        const auto& ob = m.objects()[v];
        const double rho = std::hypot(ob.x, ob.y), theta = std::atan2(ob.y, ob.x);
        const double pd =
            std::clamp(o.probabilistic.p_detect_near +
                           (o.probabilistic.p_detect_far - o.probabilistic.p_detect_near) * rho / R,
                       1e-6, 1 - 1e-6);
        base += std::log(1 - pd);
        for (size_t j = 0; j < n; j++)
        {
            const auto& d = obs.detections[j];
            const double dr = (d.range_m - rho) / sr, db = (d.bearing_rad - theta) / sb;
            logW[j][v] = std::log(pd / (1 - pd)) + std::log(1 - o.probabilistic.p_confusion) -
                         0.5 * dr * dr - 0.5 * db * db - std::log(2 * M_PI * sr * sb) - logKappa;
        }
    }
    const double exact = base + denseLogSum(logW);
    const double fast = m.computeLogLikelihood(obs, pose);
    EXPECT_EQ(m.associationsApproximated(), 1u);
    EXPECT_LE(fast, exact + 1e-6);  // the pairs left out make it a lower bound
    EXPECT_GT(fast, exact - 0.1);   // ... of the heaviest partial associations: most of it
    std::cout << "dense scene: exact " << exact << ", approximated " << fast << "\n";
    m.resetAssociationCount();
    EXPECT_EQ(m.associationsApproximated(), 0u);
    // With ids each detection names its object: groups of one pair, exact.
    for (size_t j = 0; j < n; j++)
    {
        obs.detections[j].object_id = static_cast<int32_t>(j + 1);
    }
    ref::SemanticTerms t;
    EXPECT_NEAR(m.computeLogLikelihood(obs, pose), ref::semanticLogLikelihood(m, obs, pose, &t),
                1e-4 * static_cast<double>(n));
    EXPECT_EQ(m.associationsApproximated(), 0u);
}

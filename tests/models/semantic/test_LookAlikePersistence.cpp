/* semloc tests — look-alike persistence (CSemanticMap's lookalike_persistence): the clutter
 * density a detection near an earlier scan's gets, against its closed form; what it leaves
 * alone (other labels, far detections, old scans, a run back in time); the filter's frame
 * likelihood with it; and a pose that explains a look-alike as a map object no longer gaining
 * from it scan after scan. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/filter/SensoryFrameLikelihood.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cmath>
#include <memory>
#include <vector>

#include <semloc/models/semantic/LookAlikeMemory.h>

using mrpt::math::TPose2D;
using semloc::CObservationSemantic;
using semloc::CSemanticMap;
using semloc::LookAlikeMemory;

namespace
{
constexpr double kRho = 0.2;

/** One pillar at (5, 0); the probabilistic model with look-alike persistence rho. */
std::shared_ptr<CSemanticMap> pillarMap(double rho = kRho)
{
    auto m = std::make_shared<CSemanticMap>();
    m->addObject({1, "pillar", 5, 0, 0, 0.3, 1});
    auto& lo = m->likelihoodOptions;
    lo.model = CSemanticMap::Model::Probabilistic;
    lo.detector.sigma_range_m = 0.1;
    lo.detector.sigma_bearing_deg = 1;
    lo.probabilistic.clutter_per_scan = 0.3;
    lo.probabilistic.p_confusion = 0;
    lo.lookalike.lookalike_persistence = rho;
    lo.lookalike.lookalike_speed_mps = 0.3;
    lo.lookalike.lookalike_window_s = 1.0;
    return m;
}

/** A scan at time t [s] with detections (label, range, bearing). */
CObservationSemantic scan(double t, const std::vector<std::tuple<std::string, double, double>>& d)
{
    CObservationSemantic o;
    o.timestamp = mrpt::Clock::fromDouble(1000 + t);
    o.maxRange_m = 10;
    o.fov_rad = M_PI / 2;
    for (const auto& [label, r, b] : d)
    {
        semloc::TSemanticDetection det;
        det.label = label;
        det.range_m = r;
        det.bearing_rad = b;
        o.detections.push_back(det);
    }
    return o;
}

/** The closed form: log(1 + rho r N(dist; 0, v_k + v_j + (u dt)^2) / kappa). */
double expectedFactor(const CSemanticMap& m, const CObservationSemantic& o, double r1, double r2,
                      double dist, double dt)
{
    const auto& lo = m.likelihoodOptions;
    const double sb = lo.detector.sigma_bearing_deg * M_PI / 180;
    const double var = 2 * lo.detector.sigma_range_m * lo.detector.sigma_range_m +
                       (r1 * r1 + r2 * r2) * sb * sb +
                       std::pow(lo.lookalike.lookalike_speed_mps * dt, 2);
    const double n = std::exp(-0.5 * dist * dist / var) / (2 * M_PI * var);
    return std::log1p(lo.lookalike.lookalike_persistence * r2 * n / m.clutterDensity(o));
}
}  // namespace

TEST(LookAlikePersistence, FactorIsTheClosedFormForADetectionNearAnEarlierOne)
{
    const auto map = pillarMap();
    LookAlikeMemory mem;
    std::vector<double> f;
    // A look-alike 3 m ahead, 1 m left of the pillar's line; the vehicle moves 0.1 m on.
    const auto a = scan(0, {{"pillar", 3.0, 0.3}});
    mem.note(a, *map, TPose2D(0, 0, 0), f);
    ASSERT_EQ(f.size(), 1u);
    EXPECT_EQ(f[0], 0.0);  // nothing earlier
    const double ax = 3.0 * std::cos(0.3), ay = 3.0 * std::sin(0.3);
    // The same point, seen 0.25 s later from 0.1 m further on, plus 5 cm.
    const double bx = ax + 0.05 - 0.1, by = ay;
    const double rb = std::hypot(bx, by), bb = std::atan2(by, bx);
    const auto b = scan(0.25, {{"pillar", rb, bb}, {"pillar", 4.0, -0.5}});
    mem.note(b, *map, TPose2D(0.1, 0, 0), f);
    ASSERT_EQ(f.size(), 2u);
    EXPECT_NEAR(f[0], expectedFactor(*map, b, 3.0, rb, 0.05, 0.25), 1e-9);
    EXPECT_GT(f[0], 2.0);   // a look-alike's second sighting: clutter far likelier
    EXPECT_LT(f[1], 1e-6);  // metres from anything seen before
    EXPECT_EQ(mem.size(), 3u);
}

TEST(LookAlikePersistence, OtherLabelsOldScansAndUnknownLabelsGiveNothing)
{
    const auto map = pillarMap();
    map->addObject({2, "anchor", 2, 2, 0, 0.3, 1});
    LookAlikeMemory mem;
    std::vector<double> f;
    mem.note(scan(0, {{"pillar", 3.0, 0.2}, {"diver", 3.0, 0.2}}), *map, TPose2D(0, 0, 0), f);
    EXPECT_EQ(mem.size(), 1u);  // the diver is unknown to the map: not remembered
    mem.note(scan(0.2, {{"anchor", 3.0, 0.2}, {"diver", 3.0, 0.2}}), *map, TPose2D(0, 0, 0), f);
    EXPECT_EQ(f[0], 0.0);  // another label
    EXPECT_EQ(f[1], 0.0);  // unknown label: not scored at all
    mem.note(scan(1.5, {{"pillar", 3.0, 0.2}}), *map, TPose2D(0, 0, 0), f);
    EXPECT_EQ(f[0], 0.0);  // the pillar detection is 1.5 s old: beyond the 1 s window
    mem.note(scan(0.1, {{"pillar", 3.0, 0.2}}), *map, TPose2D(0, 0, 0), f);
    EXPECT_EQ(f[0], 0.0);  // back in time: the memory starts over
    EXPECT_EQ(mem.size(), 1u);
    auto noTime = scan(2, {{"pillar", 3.0, 0.2}});
    noTime.timestamp = INVALID_TIMESTAMP;
    EXPECT_THROW(mem.note(noTime, *map, TPose2D(0, 0, 0), f), std::exception);
}

TEST(LookAlikePersistence, OptionsAreReadCheckedAndPaperModelRefused)
{
    mrpt::config::CConfigFileMemory c;
    c.write("L", "model", "probabilistic");
    c.write("L", "lookalike_persistence", "0.3");
    c.write("L", "lookalike_speed_mps", "0.5");
    c.write("L", "lookalike_window_s", "2");
    CSemanticMap::TLikelihoodOptions lo;
    lo.loadFromConfigFile(c, "L");
    EXPECT_EQ(lo.lookalike.lookalike_persistence, 0.3);
    EXPECT_EQ(lo.lookalike.lookalike_speed_mps, 0.5);
    EXPECT_EQ(lo.lookalike.lookalike_window_s, 2.0);
    c.write("L", "lookalike_persistence", "1.5");
    EXPECT_THROW(lo.loadFromConfigFile(c, "L"), std::exception);
    c.write("L", "lookalike_persistence", "0.3");
    c.write("L", "model", "paper");
    EXPECT_THROW(lo.loadFromConfigFile(c, "L"), std::exception);
}

TEST(LookAlikePersistence, FrameLikelihoodUsesTheFactorsAndLosesThePullOfALookAlike)
{
    // Truth at the origin facing +x: the pillar (5, 0) dead ahead; a look-alike persists at
    // 4 m, 0.5 rad. The wrong pose is turned by 0.5 rad so that it sees the look-alike where the
    // pillar is, from (1, 0). Scan after scan, without persistence, the wrong pose gains the same;
    // with it, the second scan on gains far less.
    const TPose2D truth(0, 0, 0);
    const std::vector<TPose2D> poses = {truth, TPose2D(1, 0, -0.5)};
    semloc::ParallelExecutor ex(1);
    double gain[2][3];
    for (int on = 0; on < 2; on++)
    {
        const auto map = pillarMap(on ? kRho : 0);
        semloc::SensoryFrameLikelihood lik(*map);
        for (int s = 0; s < 3; s++)
        {
            mrpt::obs::CSensoryFrame sf;
            sf.insert(
                std::make_shared<CObservationSemantic>(scan(0.25 * s, {{"pillar", 4.0, 0.5}})));
            lik.plan(sf, ex);
            const TPose2D odo(0, 0, 0);
            lik.beginUpdate(poses.size(), &odo);
            std::vector<double> out(poses.size());
            lik.evaluateChunk(poses.data(), 0, poses.size(), out.data());
            lik.endUpdate(out.data(), poses.size());
            gain[on][s] = out[1] - out[0];
            // The reference of the evidence trigger moves with the clutter densities.
            EXPECT_LT(lik.withoutObjects().logLik, out[0] + 50);
        }
    }
    for (int s = 0; s < 3; s++)
    {
        EXPECT_GT(gain[0][s], 3.0) << "scan " << s;  // the pose that sees the pillar there gains
    }
    EXPECT_NEAR(gain[1][0], gain[0][0], 1e-9);  // the first sighting: the same
    EXPECT_LT(gain[1][1], gain[0][1] - 2.0);    // later sightings: much less
    EXPECT_LT(gain[1][2], gain[0][2] - 2.0);
}

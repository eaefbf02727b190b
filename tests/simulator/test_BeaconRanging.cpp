/* semloc tests — the simulator's range-only acoustic positioning ([BeaconRanging]): slant
 * ranges with the configured noise, MRPT's beacon map's geometry, nothing when disabled, the
 * other sensors' data untouched when enabled. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <string>
#include <vector>

#include "TestHelpers.h"

using mrpt::math::TPose2D;
using mrpt::obs::CObservationBeaconRanges;
using semloc::BeaconRangingModel;
using semloc::SimulationResult;
using semloc::Simulator;
using semloc::TSimulatorOptions;
using semloc::World;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kLbl = SEMLOC_SOURCE_DIR "/maps/paper_50x50_lbl.yaml";

/** Four beacons: two near, one on the seabed below the area, one 300 m away. */
World fourBeacons()
{
    return World::FromText(R"(bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}
objects: []
beacons:
  - {id: 3, x: 0, y: 0}
  - {id: 9, x: 40, y: 10}
  - {id: 0, x: 20, y: 30, z: -15}
  - {id: 5, x: 320, y: 10}
)",
                           "four.yaml");
}

/** The paper world for `steps` steps (the lbl world: the same objects, with beacons). */
TSimulatorOptions run(const std::string& world, int steps)
{
    TSimulatorOptions o;
    o.simulation.world_file = world;
    o.simulation.max_steps = steps;
    return o;
}

/** `obj` serialized as MRPT writes it to a rawlog. */
std::string bytesOf(const mrpt::serialization::CSerializable& obj)
{
    mrpt::io::CMemoryStream m;
    auto ar = mrpt::serialization::archiveFrom(m);
    ar << obj;
    return {static_cast<const char*>(m.getRawBufferData()),
            static_cast<size_t>(m.getTotalBytesCount())};
}

/** The sensory frame of step k. */
mrpt::obs::CSensoryFrame::Ptr frameOf(const SimulationResult& r, size_t k)
{
    return std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(r.rawlog.getAsGeneric(2 * k + 1));
}
}  // namespace

TEST(BeaconRangingModel, RangesAreTheSlantRangesWithTheConfiguredNoise)
{
    const World w = fourBeacons();
    BeaconRangingModel::TOptions o;
    o.enabled = true;
    o.range_std_m = 0.3;
    o.max_range_m = 100;
    o.sensor_x_m = 1.5;
    o.sensor_y_m = -0.5;
    const BeaconRangingModel model(w, o);
    const TPose2D vehicle(10, 20, 0.7);
    // The transducer in the world: the vehicle's pose composed with its mounting.
    const double tx = 10 + std::cos(0.7) * 1.5 + std::sin(0.7) * 0.5;
    const double ty = 20 + std::sin(0.7) * 1.5 - std::cos(0.7) * 0.5;
    const std::vector<double> truth = {
        std::hypot(tx, ty), std::hypot(40 - tx, 10 - ty),
        std::sqrt(std::pow(20 - tx, 2) + std::pow(30 - ty, 2) + 225)};
    mrpt::random::CRandomGenerator rng(42);
    const int n = 20000;
    std::vector<double> sum(3, 0), sum2(3, 0);
    for (int i = 0; i < n; i++)
    {
        const auto obs = model.measure(vehicle, rng);
        ASSERT_EQ(obs->sensedData.size(), 3u) << "the beacon 310 m away does not answer";
        for (size_t b = 0; b < 3; b++)
        {
            const auto& m = obs->sensedData[b];
            ASSERT_EQ(m.beaconID, std::vector<int>({3, 9, 0})[b]) << "the world's order";
            ASSERT_EQ(m.sensorLocationOnRobot, mrpt::poses::CPoint3D(1.5, -0.5, 0));
            const double e = m.sensedDistance - truth[b];
            sum[b] += e;
            sum2[b] += e * e;
        }
    }
    for (size_t b = 0; b < 3; b++)
    {
        const double mean = sum[b] / n, sd = std::sqrt(sum2[b] / n - mean * mean);
        EXPECT_NEAR(mean, 0.0, 4 * 0.3 / std::sqrt(n)) << b;  // float ranges: ~1e-6 m
        EXPECT_NEAR(sd, 0.3, 4 * 0.3 / std::sqrt(2.0 * n)) << b;
    }
    const auto obs = model.measure(vehicle, rng);
    EXPECT_EQ(obs->sensorLabel, "LBL");
    EXPECT_FLOAT_EQ(obs->stdError, 0.3f);
    EXPECT_FLOAT_EQ(obs->minSensorDistance, 0.0f);
    EXPECT_FLOAT_EQ(obs->maxSensorDistance, 100.0f);

    // Every 4th step from step 0; never when disabled.
    o.period_steps = 4;
    EXPECT_TRUE(BeaconRangingModel(w, o).pingsAt(0));
    EXPECT_FALSE(BeaconRangingModel(w, o).pingsAt(3));
    EXPECT_TRUE(BeaconRangingModel(w, o).pingsAt(8));
    o.enabled = false;
    EXPECT_FALSE(BeaconRangingModel(w, o).pingsAt(0));
}

TEST(BeaconRangingModel, NoiseFreeRangesAreWhatMrptsBeaconMapExpects)
{
    // The simulated geometry (mounting, 3D slant range) is the one CBeaconMap scores: exact
    // ranges score ~0 at the true pose, and less 1 m off it.
    const World w = fourBeacons();
    BeaconRangingModel::TOptions o;
    o.enabled = true;
    o.range_std_m = 0;
    o.sensor_x_m = 2;
    o.sensor_y_m = 1;
    mrpt::random::CRandomGenerator rng(1);
    const TPose2D vehicle(12, 7, -2.1);
    const auto obs = BeaconRangingModel(w, o).measure(vehicle, rng);
    mrpt::maps::CBeaconMap map;
    map.likelihoodOptions.rangeStd = 0.1;
    for (const auto& b : w.beacons)
    {
        mrpt::maps::CBeacon c;
        c.m_ID = b.id;
        c.m_typePDF = mrpt::maps::CBeacon::pdfGauss;
        c.m_locationGauss.mean = mrpt::poses::CPoint3D(b.x, b.y, b.z);
        map.push_back(c);
    }
    const auto at = [&](double x, double y, double phi)
    { return map.computeObservationLikelihood(*obs, mrpt::poses::CPose3D(x, y, 0, phi, 0, 0)); };
    EXPECT_GT(at(12, 7, -2.1), -1e-6);
    EXPECT_LT(at(13, 7, -2.1), -5.0);
    EXPECT_LT(at(12, 7, -1.9), -0.5) << "the transducer is off the vehicle's centre";
}

TEST(SimulatorBeacons, DisabledAddsNothingAndTheBeaconsOfAWorldChangeNothing)
{
    // The lbl world has the paper world's objects: with [BeaconRanging] off (whatever its
    // other keys), its dataset is the paper world's, byte for byte.
    const auto paper = Simulator(run(kPaper, 30)).run();
    TSimulatorOptions o = run(kLbl, 30);
    o.beacons.range_std_m = 2;
    o.beacons.period_steps = 3;
    const auto lbl = Simulator(o).run();
    ASSERT_EQ(paper.rawlog.size(), lbl.rawlog.size());
    for (size_t i = 0; i < paper.rawlog.size(); i++)
    {
        ASSERT_EQ(bytesOf(*paper.rawlog.getAsGeneric(i)), bytesOf(*lbl.rawlog.getAsGeneric(i)))
            << "entry " << i;
    }
    EXPECT_EQ(frameOf(lbl, 0)->size(), 2u);
    EXPECT_EQ(lbl.pings, 0u);
    EXPECT_EQ(lbl.summary().find("ping"), std::string::npos) << lbl.summary();
}

TEST(SimulatorBeacons, EnabledAppendsTheRangesAndLeavesTheOtherSensorsAsTheyWere)
{
    TSimulatorOptions o = run(kLbl, 31);
    const auto off = Simulator(o).run();
    o.beacons.enabled = true;
    o.beacons.period_steps = 3;
    const auto on = Simulator(o).run();
    const World w = World::FromFile(kLbl);
    ASSERT_EQ(on.steps, 31u);
    EXPECT_EQ(on.pings, 11u);
    EXPECT_EQ(on.meanBeaconRanges, 3.0);
    EXPECT_NE(on.summary().find("11 pings, 3.00 beacon ranges/ping"), std::string::npos)
        << on.summary();
    double sum2 = 0;
    size_t ranges = 0;
    for (size_t k = 0; k < on.steps; k++)
    {
        // The odometry and the first two observations are those of the run without ranges.
        ASSERT_EQ(bytesOf(*on.rawlog.getAsGeneric(2 * k)),
                  bytesOf(*off.rawlog.getAsGeneric(2 * k)));
        const auto a = frameOf(on, k), b = frameOf(off, k);
        ASSERT_EQ(a->size(), k % 3 == 0 ? 3u : 2u) << k;
        for (size_t j = 0; j < 2; j++)
        {
            ASSERT_EQ(bytesOf(*a->getObservationByIndex(j)), bytesOf(*b->getObservationByIndex(j)));
        }
        if (k % 3 != 0)
        {
            continue;
        }
        const auto r =
            std::dynamic_pointer_cast<CObservationBeaconRanges>(a->getObservationByIndex(2));
        ASSERT_TRUE(r) << k;
        EXPECT_EQ(r->timestamp, a->getObservationByIndex(0)->timestamp);
        EXPECT_EQ(r->sensorLabel, "LBL");
        ASSERT_EQ(r->sensedData.size(), w.beacons.size());
        const auto& gt = on.groundTruth[k];
        for (size_t j = 0; j < w.beacons.size(); j++)
        {
            const auto& bc = w.beacons[j];
            const double truth =
                std::sqrt(std::pow(bc.x - gt.x, 2) + std::pow(bc.y - gt.y, 2) + bc.z * bc.z);
            const double e = r->sensedData[j].sensedDistance - truth;
            EXPECT_LT(std::abs(e), 5 * o.beacons.range_std_m) << k << " " << j;
            sum2 += e * e;
            ranges++;
        }
    }
    EXPECT_EQ(ranges, 33u);
    // 33 draws of N(0, 0.5^2): their RMS within 0.5 (1 +- 0.5) (a chi-square bound).
    EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(ranges)), 0.5, 0.25);
}

TEST(SimulatorBeacons, TheEffectiveIniReproducesTheRanges)
{
    TSimulatorOptions o = run(kLbl, 12);
    o.beacons.enabled = true;
    o.beacons.range_std_m = 1.0 / 3;
    o.beacons.max_range_m = 50;  // beacons 2 and 3 are out of range at first
    const Simulator sim(o);
    const auto res = sim.run();
    EXPECT_LT(res.meanBeaconRanges, 3.0);
    EXPECT_GT(res.meanBeaconRanges, 1.0);
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/sim_beacons.rawlog";
    sim.writeDataset(res, path);
    const auto back = TSimulatorOptions::FromConfigFile(Simulator::configPath(path));
    EXPECT_TRUE(back.beacons.enabled);
    EXPECT_EQ(back.beacons.range_std_m, 1.0 / 3);
    const auto again = Simulator(back).run();
    ASSERT_EQ(again.rawlog.size(), res.rawlog.size());
    for (size_t i = 0; i < res.rawlog.size(); i++)
    {
        ASSERT_EQ(bytesOf(*again.rawlog.getAsGeneric(i)), bytesOf(*res.rawlog.getAsGeneric(i)));
    }
}

TEST(SimulatorBeacons, BadSettingsAreErrorsNamingTheKey)
{
    // Ranging in a world without beacons.
    TSimulatorOptions o = run(kPaper, 5);
    o.beacons.enabled = true;
    const std::string e = semloc::test::errorOf([&] { Simulator s(o); });
    EXPECT_NE(e.find("ini [BeaconRanging] enabled"), std::string::npos) << e;
    EXPECT_NE(e.find("paper_50x50.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("no beacons"), std::string::npos) << e;
    // Values out of range, unknown keys.
    auto loadError = [](const std::string& text)
    {
        return semloc::test::errorOf(
            [&]
            {
                TSimulatorOptions t;
                t.loadFromConfigFile(semloc::test::iniText(text));
            });
    };
    EXPECT_EQ(loadError("[BeaconRanging]\nenabled = true\nperiod_steps = 5\n"), "");
    for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
             {"period_steps = 0", "[BeaconRanging] period_steps"},
             {"range_std_m = -0.1", "[BeaconRanging] range_std_m"},
             {"range_std_m = nan", "[BeaconRanging] range_std_m"},
             {"max_range_m = 0", "[BeaconRanging] max_range_m"},
             {"enabled = maybe", "[BeaconRanging] enabled"},
             {"range_sdt_m = 1", "[BeaconRanging] range_sdt_m"}})
    {
        const std::string err = loadError("[BeaconRanging]\n" + text + "\n");
        EXPECT_NE(err.find(key), std::string::npos) << text << ": " << err;
    }
}

/* semloc tests — the robustness experiment (config/benchmark/robustness.ini): the fault
 * scenarios simulate the rates they document, and the filters keep working under them:
 * semantic under 30 % false positives, 50 % missed detections, 10 % class confusion (each
 * alone and together), geometric under 30 % sonar dropouts, converge in >= 90 % of 20 seeded
 * runs; after a kidnapping to a random pose, augmented MCL re-localizes within 100 steps in
 * >= 90 % of them. */
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <stdexcept>

#include <unistd.h>

namespace fs = std::filesystem;
using semloc::Benchmark;

namespace
{
const std::string kRobustness = SEMLOC_SOURCE_DIR "/config/benchmark/robustness.ini";

const Benchmark& scenario(const Benchmark& b, const std::string& name)
{
    for (const auto& s : b.scenarios())
    {
        if (s.scenario().name == name)
        {
            return s;
        }
    }
    throw std::runtime_error("no scenario " + name);
}

/** Detection and sonar statistics of seeds 1..`seeds` of a scenario's simulation. */
struct TFaultRates
{
    double detections = 0, falsePositives = 0, confused = 0, beams = 0, invalidBeams = 0;
    size_t scans = 0;
    double perScan(double n) const { return n / static_cast<double>(scans); }
};

TFaultRates faultRates(const Benchmark& b, int seeds)
{
    auto o = b.simulation();
    o.detector.report_ids = true;  // ids tell true detections (and their labels) from clutter
    TFaultRates r;
    for (int seed = 1; seed <= seeds; seed++)
    {
        o.simulation.seed = static_cast<uint32_t>(seed);
        const semloc::Simulator sim(o);
        std::map<int, std::string> labelOf;
        for (const auto& obj : sim.world().objects)
        {
            labelOf[obj.id] = obj.label;
        }
        const auto data = sim.run();
        for (size_t i = 0; i < data.rawlog.size(); i++)
        {
            if (data.rawlog.getType(i) != mrpt::obs::CRawlog::etSensoryFrame)
            {
                continue;
            }
            const auto sf = data.rawlog.getAsObservations(i);
            const auto sem = sf->getObservationByClass<semloc::CObservationSemantic>();
            const auto scan = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
            if (!sem || !scan)
            {
                throw std::runtime_error("a step without sonar scan or detections");
            }
            r.scans++;
            for (const auto& d : sem->detections)
            {
                r.detections++;
                r.falsePositives += d.object_id < 0 ? 1 : 0;
                r.confused += d.object_id >= 0 && d.label != labelOf[d.object_id] ? 1 : 0;
            }
            for (size_t k = 0; k < scan->getScanSize(); k++)
            {
                r.beams++;
                r.invalidBeams += scan->getScanRangeValidity(k) ? 0 : 1;
            }
        }
    }
    return r;
}
}  // namespace

TEST(Robustness, FaultScenariosSimulateTheDocumentedRates)
{
    const auto b = Benchmark::FromConfigFile(kRobustness);
    ASSERT_EQ(b.scenarios().size(), 6u);
    const int seeds = 5;
    const auto nominal = faultRates(scenario(b, "class_confusion"), seeds);
    const double nominalTrue = nominal.perScan(nominal.detections - nominal.falsePositives);

    const auto fp = faultRates(scenario(b, "false_positives"), seeds);
    EXPECT_NEAR(fp.falsePositives / fp.detections, 0.30, 0.03) << "30 % of reports are false";

    const auto miss = faultRates(scenario(b, "missed_detections"), seeds);
    EXPECT_NEAR(miss.perScan(miss.detections - miss.falsePositives) / nominalTrue, 0.5, 0.05)
        << "half of the nominal true detections";

    EXPECT_NEAR(nominal.confused / (nominal.detections - nominal.falsePositives), 0.1, 0.02)
        << "10 % of true detections carry another label";

    const auto all = faultRates(scenario(b, "detector_all"), seeds);
    EXPECT_GT(all.falsePositives / all.detections, 0.30);
    EXPECT_NEAR(all.confused / (all.detections - all.falsePositives), 0.1, 0.03);

    const auto sonar = faultRates(scenario(b, "sonar_dropouts"), seeds);
    EXPECT_NEAR(sonar.invalidBeams / sonar.beams, 0.30, 0.02);

    const auto& k = scenario(b, "kidnapping");
    EXPECT_TRUE(k.simulation().kidnapping.enabled);
    EXPECT_TRUE(k.simulation().kidnapping.random_pose);
    // semantic.ini's own recovery, as shipped.
    EXPECT_FALSE(k.scenario().recovery);
    EXPECT_EQ(k.variants().front().options.filter.recovery.trigger,
              semloc::RecoveryTrigger::Evidence);
}

#ifdef SEMLOC_SANITIZED
// The sanitized suite (tests/sanitize.sh) looks for memory errors and undefined behaviour, not
// statistics: it runs every scenario and variant on 2 seeds and checks what does not depend on
// the number of runs; the rates over 20 seeds are asserted in the plain build.
constexpr int kRuns = 2;
#else
constexpr int kRuns = 20;
#endif

TEST(Robustness, FiltersKeepWorkingUnderFaultsAndKidnapping)
{
    const fs::path out = fs::path(SEMLOC_TEST_OUT) / ("robustness_" + std::to_string(::getpid()));
    const auto b = Benchmark::FromConfigFile(kRobustness, out.string(), kRuns);
    ASSERT_EQ(b.options().runs, kRuns);
    const auto res = b.run();
    ASSERT_EQ(res.summaries.size(), 6u);
    std::cout << res.table;
    for (const auto& s : res.summaries)
    {
        EXPECT_EQ(s.runs, static_cast<size_t>(kRuns)) << s.scenario;
        if (kRuns < 20)
        {
            EXPECT_EQ(s.kidnap_step, s.scenario == "kidnapping" ? 200 : -1) << s.scenario;
            continue;
        }
        EXPECT_GE(s.successRate(), 0.9) << s.scenario << " / " << s.variant;
        if (s.scenario == "kidnapping")
        {
            ASSERT_EQ(s.kidnap_step, 200);
            EXPECT_LE(s.mean_recovery_steps, 100);
            std::cout << "kidnapping: mean recovery steps " << s.mean_recovery_steps << "\n";
            RecordProperty("mean_recovery_steps", std::to_string(s.mean_recovery_steps));
        }
        RecordProperty(s.scenario + "_success_rate", std::to_string(s.successRate()));
    }
    // The kidnapping really lost the filter: far off right after the teleport.
    size_t lost = 0, kidnapRuns = 0;
    for (const auto& r : res.runs)
    {
        if (r.scenario == "kidnapping")
        {
            kidnapRuns++;
            lost += r.records.at(200).errXY() > 5 ? 1 : 0;
        }
    }
    EXPECT_EQ(kidnapRuns, static_cast<size_t>(kRuns));
    EXPECT_GE(lost, static_cast<size_t>(kRuns * 9 / 10));
    for (const char* f : {"report.md", "scenarios.csv", "kidnapping/results.csv",
                          "sonar_dropouts/report.md", "detector_all/curves.csv"})
    {
        EXPECT_TRUE(fs::exists(out / f)) << f;
    }
    fs::remove_all(out);
}

/* Tests of semloc::Benchmark: config/benchmark/benchmark.ini's defaults, the uniform filter, strict
 * keys, and runs that depend on their seed only. */
#include <gtest/gtest.h>
#include <mrpt/core/exceptions.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "TestHelpers.h"
#include "experiment/BenchmarkTables.h"

namespace
{
const std::string kConfig = std::string(SEMLOC_SOURCE_DIR) + "/config/";

std::string writeIni(const std::string& name, const std::string& body)
{
    std::string path = std::string(SEMLOC_TEST_OUT) + "/" + name;
    std::ofstream(path) << "[Benchmark]\nsimulate_ini = " << kConfig
                        << "simulate/simulate.ini\nvariants = " << kConfig
                        << "localize/semantic.ini, " << kConfig
                        << "localize/geometric.ini\noutput_dir = " << SEMLOC_TEST_OUT
                        << "/bench_unused\n"
                        << body;
    return path;
}

/** A benchmark of semantic.ini alone with `sweep = <sweep>` (and what follows it). */
std::string writeSweepIni(const std::string& name, const std::string& sweep)
{
    std::string path = std::string(SEMLOC_TEST_OUT) + "/" + name;
    std::ofstream(path) << "[Benchmark]\nsimulate_ini = " << kConfig
                        << "simulate/simulate.ini\nvariants = " << kConfig
                        << "localize/semantic.ini\noutput_dir = " << SEMLOC_TEST_OUT
                        << "/bench_unused\nsweep = " << sweep << "\n";
    return path;
}

std::string errorOf(const std::string& path)
{
    try
    {
        (void)semloc::Benchmark::FromConfigFile(path);
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);
    }
    return {};
}

/** `variants[shipped]` is semantic.ini's recovery (re-seeding while the particles are spread,
 *  10 m²), `variants[challengers]` it with a challenger set of 20 frames, `variants[noReseed]`
 *  it without the re-seeding. */
template <typename Variants>
void expectRecoveryVariants(const Variants& variants, size_t shipped, size_t challengers,
                            size_t noReseed)
{
    EXPECT_EQ(variants[challengers].name(), "semantic_challengers");
    EXPECT_EQ(variants[shipped].options.filter.recovery.challenger_frames, 0u);
    EXPECT_EQ(variants[challengers].options.filter.recovery.challenger_frames, 20u);
    EXPECT_EQ(variants[noReseed].name(), "semantic_no_reseed");
    EXPECT_EQ(variants[shipped].options.filter.recovery.lost_var_xy_m2, 10.0);
    EXPECT_EQ(variants[challengers].options.filter.recovery.lost_var_xy_m2, 10.0);
    EXPECT_EQ(variants[noReseed].options.filter.recovery.lost_var_xy_m2, 0.0);
}
}  // namespace

TEST(Benchmark, ShippedIniIsThePapersExperimentWithOneParticleBudgetForAllVariants)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/benchmark.ini");
    EXPECT_EQ(b.options().runs, 100);
    EXPECT_FALSE(b.options().same_filter);
    ASSERT_EQ(b.variants().size(), 5u);
    using Mode = semloc::Localizer::InitMode;
    for (const auto& v : b.variants())
    {
        const auto& f = v.options.filter;
        EXPECT_EQ(f.particles_count, 2000) << v.name();
        EXPECT_EQ(f.threads, 1) << v.name();
        // Each variant's own filter: the ones with a semantic map start from the detections,
        // the others uniform; only semantic recovers.
        const bool seeded = v.name() == "semantic" || v.name() == "fused";
        EXPECT_EQ(f.init_PDF_mode, seeded ? Mode::FromDetections : Mode::FreeSpace) << v.name();
        EXPECT_EQ(f.recovery.enabled(), v.name() == "semantic") << v.name();
    }
    EXPECT_EQ(b.variants()[0].name(), "semantic");
    EXPECT_EQ(b.variants()[4].name(), "fused");
}

TEST(Benchmark, SameFilterStartsVariantsWithoutSemanticMapUniformly)
{
    // semantic.ini starts from the first detections; with same_filter the geometric variant
    // runs its filter but, with no semantic map to place a detection, from the uniform start,
    // and without the evidence recovery trigger, which weighs the detections alone.
    const auto b = semloc::Benchmark::FromConfigFile(writeIni("bench_same.ini", ""));
    ASSERT_TRUE(b.options().same_filter);
    ASSERT_EQ(b.variants().size(), 2u);
    using Mode = semloc::Localizer::InitMode;
    EXPECT_EQ(b.variants()[0].options.filter.init_PDF_mode, Mode::FromDetections);
    EXPECT_EQ(b.variants()[1].options.filter.init_PDF_mode, Mode::FreeSpace);
    EXPECT_EQ(b.variants()[0].options.filter.recovery.trigger, semloc::RecoveryTrigger::Evidence);
    EXPECT_EQ(b.variants()[1].options.filter.recovery.trigger, semloc::RecoveryTrigger::Off);
    EXPECT_EQ(b.variants()[1].options.filter.particles_count,
              b.variants()[0].options.filter.particles_count);
}

TEST(Benchmark, ErrorsNameTheKey)
{
    EXPECT_NE(errorOf(writeIni("bench_bad1.ini", "runs = 0\n")).find("[Benchmark] runs"),
              std::string::npos);
    EXPECT_NE(errorOf(writeIni("bench_bad2.ini", "partcles = 10\n")).find("partcles"),
              std::string::npos);
    EXPECT_NE(errorOf(writeIni("bench_bad3.ini", "simulate_ini = nope.ini\n"))
                  .find("[Benchmark] simulate_ini"),
              std::string::npos);
}

TEST(Benchmark, ARunDependsOnItsSeedOnly)
{
    const auto b = semloc::Benchmark::FromConfigFile(
        writeIni("bench_seed.ini", "max_steps = 15\nparticles = 200\n"));
    const auto a1 = b.runOne(1), a2 = b.runOne(2), again = b.runOne(1);
    ASSERT_EQ(a1.size(), 2u);
    for (size_t k = 0; k < a1.size(); k++)
    {
        ASSERT_EQ(a1[k].records.size(), 15u);
        EXPECT_EQ(a1[k].variant, again[k].variant);
        EXPECT_EQ(a1[k].records.back().est.x, again[k].records.back().est.x);
        EXPECT_EQ(a1[k].records.back().var_xy, again[k].records.back().var_xy);
        EXPECT_EQ(a1[k].records.back().cov_xphi, again[k].records.back().cov_xphi);
        EXPECT_EQ(a1[k].metrics.nees_median, again[k].metrics.nees_median);
        EXPECT_EQ(a1[k].metrics.nees_mean_well_conditioned,
                  again[k].metrics.nees_mean_well_conditioned);
        EXPECT_TRUE(std::isfinite(a1[k].metrics.nees_median)) << a1[k].variant;
        EXPECT_NE(a1[k].records.back().est.x, a2[k].records.back().est.x);
        EXPECT_EQ(a1[k].seed, 1u);
    }
    // The detector's bound: one per step of the simulation for the variant of the detections
    // alone, none for the sonar's (which has other information).
    ASSERT_EQ(a1[0].variant, "semantic");
    ASSERT_EQ(a1[0].detectorBound.size(), 15u);
    EXPECT_TRUE(a1[1].detectorBound.empty()) << a1[1].variant;
    for (size_t s = 0; s < 15; s++)
    {
        EXPECT_EQ(a1[0].detectorBound[s].rms_xy_m, again[0].detectorBound[s].rms_xy_m);
    }
    EXPECT_LT(a1[0].detectorBound.back().rms_xy_m, a1[0].detectorBound.front().rms_xy_m);
}

TEST(Benchmark, InterruptStopsTheRunsAndWritesNothing)
{
    // Ctrl-C as semloc-benchmark sees it: the handler turns SIGINT into a request...
    semloc::installInterruptHandlers();
    std::raise(SIGINT);
    EXPECT_TRUE(semloc::interruptRequested());
    semloc::clearInterrupt();
    std::signal(SIGINT, SIG_DFL);

    // ...and a request while runs are under way ends them: Interrupted, no output directory,
    // no staging directory left beside it.
    const std::string out = std::string(SEMLOC_TEST_OUT) + "/bench_interrupted";
    std::filesystem::remove_all(out);
    const auto b = semloc::Benchmark::FromConfigFile(
        writeIni("bench_interrupt.ini", "runs = 4\njobs = 2\nmax_steps = 15\nparticles = 200\n"),
        out);
    size_t seen = 0;
    EXPECT_THROW(b.run(semloc::test::interruptAt(1, seen)), semloc::Interrupted);
    semloc::clearInterrupt();
    EXPECT_GE(seen, 1u);
    EXPECT_LT(seen, 4u) << "runs went on after the request";
    EXPECT_FALSE(std::filesystem::exists(out));
    for (const auto& e : std::filesystem::directory_iterator(SEMLOC_TEST_OUT))
    {
        EXPECT_EQ(e.path().filename().string().rfind(".bench_interrupted", 0), std::string::npos)
            << e.path();
    }
}

TEST(Benchmark, ShippedAssociationIniComparesTheTwoAssociationsInTheirWorlds)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/association.ini");
    ASSERT_EQ(b.scenarios().size(), 3u);
    for (const auto& sc : b.scenarios())
    {
        ASSERT_EQ(sc.variants().size(), 2u);
        EXPECT_EQ(sc.variants()[0].name(), "semantic");
        EXPECT_EQ(sc.variants()[1].name(), "semantic_marginal");
        // map_from_world: the harbour's variants localize in the harbour, the others in the
        // world of their own ini (the paper's).
        for (const auto& v : sc.variants())
        {
            ASSERT_TRUE(v.maps.world.has_value());
            EXPECT_EQ(v.maps.world->name,
                      sc.scenario().name == "harbour" ? "harbour_symmetric" : "paper_50x50")
                << sc.scenario().name;
        }
    }
}

TEST(Benchmark, ScenarioSetsTheInitialCloudOfEveryVariant)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/global_start.ini");
    ASSERT_EQ(b.scenarios().size(), 2u);
    using Mode = semloc::Localizer::InitMode;
    for (const auto& sc : b.scenarios())
    {
        const Mode want =
            sc.scenario().name == "detections" ? Mode::FromDetections : Mode::FreeSpace;
        ASSERT_EQ(sc.variants().size(), 3u);
        for (const auto& v : sc.variants())
        {
            EXPECT_EQ(v.options.filter.init_PDF_mode, want) << v.name();
            // semantic_norecovery.ini's filter for all: the start alone differs.
            EXPECT_FALSE(v.options.filter.recovery.enabled()) << v.name();
        }
    }
    // A variant without a semantic map cannot start from the detections.
    const std::string scenario = std::string(SEMLOC_TEST_OUT) + "/bench_init3.ini";
    std::ofstream(scenario) << "[Scenario]\nname = seeded\ninit_PDF_mode = 3\n";
    EXPECT_NE(errorOf(writeIni("bench_init3_main.ini", "scenarios = " + scenario + "\n"))
                  .find("variant 'geometric': init_PDF_mode = 3 (from the first detections) "
                        "needs a semanticMap"),
              std::string::npos);
}

TEST(Benchmark, ShippedRealDataIniOverlaysTheConditionsOnThePaperScenario)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/realdata.ini");
    ASSERT_EQ(b.scenarios().size(), 7u);
    const auto& all = b.scenarios().back();
    EXPECT_EQ(b.scenarios()[4].scenario().name, "misread_ranges");
    EXPECT_EQ(b.scenarios()[4].simulation().detector.p_range_outlier, 0.2);
    EXPECT_EQ(all.simulation().detector.p_range_outlier, 0.0);
    EXPECT_EQ(all.simulation().detector.distractors, 4);
    EXPECT_EQ(b.scenarios()[3].scenario().name, "distractors");
    EXPECT_EQ(b.scenarios()[3].simulation().detector.distractors, 4);
    EXPECT_EQ(all.scenario().name, "all");
    EXPECT_EQ(all.simulation().odometry.heading_drift_deg_per_min, 15.0);
    EXPECT_EQ(all.simulation().detector.p_detect_near, 0.3);
    EXPECT_EQ(all.simulation().detector.gap_every_s, 120.0);
    EXPECT_EQ(b.scenarios().front().simulation().odometry.heading_drift_deg_per_min, 0.0);
    const auto& driftingSilences = b.scenarios()[5].simulation();
    EXPECT_EQ(b.scenarios()[5].scenario().name, "drifting_silences");
    EXPECT_EQ(driftingSilences.odometry.heading_drift_deg_per_min, 15.0);
    EXPECT_EQ(driftingSilences.detector.gap_every_s, 120.0);
    // The nominal detector otherwise (the drifting odometry's scenario has it).
    EXPECT_EQ(driftingSilences.detector.p_detect_near,
              b.scenarios()[1].simulation().detector.p_detect_near);
    // The filter without defences for real data, the shipped one without recovery, with
    // augmented MCL's trigger, the shipped one, and that with a heading drift state.
    ASSERT_EQ(all.variants().size(), 7u);
    EXPECT_EQ(all.variants()[0].name(), "semantic_basic");
    EXPECT_EQ(all.variants()[1].name(), "semantic_norecovery");
    EXPECT_EQ(all.variants()[2].name(), "semantic_amcl");
    EXPECT_EQ(all.variants()[3].name(), "semantic");
    EXPECT_FALSE(all.variants()[0].options.filter.recovery.enabled());
    EXPECT_FALSE(all.variants()[1].options.filter.recovery.enabled());
    EXPECT_EQ(all.variants()[2].options.filter.recovery.trigger, semloc::RecoveryTrigger::Amcl);
    EXPECT_TRUE(all.variants()[2].options.filter.recovery.enabled());
    EXPECT_EQ(all.variants()[3].options.filter.recovery.trigger, semloc::RecoveryTrigger::Evidence);
    EXPECT_EQ(all.variants()[4].name(), "semantic_nodrift");
    EXPECT_TRUE(all.variants()[3].options.filter.motion_model.headingDrift());
    EXPECT_EQ(all.variants()[3].options.filter.motion_model.heading_drift_std_deg_per_min, 0.0);
    EXPECT_EQ(all.variants()[3].options.filter.motion_model.heading_drift_walk_deg_per_min, 5.0);
    EXPECT_FALSE(all.variants()[4].options.filter.motion_model.headingDrift());
    EXPECT_FALSE(all.variants()[0].options.filter.motion_model.headingDrift());
    // The shipped filter with its injected particles in a challenger set, and without
    // re-seeding its particles while they are spread.
    expectRecoveryVariants(all.variants(), 3, 5, 6);
}

TEST(Benchmark, ShippedRecoveryIniKidnapsWithEachVariantsOwnRecovery)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/recovery.ini");
    ASSERT_EQ(b.scenarios().size(), 2u);
    EXPECT_EQ(b.scenarios()[0].scenario().name, "nominal");
    EXPECT_FALSE(b.scenarios()[0].simulation().kidnapping.enabled);
    EXPECT_EQ(b.scenarios()[1].scenario().name, "kidnapping");
    EXPECT_TRUE(b.scenarios()[1].simulation().kidnapping.enabled);
    for (const auto& sc : b.scenarios())
    {
        ASSERT_EQ(sc.variants().size(), 6u);
        // No scenario turns recovery on: semantic_norecovery runs without, semantic_amcl with
        // augmented MCL's trigger, semantic (shipped) with the evidence trigger, both with
        // injected particles at 3e-6 of a resampled one's weight; semantic_nodrift is semantic
        // without the heading drift state, semantic_challengers semantic with a challenger set,
        // semantic_no_reseed semantic not re-seeding while its particles are spread.
        EXPECT_EQ(sc.variants()[1].name(), "semantic_amcl");
        expectRecoveryVariants(sc.variants(), 2, 4, 5);
        EXPECT_EQ(sc.variants()[2].name(), "semantic");
        EXPECT_EQ(sc.variants()[3].name(), "semantic_nodrift");
        EXPECT_FALSE(sc.variants()[3].options.filter.motion_model.headingDrift());
        EXPECT_TRUE(sc.variants()[2].options.filter.motion_model.headingDrift());
        EXPECT_FALSE(sc.variants()[0].options.filter.recovery.enabled());
        EXPECT_EQ(sc.variants()[1].options.filter.recovery.trigger, semloc::RecoveryTrigger::Amcl);
        EXPECT_EQ(sc.variants()[2].options.filter.recovery.trigger,
                  semloc::RecoveryTrigger::Evidence);
        for (size_t v = 1; v < 3; v++)
        {
            EXPECT_TRUE(sc.variants()[v].options.filter.recovery.enabled());
            EXPECT_EQ(sc.variants()[v].options.filter.recovery.injected_weight, 3e-6);
        }
    }
}

TEST(Benchmark, ShippedKldIniComparesTheFixedCountWithKld)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/kld.ini");
    ASSERT_EQ(b.scenarios().size(), 7u);
    EXPECT_TRUE(b.scenarios().back().simulation().kidnapping.enabled);
    for (const auto& sc : b.scenarios())
    {
        ASSERT_EQ(sc.variants().size(), 2u);
        // particles = 0: each its own count, the KLD filter its own sample size.
        const auto& fixed = sc.variants()[0].options.filter;
        const auto& kld = sc.variants()[1].options.filter;
        EXPECT_EQ(fixed.particles_count, 10000);
        EXPECT_EQ(kld.particles_count, 10000);
        EXPECT_FALSE(fixed.pf.adaptiveSampleSize);
        EXPECT_TRUE(kld.pf.adaptiveSampleSize);
        EXPECT_TRUE(kld.kld_at_resampling);
        EXPECT_EQ(kld.kld.KLD_minSampleSize, 5000u);
        EXPECT_TRUE(kld.recovery.enabled());
    }
}

TEST(Benchmark, ShippedMisreadIniComparesTheGaussianRangeWithTheHeavyTailedOne)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/misread.ini");
    ASSERT_EQ(b.scenarios().size(), 5u);
    EXPECT_EQ(b.scenarios()[2].scenario().name, "misread_ranges");
    EXPECT_EQ(b.scenarios()[2].simulation().detector.p_range_outlier, 0.2);
    EXPECT_TRUE(b.scenarios()[1].simulation().kidnapping.enabled);
    for (const auto& sc : b.scenarios())
    {
        ASSERT_EQ(sc.variants().size(), 2u);
        std::vector<double> eps;
        for (const auto& v : sc.variants())
        {
            const auto sem = v.maps.map->mapByClass<semloc::CSemanticMap>();
            ASSERT_TRUE(sem) << v.name();
            eps.push_back(sem->likelihoodOptions.detector.p_range_outlier);
        }
        EXPECT_EQ(sc.variants()[0].name(), "semantic");
        EXPECT_EQ(sc.variants()[1].name(), "semantic_misread");
        EXPECT_EQ(eps, (std::vector<double>{0.0, 0.05}));
    }
}

TEST(Benchmark, ShippedPaperModelIniRunsThePaperLikelihoodEverywhere)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/paper_model.ini");
    ASSERT_EQ(b.scenarios().size(), 6u);
    for (const auto& sc : b.scenarios())
    {
        ASSERT_EQ(sc.variants().size(), 1u);
        EXPECT_EQ(sc.variants()[0].name(), "semantic_paper");
    }
    EXPECT_EQ(b.scenarios().back().simulation().detector.distractors, 4);
}

TEST(Benchmark, ShippedChangedWorldIniSimulatesInAChangedWorld)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/changed_world.ini");
    ASSERT_EQ(b.scenarios().size(), 8u);
    const auto& far = b.scenarios()[7].scenario();
    EXPECT_EQ(far.name, "all_1m");
    EXPECT_EQ(far.world_changes.shift_sigma_m, 1.0);
    EXPECT_EQ(far.world_changes.removed_share, 0.2);
    EXPECT_EQ(b.scenarios()[6].scenario().world_changes.shift_sigma_m, 1.0);
    EXPECT_EQ(b.scenarios()[6].scenario().world_changes.added, 0);
    EXPECT_EQ(b.scenarios()[0].scenario().name, "nominal");
    const auto& all = b.scenarios()[4].scenario();
    EXPECT_EQ(all.name, "all");
    EXPECT_EQ(all.world_changes.shift_sigma_m, 0.5);
    EXPECT_EQ(all.world_changes.removed_share, 0.2);
    EXPECT_EQ(all.world_changes.added, 5);
    EXPECT_EQ(b.scenarios()[1].scenario().world_changes.removed_share, 0.0);
    const semloc::World paper = semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    // The variants carry their map file's map, all of it: the exact one, and for
    // semantic_surveyed the surveyed one, whose objects carry how sure the map is of them.
    const auto& variants = b.scenarios()[4].variants();
    ASSERT_EQ(variants.size(), 6u);
    for (const auto& v : variants)
    {
        ASSERT_TRUE(v.maps.world.has_value());
        EXPECT_EQ(v.maps.world->objects.size(), paper.objects.size());
        const auto sem = v.maps.map->mapByClass<semloc::CSemanticMap>();
        ASSERT_TRUE(sem);
        const bool surveyed = v.name() == "semantic_surveyed";
        EXPECT_EQ(surveyed, &v == &variants[4]);
        for (const auto& o : sem->objects())
        {
            EXPECT_EQ(o.sigma_m, surveyed ? 0.5 : 0.0) << v.name();
            EXPECT_EQ(o.p_exist, surveyed ? 0.8 : 1.0) << v.name();
            EXPECT_EQ(o.classes.empty(), !surveyed || (o.label != "anchor" && o.label != "wreck"))
                << v.name() << " " << o.id;
        }
    }
    // The detector that confuses anchors and wrecks: the surveyed world simulated.
    const auto& classes = b.scenarios()[5];
    EXPECT_EQ(classes.scenario().name, "classes");
    const semloc::World world = semloc::World::FromFile(classes.simulation().simulation.world_file);
    ASSERT_EQ(world.objects.size(), paper.objects.size());
    for (size_t i = 0; i < world.objects.size(); i++)
    {
        // The surveyed map is the paper's world, object for object.
        EXPECT_EQ(world.objects[i].id, paper.objects[i].id);
        EXPECT_EQ(world.objects[i].label, paper.objects[i].label);
        EXPECT_EQ(world.objects[i].center.x, paper.objects[i].center.x);
        EXPECT_EQ(world.objects[i].center.y, paper.objects[i].center.y);
    }
}

TEST(Benchmark, ShippedMapDoubtsIniGivesEachVariantOneDoubtOfTheSurveyedMap)
{
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/map_doubts.ini");
    ASSERT_EQ(b.scenarios().size(), 6u);
    EXPECT_EQ(b.scenarios()[4].scenario().name, "all");
    const semloc::World surveyed =
        semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/paper_50x50_surveyed.yaml");
    const auto& variants = b.scenarios()[4].variants();
    ASSERT_EQ(variants.size(), 5u);
    // Which of the surveyed map's doubts each variant's map keeps: position, existence, class.
    const std::vector<std::tuple<std::string, bool, bool, bool>> doubts = {
        {"semantic", false, false, false},
        {"semantic_positions", true, false, false},
        {"semantic_existence", false, true, false},
        {"semantic_classes", false, false, true},
        {"semantic_surveyed", true, true, true}};
    for (size_t k = 0; k < variants.size(); k++)
    {
        const auto& [name, position, existence, cls] = doubts[k];
        const auto& v = variants[k];
        ASSERT_EQ(v.name(), name);
        const auto sem = v.maps.map->mapByClass<semloc::CSemanticMap>();
        ASSERT_TRUE(sem);
        ASSERT_EQ(sem->objects().size(), surveyed.objects.size()) << name;
        for (size_t i = 0; i < surveyed.objects.size(); i++)
        {
            const auto& o = sem->objects()[i];
            const auto& s = surveyed.objects[i];
            EXPECT_EQ(o.id, s.id) << name;
            EXPECT_EQ(o.label, s.label) << name;
            EXPECT_EQ(o.sigma_m, position ? s.sigma_m : 0.0) << name << " " << o.id;
            EXPECT_EQ(o.p_exist, existence ? s.p_exist : 1.0) << name << " " << o.id;
            EXPECT_EQ(o.classes.empty(), !cls || s.classes.empty()) << name << " " << o.id;
        }
    }
}

TEST(Benchmark, ScenarioSectionsOverlayTheVariantsOwn)
{
    // config/benchmark/sensitivity.ini: each scenario replaces one key of the variants' semantic
    // model, in memory (the shipped files stay as they are).
    const std::string before = semloc::test::readText(kConfig + "localize/semantic.ini");
    const auto b = semloc::Benchmark::FromConfigFile(kConfig + "benchmark/sensitivity.ini");
    ASSERT_EQ(b.scenarios().size(), 13u);
    auto model = [](const semloc::Benchmark& sc, size_t v)
    { return sc.variants()[v].maps.map->mapByClass<semloc::CSemanticMap>()->likelihoodOptions; };
    EXPECT_EQ(model(b.scenarios()[0], 0).detector.sigma_range_m, 0.5);  // nominal: the file's
    EXPECT_EQ(b.scenarios()[1].scenario().name, "sigma_range_m_half");
    for (size_t v = 0; v < 2; v++)
    {
        EXPECT_EQ(model(b.scenarios()[1], v).detector.sigma_range_m, 0.25) << v;
        EXPECT_EQ(model(b.scenarios()[1], v).detector.sigma_bearing_deg, 3.0) << v;
        EXPECT_EQ(model(b.scenarios()[8], v).probabilistic.p_detect_far, 0.2) << v;
    }
    // The rest of a variant is its own: semantic_basic runs without recovery, semantic with.
    EXPECT_FALSE(b.scenarios()[1].variants()[0].options.filter.recovery.enabled());
    EXPECT_TRUE(b.scenarios()[1].variants()[1].options.filter.recovery.enabled());
    EXPECT_EQ(semloc::test::readText(kConfig + "localize/semantic.ini"), before);

    // A key the variants do not know is an error naming it.
    const std::string scenario = std::string(SEMLOC_TEST_OUT) + "/bench_overlay.ini";
    std::ofstream(scenario)
        << "[Scenario]\nname = typo\n[MetricMap_semanticMap_00_likelihoodOpts]\nsigma_rnge_m = 1\n";
    const auto msg = errorOf(writeIni("bench_overlay_main.ini", "scenarios = " + scenario + "\n"));
    EXPECT_NE(msg.find("sigma_rnge_m"), std::string::npos) << msg;
}

TEST(Benchmark, PairedTableComparesEachVariantWithTheReferenceRunByRun)
{
    using R = semloc::Benchmark::TRunResult;
    auto result = [](int run, const std::string& variant, bool converged, double err)
    {
        R r;
        r.run = run;
        r.variant = variant;
        r.metrics.converged = converged;
        r.metrics.mean_err_after_conv_m = converged ? err : std::nan("");
        return r;
    };
    // "semantic" is the reference whatever its place. Runs 1-3 both converge (differences
    // -0.1, +0.2, -0.4: mean -0.1, standard error sqrt(0.09)/sqrt(3)); run 4 only "other",
    // run 5 only "semantic"; run 6 has no "semantic" result and is left out.
    const std::vector<R> runs = {
        result(1, "other", true, 0.9), result(1, "semantic", true, 1.0),
        result(2, "other", true, 1.2), result(2, "semantic", true, 1.0),
        result(3, "other", true, 0.6), result(3, "semantic", true, 1.0),
        result(4, "other", true, 0.5), result(4, "semantic", false, 0),
        result(5, "other", false, 0),  result(5, "semantic", true, 0.5),
        result(6, "other", true, 9.0),
    };
    const std::string t = semloc::Benchmark::pairedTable(runs, {"other", "semantic"});
    EXPECT_NE(t.find("| other | semantic | 3 | -0.1000 | 0.1732 | 2 | 1 | 1 |"), std::string::npos)
        << t;
    EXPECT_EQ(t.find("| semantic | semantic"), std::string::npos) << t;
    EXPECT_TRUE(semloc::Benchmark::pairedTable(runs, {"semantic"}).empty());
}

TEST(Benchmark, ResultsAndTablesShowTheConsistencyOfEveryRun)
{
    // results.csv has each run's median NEES, share inside, mean NEES of the well-conditioned
    // steps and their share; the report's tables show, over the runs that have them (a run
    // without ground truth has none), the median of the medians and the means of the others.
    using R = semloc::Benchmark::TRunResult;
    auto result = [](int run, const std::string& variant, double median, double inside,
                     double meanWc, double wc)
    {
        R r;
        r.run = run;
        r.variant = variant;
        r.metrics.nees_mean = 1e12;  // a degenerate step's: shown nowhere
        r.metrics.nees_median = median;
        r.metrics.nees_inside_share = inside;
        r.metrics.nees_mean_well_conditioned = meanWc;
        r.metrics.nees_well_conditioned_share = wc;
        return r;
    };
    const std::vector<R> runs = {
        result(1, "semantic", 2.0, 0.9, 3.5, 1.0), result(2, "semantic", 4.5, 0.96, 2.5, 0.8),
        result(3, "semantic", 1.0, 0.5, NAN, 0.0), result(4, "semantic", NAN, NAN, NAN, NAN),
        result(1, "other", 1234.5, 0.25, 5678, 0.5)};
    const std::string csv = semloc::detail::resultsCsv(runs);
    const std::string header = csv.substr(0, csv.find('\n'));
    const std::string tail =
        ",kidnap_step,recovery_steps,nees_median,nees_inside_share,nees_mean_well_conditioned,"
        "nees_well_conditioned_share,control,distance_to_convergence_m";
    EXPECT_EQ(header.substr(header.size() - tail.size()), tail) << header;
    EXPECT_EQ(csv.find("1e+12"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",,2,0.9,3.5,1,route,\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",,1,0.5,,0,route,\n"), std::string::npos) << "no well-conditioned step\n"
                                                                  << csv;
    EXPECT_NE(csv.find(",,,,,,route,\n"), std::string::npos) << "no ground truth: empty cells\n"
                                                             << csv;

    const std::string t = semloc::Benchmark::reportTable(runs, {"semantic", "other"});
    EXPECT_NE(t.find("| detector bound after conv. [m] | median NEES | NEES inside 95 % [%] | "
                     "mean NEES, well-conditioned steps | well-conditioned steps [%] | mean "
                     "var_xy [m²] |"),
              std::string::npos)
        << t;
    // semantic: median of (2, 4.5, 1) 2, inside (90 + 96 + 50) / 3 %, mean NEES (3.5 + 2.5)
    // / 2 over the runs with a well-conditioned step, their share (100 + 80 + 0) / 3 %.
    EXPECT_NE(t.find("| - | 2 | 79 | 3 | 60 |"), std::string::npos) << t;
    EXPECT_NE(t.find("| - | 1.23e+03 | 25 | 5.68e+03 | 50 |"), std::string::npos) << t;
    EXPECT_EQ(t.find("1e+12"), std::string::npos) << t;

    semloc::Benchmark::TScenarioSummary s;
    s.scenario = "all";
    s.variant = "semantic";
    s.runs = 3;
    s.mean_err_after_conv_m = 0.25;
    s.nees_median = 2.5;
    s.nees_inside_share = 0.93;
    s.nees_mean_well_conditioned = 3.25;
    s.nees_well_conditioned_share = 0.875;
    const std::string sc = semloc::Benchmark::scenariosTable({s});
    EXPECT_NE(sc.find("| mean err after conv. [m] | median NEES | NEES inside 95 % [%] | mean "
                      "NEES, well-conditioned steps | well-conditioned steps [%] |"),
              std::string::npos)
        << sc;
    EXPECT_NE(sc.find("| 0.250 | 2.5 | 93 | 3.25 | 88 |"), std::string::npos) << sc;
    const std::string scCsv = semloc::detail::scenariosCsv({s});
    EXPECT_NE(scCsv.find(",nees_median,nees_inside_share,nees_mean_well_conditioned,"
                         "nees_well_conditioned_share\n"),
              std::string::npos)
        << scCsv;
    EXPECT_NE(scCsv.find(",2.5,0.93,3.25,0.875\n"), std::string::npos) << scCsv;
}

TEST(Benchmark, ASweepMakesAVariantOfEachValue)
{
    const auto b = semloc::Benchmark::FromConfigFile(writeSweepIni(
        "bench_sweep.ini", "MetricMap_semanticMap_00_likelihoodOpts.sigma_range_m: 0.25, 1.5"));
    ASSERT_EQ(b.variants().size(), 2u);
    EXPECT_EQ(b.variants()[0].name(), "semantic@sigma_range_m=0.25");
    EXPECT_EQ(b.variants()[1].name(), "semantic@sigma_range_m=1.5");
    const auto sigma = [&](size_t k)
    {
        return b.variants()[k]
            .maps.map->mapByClass<semloc::CSemanticMap>()
            ->likelihoodOptions.detector.sigma_range_m;
    };
    EXPECT_EQ(sigma(0), 0.25);
    EXPECT_EQ(sigma(1), 1.5);
    // A swept filter key stays swept under same_filter (each value its own reference).
    const auto f = semloc::Benchmark::FromConfigFile(
        writeSweepIni("bench_sweep_pf.ini", "PF_options.powFactor: 0.5, 1\nsame_filter = true"));
    ASSERT_EQ(f.variants().size(), 2u);
    EXPECT_EQ(f.variants()[0].options.filter.pf.powFactor, 0.5);
    EXPECT_EQ(f.variants()[1].options.filter.pf.powFactor, 1.0);
}

TEST(Benchmark, ABadSweepIsAnErrorNamingIt)
{
    EXPECT_NE(errorOf(writeSweepIni("bench_sweep_bad1.ini", "sigma_range_m: 0.25"))
                  .find("[Benchmark] sweep"),
              std::string::npos);
    EXPECT_NE(errorOf(writeSweepIni("bench_sweep_bad2.ini", "PF_options.powFactor 0.5"))
                  .find("not a section and key followed by values"),
              std::string::npos);
    EXPECT_NE(errorOf(writeSweepIni("bench_sweep_bad3.ini", "PF_options.powFactor: 0.5, 0.5"))
                  .find("the value '0.5' appears twice"),
              std::string::npos);
    EXPECT_NE(
        errorOf(writeSweepIni("bench_sweep_bad4.ini", "PF_options.powFactr: 0.5")).find("powFactr"),
        std::string::npos);
    // A key the variant does not have is the sweep line's error, not its file's.
    const std::string notRead = errorOf(writeSweepIni(
        "bench_sweep_bad5.ini", "MetricMap_semanticMap_01_likelihoodOpts.sigma_range_m: 1, 2"));
    EXPECT_EQ(notRead.rfind("ini [Benchmark] sweep: 'MetricMap_semanticMap_01_likelihoodOpts."
                            "sigma_range_m: 1, 2': the value '1' (variant '",
                            0),
              0u)
        << notRead;
    EXPECT_NE(notRead.find("semanticMap_count = 1"), std::string::npos) << notRead;
}

TEST(Benchmark, ASweepOfMapsIsOneWithoutMapFromWorld)
{
    const std::string maps = kConfig + "../maps/";
    const std::string line = "LocalizationExperiment.map_file: " + maps + "paper_50x50.yaml, " +
                             maps + "paper_50x50_surveyed.yaml";
    EXPECT_NE(errorOf(writeSweepIni("bench_sweep_maps_world.ini", line))
                  .find("map_from_world = true: every variant localizes against the simulated"),
              std::string::npos);
    const auto b = semloc::Benchmark::FromConfigFile(
        writeSweepIni("bench_sweep_maps.ini", line + "\nmap_from_world = false"));
    ASSERT_EQ(b.variants().size(), 2u);
    EXPECT_EQ(b.variants()[0].options.map_file, maps + "paper_50x50.yaml");
    EXPECT_EQ(b.variants()[1].options.map_file, maps + "paper_50x50_surveyed.yaml");
}

TEST(Benchmark, AWideSweepDrawsNineOfItsSeriesAndTablesEveryOne)
{
    // 12 values: the figures draw 9 (the first, the last and 7 evenly between), world_paths.png
    // in 9 panels; curves.csv, results.csv and the tables have all 12, and report.md says so.
    std::string values;
    for (int k = 0; k < 12; k++)
    {
        values += (k ? ", " : "") + std::to_string(0.3 + 0.1 * k).substr(0, 3);
    }
    const std::string ini = writeSweepIni(
        "bench_wide_sweep.ini", "MetricMap_semanticMap_00_likelihoodOpts.sigma_range_m: " + values +
                                    "\nruns = 1\nmax_steps = 4\nparticles = 50\njobs = 1");
    const std::string out = std::string(SEMLOC_TEST_OUT) + "/bench_wide_sweep_out";
    std::filesystem::remove_all(out);
    const auto res = semloc::Benchmark::FromConfigFile(ini, out).run();
    ASSERT_EQ(res.runs.size(), 12u);
    const std::string gp = semloc::test::readText(out + "/world_paths.gp");
    EXPECT_NE(gp.find("set multiplot layout 3,3"), std::string::npos) << gp;
    size_t panels = 0;
    for (size_t at = 0; (at = gp.find("\nplot ", at)) != std::string::npos; at++)
    {
        panels++;
    }
    EXPECT_EQ(panels, 9u);
    for (const char* shown : {"sigma_range_m=0.3,", "sigma_range_m=0.4,", "sigma_range_m=1.4,"})
    {
        EXPECT_NE(gp.find(shown), std::string::npos) << shown << " (first, second, last)";
    }
    EXPECT_EQ(gp.find("sigma_range_m=0.5,"), std::string::npos) << "not among the 9";
    EXPECT_FALSE(std::filesystem::exists(out + "/world_paths_10.dat"));
    const std::string figures = semloc::test::readText(out + "/figures.gp");
    EXPECT_EQ(figures.find("sigma_range_m=0.5'"), std::string::npos) << figures;
    EXPECT_NE(figures.find("sigma_range_m=1.4'"), std::string::npos) << figures;
    const std::string curves = semloc::test::readText(out + "/curves.csv");
    EXPECT_NE(curves.find("semantic@sigma_range_m=0.5,"), std::string::npos);
    const std::string report = semloc::test::readText(out + "/report.md");
    EXPECT_NE(report.find("| semantic@sigma_range_m=0.5 |"), std::string::npos);
    EXPECT_NE(report.find("9 of the 12 series, evenly spread over them"), std::string::npos)
        << report;
}

TEST(Benchmark, TheWorkAfterTheRunsIsReportedStageByStage)
{
    // What the progress bar does not show: after the last run, a line per stage as it starts.
    std::vector<std::string> stages;
    semloc::Benchmark::SetStageReporter([&](const std::string& s) { stages.push_back(s); });
    const std::string out = std::string(SEMLOC_TEST_OUT) + "/bench_stages_out";
    std::filesystem::remove_all(out);
    const auto b = semloc::Benchmark::FromConfigFile(
        writeIni("bench_stages.ini", "runs = 2\nmax_steps = 4\nparticles = 50\njobs = 1\n"), out);
    size_t runsDone = 0, stagesAtLastRun = 99;
    b.run(
        [&](size_t done, size_t total)
        {
            runsDone = done;
            stagesAtLastRun = done == total ? stages.size() : stagesAtLastRun;
        });
    semloc::Benchmark::SetStageReporter({});
    EXPECT_EQ(runsDone, 2u);
    EXPECT_EQ(stagesAtLastRun, 0u) << "the stages come after the runs";
    const std::vector<std::string> expected{"reading the results of 2 runs x 2 series",
                                            "writing results.csv and curves.csv",
                                            "drawing fig_variance.png and fig_error.png",
                                            "drawing world_paths.png", "writing report.md"};
    EXPECT_EQ(stages, expected);
    EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
}

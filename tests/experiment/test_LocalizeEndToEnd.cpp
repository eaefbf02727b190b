/* semloc tests — semloc-localize end to end (LocalizationExperiment, the shipped configs) on
 * the paper's scenario simulated by semloc::Simulator: global localization of the semantic
 * and geometric variants, byte-identical outputs on 1, 2 and 3 threads (KLD on and off),
 * recovery from kidnapping, re-initialization when every weight vanishes,
 * observations-only rawlogs, and clear errors with no output for bad configurations. */
#include <gtest/gtest.h>
#include <mrpt/containers/yaml.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/simulator/Simulator.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include <unistd.h>

#include "TestHelpers.h"
#include "experiment/LocalizeRun.h"

using semloc::test::errorOf;
using semloc::test::interruptAt;

namespace fs = std::filesystem;
using semloc::LocalizationExperiment;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "localize";
const std::string kConfig = SEMLOC_SOURCE_DIR "/config/";

using semloc::test::readText;
using semloc::test::stepsWithoutTiming;
using semloc::test::withKeys;

/** Every file of an output directory, the timing and thread-count values removed: the
 *  update_us column of steps.csv, the timing and `threads` lines of summary.yaml and the
 *  `threads` line of config.ini (the thread count is an input). */
std::map<std::string, std::string> outputsWithoutTiming(const fs::path& dir)
{
    const std::vector<std::string> dropped = {"threads", "wall_time_s", "total_update_s",
                                              "mean_update_us_per_particle"};
    std::map<std::string, std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
    {
        const std::string name = e.path().filename().string();
        if (name == "steps.csv")
        {
            out[name] = stepsWithoutTiming(dir);
            continue;
        }
        std::istringstream in(readText(e.path()));
        std::string line, kept;
        while (std::getline(in, line))
        {
            const std::string key = line.substr(0, line.find_first_of(" :="));
            if (std::find(dropped.begin(), dropped.end(), key) == dropped.end())
            {
                kept += line + "\n";
            }
        }
        out[name] = kept;
    }
    return out;
}

/** `config` (a file of config/localize/, its base resolved) with `key = value` lines replaced (the
 * key must be there) and map_file made absolute (the paper world unless given), written to the test
 * output directory.
 */
std::string patchedConfig(const std::string& config,
                          std::vector<std::pair<std::string, std::string>> keys,
                          const std::string& name)
{
    if (std::none_of(keys.begin(), keys.end(), [](const auto& k) { return k.first == "map_file"; }))
    {
        keys.emplace_back("map_file", SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml");
    }
    const std::string out =
        withKeys(semloc::config::readIniText(kConfig + "localize/" + config), config, keys);
    const auto path = kOut / (name + ".ini");
    std::ofstream(path) << out;
    return path.string();
}

/** Runs `ini` on `rawlog` into kOut/<name>. */
LocalizationExperiment::TResult localize(const std::string& ini, const std::string& rawlog,
                                         const std::string& name, int particles, int threads = 2)
{
    return semloc::test::localizeRun(ini, rawlog, (kOut / name).string(), particles, threads);
}

class LocalizeEndToEnd : public ::testing::Test
{
protected:
    /** The paper dataset of config/simulate/simulate.ini (431 steps), and its ground truth. */
    static std::string rawlog;

    static void SetUpTestSuite()
    {
        fs::create_directories(kOut);
        // ctest runs every test of this suite as its own process, in parallel: each simulates
        // into its own file (a shared one was overwritten while another process read it).
        rawlog = (kOut / ("paper_" + std::to_string(::getpid()) + ".rawlog")).string();
        const semloc::Simulator sim(
            semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini"));
        sim.writeDataset(sim.run(), rawlog);
    }
};
std::string LocalizeEndToEnd::rawlog;
}  // namespace

TEST_F(LocalizeEndToEnd, SemanticConvergesFromUniformStartAndWritesTheContract)
{
    const auto res = localize(kConfig + "localize/semantic.ini", rawlog, "semantic", 8000);
    const auto& m = res.metrics;
    EXPECT_EQ(res.variant, "semantic");
    EXPECT_EQ(m.steps, 431u);
    EXPECT_EQ(m.steps_with_ground_truth, 431u);
    EXPECT_TRUE(m.converged);
    EXPECT_LT(m.final_err_m, 0.5);
    EXPECT_LT(m.mean_err_after_conv_m, 0.5);
    EXPECT_EQ(res.likelihood.detections_invalid, 0u);

    const fs::path dir = kOut / "semantic";
    const std::string csv = readText(dir / "steps.csv");
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "step,t,gt_x,gt_y,gt_phi,est_x,est_y,est_phi,err_xy,err_phi,var_xy,ess,n_particles,"
              "update_us,nees,var_x,var_y,var_phi,cov_xy,cov_xphi,cov_yphi");
    const auto y = mrpt::containers::yaml::FromFile((dir / "summary.yaml").string());
    for (const char* key : {"variant",
                            "particles",
                            "seed",
                            "steps",
                            "converged",
                            "convergence_step",
                            "convergence_time_s",
                            "mean_err_after_conv_m",
                            "rmse_m",
                            "final_err_m",
                            "total_update_s",
                            "mean_update_us_per_particle",
                            "threads",
                            "observations_skipped",
                            "detections_invalid",
                            "reinitializations",
                            "nees_median",
                            "nees_inside_share",
                            "nees_mean_well_conditioned",
                            "nees_well_conditioned_share",
                            "lost_after_convergence_steps",
                            "lost_after_convergence_s",
                            "lost_episodes",
                            "first_lost_after_convergence_s",
                            "longest_lost_s"})
    {
        EXPECT_TRUE(y.has(key)) << key;
    }
    EXPECT_FALSE(y.has("nees_mean")) << "a mean of every step: one degenerate step sets it";
    EXPECT_NEAR(y["nees_median"].as<double>(), m.nees_median, 1e-9 * m.nees_median);
    EXPECT_NEAR(y["nees_mean_well_conditioned"].as<double>(), m.nees_mean_well_conditioned,
                1e-9 * m.nees_mean_well_conditioned);
    EXPECT_GT(m.nees_well_conditioned_share, 0.5);
    EXPECT_LE(m.nees_well_conditioned_share, 1.0);
    EXPECT_GT(m.nees_inside_share, 0.0);
    EXPECT_LE(m.nees_inside_share, 1.0);
    EXPECT_EQ(y["lost_episodes"].as<int>(), static_cast<int>(m.lost_episodes));
    EXPECT_EQ(y["variant"].as<std::string>(), "semantic");
    EXPECT_EQ(y["particles"].as<int>(), 8000);
    EXPECT_EQ(y["threads"].as<int>(), 2);
    EXPECT_TRUE(y["converged"].as<bool>());
    EXPECT_NEAR(y["final_err_m"].as<double>(), m.final_err_m, 1e-12);

    // config.ini is the effective configuration: rerun from it, the same steps.
    const std::string eff = readText(dir / "config.ini");
    EXPECT_NE(eff.find("particles_count"), std::string::npos);
    EXPECT_NE(eff.find("p_confusion"), std::string::npos) << "defaults written out";
    LocalizationExperiment::TOverrides ov;
    ov.logOutput_dir = (kOut / "semantic_rerun").string();
    fs::copy_file(dir / "config.ini", kOut / "semantic_effective.ini",
                  fs::copy_options::overwrite_existing);
    LocalizationExperiment::FromConfigFile((kOut / "semantic_effective.ini").string(), ov).run();
    EXPECT_EQ(stepsWithoutTiming(dir), stepsWithoutTiming(kOut / "semantic_rerun"));
}

TEST_F(LocalizeEndToEnd, StartSeededByTheFirstDetectionsConvergesAtOnceWhateverTheThreads)
{
    // semantic.ini's start (init_PDF_mode = 3): 80 % of 2000 particles drawn from the first
    // detections; the uniform start of the same filter converges tens of steps later. Neither
    // re-seeded while spread (lost_var_xy_m2 = 0): the start alone.
    const std::string ini =
        patchedConfig("semantic.ini", {{"lost_var_xy_m2", "0"}}, "semantic_seeded");
    const auto one = localize(ini, rawlog, "seeded_1", 2000, 1);
    const auto two = localize(ini, rawlog, "seeded_2", 2000, 2);
    EXPECT_NEAR(static_cast<double>(one.initialized_from_detections), 1600.0, 60.0);
    EXPECT_TRUE(one.metrics.converged);
    EXPECT_LT(one.metrics.convergence_step, 20);
    EXPECT_LT(one.metrics.mean_err_after_conv_m, 0.25);
    EXPECT_EQ(stepsWithoutTiming(kOut / "seeded_1"), stepsWithoutTiming(kOut / "seeded_2"));
    EXPECT_EQ(two.initialized_from_detections, one.initialized_from_detections);
    const auto uniform =
        localize(patchedConfig("semantic.ini", {{"init_PDF_mode", "0"}, {"lost_var_xy_m2", "0"}},
                               "semantic_uniform"),
                 rawlog, "uniform_2000", 2000, 1);
    EXPECT_EQ(uniform.initialized_from_detections, 0u);
    EXPECT_GT(uniform.metrics.convergence_step, one.metrics.convergence_step + 20);
    EXPECT_NE(readText(kOut / "seeded_1" / "summary.yaml").find("initialized_from_detections: "),
              std::string::npos);
}

TEST_F(LocalizeEndToEnd, TemperedLikelihoodsLeaveTheEvidenceTriggerAsItWas)
{
    // A tempered likelihood (powFactor 0.05) carries a twentieth of each frame's evidence; the
    // evidence trigger weighs it on the untempered scale, so a tracked vehicle does not look
    // lost (on the tempered scale every frame fell short of the 2-nat margin). The trigger
    // alone: no re-seeding while spread (a cloud tempered this much stays above 10 m^2).
    const auto full =
        localize(patchedConfig("semantic.ini", {{"lost_var_xy_m2", "0"}}, "semantic_pow1"), rawlog,
                 "tempered_1", 2000, 1);
    const auto tempered =
        localize(patchedConfig("semantic.ini", {{"powFactor", "0.05"}, {"lost_var_xy_m2", "0"}},
                               "semantic_pow005"),
                 rawlog, "tempered_005", 2000, 1);
    ASSERT_TRUE(full.metrics.converged);
    ASSERT_TRUE(tempered.metrics.converged);
    EXPECT_LT(tempered.metrics.mean_err_after_conv_m, 0.3);
    std::cout << "injection steps: " << full.recovery.injection_steps << " at powFactor 1, "
              << tempered.recovery.injection_steps << " at 0.05, of "
              << tempered.metrics.steps_with_ground_truth << " steps\n";
    EXPECT_LE(tempered.recovery.injection_steps, full.recovery.injection_steps + 10);
    EXPECT_LT(tempered.recovery.injection_steps, tempered.metrics.steps_with_ground_truth / 10);
}

TEST_F(LocalizeEndToEnd, GeometricConvergesFromUniformStart)
{
    const auto res = localize(kConfig + "localize/geometric.ini", rawlog, "geometric", 6000);
    EXPECT_EQ(res.variant, "geometric");
    EXPECT_TRUE(res.metrics.converged);
    EXPECT_LT(res.metrics.final_err_m, 0.5);
    EXPECT_LT(res.metrics.mean_err_after_conv_m, 0.5);
}

TEST_F(LocalizeEndToEnd, OutputsAreByteIdenticalWhateverTheThreadCount)
{
    // Same inputs and seed: every output file the same byte for byte, except the timing
    // (update_us; wall_time_s, total_update_s, mean_update_us_per_particle) and the thread
    // count itself (the `threads` key of summary.yaml and config.ini). KLD on and off (MRPT's
    // and at the resampling steps), a map of uncertain objects, misread ranges, the marginal
    // association.
    const std::vector<std::pair<std::string, std::string>> runs = {
        {"semantic", "semantic.ini"},
        {"semantic_kld",
         patchedConfig("semantic_nodrift.ini",  // MRPT's KLD carries no drift rates
                       {{"adaptiveSampleSize", "1"}, {"resamplingMethod", "0"}}, "semantic_kld")},
        {"geometric_kld",
         patchedConfig("geometric.ini", {{"adaptiveSampleSize", "1"}, {"resamplingMethod", "0"}},
                       "geometric_kld")},
        {"grid_lf", "grid_lf.ini"},
        {"fused", "fused.ini"},
        {"semantic_surveyed", "semantic_surveyed.ini"},
        {"semantic_marginal", "semantic_marginal.ini"},
        {"semantic_misread", "semantic_misread.ini"},
        {"semantic_kld_at_resampling", "semantic_kld.ini"},
        {"semantic_drift", patchedConfig("semantic.ini",
                                         {{"heading_drift_std_deg_per_min", "15"},
                                          {"heading_drift_walk_deg_per_min", "1"}},
                                         "semantic_drift_threads")}};
    for (const auto& [name, ini] : runs)
    {
        const std::string path =
            ini.find('/') == std::string::npos ? kConfig + "localize/" + ini : ini;
        std::map<std::string, std::string> reference;
        for (int threads : {1, 2, 3})
        {
            // One output directory for all: logOutput_dir is in config.ini.
            const std::string dir = name + "_threads";
            const auto res = localize(path, rawlog, dir, 1000, threads);
            ASSERT_EQ(res.threads, static_cast<size_t>(threads));
            const auto files = outputsWithoutTiming(kOut / dir);
            EXPECT_EQ(files.size(), 4u) << "steps.csv, summary.yaml, config.ini, the marker";
            EXPECT_TRUE(files.count(semloc::kOutputMarker));
            if (threads == 1)
            {
                reference = files;
                continue;
            }
            ASSERT_EQ(files.size(), reference.size()) << name;
            for (const auto& [file, text] : files)
            {
                ASSERT_TRUE(reference.count(file)) << name << ": " << file;
                EXPECT_TRUE(text == reference[file])
                    << name << ": " << file << " differs between 1 and " << threads << " threads";
            }
        }
    }
}

TEST_F(LocalizeEndToEnd, KidnappedVehicleIsRelocalizedWithRecovery)
{
    auto so = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    so.kidnapping.enabled = true;  // at step 200, to (25, 25, 0)
    const semloc::Simulator sim(so);
    const std::string kidnapped = (kOut / "kidnapped.rawlog").string();
    sim.writeDataset(sim.run(), kidnapped);

    // semantic.ini as shipped (recovery on), with seed 2: relocalized within 100 steps.
    const auto ini = patchedConfig("semantic.ini", {{"seed", "2"}}, "semantic_kidnapped");
    const auto res = localize(ini, kidnapped, "kidnapped", 10000);
    const size_t kidnap = static_cast<size_t>(so.kidnapping.step);
    ASSERT_GT(res.records.size(), kidnap + 100);
    EXPECT_LT(res.records[kidnap - 1].errXY(), 0.5) << "localized before the kidnapping";
    EXPECT_GT(res.records[kidnap].errXY(), 5) << "lost right after it";
    EXPECT_GT(res.recovery.injected_particles, 0u);
    for (size_t k = kidnap + 100; k < res.records.size(); k++)
    {
        ASSERT_LT(res.records[k].errXY(), 1.0) << "step " << k;
    }
    EXPECT_LT(res.metrics.final_err_m, 0.5);
}

TEST(LocalizeHeadingDrift, TheDriftStateLearnsTheOdometrysDriftAndKeepsTheTrack)
{
    // The paper scenario with odometry whose heading gains 15 deg a minute (unknown to the
    // rawlog's Gaussian) and a detector silent for 60-120 s every two minutes: with the drift
    // state the filter's drift rate ends near 15 deg/min and its error after convergence is
    // below the same filter's without it (which reports 0).
    fs::create_directories(kOut);
    auto so = semloc::TSimulatorOptions::FromConfigFile(kConfig + "simulate/simulate.ini");
    so.odometry.heading_drift_deg_per_min = 15;
    so.detector.gap_every_s = 120;
    so.detector.gap_min_s = 60;
    so.detector.gap_max_s = 120;
    const std::string rawlog = (kOut / "drift15.rawlog").string();
    const semloc::Simulator sim(so);
    sim.writeDataset(sim.run(), rawlog);
    const auto off =
        localize(kConfig + "localize/semantic_nodrift.ini", rawlog, "drift_off", 2000, 1);
    const auto on = localize(patchedConfig("semantic.ini",
                                           {{"heading_drift_std_deg_per_min", "15"},
                                            {"heading_drift_walk_deg_per_min", "1"}},
                                           "semantic_drift"),
                             rawlog, "drift_on", 2000, 1);
    ASSERT_TRUE(off.metrics.converged);
    ASSERT_TRUE(on.metrics.converged);
    EXPECT_EQ(off.heading_drift_deg_per_min, 0);
    EXPECT_GT(on.heading_drift_deg_per_min, 10);
    EXPECT_LT(on.heading_drift_deg_per_min, 20);
    EXPECT_LT(on.metrics.mean_err_after_conv_m, off.metrics.mean_err_after_conv_m);
    EXPECT_NE(readText(kOut / "drift_on" / "summary.yaml").find("heading_drift_deg_per_min: "),
              std::string::npos);
}

TEST_F(LocalizeEndToEnd, EveryWeightVanishingReinitializesAndSaysSo)
{
    // The paper dataset localized in an 8 x 8 m world: the vehicle's 50 m legs carry every
    // hypothesis out of the free space, so every weight becomes zero, again and again.
    const auto tiny = kOut / "tiny_world.yaml";
    std::ofstream(tiny) << "name: tiny\nbounds: {x_min: 0, x_max: 8, y_min: 0, y_max: 8}\n"
                           "objects:\n  - {id: 1, label: wellhead, shape: box, center: [4, 4], "
                           "size: [1, 1]}\n";
    for (const bool kld : {false, true})
    {
        const std::string name = kld ? "depleted_kld" : "depleted";
        std::vector<std::pair<std::string, std::string>> keys = {{"map_file", tiny.string()}};
        if (kld)
        {
            keys.insert(keys.end(), {{"adaptiveSampleSize", "1"},
                                     {"resamplingMethod", "0"},
                                     {"heading_drift_walk_deg_per_min", "0"}});
        }
        const auto ini = patchedConfig("semantic.ini", keys, name);
        testing::internal::CaptureStdout();
        testing::internal::CaptureStderr();
        const auto res = localize(ini, rawlog, name, 2000);
        const std::string err = testing::internal::GetCapturedStderr();
        const std::string out = testing::internal::GetCapturedStdout();

        EXPECT_GT(res.recovery.reinitializations, 5u) << name;
        EXPECT_NE(err.find("[warning|CParallelMonteCarloLocalization2D] every particle weight "
                           "is zero"),
                  std::string::npos)
            << name << ": a warning on stderr; got: " << err.substr(0, 300);
        EXPECT_EQ(out, "") << name << ": warnings go to stderr, not stdout";
        EXPECT_NE(res.summaryParagraph().find("Re-initialized"), std::string::npos) << name;
        const auto y = mrpt::containers::yaml::FromFile((kOut / name / "summary.yaml").string());
        EXPECT_EQ(y["reinitializations"].as<size_t>(), res.recovery.reinitializations) << name;

        ASSERT_EQ(res.records.size(), 431u) << name;
        for (const auto& r : res.records)
        {
            ASSERT_GT(r.n_particles, 0u) << name << " step " << r.step;
            ASSERT_TRUE(std::isfinite(r.est.x) && std::isfinite(r.est.y) &&
                        std::isfinite(r.est.phi) && std::isfinite(r.var_xy) && std::isfinite(r.ess))
                << name << " step " << r.step;
            ASSERT_TRUE(!r.gt || std::isfinite(r.nees())) << name << " step " << r.step;
        }
        const std::string csv = readText(kOut / name / "steps.csv");
        for (const char* bad : {"nan", "inf"})
        {
            EXPECT_EQ(csv.find(bad), std::string::npos) << name << ": steps.csv holds " << bad;
        }
        std::istringstream rows(csv);
        std::string row;
        std::getline(rows, row);  // header
        size_t n = 0;
        while (std::getline(rows, row))
        {
            std::vector<std::string> cols;
            std::stringstream ss(row);
            for (std::string c; std::getline(ss, c, ',');)
            {
                cols.push_back(c);
            }
            ASSERT_EQ(cols.size(), 21u) << row;
            EXPECT_GT(std::stoul(cols[12]), 0u) << "n_particles of " << row;
            n++;
        }
        EXPECT_EQ(n, 431u);
    }
}

TEST_F(LocalizeEndToEnd, MoreThreadsThanTheMachineHasIsAWarning)
{
    const auto ini = patchedConfig("semantic.ini", {}, "threads_warning");
    LocalizationExperiment::TOverrides ov;
    ov.rawlog_file = rawlog;
    ov.logOutput_dir = (kOut / "threads_warning").string();
    const size_t cores = std::thread::hardware_concurrency();
    ASSERT_GT(cores, 0u);
    ov.threads = static_cast<int>(cores) + 1;
    const auto warnings = LocalizationExperiment::FromConfigFile(ini, ov).warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], mrpt::format("--threads %zu exceeds the %zu hardware threads of this "
                                        "machine: the run is slower, not faster",
                                        cores + 1, cores));
    for (const int threads : {0, static_cast<int>(cores)})
    {
        ov.threads = threads;
        EXPECT_TRUE(LocalizationExperiment::FromConfigFile(ini, ov).warnings().empty())
            << "threads " << threads;
    }
}

TEST_F(LocalizeEndToEnd, ObservationsOnlyRawlogWorks)
{
    // The same dataset as odometry readings plus bare observations (pf-localization's
    // observations-only format): odometry = sum of the actions' mean increments.
    mrpt::obs::CRawlog in, out;
    ASSERT_TRUE(in.loadFromRawLogFile(rawlog));
    mrpt::poses::CPose2D odo(10, 10, 0.5);
    for (size_t i = 0; i + 1 < in.size(); i += 2)
    {
        odo = odo + in.getAsAction(i)->getBestMovementEstimation()->poseChange->getMeanVal();
        const auto sf = in.getAsObservations(i + 1);
        auto reading = std::make_shared<mrpt::obs::CObservationOdometry>();
        reading->odometry = odo;
        reading->timestamp = sf->getObservationByIndex(0)->timestamp;
        out.insert(reading);
        for (const auto& o : *sf)
        {
            out.insert(o);
        }
    }
    const std::string obsOnly = (kOut / "obs_only.rawlog").string();
    ASSERT_TRUE(out.saveToRawLogFile(obsOnly));
    fs::copy_file(semloc::GroundTruthFile::PathFor(rawlog),
                  semloc::GroundTruthFile::PathFor(obsOnly), fs::copy_options::overwrite_existing);

    const auto res = localize(kConfig + "localize/semantic.ini", obsOnly, "obs_only", 8000);
    EXPECT_EQ(res.rawlogFormat, "observations-only");
    EXPECT_EQ(res.metrics.steps, 431u) << "one step per timestamp: sonar + detections together";
    EXPECT_TRUE(res.metrics.converged);
    EXPECT_LT(res.metrics.final_err_m, 0.5);

    // rawlog_offset skips steps (pf-localization's meaning) in both formats; a Gaussian start
    // at the true pose of the first step run keeps the filter on track only if that step's
    // motion is zero and the next ones are the increments since it.
    const auto truth = semloc::GroundTruth::FromFile(semloc::GroundTruthFile::PathFor(rawlog));
    const auto& first = truth.rows()[100];
    const auto ini =
        patchedConfig("semantic.ini",
                      {{"rawlog_offset", "100"},
                       {"init_PDF_mode", "2"},
                       {"init_PDF_mean_x", std::to_string(first.x)},
                       {"init_PDF_mean_y", std::to_string(first.y)},
                       {"init_PDF_mean_yaw_deg", std::to_string(first.phi * 180 / M_PI)},
                       {"init_PDF_std_xy", "0.2"},
                       {"init_PDF_std_yaw_deg", "3"}},
                      "semantic_offset");
    for (const auto& file : {rawlog, obsOnly})
    {
        const auto r = localize(ini, file, "offset", 1000);
        ASSERT_EQ(r.metrics.steps, 331u) << file;
        EXPECT_DOUBLE_EQ(r.records.front().t, first.t) << file;
        EXPECT_LT(r.records.front().errXY(), 0.5) << file;
        EXPECT_LT(r.metrics.rmse_m, 0.5) << file;
    }
}

TEST_F(LocalizeEndToEnd, InterruptWritesNoOutputAndKeepsAPreviousOne)
{
    // Ctrl-C in semloc-localize (a request, as its handler makes): Interrupted at the next
    // rawlog entry, or before the staged outputs replace a previous run's; nothing of the
    // interrupted run is left, a previous output directory stays as it was.
    const std::string ini = kConfig + "localize/semantic.ini";
    const auto first = localize(ini, rawlog, "interrupted_run", 300, 1);
    const std::string steps = readText(first.outputDir + "/steps.csv");
    size_t seen = 0;
    LocalizationExperiment::TOverrides ov;
    ov.rawlog_file = rawlog;
    ov.logOutput_dir = (kOut / "interrupted_run").string();
    ov.particles_count = 300;
    ov.threads = 1;
    const auto experiment = LocalizationExperiment::FromConfigFile(ini, ov);
    EXPECT_THROW(experiment.run(interruptAt(20, seen)), semloc::Interrupted);
    semloc::clearInterrupt();
    EXPECT_EQ(seen, 20u) << "the run went on after the request";
    EXPECT_EQ(readText(first.outputDir + "/steps.csv"), steps);
    for (const auto& e : fs::directory_iterator(kOut))
    {
        EXPECT_EQ(e.path().filename().string().rfind(".interrupted_run", 0), std::string::npos)
            << e.path();
    }
}

TEST_F(LocalizeEndToEnd, BadConfigurationsFailClearlyWithoutOutput)
{
    const std::string outName = "must_not_exist";
    const fs::path outDir = kOut / outName;
    fs::remove_all(outDir);
    auto failWith = [&](const std::string& text)
    {
        const fs::path ini = kOut / "bad.ini";
        std::ofstream(ini) << text;
        LocalizationExperiment::TOverrides ov;
        ov.logOutput_dir = outDir.string();
        return errorOf([&] { LocalizationExperiment::FromConfigFile(ini.string(), ov).run(); });
    };
    const std::string good = "[LocalizationExperiment]\nrawlog_file = " + rawlog +
                             "\nmap_file = " SEMLOC_SOURCE_DIR
                             "/maps/paper_50x50.yaml\nlogOutput_dir = x\nparticles_count = 200\n";
    const std::string maps = "[MetricMap]\nsemanticMap_count = 1\n";
    ASSERT_EQ(failWith(good + maps), "") << "the base configuration is valid";
    fs::remove_all(outDir);

    const std::vector<std::pair<std::string, std::string>> cases = {
        {good + maps + "[PF_option]\nBETA = 0.5\n", "[PF_option]: unknown section"},
        {good + "particle_count = 100\n" + maps, "[LocalizationExperiment] particle_count"},
        {good + "seed = -3\n" + maps, "[LocalizationExperiment] seed"},
        {good + maps + "[PF_options]\nthreads = many\n", "[PF_options] threads"},
        {good + "[MetricMap]\nsemantcMap_count = 1\n", "semantcMap"},
        {good + maps + "[MetricMap_semanticMap_00_likelihoodOpts]\nsigma_rang_m = 1\n",
         "sigma_rang_m"},
        {"[LocalizationExperiment]\nrawlog_file = /no/such.rawlog\nlogOutput_dir = x\n" + maps,
         "/no/such.rawlog"},
        {"[LocalizationExperiment]\nrawlog_file = " + rawlog +
             "\nmap_file = /no/such_world.yaml\nlogOutput_dir = x\n" + maps,
         "/no/such_world.yaml"},
        {good + "ground_truth_path_file = /no/such_gt.txt\n" + maps, "/no/such_gt.txt"},
        {good + "use_3D_poses = true\n" + maps, "use_3D_poses"},
    };
    for (const auto& [text, expected] : cases)
    {
        const std::string msg = failWith(text);
        EXPECT_NE(msg.find(expected), std::string::npos)
            << "expected '" << expected << "' in: " << msg;
        EXPECT_FALSE(fs::exists(outDir)) << expected;
    }

    // An error while running (a corrupt rawlog) leaves no output and no staging directory.
    const fs::path corrupt = kOut / "corrupt.rawlog";
    std::ofstream(corrupt) << "not a rawlog at all";
    const std::string msg = failWith(
        "[LocalizationExperiment]\nrawlog_file = " + corrupt.string() +
        "\nmap_file = " SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml\nlogOutput_dir = x\n" + maps);
    EXPECT_NE(msg.find("corrupt.rawlog"), std::string::npos) << msg;
    for (const auto& e : fs::directory_iterator(kOut))
    {
        EXPECT_EQ(e.path().filename().string().find(outName), std::string::npos)
            << e.path() << " left behind";
    }
}

TEST(ShippedConfigs, VariantsNameTheirBaseAndSetTheirKeysOnly)
{
    // A variant file names its base and sets its own keys, its name and its output directory:
    // read with its base, every other key has the base's value. A variant of other maps
    // (geometric, the grids, fused) sets its own [MetricMap*] sections too, and no other key
    // of the filter than its own.
    using Keys = std::map<std::string, std::string>;
    auto keysOf = [](const std::string& file)
    {
        const semloc::config::IniFileInMemory ini(kConfig + "localize/" + file);
        std::vector<std::string> sections;
        ini.getAllSections(sections);
        Keys keys;  // "[section] key" -> value
        for (const auto& section : sections)
        {
            std::vector<std::string> names;
            ini.getAllKeys(section, names);
            for (const auto& k : names)
            {
                keys["[" + section + "] " + k] = ini.read_string(section, k, "");
            }
        }
        return keys;
    };
    struct Variant
    {
        std::string name, base;
        Keys own;              // key -> the text after "= " up to any comment
        bool ownMaps = false;  // its [MetricMap*] sections are its own
    };
    const std::vector<Variant> variants = {
        {"semantic",
         "filter",
         {{"init_PDF_mode", "3"},
          {"trigger", "evidence"},
          {"injected_weight", "0.000003"},
          {"lost_var_xy_m2", "10"},
          {"heading_drift_walk_deg_per_min", "5"}},
         true},
        {"geometric", "filter", {}, true},
        {"grid_lf", "filter", {}, true},
        {"grid_rt", "filter", {}, true},
        {"fused",
         "semantic",
         {{"trigger", "off"}, {"lost_var_xy_m2", "0"}, {"heading_drift_walk_deg_per_min", "0"}},
         true},
        {"semantic_marginal", "semantic", {{"association", "marginal"}}},
        {"semantic_misread", "semantic", {{"p_range_outlier", "0.05"}}},
        {"semantic_surveyed", "semantic", {{"map_file", "../../maps/paper_50x50_surveyed.yaml"}}},
        {"semantic_positions", "semantic", {{"map_file", "../../maps/paper_50x50_positions.yaml"}}},
        {"semantic_existence", "semantic", {{"map_file", "../../maps/paper_50x50_existence.yaml"}}},
        {"semantic_classes", "semantic", {{"map_file", "../../maps/paper_50x50_classes.yaml"}}},
        {"semantic_norecovery", "semantic", {{"trigger", "off"}, {"lost_var_xy_m2", "0"}}},
        {"semantic_nodrift", "semantic", {{"heading_drift_walk_deg_per_min", "0"}}},
        {"semantic_challengers", "semantic", {{"challenger_frames", "20"}}},
        {"semantic_no_reseed", "semantic", {{"lost_var_xy_m2", "0"}}},
        {"semantic_amcl",
         "semantic",
         {{"trigger", "amcl"}, {"alpha_slow", "0.001"}, {"alpha_fast", "0.1"}}},
        {"semantic_basic",
         "semantic",
         {{"init_PDF_mode", "0"},
          {"heading_drift_walk_deg_per_min", "0"},
          {"trigger", "off"},
          {"lost_var_xy_m2", "0"},
          {"injected_weight", "1"},
          {"outage_every_s", "0"}}},
        {"semantic_kld",
         "semantic",
         {{"adaptiveSampleSize", "1"}, {"kld_at_resampling", "1"}, {"KLD_minSampleSize", "5000"}}},
        {"semantic_paper",
         "semantic_basic",
         {{"model", "paper"}, {"init_PDF_mode", "3"}, {"missed_object_penalty", "0.9"}}}};
    for (const auto& v : variants)
    {
        const std::string text = readText(kConfig + "localize/" + v.name + ".ini");
        EXPECT_NE(text.find("\nbase = " + v.base + ".ini\n"), std::string::npos) << v.name;
        Keys mine = keysOf(v.name + ".ini"), base = keysOf(v.base + ".ini");
        for (Keys* keys : {&mine, &base})
        {
            for (auto it = keys->begin(); v.ownMaps && it != keys->end();)
            {
                it = it->first.rfind("[MetricMap", 0) == 0 ? keys->erase(it) : std::next(it);
            }
        }
        EXPECT_GT(base.size(), 50u) << v.base;
        Keys expected = base;
        for (const auto& own : v.own)
        {
            // The own keys are the base's, with another value.
            const std::string& key = own.first;
            const std::string& value = own.second;
            const auto it = std::find_if(
                base.begin(), base.end(),
                [&key](const auto& kv) { return kv.first.substr(kv.first.find("] ") + 2) == key; });
            ASSERT_NE(it, base.end()) << v.name << " " << key;
            EXPECT_NE(it->second, value) << v.name << " " << key;
            expected[it->first] = value;
        }
        expected["[LocalizationExperiment] variant"] = v.name;
        expected["[LocalizationExperiment] logOutput_dir"] = "results/" + v.name;
        EXPECT_EQ(mine, expected) << v.name;
    }
}

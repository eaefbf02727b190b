/* semloc tests — Benchmark's maps and figures: the variants localize against the simulated
 * world unless map_from_world = false, a map that differs from that world is said (stderr,
 * report.md), every shipped benchmark keeps the maps it had; a benchmark of one particle (no
 * spread: zero on a log axis) draws every figure. */
#include <gtest/gtest.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/ConfigHelpers.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "TestHelpers.h"

namespace
{
namespace fs = std::filesystem;
const std::string kConfig = std::string(SEMLOC_SOURCE_DIR) + "/config/";
const std::string kMaps = std::string(SEMLOC_SOURCE_DIR) + "/maps/";

/** A benchmark of config/localize/semantic.ini on simulate.ini with the world `world` (in dir
 * `name`). */
std::string writeBenchmark(const std::string& name, const std::string& world,
                           const std::string& extra)
{
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ifstream in(kConfig + "simulate/simulate.ini");
    std::ofstream sim(dir / "sim.ini");
    for (std::string line; std::getline(in, line);)
    {
        sim << (line.rfind("world_file", 0) == 0 ? "world_file = " + world : line) << "\n";
    }
    std::ofstream(dir / "bench.ini")
        << "[Benchmark]\nruns = 2\njobs = 2\nmax_steps = 40\n"
        << "variants = " << kConfig << "localize/semantic.ini\n"
        << "simulate_ini = sim.ini\noutput_dir = " << (dir / "out").string() << "\n"
        << extra;
    return (dir / "bench.ini").string();
}

/** The world name of `ini`'s [LocalizationExperiment] map_file (resolved next to it). */
std::string ownMapName(const std::string& ini)
{
    const semloc::config::IniFileInMemory c(ini);
    return semloc::World::FromFile(semloc::config::resolveNextToIni(
                                       c, c.read_string("LocalizationExperiment", "map_file", "")))
        .name;
}
}  // namespace

TEST(BenchmarkMaps, TheMapFollowsTheSimulatedWorld)
{
    const auto b = semloc::Benchmark::FromConfigFile(
        writeBenchmark("maps_follow", kMaps + "harbour_symmetric.yaml", ""));
    EXPECT_TRUE(b.mapFromWorld());
    ASSERT_EQ(b.variants().size(), 1u);
    ASSERT_TRUE(b.variants()[0].maps.world.has_value());
    EXPECT_EQ(b.variants()[0].maps.world->name, "harbour_symmetric");
    EXPECT_TRUE(b.mapWarnings().empty());
}

TEST(BenchmarkMaps, AnotherMapIsKeptWhenAskedAndSaidOutLoud)
{
    const auto b = semloc::Benchmark::FromConfigFile(
        writeBenchmark("maps_own", kMaps + "harbour_symmetric.yaml", "map_from_world = false\n"));
    EXPECT_FALSE(b.mapFromWorld());
    ASSERT_TRUE(b.variants()[0].maps.world.has_value());
    EXPECT_EQ(b.variants()[0].maps.world->name, "paper_50x50");
    ASSERT_EQ(b.mapWarnings().size(), 1u);
    const std::string w = b.mapWarnings()[0];
    // The map as the variant names it (a path from the working directory where it exists
    // there, else resolved next to its ini).
    const auto at = w.find("variant 'semantic' localizes against '");
    ASSERT_NE(at, std::string::npos) << w;
    const auto named = w.substr(at + 38, w.find('\'', at + 38) - at - 38);
    EXPECT_TRUE(fs::equivalent(named, kMaps + "paper_50x50.yaml")) << w;
    EXPECT_NE(w.find("(map_from_world = false)"), std::string::npos) << w;
    EXPECT_NE(w.find("harbour_symmetric.yaml"), std::string::npos) << w;
    const auto res = b.run();
    const std::string md = semloc::test::readText(fs::path(res.outputDir) / "report.md");
    EXPECT_NE(md.find("- **warning: the map differs from the simulated world**: " + w),
              std::string::npos)
        << md;
    // The simulation's ini as named from the working directory when it lies under it (the
    // tests run in the build's tests directory, where writeBenchmark writes it).
    const fs::path sim = fs::path(SEMLOC_TEST_OUT) / "maps_own" / "sim.ini";
    const fs::path rel = sim.lexically_proximate(fs::current_path());
    const bool under = !rel.empty() && *rel.begin() != "..";
    EXPECT_NE(md.find("simulates the scenario of `" + (under ? rel : sim).string() + "`"),
              std::string::npos)
        << md;
}

TEST(BenchmarkMaps, SameWorldUnderAnotherFileIsNotADifferentMap)
{
    // The variant's map_file is maps/paper_50x50.yaml; the simulation reads a copy of it.
    const fs::path copy = fs::path(SEMLOC_TEST_OUT) / "paper_copy.yaml";
    fs::copy_file(kMaps + "paper_50x50.yaml", copy, fs::copy_options::overwrite_existing);
    const auto b = semloc::Benchmark::FromConfigFile(
        writeBenchmark("maps_copy", copy.string(), "map_from_world = false\n"));
    ASSERT_EQ(b.mapWarnings().size(), 1u);
    EXPECT_NE(b.mapWarnings()[0].find("another file than the simulated world"), std::string::npos)
        << b.mapWarnings()[0];
}

// Before map_from_world = true became the default, a variant used its own map_file unless a
// scenario said map_from_world = true: every shipped benchmark still means that.
TEST(BenchmarkMaps, EveryShippedBenchmarkKeepsItsMaps)
{
    size_t checked = 0;
    for (const auto& e : fs::directory_iterator(kConfig + "benchmark"))
    {
        if (!e.is_regular_file() || e.path().extension() != ".ini" ||
            !semloc::config::IniFileInMemory(e.path().string()).sectionExists("Benchmark"))
        {
            continue;
        }
        const auto b = semloc::Benchmark::FromConfigFile(e.path().string());
        std::vector<const semloc::Benchmark*> parts = {&b};
        for (const auto& sc : b.scenarios())
        {
            parts.push_back(&sc);
        }
        for (const auto* p : parts)
        {
            const bool scenarioSaysWorld = p->scenario().map_from_world.value_or(false);
            const std::string simulated =
                semloc::World::FromFile(p->simulation().simulation.world_file).name;
            for (const auto& v : p->variants())
            {
                ASSERT_TRUE(v.maps.world.has_value()) << v.iniPath;
                EXPECT_EQ(v.maps.world->name, scenarioSaysWorld ? simulated : ownMapName(v.iniPath))
                    << e.path() << ", scenario " << p->scenario().name << ", " << v.name();
                checked++;
            }
        }
    }
    EXPECT_GT(checked, 100u);
}

TEST(BenchmarkMaps, OneParticleBenchmarkDrawsEveryFigure)
{
    const auto b = semloc::Benchmark::FromConfigFile(
        writeBenchmark("one_particle", kMaps + "paper_50x50.yaml", "particles = 1\n"));
    const auto res = b.run();
    for (const auto& w : res.figureWarnings)
    {
        ADD_FAILURE() << w.text();
    }
    for (const char* f : {"fig_variance.png", "fig_error.png", "world_paths.png", "report.md",
                          "results.csv", "curves.csv"})
    {
        const fs::path p = fs::path(res.outputDir) / f;
        EXPECT_TRUE(fs::exists(p) && fs::file_size(p) > 0) << f;
    }
}

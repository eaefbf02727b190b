/* semloc tests — WorldPlot renders a valid PNG of a world through gnuplot. */
#include <gtest/gtest.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/plot/WorldPlot.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace
{
/** Width and height from a PNG's IHDR chunk; {0, 0} if it is not a PNG. */
std::pair<uint32_t, uint32_t> pngSize(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    std::array<unsigned char, 24> h{};
    f.read(reinterpret_cast<char*>(h.data()), h.size());
    const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!f || !std::equal(sig, sig + 8, h.begin()) ||
        std::string(h.begin() + 12, h.begin() + 16) != "IHDR")
    {
        return {0, 0};
    }
    auto be = [&](size_t i)
    {
        return (uint32_t(h[i]) << 24) | (uint32_t(h[i + 1]) << 16) | (uint32_t(h[i + 2]) << 8) |
               h[i + 3];
    };
    return {be(16), be(20)};
}
}  // namespace

TEST(WorldPlot, DrawsThePaperWorldToPng)
{
    auto world = semloc::World::FromFile(std::string(SEMLOC_SOURCE_DIR) + "/maps/paper_50x50.yaml");
    semloc::WorldPlot plot(world, "paper scenario");
    plot.addWorldTrajectory();
    plot.addPath("estimate", {{5, 5}, {10, 6}, {20, 8}});
    const std::string png = std::string(SEMLOC_TEST_OUT) + "/paper_world.png";
    std::remove(png.c_str());
    plot.savePng(png, 640, 480);
    const auto [w, h] = pngSize(png);
    EXPECT_EQ(w, 640u);
    EXPECT_EQ(h, 480u);
    // Every object is labelled; every path is in the legend.
    const std::string script = plot.script("d.dat", "o.png", 640, 480);
    for (const auto& o : world.objects)
    {
        EXPECT_NE(script.find(o.label + " #" + std::to_string(o.id)), std::string::npos);
    }
    EXPECT_NE(script.find("'trajectory'"), std::string::npos);
    EXPECT_NE(script.find("'estimate'"), std::string::npos);
}

TEST(WorldPlot, UnwritableOutputFailsCleanly)
{
    semloc::WorldPlot plot(
        semloc::World::FromFile(std::string(SEMLOC_SOURCE_DIR) + "/maps/paper_50x50.yaml"));
    EXPECT_THROW(plot.savePng("/nonexistent-dir/x.png"), std::exception);
}

namespace
{
/** Every name in `d`. */
std::set<std::string> names(const std::string& d)
{
    std::set<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(d))
    {
        out.insert(e.path().filename().string());
    }
    return out;
}

std::string freshDir(const std::string& name)
{
    std::string d = std::string(SEMLOC_TEST_OUT) + "/" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

semloc::WorldPlot paperPlot()
{
    return semloc::WorldPlot(
        semloc::World::FromFile(std::string(SEMLOC_SOURCE_DIR) + "/maps/paper_50x50.yaml"));
}
}  // namespace

TEST(WorldPlot, KeptScriptDrawsThePngFromTheKeptData)
{
    // --keep-script: the PNG, its script and its data, nothing else; the script reads the kept
    // data and draws the PNG itself.
    const std::string d = freshDir("plot_keep");
    paperPlot().savePng(d + "/w.png", 300, 300, true);
    EXPECT_EQ(names(d), std::set<std::string>({"w.png", "w.png.dat", "w.png.gp"}));
    std::ifstream f(d + "/w.png.gp");
    std::stringstream script;
    script << f.rdbuf();
    EXPECT_NE(script.str().find("set output '" + d + "/w.png'\n"), std::string::npos)
        << script.str();
    EXPECT_NE(script.str().find("plot '" + d + "/w.png.dat'"), std::string::npos) << script.str();
}

TEST(WorldPlot, InterruptRequestWritesNothing)
{
    const std::string d = freshDir("plot_interrupted");
    semloc::requestInterrupt();
    EXPECT_THROW(paperPlot().savePng(d + "/w.png", 300, 300, true), semloc::Interrupted);
    semloc::clearInterrupt();
    EXPECT_TRUE(names(d).empty());
}

TEST(WorldPlot, MissingGnuplotNamesItsPackageAndLeavesNothing)
{
    const std::string d = freshDir("plot_no_gnuplot");
    const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
    ::setenv("PATH", d.c_str(), 1);
    std::string msg;
    try
    {
        paperPlot().savePng(d + "/w.png");
    }
    catch (const std::exception& e)
    {
        msg = semloc::errorMessage(e);
    }
    ::setenv("PATH", path.c_str(), 1);
    EXPECT_NE(msg.find("cannot run 'gnuplot'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("gnuplot-nox"), std::string::npos) << msg;
    EXPECT_TRUE(names(d).empty());
}

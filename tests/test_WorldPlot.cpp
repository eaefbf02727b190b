/* semloc tests — WorldPlot renders a valid PNG of a world through gnuplot. */
#include <gtest/gtest.h>
#include <semloc/WorldPlot.h>

#include <array>
#include <fstream>

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

/* semloc tests — LocalizationMap: [MetricMap] read strictly, maps filled from a world file. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <semloc/maps/CSemanticMap.h>
#include <semloc/maps/LocalizationMap.h>

#include <string>

#include "TestHelpers.h"

using semloc::test::errorOf;

using semloc::test::iniText;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";

}  // namespace

TEST(LocalizationMap, StrictMetricMapAndWorldFilling)
{
    auto fromText = [](const std::string& text, const std::string& mapFile = kPaperWorld)
    { return semloc::LocalizationMap::FromConfig(iniText(text), mapFile); };

    const auto lm = fromText(R"(
[MetricMap]
semanticMap_count = 1
structureMap_count = 1
occupancyGrid_count = 1
likelihoodMapSelection = -1
[MetricMap_occupancyGrid_00_creationOpts]
resolution = 0.25
[MetricMap_occupancyGrid_00_likelihoodOpts]
likelihoodMethod = 1
)");
    ASSERT_EQ(lm.map->maps.size(), 3u);
    ASSERT_TRUE(lm.world);
    EXPECT_EQ(lm.variant(), "grid_rt+semantic+geometric");
    const auto grid = lm.map->mapByClass<mrpt::maps::COccupancyGridMap2D>();
    EXPECT_FLOAT_EQ(grid->getResolution(), 0.25f);
    EXPECT_NEAR(grid->getXMax(), 50, 0.3);
    EXPECT_EQ(grid->likelihoodOptions.likelihoodMethod,
              mrpt::maps::COccupancyGridMap2D::lmRayTracing)
        << "the ini's options survive the rasterization";
    EXPECT_EQ(lm.map->mapByClass<semloc::CSemanticMap>()->objects().size(),
              lm.world->objects.size());
    EXPECT_EQ(fromText("[MetricMap]\nsemanticMap_count = 1\nstructureMap_count = 1\n").variant(),
              "fused");
    EXPECT_EQ(fromText("[MetricMap]\nstructureMap_count = 1\n").variant(), "geometric");

    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemantcMap_count = 1\n"); })
                  .find("[MetricMap] semantcMap_count: unknown map 'semantcMap'"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemanticMap_count = one\n"); })
                  .find("semanticMap_count"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemanticMaps = 1\n"); }).find("semanticMaps"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\n"); }).find("no map"), std::string::npos);
    EXPECT_NE(errorOf(
                  [&]
                  {
                      fromText(
                          "[MetricMap]\nsemanticMap_count = 1\n[MetricMap_semanticMap_01_"
                          "likelihoodOpts]\nsigma_range_m = 1\n");
                  })
                  .find("[MetricMap_semanticMap_01_likelihoodOpts]"),
              std::string::npos);
    EXPECT_NE(errorOf(
                  [&]
                  {
                      fromText(
                          "[MetricMap]\nsemanticMap_count = 1\n[MetricMap_semantcMap_00_"
                          "likelihoodOpts]\nsigma_range_m = 1\n");
                  })
                  .find("unknown section"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemanticMap_count = 1\n", ""); })
                  .find("the semantic map is empty"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemanticMap_count = 1\n", "/no/such.yaml"); })
                  .find("/no/such.yaml"),
              std::string::npos);
    EXPECT_NE(
        errorOf([&] { fromText("[MetricMap]\noccupancyGrid_count = 1\n", kPaperWorld + ".txt"); })
            .find("does not exist"),
        std::string::npos);
}

// The map file's world already loaded builds the same maps and effective configuration as the
// file read by FromConfig; a loaded world stands for a world file only.
TEST(LocalizationMap, LoadedWorldEqualsItsFile)
{
    const auto ini = iniText(R"(
[MetricMap]
semanticMap_count = 1
structureMap_count = 1
occupancyGrid_count = 1
[MetricMap_occupancyGrid_00_creationOpts]
resolution = 0.5
)");
    const auto world = semloc::World::FromFile(kPaperWorld);
    const auto fromFile = semloc::LocalizationMap::FromConfig(ini, kPaperWorld);
    const auto fromWorld = semloc::LocalizationMap::FromConfig(ini, world, kPaperWorld);
    EXPECT_EQ(fromWorld.variant(), fromFile.variant());
    EXPECT_EQ(fromWorld.effectiveConfig(ini), fromFile.effectiveConfig(ini));
    ASSERT_TRUE(fromWorld.world);
    EXPECT_EQ(fromWorld.world->toYamlText(), world.toYamlText());
    const auto* grid = fromWorld.map->mapByClass<mrpt::maps::COccupancyGridMap2D>().get();
    ASSERT_NE(grid, nullptr);
    EXPECT_EQ(grid->getSizeX(),
              fromFile.map->mapByClass<mrpt::maps::COccupancyGridMap2D>()->getSizeX());
    const std::string e = errorOf(
        [&] { semloc::LocalizationMap::FromConfig(ini, world, SEMLOC_SOURCE_DIR "/x.gridmap"); });
    EXPECT_NE(e.find("a loaded world stands for a world YAML file"), std::string::npos) << e;
}

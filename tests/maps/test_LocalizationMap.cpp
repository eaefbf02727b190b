/* semloc tests — LocalizationMap: [MetricMap] read strictly, maps filled from a world file. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <semloc/maps/LocalizationMap.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <fstream>
#include <string>

#include "TestHelpers.h"

using semloc::test::errorOf;

using semloc::test::iniText;

namespace
{
const std::string kPaperWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kLblWorld = SEMLOC_SOURCE_DIR "/maps/paper_50x50_lbl.yaml";
const std::string kBeaconIni = R"(
[MetricMap]
semanticMap_count = 1
beaconMap_count = 1
[MetricMap_beaconMap_00_likelihoodOpts]
rangeStd = 0.5
)";

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
    // A map filled from a world of no object: the world file is named, not the ini's key.
    const std::string emptyWorld = std::string(SEMLOC_TEST_OUT) + "/localization_map_empty.yaml";
    std::ofstream(emptyWorld) << "name: empty\nbounds: {x_min: 0, x_max: 10, y_min: 0, y_max: "
                                 "10}\nobjects: []\n";
    EXPECT_NE(
        errorOf([&] { fromText("[MetricMap]\nsemanticMap_count = 1\n", emptyWorld); })
            .find("map_file '" + emptyWorld + "': the world holds no object for the semantic map"),
        std::string::npos);
    EXPECT_NE(errorOf([&] { fromText("[MetricMap]\nsemanticMap_count = 1\n", "/no/such.yaml"); })
                  .find("/no/such.yaml"),
              std::string::npos);
    EXPECT_NE(
        errorOf([&] { fromText("[MetricMap]\noccupancyGrid_count = 1\n", kPaperWorld + ".txt"); })
            .find("does not exist"),
        std::string::npos);
}

TEST(LocalizationMap, MessagesShowKeysEscapedAndCut)
{
    const std::string key = "semantic\x1b[2J" + std::string(300, 'M') + "_count";
    const std::string e = errorOf(
        [&]
        { semloc::LocalizationMap::FromConfig(iniText("[MetricMap]\n" + key + " = 1\n"), ""); });
    EXPECT_NE(e.find("ini [MetricMap] semantic\\x1B[2JMMM"), std::string::npos) << e.substr(0, 400);
    EXPECT_EQ(e.find('\x1b'), std::string::npos);
    EXPECT_EQ(e.find(std::string(100, 'M')), std::string::npos);
}

TEST(LocalizationMap, AMapSectionsErrorNamesSectionAndKeyOnceAndTheIniFile)
{
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/localization_map_names_file.ini";
    std::ofstream(path) << "[MetricMap]\nsemanticMap_count = 1\n"
                           "[MetricMap_semanticMap_00_likelihoodOpts]\nsigma_range_m = -1\n";
    const std::string e = errorOf(
        [&] { semloc::LocalizationMap::FromConfig(mrpt::config::CConfigFile(path), kPaperWorld); });
    EXPECT_NE(e.find("ini '" + path +
                     "': [MetricMap_semanticMap_00_likelihoodOpts] sigma_range_m: value -1 is "
                     "out of range"),
              std::string::npos)
        << e;
    EXPECT_EQ(e.find("ini [MetricMap_semanticMap_00_*]"), std::string::npos) << e;
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

TEST(LocalizationMap, ABeaconMapHoldsTheWorldsBeacons)
{
    // MRPT's CBeaconMap from [MetricMap] beaconMap_count, filled from the map file's world.
    const auto lm = semloc::LocalizationMap::FromConfig(iniText(kBeaconIni), kLblWorld);
    ASSERT_TRUE(lm.world);
    EXPECT_EQ(lm.variant(), "beaconMap+semantic");
    const auto beacons = lm.map->mapByClass<mrpt::maps::CBeaconMap>();
    ASSERT_TRUE(beacons);
    EXPECT_EQ(beacons->likelihoodOptions.rangeStd, 0.5);
    ASSERT_EQ(beacons->size(), lm.world->beacons.size());
    ASSERT_EQ(beacons->size(), 3u);
    for (size_t i = 0; i < beacons->size(); i++)
    {
        const auto& b = beacons->get(i);
        const auto& w = lm.world->beacons[i];
        EXPECT_EQ(b.m_ID, w.id);
        EXPECT_EQ(b.m_typePDF, mrpt::maps::CBeacon::pdfGauss);
        EXPECT_EQ(b.m_locationGauss.mean, mrpt::poses::CPoint3D(w.x, w.y, w.z));
        EXPECT_LE(b.m_locationGauss.cov.maxCoeff(), 1e-6);
    }
    // The ranges of a pose score best there (the ranges to beacons 1 and 3).
    mrpt::obs::CObservationBeaconRanges obs;
    for (const int id : {1, 3})
    {
        const auto& w = lm.world->beacons[static_cast<size_t>(id - 1)];
        mrpt::obs::CObservationBeaconRanges::TMeasurement m;
        m.beaconID = id;
        m.sensedDistance = static_cast<float>(
            std::sqrt((w.x - 20) * (w.x - 20) + (w.y - 30) * (w.y - 30) + w.z * w.z));
        obs.sensedData.push_back(m);
    }
    const auto at = [&](double x, double y)
    { return beacons->computeObservationLikelihood(obs, mrpt::poses::CPose3D(x, y, 0, 0, 0, 0)); };
    EXPECT_GT(at(20, 30), at(21, 30));
    EXPECT_GT(at(20, 30), at(20, 29));
    // The effective configuration says the ranges' standard deviation.
    EXPECT_NE(lm.effectiveConfig(iniText(kBeaconIni)).find("rangeStd"), std::string::npos);

    // A world given by the semantic map's own world_file fills it as well.
    const auto own = semloc::LocalizationMap::FromConfig(
        iniText(kBeaconIni + "[MetricMap_semanticMap_00_creationOpts]\nworld_file = " + kLblWorld +
                "\n"),
        "");
    EXPECT_EQ(own.map->mapByClass<mrpt::maps::CBeaconMap>()->size(), 3u);
}

TEST(LocalizationMap, ABeaconMapWithoutBeaconsIsAnErrorNamingTheKeyAndTheWorld)
{
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/localization_map_beacons.ini";
    std::ofstream(path) << kBeaconIni;
    const std::string e = errorOf(
        [&] { semloc::LocalizationMap::FromConfig(mrpt::config::CConfigFile(path), kPaperWorld); });
    EXPECT_NE(e.find("ini '" + path + "': [MetricMap] beaconMap_count: "), std::string::npos) << e;
    EXPECT_NE(e.find("world file '" + kPaperWorld + "', which has none"), std::string::npos) << e;

    const std::string noWorld = errorOf(
        [&] {
            semloc::LocalizationMap::FromConfig(iniText("[MetricMap]\nbeaconMap_count = 1\n"), "");
        });
    EXPECT_NE(noWorld.find("ini [MetricMap] beaconMap_count: the beacon map is empty"),
              std::string::npos)
        << noWorld;

    for (const char* bad : {"0", "-0.5"})
    {
        const std::string text = std::string("[MetricMap]\nbeaconMap_count = 1\n") +
                                 "[MetricMap_beaconMap_00_likelihoodOpts]\nrangeStd = " + bad +
                                 "\n";
        const std::string r =
            errorOf([&] { semloc::LocalizationMap::FromConfig(iniText(text), kLblWorld); });
        EXPECT_NE(r.find("ini [MetricMap_beaconMap_00_likelihoodOpts] rangeStd: "),
                  std::string::npos)
            << r;
    }
    const std::string inf = errorOf(
        [&]
        {
            semloc::LocalizationMap::FromConfig(
                iniText("[MetricMap]\nbeaconMap_count = 1\n"
                        "[MetricMap_beaconMap_00_likelihoodOpts]\nrangeStd = inf\n"),
                kLblWorld);
        });
    EXPECT_NE(inf.find("rangeStd: 'inf' is not a finite number"), std::string::npos) << inf;
}

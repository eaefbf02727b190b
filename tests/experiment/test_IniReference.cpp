/* semloc tests — docs/ini-reference.md is exactly what the options structs write. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <semloc/experiment/IniReference.h>

#include <fstream>
#include <sstream>

TEST(IniReference, DocsHoldTheGeneratedReference)
{
    std::ifstream f(std::string(SEMLOC_SOURCE_DIR) + "/docs/ini-reference.md");
    ASSERT_TRUE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string page = ss.str();
    const std::string begin = "<!-- ini-reference:begin -->\n```ini\n";
    const std::string end = "```\n<!-- ini-reference:end -->";
    const auto b = page.find(begin), e = page.find(end);
    ASSERT_NE(b, std::string::npos) << "docs/ini-reference.md lacks the ini-reference markers";
    ASSERT_NE(e, std::string::npos);
    const std::string inPage = page.substr(b + begin.size(), e - b - begin.size());
    EXPECT_EQ(inPage, semloc::iniReference())
        << "docs/ini-reference.md is stale: paste `build/bin/semloc-ini-reference`'s output";
}

TEST(IniReference, TheReferenceItselfIsAValidConfiguration)
{
    // Every section parses back through the real loaders (no unknown key, no bad value),
    // given a world file that exists.
    std::string ini = semloc::iniReference();
    const std::string world = std::string(SEMLOC_SOURCE_DIR) + "/maps/paper_50x50.yaml";
    const std::string rel = "maps/paper_50x50.yaml";
    for (size_t p = ini.find(rel); p != std::string::npos; p = ini.find(rel, p + world.size()))
    {
        ini.replace(p, rel.size(), world);
    }
    mrpt::config::CConfigFileMemory cfg("[MetricMap]\nsemanticMap_count=1\nstructureMap_count=1\n" +
                                        ini);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "MetricMap");
    mrpt::maps::CMultiMetricMap mm;
    mm.setListOfMaps(inits);
    EXPECT_EQ(mm.maps.size(), 2u);
}

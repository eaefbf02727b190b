/* semloc tests — ini files that name their base (config::readIniText, IniFileInMemory): the
 * keys laid over the base's, chains of bases, paths next to a base, and every refusal. */
#include <gtest/gtest.h>
#include <semloc/io/ConfigHelpers.h>

#include <filesystem>
#include <fstream>
#include <string>

using semloc::config::IniFileInMemory;
using semloc::config::readIniText;

namespace
{
namespace fs = std::filesystem;

/** A fresh directory for one test. */
fs::path freshDir(const std::string& name)
{
    auto dir = fs::path(SEMLOC_TEST_OUT) / "ini_base" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

void write(const fs::path& p, const std::string& text)
{
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
}

/** readIniText's message for `path`, or "" if it reads it. */
std::string problem(const fs::path& path)
{
    try
    {
        (void)readIniText(path.string());
        return {};
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
}
}  // namespace

TEST(IniBase, AFileWithoutABaseReadsAsItIs)
{
    const auto dir = freshDir("plain");
    const std::string text = "# a comment\n[A]\nx = 1 // inline\n";
    write(dir / "a.ini", text);
    std::vector<std::string> files;
    EXPECT_EQ(readIniText((dir / "a.ini").string(), "config file", &files), text);
    EXPECT_EQ(files, std::vector<std::string>{(dir / "a.ini").string()});
}

TEST(IniBase, KeysReplaceTheBasesOnTheirLineNewKeysAndSectionsFollow)
{
    const auto dir = freshDir("overlay");
    write(dir / "base.ini", "# the base\n[A]\nx = 1\ny = 2\n\n[B]\nz = 3\n");
    write(dir / "v.ini",
          "# the variant\nbase = base.ini   // the file it changes\n[a]\nY = 20\nw = 4\n[C]\n"
          "q = 5\n[B]\nz = 30\n");
    EXPECT_EQ(readIniText((dir / "v.ini").string()),
              "# the base\n[A]\nx = 1\nY = 20\nw = 4\n\n[B]\nz = 30\n[C]\nq = 5\n");
    // Read as MRPT reads it: the variant's values win, the base's others stay.
    const IniFileInMemory ini((dir / "v.ini").string());
    EXPECT_EQ(ini.read_int("A", "x", 0), 1);
    EXPECT_EQ(ini.read_int("A", "y", 0), 20);
    EXPECT_EQ(ini.read_int("A", "w", 0), 4);
    EXPECT_EQ(ini.read_int("B", "z", 0), 30);
    EXPECT_EQ(ini.read_int("C", "q", 0), 5);
    EXPECT_FALSE(ini.keyExists("", "base"));
}

TEST(IniBase, KeysBeforeAnySectionStayBeforeIt)
{
    const auto dir = freshDir("front");
    write(dir / "base.ini", "[A]\nx = 1\n");
    write(dir / "v.ini", "base = base.ini\nglobal = 7\n");
    const IniFileInMemory ini((dir / "v.ini").string());
    EXPECT_EQ(ini.read_int("", "global", 0), 7);
    EXPECT_FALSE(ini.keyExists("A", "global"));
}

TEST(IniBase, BasesChainAndPathsResolveNextToTheFileThatNamesThem)
{
    const auto dir = freshDir("chain");
    write(dir / "root" / "root.ini", "[A]\nx = 1\ny = 1\nz = 1\nmap_file = maps/w.yaml\n");
    write(dir / "root" / "maps" / "w.yaml", "objects: []\n");
    write(dir / "mid" / "mid.ini", "base = ../root/root.ini\n[A]\ny = 2\nz = 2\n");
    write(dir / "top.ini", "base = mid/mid.ini\n[A]\nz = 3\n");
    const IniFileInMemory ini((dir / "top.ini").string());
    EXPECT_EQ(ini.read_int("A", "x", 0), 1);
    EXPECT_EQ(ini.read_int("A", "y", 0), 2);
    EXPECT_EQ(ini.read_int("A", "z", 0), 3);
    ASSERT_EQ(ini.files().size(), 3u);
    EXPECT_EQ(ini.files()[0], (dir / "top.ini").string());
    EXPECT_EQ(fs::path(ini.files()[2]).filename(), "root.ini");
    // A path the root's line names is found next to the root.
    const std::string map = semloc::config::resolveNextToIni(ini, "maps/w.yaml");
    EXPECT_TRUE(fs::exists(map)) << map;
    EXPECT_EQ(fs::weakly_canonical(map), fs::weakly_canonical(dir / "root" / "maps" / "w.yaml"));
    // A missing one names every place tried.
    const std::string m = semloc::config::missingFileMessage(ini, "maps/nope.yaml");
    EXPECT_NE(m.find("next to the ini '" + (dir / "top.ini").string() + "'"), std::string::npos)
        << m;
    EXPECT_NE(m.find("next to its base '"), std::string::npos) << m;
    EXPECT_NE(m.find("from the working directory"), std::string::npos) << m;
    EXPECT_EQ(semloc::config::iniFileAndBases((dir / "top.ini").string()), ini.files());
}

TEST(IniBase, RefusesAMissingEmptyOrCyclicBaseNamingFileAndLine)
{
    const auto dir = freshDir("refusals");
    write(dir / "missing.ini", "# x\nbase = nope.ini\n[A]\nx = 1\n");
    EXPECT_NE(problem(dir / "missing.ini")
                  .find("config file '" + (dir / "missing.ini").string() +
                        "':2: base 'nope.ini' does not exist (tried '"),
              std::string::npos)
        << problem(dir / "missing.ini");
    write(dir / "empty.ini", "base =\n");
    EXPECT_NE(problem(dir / "empty.ini").find(":1: base: empty"), std::string::npos)
        << problem(dir / "empty.ini");
    write(dir / "a.ini", "base = b.ini\n");
    write(dir / "b.ini", "base = a.ini\n");
    EXPECT_NE(problem(dir / "a.ini").find("form a cycle"), std::string::npos)
        << problem(dir / "a.ini");
    write(dir / "self.ini", "base = self.ini\n");
    EXPECT_NE(problem(dir / "self.ini").find("form a cycle"), std::string::npos);
    write(dir / "twice.ini", "base = a.ini\nbase = b.ini\n");
    EXPECT_NE(problem(dir / "twice.ini").find(":2: [] base: set twice"), std::string::npos)
        << problem(dir / "twice.ini");
    // A bad line in a base names the base, not the file that names it.
    write(dir / "bad_base.ini", "[A]\nthis is no key\n");
    write(dir / "uses_bad.ini", "base = bad_base.ini\n");
    EXPECT_NE(problem(dir / "uses_bad.ini")
                  .find("config file '" + (dir / "bad_base.ini").string() + "':2: "),
              std::string::npos)
        << problem(dir / "uses_bad.ini");
    // A chain deeper than 16.
    for (int i = 0; i < 20; i++)
    {
        write(dir / ("d" + std::to_string(i) + ".ini"),
              "base = d" + std::to_string(i + 1) + ".ini\n");
    }
    write(dir / "d20.ini", "[A]\nx = 1\n");
    EXPECT_NE(problem(dir / "d0.ini").find("bases deep"), std::string::npos)
        << problem(dir / "d0.ini");
    EXPECT_NE(problem(dir / "nowhere.ini").find("does not exist"), std::string::npos);
}

TEST(IniBase, ABaseKeyInsideASectionIsAnOrdinaryKey)
{
    const auto dir = freshDir("in_section");
    write(dir / "a.ini", "[A]\nbase = b.ini\n");
    const IniFileInMemory ini((dir / "a.ini").string());
    EXPECT_EQ(ini.read_string("A", "base", ""), "b.ini");
    EXPECT_EQ(ini.files().size(), 1u);
}

TEST(IniBase, MovedKeysReadAtTheirOldPlaceWithAWarningAndOverrideEitherWay)
{
    const auto dir = freshDir("moved");
    // A file of the old layout: the recovery keys in [PF_options].
    write(dir / "old.ini",
          "[PF_options]\nBETA = 0.5\nrecovery_trigger = amcl  // old place\n"
          "recovery_alpha_slow = 0.001\n[KLD_options]\nKLD_delta = 0.02\n");
    std::vector<std::string> warnings;
    const std::string text =
        readIniText((dir / "old.ini").string(), "config file", nullptr, &warnings);
    EXPECT_EQ(text,
              "[PF_options]\nBETA = 0.5\n[KLD_options]\nKLD_delta = 0.02\n[Recovery]\n"
              "trigger = amcl  // old place\nalpha_slow = 0.001\n");
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_NE(warnings[0].find("old.ini':3: [PF_options] recovery_trigger is deprecated: write "
                               "[Recovery] trigger"),
              std::string::npos)
        << warnings[0];

    // An old-layout variant over a new-layout base, and the other way round: the variant's
    // value wins either way, under the new name.
    write(dir / "new.ini", "[PF_options]\nBETA = 0.5\n\n[Recovery]\ntrigger = evidence\n");
    write(dir / "old_over_new.ini", "base = new.ini\n[PF_options]\nrecovery_trigger = off\n");
    IniFileInMemory a((dir / "old_over_new.ini").string());
    EXPECT_EQ(a.read_string("Recovery", "trigger", ""), "off");
    EXPECT_FALSE(a.keyExists("PF_options", "recovery_trigger"));
    EXPECT_EQ(a.warnings().size(), 1u);
    write(dir / "new_over_old.ini", "base = old.ini\n[Recovery]\ntrigger = off\n");
    IniFileInMemory b((dir / "new_over_old.ini").string());
    EXPECT_EQ(b.read_string("Recovery", "trigger", ""), "off");
    EXPECT_EQ(b.read_string("Recovery", "alpha_slow", ""), "0.001");
    EXPECT_FALSE(b.keyExists("PF_options", "recovery_trigger"));
    EXPECT_EQ(b.warnings().size(), 2u);  // the base's old names

    // Both names in one file: an error naming the file and both lines.
    write(dir / "both.ini", "[PF_options]\nrecovery_trigger = off\n[Recovery]\ntrigger = amcl\n");
    const std::string why = problem(dir / "both.ini");
    EXPECT_NE(why.find("both.ini':2: [PF_options] recovery_trigger and line 4's [Recovery] "
                       "trigger: the same setting twice"),
              std::string::npos)
        << why;
    EXPECT_EQ(semloc::config::movedKeyNames().size(), 8u);
}

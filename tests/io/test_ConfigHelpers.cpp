/* semloc tests — the ini file check (config::checkIniText / checkIniFile): lines MRPT would
 * skip, keys set twice, the UTF-8 byte-order mark. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <semloc/io/ConfigHelpers.h>

#include <fstream>
#include <string>

using semloc::config::checkIniFile;
using semloc::config::checkIniText;

namespace
{
/** checkIniText's message for `text`, or "" if it accepts it. */
std::string problem(const std::string& text)
{
    try
    {
        checkIniText(text, "config file 'x.ini'");
        return {};
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
}
}  // namespace

TEST(ConfigHelpers, AcceptsWhatMrptReads)
{
    EXPECT_EQ(problem(""), "");
    EXPECT_EQ(problem("; comment\n# comment\n// comment\n% comment\n@define N 3\n\n"
                      "[A]\nx = 1\ny=${N}\n[B]\nx = 2\n"),
              "");
}

TEST(ConfigHelpers, RefusesALineMrptWouldSkip)
{
    const std::string m = problem("[A]\nx 1\n");
    EXPECT_NE(m.find("config file 'x.ini':2: 'x 1' is neither a [section] nor key = value"),
              std::string::npos)
        << m;
}

TEST(ConfigHelpers, RefusesAKeySetTwiceNamingBothLines)
{
    const std::string m = problem("[A]\nx = 1\ny = 2\nx = 3\n");
    EXPECT_NE(m.find("config file 'x.ini':4: [A] x: set twice (also on line 2"), std::string::npos)
        << m;
    // MRPT matches keys and sections regardless of case: so does the check.
    const std::string c = problem("[PF_options]\nBETA = 1\n[pf_OPTIONS]\nbeta = 2\n");
    EXPECT_NE(c.find("x.ini':4: [PF_options] beta: set twice (also on line 2"), std::string::npos)
        << c;
    // Keys before any section belong to the unnamed section.
    EXPECT_NE(problem("a = 1\na = 2\n").find("x.ini':2: [] a: set twice"), std::string::npos);
}

TEST(ConfigHelpers, AcceptsARepeatedSectionWithOtherKeys)
{
    // MRPT merges the keys of a section written twice; so the check accepts it.
    EXPECT_EQ(problem("[A]\nx = 1\n[B]\nx = 1\n[A]\ny = 2\n"), "");
    // The same key name in two sections is two keys.
    EXPECT_EQ(problem("[A]\nx = 1\n[B]\nx = 2\n"), "");
}

TEST(ConfigHelpers, SkipsAUtf8ByteOrderMarkAsMrptDoes)
{
    const std::string bom = "\xEF\xBB\xBF";
    EXPECT_EQ(problem(bom + "[LocalizationExperiment]\nrawlog_offset = 3\n"), "");
    // Only at the start of the text: elsewhere it is part of the line.
    const std::string m = problem("[A]\n" + bom + "[B]\n");
    EXPECT_NE(m.find("x.ini':2: '" + bom + "[B]' is neither"), std::string::npos) << m;

    // checkIniFile on a file with the mark, and MRPT's reader on the same file.
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/bom.ini";
    std::ofstream(path, std::ios::binary)
        << bom << "[LocalizationExperiment]\r\nrawlog_offset = 3\r\n";
    EXPECT_NO_THROW(checkIniFile(path));
    const mrpt::config::CConfigFile ini(path);
    EXPECT_EQ(ini.read_int("LocalizationExperiment", "rawlog_offset", 0), 3);
}

TEST(ConfigHelpers, CheckIniFileNamesTheFile)
{
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/twice.ini";
    std::ofstream(path) << "[A]\nx = 1\nx = 2\n";
    try
    {
        checkIniFile(path, "ini file");
        FAIL() << "accepted a key set twice";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("ini file '" + path + "':3: [A] x: set twice (also on line 2"),
                  std::string::npos)
            << m;
    }
    EXPECT_THROW(checkIniFile(std::string(SEMLOC_TEST_OUT) + "/no-such.ini"), std::exception);
}

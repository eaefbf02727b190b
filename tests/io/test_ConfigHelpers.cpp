/* semloc tests — the ini file check (config::checkIniText / checkIniFile): lines MRPT would
 * skip, keys set twice, the UTF-8 byte-order mark. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>

#include <filesystem>
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

TEST(ConfigHelpers, RefusesAnExpansionMrptWouldNotCloseNamingTheLine)
{
    // MRPT's reader throws "Line N: Expected closing `}`" for these, N a line of the text
    // with its bases resolved, no file named.
    for (const std::string value : {"${abc", "$env{HOME", "$eval{1+2"})
    {
        const std::string m = problem("[A]\nx = 1\ny = " + value + "\n");
        EXPECT_NE(m.find("config file 'x.ini':3: 'y = " + value + "' opens MRPT's "),
                  std::string::npos)
            << m;
        EXPECT_THROW(mrpt::config::CConfigFileMemory("[A]\ny = " + value + "\n"), std::exception)
            << "MRPT's reader refuses it too";
    }
    EXPECT_EQ(problem("[A]\nx = ${N} $env{HOME} $eval{1+2} cost $5 {a}\n"), "");
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
    // Only at the start of the text: elsewhere it is part of the line, shown escaped.
    const std::string m = problem("[A]\n" + bom + "[B]\n");
    EXPECT_NE(m.find("x.ini':2: '\\xEF\\xBB\\xBF[B]' is neither"), std::string::npos) << m;

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

TEST(ConfigHelpers, ValuesInMessagesAreEscapedAndCut)
{
    const std::string m = problem("[A]\n\x1b[2J" + std::string(500, 'q') + "\n");
    EXPECT_NE(m.find("x.ini':2: '\\x1B[2Jqqq"), std::string::npos) << m.substr(0, 300);
    EXPECT_EQ(m.find('\x1b'), std::string::npos);
    EXPECT_EQ(m.find(std::string(100, 'q')), std::string::npos);
    mrpt::config::CConfigFileMemory ini("[A]\nx = \x01" + std::string(200, '9') + "\n");
    double x = 0;
    try
    {
        semloc::config::readDouble(ini, "A", "x", x, 0, 1);
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        const std::string what = e.what();
        EXPECT_NE(what.find("ini [A] x: '\\x01999"), std::string::npos) << what.substr(0, 300);
        EXPECT_EQ(what.find(std::string(100, '9')), std::string::npos);
    }
}

TEST(ConfigHelpers, AMissingFileShowsThePathTriedNextToTheIni)
{
    const auto dir = std::filesystem::path(SEMLOC_TEST_OUT) / "config_helpers_missing";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "real");
    std::filesystem::create_directories(dir / "link");
    std::ofstream(dir / "real" / "a.ini") << "[A]\nmap_file = ../maps/w.yaml\n";
    std::filesystem::create_symlink("../real/a.ini", dir / "link" / "a.ini");
    const std::string ini = (dir / "link" / "a.ini").string();
    const mrpt::config::CConfigFile c(ini);
    EXPECT_EQ(semloc::config::missingFileMessage(c, "../maps/w.yaml"),
              "file '../maps/w.yaml' does not exist (tried '" + (dir / "link").string() +
                  "/../maps/w.yaml' next to the ini '" + ini +
                  "' and '../maps/w.yaml' from the working directory)");
    EXPECT_EQ(semloc::config::missingFileMessage(c, "/abs/w.yaml"),
              "file '/abs/w.yaml' does not exist");
}

TEST(ConfigHelpers, LinesEndWithLfCrLfOrACrAloneAsMrptReadsThem)
{
    EXPECT_EQ(problem("[A]\rx = 1\ry = 2\r[B]\rx = 3\r"), "");
    const std::string m = problem("[A]\rx = 1\rx 2\r");
    EXPECT_NE(m.find("config file 'x.ini':3: 'x 2' is neither a [section] nor key = value"),
              std::string::npos)
        << m;
    EXPECT_NE(
        problem("[A]\r\nx = 1\r\nx = 2\r\n").find("x.ini':3: [A] x: set twice (also on line 2"),
        std::string::npos);
}

TEST(ConfigHelpers, AnErrorMrptWrappedShowsItsTextWithoutTheBacktrace)
{
    // MRPT's gz stream wraps std::filesystem's error on a device: "Message:" empty, the text
    // after "Location:", then the call stack.
    std::string shown;
    try
    {
        mrpt::io::CFileGZInputStream in;
        std::string why;
        (void)in.open("/dev/null", why);
        ADD_FAILURE() << "MRPT opened /dev/null";
    }
    catch (const std::exception& e)
    {
        ASSERT_NE(std::string(e.what()).find("Call stack"), std::string::npos) << e.what();
        shown = semloc::errorMessage(e);
    }
    EXPECT_EQ(shown.find("Call stack"), std::string::npos) << shown;
    EXPECT_EQ(shown.find("===="), std::string::npos) << shown;
    EXPECT_NE(shown.find("/dev/null"), std::string::npos) << shown;
}

/* semloc tests — CsvTable: semloc-import's CSV files read strictly, every error naming the
 * file, the line and the column. */
#include <gtest/gtest.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/RawlogWriter.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "TestHelpers.h"

#include "dataset/CsvTable.h"

namespace
{
using semloc::detail::CsvTable;

/** The message of the error reading `text` as f.csv with columns t,x (required), id
 *  (optional); "" if it reads. */
std::string errorOf(const std::string& text, bool strictTime = true)
{
    try
    {
        const auto t = CsvTable::FromText(text, "f.csv", {"t", "x"}, {"id"});
        for (size_t r = 0; r < t.rows(); r++)
        {
            (void)t.number(r, "t");
            (void)t.number(r, "x");
        }
        t.checkIncreasing("t", strictTime);
        return "";
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);  // the message alone, as the tools print it
    }
}

void expectError(const std::string& text, const std::string& excerpt, bool strictTime = true)
{
    const std::string e = errorOf(text, strictTime);
    EXPECT_NE(e.find(excerpt), std::string::npos) << "error: '" << e << "'\nexpected: " << excerpt;
}

TEST(CsvTable, ReadsColumnsByNameInAnyOrderSkippingComments)
{
    const auto t = CsvTable::FromText("# a comment\n\n x , t ,id\r\n1.5,2,\n# again\n-3, 4 ,7\n",
                                      "f.csv", {"t", "x"}, {"id"});
    ASSERT_EQ(t.rows(), 2u);
    EXPECT_EQ(t.headerLine(), 3u);
    EXPECT_EQ(t.line(1), 6u);
    EXPECT_DOUBLE_EQ(t.number(0, "x"), 1.5);
    EXPECT_DOUBLE_EQ(t.number(1, "t"), 4);
    EXPECT_TRUE(t.empty(0, "id"));
    EXPECT_DOUBLE_EQ(t.numberOr(0, "id", -1), -1);
    EXPECT_DOUBLE_EQ(t.numberOr(1, "id", -1), 7);
    EXPECT_TRUE(t.has("id"));
    EXPECT_FALSE(t.has("y"));
    EXPECT_EQ(errorOf("t,x\n1,2\n"), "");
}

TEST(CsvTable, FailNamesAColumnTheHeaderLacksWithoutANumber)
{
    const auto t = CsvTable::FromText("t,x\n1,2\n", "f.csv", {"t", "x"}, {"id"});
    auto message = [&](const std::string& column)
    {
        try
        {
            t.fail(0, column, "bad");
        }
        catch (const std::exception& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message("x").find("f.csv:2: column 2 'x': bad"), std::string::npos);
    EXPECT_NE(message("id").find("f.csv:2: 'id' (not a column of the header): bad"),
              std::string::npos)
        << message("id");
}

TEST(CsvTable, UnknownColumn)
{
    expectError("t,x,speed\n1,2,3\n",
                "f.csv:1: column 3 'speed': unknown column (known: t, x, id)");
}

TEST(CsvTable, MissingColumn)
{
    expectError("# header next\nt,id\n1,2\n",
                "f.csv:2: missing column 'x' (the header names: t, id)");
}

TEST(CsvTable, ColumnNamedTwice)
{
    expectError("t,x,t\n1,2,3\n", "f.csv:1: column 3 't': named twice");
}

TEST(CsvTable, NonNumberNamesLineAndColumn)
{
    expectError("t,x\n1,2\n2,abc\n", "f.csv:3: column 2 'x': 'abc' is not a number");
    expectError("x,t\n1,2\n2,3q\n", "f.csv:3: column 2 't': '3q' is not a number");
    expectError("t,x\n1,\n", "f.csv:2: column 2 'x': empty (a number is required)");
}

TEST(CsvTable, NonFinite)
{
    expectError("t,x\n1,nan\n", "f.csv:2: column 2 'x': 'nan' is not a finite number");
    expectError("t,x\n1,2\n2,-inf\n", "f.csv:3: column 2 'x': '-inf' is not a finite number");
    expectError("t,x\n1e999,2\n", "f.csv:2: column 1 't': '1e999' is not a finite number");
}

TEST(CsvTable, TimeGoingBack)
{
    expectError("t,x\n1,0\n3,0\n2,0\n",
                "f.csv:4: column 1 't': time 2 goes back: it is before 3 (line 3): times must "
                "increase");
    expectError("t,x\n1,0\n1,0\n", "f.csv:3: column 1 't': time 1 is not after 1 (line 2)");
    EXPECT_EQ(errorOf("t,x\n1,0\n1,0\n", false), "");  // equal times: one scan
    expectError("t,x\n1,0\n0.5,0\n", "time 0.5 goes back", false);
}

TEST(CsvTable, WrongCellCountAndNoHeader)
{
    expectError("t,x\n1,2,3\n", "f.csv:2: expected 2 cells (t, x), found 3");
    expectError("# nothing\n\n", "'f.csv' has no header row (expected the columns t, x)");
}

TEST(CsvTable, FromFileNamesThePath)
{
    const auto dir = std::filesystem::path(SEMLOC_TEST_OUT) / "csv_table";
    std::filesystem::create_directories(dir);
    const auto p = (dir / "odom.csv").string();
    std::ofstream(p) << "t,x\n1,2\n2,zz\n";
    const auto t = CsvTable::FromFile(p, {"t", "x"});
    try
    {
        (void)t.number(1, "x");
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find(p + ":3: column 2 'x': 'zz' is not a number"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(CsvTable::FromFile((dir / "nope.csv").string(), {"t"}), std::exception);
    EXPECT_THROW(CsvTable::FromFile(dir.string(), {"t"}), std::exception);
}

/** `text` gz-compressed into `path` (as gzip writes it). */
std::string writeGz(const std::filesystem::path& path, const std::string& text)
{
    semloc::GzOutputFile f(path.string(), 6);
    f.Write(text.data(), text.size());
    f.close();
    return path.string();
}

std::string fileError(const std::string& path)
{
    try
    {
        (void)CsvTable::FromFile(path, {"t", "x"});
        return "";
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);
    }
}

TEST(CsvTable, GzCompressedFilesAreReadAsTheirText)
{
    const auto dir = std::filesystem::path(SEMLOC_TEST_OUT) / "csv_table_gz";
    std::filesystem::create_directories(dir);
    std::string text = "# compressed\nt,x\n";
    for (int k = 0; k < 20000; k++)
    {
        text += std::to_string(k) + "," + std::to_string(k % 7) + "\n";
    }
    const auto t = CsvTable::FromFile(writeGz(dir / "big.csv.gz", text), {"t", "x"});
    ASSERT_EQ(t.rows(), 20000u);
    EXPECT_EQ(t.line(19999), 20002u);
    EXPECT_DOUBLE_EQ(t.number(19999, "x"), 19999 % 7);
    // Cut short: refused naming the line it reached, not read as a shorter table.
    const std::string whole = semloc::test::readText(dir / "big.csv.gz");
    std::ofstream(dir / "cut.csv.gz", std::ios::binary) << whole.substr(0, whole.size() / 2);
    const std::string cut = fileError((dir / "cut.csv.gz").string());
    EXPECT_NE(cut.find("cut.csv.gz:"), std::string::npos) << cut;
    EXPECT_NE(cut.find(": the gz-compressed data is damaged or cut short (zlib: unexpected end "
                       "of file)"),
              std::string::npos)
        << cut;
    // The caps hold inside the compressed stream: a NUL byte, a line of 2 MiB.
    EXPECT_NE(fileError(writeGz(dir / "nul.csv.gz", std::string("t,x\n1,\0\n", 8)))
                  .find("nul.csv.gz:2: byte 3 of the line is a NUL byte"),
              std::string::npos);
    EXPECT_NE(fileError(writeGz(dir / "long.csv.gz", "t,x\n" + std::string(2 << 20, '1')))
                  .find("long.csv.gz:2: the line is longer than 1048576 bytes"),
              std::string::npos);
    EXPECT_NE(fileError((dir / "nope.csv").string()).find("nope.csv' does not exist"),
              std::string::npos);
}

TEST(CsvTable, ByteOrderMarkBeforeTheHeaderIsSkipped)
{
    const auto t = CsvTable::FromText("\xEF\xBB\xBFt,x\n1,2\n", "f.csv", {"t", "x"});
    ASSERT_EQ(t.rows(), 1u);
    EXPECT_DOUBLE_EQ(t.number(0, "t"), 1);
    // Anywhere else it is text, shown escaped.
    expectError(
        "t,x\n1,\xEF\xBB\xBF"
        "2\n",
        "f.csv:2: column 2 'x': '\\xEF\\xBB\\xBF2' is not a number");
}

TEST(CsvTable, LinesEndWithLfCrLfOrCr)
{
    for (const char* end : {"\n", "\r\n", "\r"})
    {
        const std::string e = end;
        const auto t =
            CsvTable::FromText("t,x" + e + "1,2" + e + "# c" + e + "3,4" + e, "f.csv", {"t", "x"});
        ASSERT_EQ(t.rows(), 2u) << "line end " << (e == "\r" ? "CR" : "LF/CRLF");
        EXPECT_EQ(t.line(1), 4u);
        EXPECT_DOUBLE_EQ(t.number(1, "x"), 4);
    }
    expectError("t,x\r1,2\r2,q\r", "f.csv:3: column 2 'x': 'q' is not a number");
}

TEST(CsvTable, LongLinesAndNulBytesAreRefusedWhileReading)
{
    // A stream that would never end (a device file): the cap stops it.
    struct Endless : std::streambuf
    {
        int underflow() override
        {
            setg(buf, buf, buf + sizeof(buf));
            return 'a';
        }
        char buf[4096] = {};
    };
    Endless endless;
    for (char& c : endless.buf)
    {
        c = 'a';
    }
    std::istream in(&endless);
    try
    {
        (void)CsvTable::FromStream(in, "f.csv", {"t"});
        FAIL() << "no error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("f.csv:1: the line is longer than 1048576 bytes"),
                  std::string::npos)
            << std::string(e.what()).substr(0, 200);
    }
    expectError("t,x\n" + std::string(2 << 20, '7') + ",1\n",
                "f.csv:2: the line is longer than 1048576 bytes (1 MiB)");
    expectError(std::string("t,x\n1,2\0\n", 9), "f.csv:2: byte 4 of the line is a NUL byte");
}

TEST(CsvTable, ValuesInMessagesAreEscapedAndCut)
{
    const std::string cell = "\x1b[2J" + std::string(200, 'z');
    const std::string e = errorOf("t,x\n1," + cell + "\n");
    EXPECT_NE(e.find("f.csv:2: column 2 'x': '\\x1B[2Jzzz"), std::string::npos) << e;
    EXPECT_NE(e.find("z\u2026' is not a number"), std::string::npos) << e;
    EXPECT_EQ(e.find('\x1b'), std::string::npos) << e;
    EXPECT_LT(e.size(), 200u) << e;
    const std::string header = errorOf(std::string(100000, 'h') + ",t,x\n1,2,3\n");
    EXPECT_LT(header.size(), 200u) << header.substr(0, 300);
    EXPECT_NE(header.find("column 1 'hhh"), std::string::npos) << header;
}

TEST(CsvTable, TimesInMessagesAreFixedPoint)
{
    expectError("t,x\n1700000039,0\n1700000000,0\n",
                "time 1700000000 goes back: it is before 1700000039 (line 2)");
}

TEST(ShownValue, EscapesWhatDoesNotPrintAndCuts)
{
    using semloc::shownValue;
    EXPECT_EQ(shownValue("range_m"), "range_m");
    EXPECT_EQ(shownValue("a\tb\r\x7f"), "a\\x09b\\x0D\\x7F");
    EXPECT_EQ(shownValue("\xEF\xBB\xBFt"), "\\xEF\\xBB\\xBFt");  // U+FEFF prints nothing
    EXPECT_EQ(shownValue("\xC3\xA9pave"), "\xC3\xA9pave");       // UTF-8 text is kept
    EXPECT_EQ(shownValue("\xC3("), "\\xC3(");                    // not UTF-8
    EXPECT_EQ(shownValue(std::string(60, 'a')), std::string(60, 'a'));
    EXPECT_EQ(shownValue(std::string(61, 'a')), std::string(60, 'a') + "\u2026");
    EXPECT_EQ(shownValue(std::string(100, '\x01')),
              []
              {
                  std::string s;
                  for (int i = 0; i < 15; i++)
                  {
                      s += "\\x01";
                  }
                  return s + "\u2026";
              }());
}

}  // namespace

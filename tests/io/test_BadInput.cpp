/* semloc tests — every row of docs/bad-input.md's table, run through the real tools:
 * the case's bad input is built in a fresh directory, the tool runs on it, and
 * - `error` rows: exit code != 0, stderr holds the row's message, the directory is
 *   unchanged (no output, nothing half-written);
 * - `counted` rows: exit code 0 and summary.yaml holds the row's excerpt (semloc-import's
 *   rows: its summary line on stdout);
 * - `accepted` rows (an input that looks wrong but is fine): the same as `counted`;
 * - `warning` rows (a figure gnuplot cannot draw): exit code 0, stderr holds the row's
 *   message, the outputs are written.
 * A row without a case below, or a case without a row, fails TableAndCasesMatch. */
#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"

#include "io/BadInputBuilders.h"

namespace
{
using namespace semloc::test::bad_input;

/** One row of the table. */
struct Row
{
    std::string id, tool, result, message;
};

/** The rows between the bad-input markers: | `id` | tool | input | case | result | `message` |. */
std::vector<Row> tableRows()
{
    std::istringstream in(readText(kSrc + "/docs/bad-input.md"));
    std::vector<Row> rows;
    bool inside = false;
    for (std::string line; std::getline(in, line);)
    {
        if (line.find("<!-- bad-input:begin -->") != std::string::npos)
        {
            inside = true;
            continue;
        }
        if (line.find("<!-- bad-input:end -->") != std::string::npos)
        {
            break;
        }
        if (!inside || line.rfind("| `", 0) != 0)
        {
            continue;
        }
        std::vector<std::string> cells;
        for (size_t b = 1, e; (e = line.find(" | ", b)) != std::string::npos || b < line.size();)
        {
            if (e == std::string::npos)
            {
                e = line.rfind(" |");
            }
            std::string c = line.substr(b, e - b);
            c.erase(0, c.find_first_not_of(' '));
            cells.push_back(c);
            b = e + 3;
            if (b >= line.size())
            {
                break;
            }
        }
        auto unquote = [](std::string s)
        {
            if (s.size() >= 2 && s.front() == '`' && s.back() == '`')
            {
                s = s.substr(1, s.size() - 2);
            }
            return s;
        };
        EXPECT_EQ(cells.size(), 6u) << line;
        if (cells.size() == 6)
        {
            rows.push_back({unquote(cells[0]), cells[1], cells[4], unquote(cells[5])});
        }
    }
    return rows;
}

// ------------------------------------------------------------------ inputs
/** Every case of the table, by id (each id once). */
const Cases& cases()
{
    static const Cases c = []
    {
        Cases all;
        for (const auto& group : allCaseGroups())
        {
            for (const auto& [id, builder] : group)
            {
                if (!all.emplace(id, builder).second)
                {
                    throw std::logic_error("bad-input case '" + id + "' defined twice");
                }
            }
        }
        return all;
    }();
    return c;
}

/** Relative paths of every file and directory under `dir`, each file with its contents
 *  (a file overwritten in place changes the listing too). */
std::set<std::string> listing(const fs::path& dir)
{
    std::set<std::string> s;
    for (const auto& e : fs::recursive_directory_iterator(dir))
    {
        const std::string contents = e.is_regular_file() ? readText(e.path()) : std::string();
        s.insert(fs::relative(e.path(), dir).string() + " " +
                 std::to_string(std::hash<std::string>()(contents)));
    }
    return s;
}

std::string quoted(const std::string& s)
{
    std::string q = "'";
    for (const char c : s)
    {
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return q + "'";
}

void PrintTo(const Row& r, std::ostream* os)
{
    *os << r.id;
}

class BadInput : public ::testing::TestWithParam<Row>
{
};

TEST_P(BadInput, FailsClearlyOrCounts)
{
    const Row& row = GetParam();
    const auto it = cases().find(row.id);
    ASSERT_NE(it, cases().end()) << "table row '" << row.id << "' has no case in this test";
    const fs::path base =
        fs::path(SEMLOC_TEST_OUT) / "bad_input" / (row.id + "_" + std::to_string(::getpid()));
    fs::remove_all(base);
    const fs::path dir = base / "case";
    fs::create_directories(dir);
    const auto args = it->second(dir);
    ASSERT_FALSE(args.empty());
    EXPECT_EQ(args[0], row.tool) << "the table names another tool";
    const auto before = listing(dir);

    // A case with a fake-bin/ directory (a gnuplot that refuses a figure) runs with it first
    // on the PATH.
    const std::string path = fs::exists(dir / "fake-bin")
                                 ? "PATH=" + quoted((dir / "fake-bin").string()) + ":\"$PATH\" "
                                 : std::string();
    std::string cmd = "cd " + quoted(dir.string()) + " && " + path + quoted(kBin + "/" + args[0]);
    for (size_t i = 1; i < args.size(); i++)
    {
        cmd += " " + quoted(args[i]);
    }
    cmd += " >" + quoted((base / "stdout").string()) + " 2>" + quoted((base / "stderr").string());
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << "the tool crashed: " << cmd;
    const int rc = WEXITSTATUS(status);
    const std::string err = readText(base / "stderr");

    if (row.result == "error")
    {
        EXPECT_NE(rc, 0) << cmd;
        EXPECT_NE(err.find(row.message), std::string::npos) << "stderr:\n"
                                                            << err << "\nexpected to contain:\n"
                                                            << row.message;
        EXPECT_EQ(listing(dir), before) << "the failed run left files behind";
    }
    else if (row.result == "warning")
    {
        // A figure left out: exit 0, the warning on stderr, every other output written.
        EXPECT_EQ(rc, 0) << err;
        EXPECT_NE(err.find(row.message), std::string::npos) << "stderr:\n"
                                                            << err << "\nexpected to contain:\n"
                                                            << row.message;
        EXPECT_NE(listing(dir), before) << "nothing was written";
    }
    else
    {
        ASSERT_TRUE(row.result.rfind("counted", 0) == 0 || row.result == "accepted")
            << "result must be error, counted or accepted";
        ASSERT_EQ(rc, 0) << err;
        // semloc-import writes no summary.yaml: its summary line (stdout) holds the counts.
        const bool import = row.tool == "semloc-import";
        const std::string summary =
            readText(import ? base / "stdout" : dir / "out" / "summary.yaml");
        EXPECT_NE(summary.find(row.message), std::string::npos)
            << (import ? "the summary line:\n" : "summary.yaml:\n") << summary
            << "\nexpected to contain: " << row.message;
        if (row.id == "rawlog-truncated-allowed")
        {
            EXPECT_NE(err.find("--allow-truncated: localizing with the"), std::string::npos) << err;
        }
    }
    if (!HasFailure())
    {
        fs::remove_all(base);
    }
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, ::testing::ValuesIn(tableRows()),
                         [](const ::testing::TestParamInfo<Row>& p)
                         {
                             std::string n = p.param.id;
                             for (char& c : n)
                             {
                                 c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                             }
                             return n;
                         });

TEST(BadInputTable, TableAndCasesMatch)
{
    const auto rows = tableRows();
    ASSERT_GE(rows.size(), 30u) << "docs/bad-input.md's table is missing or short";
    std::set<std::string> ids;
    for (const auto& r : rows)
    {
        EXPECT_TRUE(ids.insert(r.id).second) << "duplicate table row " << r.id;
        EXPECT_TRUE(cases().count(r.id)) << "table row '" << r.id << "' has no case";
        EXPECT_FALSE(r.message.empty()) << r.id << ": no message";
    }
    for (const auto& [id, builder] : cases())
    {
        EXPECT_TRUE(ids.count(id)) << "case '" << id << "' has no table row";
    }
}

}  // namespace

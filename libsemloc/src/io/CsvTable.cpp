/* semloc — CsvTable: a comma-separated table with a header row, read strictly. */
#include "io/CsvTable.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/Text.h"

namespace semloc::detail
{
namespace
{
/** The trimmed cells of one line. */
std::vector<std::string> splitCells(const std::string& line)
{
    std::vector<std::string> cells;
    size_t b = 0;
    for (;;)
    {
        const size_t e = line.find(',', b);
        cells.push_back(trim(line.substr(b, e == std::string::npos ? std::string::npos : e - b)));
        if (e == std::string::npos)
        {
            return cells;
        }
        b = e + 1;
    }
}

std::string joined(const std::vector<std::string>& names)
{
    std::string s;
    for (const auto& n : names)
    {
        s += (s.empty() ? "" : ", ") + n;
    }
    return s;
}

/** Checks the header against the columns wanted; throws naming the file and column. */
void checkHeader(const std::vector<std::string>& header, const std::string& at,
                 const std::vector<std::string>& required, const std::vector<std::string>& optional)
{
    auto known = required;
    known.insert(known.end(), optional.begin(), optional.end());
    for (size_t c = 0; c < header.size(); c++)
    {
        if (std::find(known.begin(), known.end(), header[c]) == known.end())
        {
            THROW_EXCEPTION(mrpt::format("%s column %zu '%s': unknown column (known: %s)",
                                         at.c_str(), c + 1, header[c].c_str(),
                                         joined(known).c_str()));
        }
        if (std::find(header.begin(), header.begin() + static_cast<long>(c), header[c]) !=
            header.begin() + static_cast<long>(c))
        {
            THROW_EXCEPTION(mrpt::format("%s column %zu '%s': named twice", at.c_str(), c + 1,
                                         header[c].c_str()));
        }
    }
    for (const auto& r : required)
    {
        if (std::find(header.begin(), header.end(), r) == header.end())
        {
            THROW_EXCEPTION(mrpt::format("%s missing column '%s' (the header names: %s)",
                                         at.c_str(), r.c_str(), joined(header).c_str()));
        }
    }
}
}  // namespace

CsvTable CsvTable::FromFile(const std::string& path, const std::vector<std::string>& required,
                            const std::vector<std::string>& optional)
{
    if (std::filesystem::is_directory(path))
    {
        THROW_EXCEPTION("'" + path + "' is a directory, not a file");
    }
    std::ifstream f(path, std::ios::binary);
    if (!f)
    {
        THROW_EXCEPTION("cannot read '" + path + "'");
    }
    std::ostringstream text;
    text << f.rdbuf();
    return FromText(text.str(), path, required, optional);
}

CsvTable CsvTable::FromText(const std::string& text, const std::string& name,
                            const std::vector<std::string>& required,
                            const std::vector<std::string>& optional)
{
    CsvTable t;
    t.m_name = name;
    std::istringstream in(text);
    bool haveHeader = false;
    std::string line;
    for (size_t n = 1; std::getline(in, line); n++)
    {
        const std::string trimmed = trim(line);
        if (trimmed.empty() || trimmed[0] == '#')
        {
            continue;
        }
        auto cells = splitCells(line);
        const std::string at = mrpt::format("%s:%zu:", name.c_str(), n);
        if (!haveHeader)
        {
            checkHeader(cells, at, required, optional);
            t.m_header = std::move(cells);
            t.m_headerLine = n;
            haveHeader = true;
            continue;
        }
        if (cells.size() != t.m_header.size())
        {
            THROW_EXCEPTION(mrpt::format("%s expected %zu cells (%s), found %zu", at.c_str(),
                                         t.m_header.size(), joined(t.m_header).c_str(),
                                         cells.size()));
        }
        t.m_rows.push_back(std::move(cells));
        t.m_lines.push_back(n);
    }
    if (!haveHeader)
    {
        THROW_EXCEPTION("'" + name + "' has no header row (expected the columns " +
                        joined(required) + ")");
    }
    return t;
}

size_t CsvTable::index(const std::string& column) const
{
    const auto it = std::find(m_header.begin(), m_header.end(), column);
    return it == m_header.end() ? std::numeric_limits<size_t>::max()
                                : static_cast<size_t>(it - m_header.begin());
}

bool CsvTable::has(const std::string& column) const
{
    return index(column) != std::numeric_limits<size_t>::max();
}

std::string CsvTable::text(size_t row, const std::string& column) const
{
    const size_t c = index(column);
    return c == std::numeric_limits<size_t>::max() ? std::string() : m_rows.at(row)[c];
}

bool CsvTable::empty(size_t row, const std::string& column) const
{
    return text(row, column).empty();
}

void CsvTable::fail(size_t row, const std::string& column, const std::string& what) const
{
    const size_t c = index(column);
    const std::string where = c == std::numeric_limits<size_t>::max()
                                  ? "'" + column + "' (not a column of the header)"
                                  : mrpt::format("column %zu '%s'", c + 1, column.c_str());
    THROW_EXCEPTION(mrpt::format("%s:%zu: %s: %s", m_name.c_str(), m_lines.at(row), where.c_str(),
                                 what.c_str()));
}

double CsvTable::number(size_t row, const std::string& column) const
{
    const std::string s = text(row, column);
    if (s.empty())
    {
        fail(row, column, "empty (a number is required)");
    }
    // strtod, not >>: it reads "nan" and "inf", which get their own message.
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0')
    {
        fail(row, column, "'" + s + "' is not a number");
    }
    if (!std::isfinite(v))
    {
        fail(row, column, "'" + s + "' is not a finite number");
    }
    return v;
}

double CsvTable::numberOr(size_t row, const std::string& column, double fallback) const
{
    return empty(row, column) ? fallback : number(row, column);
}

void CsvTable::checkIncreasing(const std::string& column, bool strictly) const
{
    for (size_t r = 1; r < m_rows.size(); r++)
    {
        const double prev = number(r - 1, column), t = number(r, column);
        if (t < prev || (strictly && t == prev))
        {
            fail(r, column,
                 "time " + shortestText(t) +
                     (t < prev ? " goes back: it is before " : " is not after ") +
                     shortestText(prev) + mrpt::format(" (line %zu): times must ", m_lines[r - 1]) +
                     (strictly ? "increase" : "not go back"));
        }
    }
}

}  // namespace semloc::detail

/* semloc — CsvTable: a comma-separated table with a header row, read strictly. */
#include "dataset/CsvTable.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/ErrorMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "dataset/GzReadBuffer.h"
#include "io/Text.h"

namespace semloc::detail
{
namespace
{
/** Reads the next line of `in` (ended by LF, CRLF, CR or the end of the stream) into `line`
 *  without its end; false at the end of the stream. Throws "<name>:<n>: ..." for a line
 *  longer than kMaxCsvLineBytes or holding a NUL byte, before reading further. */
bool readLine(std::istream& in, std::string& line, const std::string& name, size_t n)
{
    line.clear();
    std::streambuf* buf = in.rdbuf();
    for (bool any = false;; any = true)
    {
        const int c = buf->sbumpc();
        if (c == std::char_traits<char>::eof())
        {
            return any;
        }
        if (c == '\n')
        {
            return true;
        }
        if (c == '\r')
        {
            if (buf->sgetc() == '\n')
            {
                buf->sbumpc();
            }
            return true;
        }
        if (c == '\0')
        {
            THROW_EXCEPTION(
                mrpt::format("%s:%zu: byte %zu of the line is a NUL byte: not a text "
                             "file",
                             name.c_str(), n, line.size() + 1));
        }
        if (line.size() >= kMaxCsvLineBytes)
        {
            THROW_EXCEPTION(
                mrpt::format("%s:%zu: the line is longer than %zu bytes (1 MiB): not a "
                             "CSV file?",
                             name.c_str(), n, kMaxCsvLineBytes));
        }
        line.push_back(static_cast<char>(c));
    }
}

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
                                         at.c_str(), c + 1, shownValue(header[c]).c_str(),
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
    // A regular file (GzReadBuffer checks it), plain or gz-compressed: zlib reads a file without
    // the gzip header as it is.
    GzReadBuffer buf(path);
    std::istream in(&buf);
    return FromStream(in, path, required, optional);
}

CsvTable CsvTable::FromText(const std::string& text, const std::string& name,
                            const std::vector<std::string>& required,
                            const std::vector<std::string>& optional)
{
    std::istringstream in(text);
    return FromStream(in, name, required, optional);
}

CsvTable CsvTable::FromStream(std::istream& in, const std::string& name,
                              const std::vector<std::string>& required,
                              const std::vector<std::string>& optional)
{
    CsvTable t;
    t.m_name = name;
    bool haveHeader = false;
    std::string line;
    size_t n = 1;
    auto next = [&]
    {
        try
        {
            return readLine(in, line, name, n);
        }
        catch (const GzReadBuffer::Damaged& e)
        {
            THROW_EXCEPTION(mrpt::format("%s:%zu: %s", name.c_str(), n, e.what()));
        }
    };
    for (; next(); n++)
    {
        if (n == 1 && line.rfind(kUtf8Bom, 0) == 0)
        {
            line.erase(0, std::string(kUtf8Bom).size());  // as some editors write it
        }
        const std::string trimmed = trim(line);
        if (trimmed.empty() || trimmed[0] == '#')
        {
            continue;
        }
        if (haveHeader)
        {
            t.addRow(line, n);
            continue;
        }
        t.m_header = splitCells(line);
        checkHeader(t.m_header, mrpt::format("%s:%zu:", name.c_str(), n), required, optional);
        t.m_headerLine = n;
        haveHeader = true;
    }
    if (in.bad())
    {
        THROW_EXCEPTION("cannot read '" + name + "'");
    }
    if (!haveHeader)
    {
        THROW_EXCEPTION("'" + name + "' has no header row (expected the columns " +
                        joined(required) + ")");
    }
    return t;
}

void CsvTable::addRow(const std::string& line, size_t lineNumber)
{
    const size_t cells = static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (cells != m_header.size())
    {
        THROW_EXCEPTION(mrpt::format("%s:%zu: expected %zu cells (%s), found %zu", m_name.c_str(),
                                     lineNumber, m_header.size(), joined(m_header).c_str(), cells));
    }
    for (const auto& c : splitCells(line))
    {
        m_cells += c;
        m_cellEnd.push_back(m_cells.size());
    }
    m_lines.push_back(lineNumber);
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
    if (c == std::numeric_limits<size_t>::max())
    {
        return {};
    }
    const size_t k = row * m_header.size() + c;
    const size_t b = k == 0 ? 0 : m_cellEnd.at(k - 1);
    return m_cells.substr(b, m_cellEnd.at(k) - b);
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
        fail(row, column, "'" + shownValue(s) + "' is not a number");
    }
    if (!std::isfinite(v))
    {
        fail(row, column, "'" + shownValue(s) + "' is not a finite number");
    }
    return v;
}

double CsvTable::numberOr(size_t row, const std::string& column, double fallback) const
{
    return empty(row, column) ? fallback : number(row, column);
}

void CsvTable::checkIncreasing(const std::string& column, bool strictly) const
{
    for (size_t r = 1; r < rows(); r++)
    {
        const double prev = number(r - 1, column), t = number(r, column);
        if (t < prev || (strictly && t == prev))
        {
            fail(r, column,
                 "time " + timeText(t) +
                     (t < prev ? " goes back: it is before " : " is not after ") + timeText(prev) +
                     mrpt::format(" (line %zu): times must ", m_lines[r - 1]) +
                     (strictly ? "increase" : "not go back"));
        }
    }
}

}  // namespace semloc::detail

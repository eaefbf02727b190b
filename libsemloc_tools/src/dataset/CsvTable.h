/* semloc — a comma-separated table with a header row, read strictly (private). */
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace semloc::detail
{
/** Longest line of a CSV file [bytes]: a longer one (a binary file, /dev/zero) is refused
 *  before it is held in memory. */
constexpr size_t kMaxCsvLineBytes = size_t{1} << 20;

/** A CSV file of semloc-import's dataset format (docs/tools.md, "semloc-import"): a header row
 *  naming the columns (any order), then one row per line; lines end with LF, CRLF or CR; a
 *  UTF-8 byte-order mark before the first line is skipped; lines that are blank or start with
 *  `#` are skipped; cells are separated by commas and trimmed of blanks (no quoting: a cell
 *  holds no comma). A line longer than kMaxCsvLineBytes or holding a NUL byte is refused.
 *  Every error names the file, the line and, for a cell, its column (number and name), and
 *  quotes values through shownValue(): `det.csv:7: column 3 'range_m': 'abc' is not a
 *  number`. The cells are held in one string (memory: about the file's size plus 8 bytes a
 *  cell). */
class CsvTable
{
public:
    /** Reads `path`. The header must name every column of `required` and may name those of
     *  `optional`; any other column, one named twice, a row with another number of cells
     *  than the header and a file without a header are errors. */
    static CsvTable FromFile(const std::string& path, const std::vector<std::string>& required,
                             const std::vector<std::string>& optional = {});
    /** The same from a stream, `name` standing for the file in messages. */
    static CsvTable FromStream(std::istream& in, const std::string& name,
                               const std::vector<std::string>& required,
                               const std::vector<std::string>& optional = {});
    /** The same from `text`. */
    static CsvTable FromText(const std::string& text, const std::string& name,
                             const std::vector<std::string>& required,
                             const std::vector<std::string>& optional = {});

    /** The file's name as messages give it. */
    const std::string& name() const { return m_name; }
    /** Number of data rows. */
    size_t rows() const { return m_lines.size(); }
    /** True when the header names `column`. */
    bool has(const std::string& column) const;
    /** The line (from 1) of the header row. */
    size_t headerLine() const { return m_headerLine; }
    /** The line (from 1) of data row `row`. */
    size_t line(size_t row) const { return m_lines[row]; }

    /** The trimmed text of a cell ("" for a column the header does not name). */
    std::string text(size_t row, const std::string& column) const;
    /** True when the cell is empty (or the header does not name the column). */
    bool empty(size_t row, const std::string& column) const;
    /** The cell as a finite number; throws naming the cell if it is empty, not a number
     *  (the whole cell must be one) or not finite. */
    double number(size_t row, const std::string& column) const;
    /** The cell as a number, or `fallback` when it is empty or the column is absent. */
    double numberOr(size_t row, const std::string& column, double fallback) const;

    /** Checks that the numbers of `column` never go back (`strictly`: always increase);
     *  throws naming the line, the column and the line before otherwise. */
    void checkIncreasing(const std::string& column, bool strictly) const;

    /** Throws "<file>:<line>: column <n> '<column>': <what>" ("<file>:<line>: '<column>' (not
     *  a column of the header): <what>" for an optional column the header lacks). */
    [[noreturn]] void fail(size_t row, const std::string& column, const std::string& what) const;

private:
    size_t index(const std::string& column) const;
    void addRow(const std::string& line, size_t lineNumber);

    std::string m_name;
    std::vector<std::string> m_header;
    /** Every cell's trimmed text, one after the other; cell k (row r, column c: k = r *
     *  columns + c) is m_cells[m_cellEnd[k - 1], m_cellEnd[k]) (from 0 for k = 0). */
    std::string m_cells;
    std::vector<size_t> m_cellEnd;
    std::vector<size_t> m_lines;
    size_t m_headerLine = 0;
};

}  // namespace semloc::detail

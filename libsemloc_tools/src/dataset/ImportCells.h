/* semloc — the cells of semloc-import's CSV files that several readers share (private). */
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "dataset/CsvTable.h"

namespace semloc::detail
{
/** A cell that must be a number within [-limit, limit] (`unit` for the message: "x 1e+308 is
 *  beyond +-1e+07 m"). */
double boundedCell(const CsvTable& t, size_t row, const std::string& col, double limit,
                   const char* unit);
/** A position cell: within the world's bound, +-1e7 m. */
double positionCell(const CsvTable& t, size_t row, const std::string& col);
/** An id cell: decimal digits (a leading '-' allowed), a whole number in [lo, hi]; `0x10`,
 *  `1e3`, `+5` or `16.0`, which read as numbers, are refused. */
long integerCell(const CsvTable& t, size_t row, const std::string& col, long lo, long hi);
/** The table of the file at `path`, or of `in` (standing for `path` in messages) if given. */
CsvTable openTable(std::istream* in, const std::string& path,
                   const std::vector<std::string>& required,
                   const std::vector<std::string>& optional = {});
}  // namespace semloc::detail

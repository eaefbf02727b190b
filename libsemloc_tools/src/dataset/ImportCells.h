/* semloc — the cells of semloc-import's CSV files that several readers share (private). */
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <istream>
#include <string>
#include <vector>

#include "dataset/CsvTable.h"

namespace semloc
{
struct TDatasetImportStats;
}

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

/** A time cell [s]: within +-kMaxImportTime_s, else refused with the unit it looks like. */
double timeCell(const CsvTable& t, size_t row, const std::string& col);
/** A time cell of a file whose times stamp observations (detections, depth, heading, fixes):
 *  a timeCell() that is not 0, MRPT's "no timestamp". */
double stampCell(const CsvTable& t, size_t row);
/** A heading cell [rad]: within +-kMaxImportHeading_rad, wrapped to [-pi, pi]. */
double headingValueCell(const CsvTable& t, size_t row, const std::string& col);
/** Whether a detection time `time` is of the scan that began at `first`, `window_s` long. */
inline bool inScan(double first, double time, double window_s)
{
    // To the microsecond: times since 1970 carry ~0.2 us of rounding.
    return time == first || (window_s > 0 && time - first <= window_s + 1e-6);
}
/** Within `tol` of each other (an absolute tolerance). */
inline bool near(double a, double b, double tol = 1e-6)
{
    return std::abs(a - b) <= tol;
}
/** The rows of `t` (times never going back) kept: the last of each run of rows of one time.
 *  Counts the others in `repeated`; `same(a, b)` tells whether rows a and b hold one reading,
 *  and when a row dropped does not, a warning in `stats` ("WHAT: 2 of the 3 repeated times
 *  hold another READING than their last row (the first on line 7): the last is kept"). */
std::vector<size_t> lastOfEachTime(const CsvTable& t,
                                   const std::function<bool(size_t, size_t)>& same,
                                   size_t& repeated, TDatasetImportStats* stats,
                                   const std::string& what, const std::string& reading,
                                   const std::string& consequence);
}  // namespace semloc::detail

/* semloc — DatasetImport's readers of the vehicle's own sensors: the depth, heading and fixes
 * CSV files of semloc-import (docs/tools.md, "semloc-import"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/CObservationDepth.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <istream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "dataset/CsvTable.h"
#include "dataset/ImportCells.h"
#include "io/Text.h"

namespace semloc
{
using detail::CsvTable;
using detail::near;
using detail::openTable;
using detail::positionCell;
using detail::stampCell;

namespace
{
/** The rows kept of a reading table (the last of each time), its times and cells checked by
 *  `check`, the repeated times counted in `counts` (`same`: whether two rows agree). */
std::vector<size_t> readingRows(const CsvTable& t, const std::function<void(size_t)>& check,
                                const std::function<bool(size_t, size_t)>& same,
                                TImportReadingCounts* counts, TDatasetImportStats* stats,
                                const std::string& what, const std::string& reading)
{
    t.checkIncreasing("t", false);
    for (size_t r = 0; r < t.rows(); r++)  // every row, also those a later one replaces
    {
        stampCell(t, r);
        check(r);
    }
    size_t repeated = 0;
    auto kept = detail::lastOfEachTime(t, same, repeated, stats, what, reading, "");
    if (counts != nullptr)
    {
        counts->repeatedTimes += repeated;
    }
    if (kept.empty())
    {
        THROW_EXCEPTION("'" + t.name() + "' holds no " + reading + " readings");
    }
    return kept;
}

/** A depth row's depth [m] (down), within [-kMaxImportHeight_m, kMaxImportDepth_m]. */
double depthCell(const CsvTable& t, size_t r)
{
    const double d = t.number(r, "depth_m");
    if (d < -kMaxImportHeight_m || d > kMaxImportDepth_m)
    {
        t.fail(r, "depth_m",
               "depth " + detail::shortestText(d) +
                   " m is outside [-10000, 100000] m (metres down from the surface)");
    }
    return d;
}

/** A depth row's altitude over the seabed [m] (NaN when empty). */
double altitudeCell(const CsvTable& t, size_t r)
{
    if (t.empty(r, "altitude_m"))
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const double a = t.number(r, "altitude_m");
    if (a < 0 || a > kMaxImportDepth_m)
    {
        t.fail(r, "altitude_m",
               "altitude " + detail::shortestText(a) +
                   " m is outside [0, 100000] m (metres over the seabed; empty: not measured)");
    }
    return a;
}

/** A warning for the depth readings CObservationDepth::problem() refuses (the models skip
 *  them). */
void warnDepthsSkipped(const CsvTable& t, const std::vector<size_t>& kept,
                       const std::vector<DepthReading>& out, TDatasetImportStats* stats)
{
    size_t n = 0, line = 0;
    std::string first;
    for (size_t k = 0; k < out.size(); k++)
    {
        CObservationDepth o;
        o.depth_m = out[k].depth_m;
        o.altitude_m = out[k].altitude_m;
        if (std::string p = o.problem(); !p.empty())
        {
            line = n++ == 0 ? t.line(kept[k]) : line;
            first = first.empty() ? p : first;
        }
    }
    if (stats != nullptr && n > 0)
    {
        stats->warnings.push_back(mrpt::format(
            "depth '%s': %zu readings the detector models do not take (the first on line %zu: "
            "%s): written as they are",
            t.name().c_str(), n, line, first.c_str()));
    }
}

std::vector<DepthReading> depthOf(std::istream* in, const std::string& path,
                                  TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t", "depth_m"}, {"altitude_m"});
    auto same = [&](size_t a, size_t b)
    {
        const double x = altitudeCell(t, a), y = altitudeCell(t, b);
        return near(depthCell(t, a), depthCell(t, b)) &&
               (std::isnan(x) ? std::isnan(y) : near(x, y));
    };
    const auto kept = readingRows(
        t,
        [&](size_t r)
        {
            depthCell(t, r);
            altitudeCell(t, r);
        },
        same, stats ? &stats->depth : nullptr, stats, "depth '" + path + "'", "depth");
    std::vector<DepthReading> out;
    out.reserve(kept.size());
    for (const size_t r : kept)
    {
        out.push_back({t.number(r, "t"), depthCell(t, r), altitudeCell(t, r)});
    }
    warnDepthsSkipped(t, kept, out, stats);
    return out;
}

std::vector<HeadingReading> headingOf(std::istream* in, const std::string& path,
                                      TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t", "heading_rad"});
    auto cell = [&](size_t r) { return detail::headingValueCell(t, r, "heading_rad"); };
    const auto kept = readingRows(
        t, [&](size_t r) { cell(r); },
        [&](size_t a, size_t b) { return near(mrpt::math::wrapToPi(cell(a) - cell(b)), 0); },
        stats ? &stats->heading : nullptr, stats, "heading '" + path + "'", "heading");
    std::vector<HeadingReading> out;
    out.reserve(kept.size());
    for (const size_t r : kept)
    {
        out.push_back({t.number(r, "t"), cell(r)});
    }
    return out;
}
/** Checks the standard deviation columns of a fixes table: `sigma_m` or both `sigma_x_m`,
 *  `sigma_y_m`, or none. */
void checkFixColumns(const CsvTable& t)
{
    const bool sx = t.has("sigma_x_m"), sy = t.has("sigma_y_m");
    if (t.has("sigma_m") && (sx || sy))
    {
        THROW_EXCEPTION(
            mrpt::format("%s:%zu: column '%s': the fixes give sigma_m and %s: one "
                         "form of the standard deviations, not both",
                         t.name().c_str(), t.headerLine(), sx ? "sigma_x_m" : "sigma_y_m",
                         sx && sy ? "sigma_x_m,sigma_y_m"
                         : sx     ? "sigma_x_m"
                                  : "sigma_y_m"));
    }
    if (sx != sy)
    {
        THROW_EXCEPTION(
            mrpt::format("%s:%zu: column '%s': given without %s: give both standard "
                         "deviations, sigma_m, or none",
                         t.name().c_str(), t.headerLine(), sx ? "sigma_x_m" : "sigma_y_m",
                         sx ? "sigma_y_m" : "sigma_x_m"));
    }
}

/** A fix's standard deviation [m] of column `col`: positive, at most 1e7 m. */
double sigmaCell(const CsvTable& t, size_t r, const std::string& col)
{
    const double s = t.number(r, col);
    if (!(s > 0 && s <= kMaxWorldCoordinate_m))
    {
        t.fail(r, col,
               col + " " + detail::shortestText(s) +
                   " is not a standard deviation in (0, 1e7] m: it must be positive");
    }
    return s;
}

/** The fix of row `r`: its position, height (`z`, or minus the depth before it) and standard
 *  deviations. */
FixReading fixRow(const CsvTable& t, size_t r, const std::vector<DepthReading>& depth)
{
    FixReading f;
    f.t = t.number(r, "t");
    f.x = positionCell(t, r, "x");
    f.y = positionCell(t, r, "y");
    if (!t.empty(r, "z"))
    {
        f.z = detail::boundedCell(t, r, "z", kMaxImportDepth_m, "m");
    }
    else if (!depth.empty())
    {
        // The last depth reading at or before the fix (the first one before any).
        auto it = std::upper_bound(depth.begin(), depth.end(), f.t,
                                   [](double time, const DepthReading& d) { return time < d.t; });
        f.z = -(it == depth.begin() ? depth.front() : *std::prev(it)).depth_m;
    }
    if (t.has("sigma_m"))
    {
        f.sigma_x_m = f.sigma_y_m = sigmaCell(t, r, "sigma_m");
    }
    else if (t.has("sigma_x_m"))
    {
        f.sigma_x_m = sigmaCell(t, r, "sigma_x_m");
        f.sigma_y_m = sigmaCell(t, r, "sigma_y_m");
    }
    return f;
}

std::vector<FixReading> fixesOf(std::istream* in, const std::string& path,
                                const std::vector<DepthReading>& depth, TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t", "x", "y"}, {"z", "sigma_m", "sigma_x_m", "sigma_y_m"});
    checkFixColumns(t);
    const auto kept = readingRows(
        t, [&](size_t r) { fixRow(t, r, depth); },
        [&](size_t a, size_t b) {
            return near(t.number(a, "x"), t.number(b, "x")) &&
                   near(t.number(a, "y"), t.number(b, "y"));
        },
        stats ? &stats->fixes : nullptr, stats, "fixes '" + path + "'", "fix");
    std::vector<FixReading> out;
    out.reserve(kept.size());
    for (const size_t r : kept)
    {
        out.push_back(fixRow(t, r, depth));
    }
    if (stats != nullptr && !t.has("sigma_m") && !t.has("sigma_x_m"))
    {
        stats->warnings.push_back(
            "fixes '" + path +
            "' carry no standard deviation (columns sigma_m, or sigma_x_m and sigma_y_m): "
            "written with a standard deviation of 1 m; set sigma_m in the poseFixMap's "
            "likelihoodOpts, or let "
            "semloc-calibrate fit it");
    }
    return out;
}
}  // namespace

std::vector<DepthReading> DatasetImport::readDepth(const std::string& path,
                                                   TDatasetImportStats* stats)
{
    return depthOf(nullptr, path, stats);
}

std::vector<DepthReading> DatasetImport::readDepth(std::istream& in, const std::string& name)
{
    return depthOf(&in, name, nullptr);
}

std::vector<HeadingReading> DatasetImport::readHeading(const std::string& path,
                                                       TDatasetImportStats* stats)
{
    return headingOf(nullptr, path, stats);
}

std::vector<HeadingReading> DatasetImport::readHeading(std::istream& in, const std::string& name)
{
    return headingOf(&in, name, nullptr);
}

std::vector<FixReading> DatasetImport::readFixes(const std::string& path,
                                                 const std::vector<DepthReading>& depth,
                                                 TDatasetImportStats* stats)
{
    return fixesOf(nullptr, path, depth, stats);
}

std::vector<FixReading> DatasetImport::readFixes(std::istream& in, const std::string& name)
{
    return fixesOf(&in, name, {}, nullptr);
}

}  // namespace semloc

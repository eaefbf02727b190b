/* semloc — DatasetImport's readers: the odometry, detections, ground-truth and landmarks CSV
 * files of semloc-import (docs/tools.md, "semloc-import"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <istream>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "dataset/CsvTable.h"
#include "dataset/ImportCells.h"
#include "io/Text.h"

namespace semloc
{
using detail::CsvTable;
using detail::integerCell;
using detail::openTable;
using detail::positionCell;

namespace detail
{
/** A cell that must be a number within [-limit, limit] (`unit` for the message: "x 1e+308 is
 *  beyond +-1e+07 m"). */
double boundedCell(const CsvTable& t, size_t row, const std::string& col, double limit,
                   const char* unit)
{
    const double v = t.number(row, col);
    if (std::abs(v) > limit)
    {
        t.fail(row, col,
               col + " " + detail::shortestText(v) + " is beyond +-" + detail::shortestText(limit) +
                   " " + unit);
    }
    return v;
}

/** A position cell: within the world's bound, +-1e7 m. */
double positionCell(const CsvTable& t, size_t row, const std::string& col)
{
    return boundedCell(t, row, col, kMaxWorldCoordinate_m, "m");
}

long integerCell(const CsvTable& t, size_t row, const std::string& col, long lo, long hi)
{
    // strtod would read 0x10 and 1e3 as 16 and 1000: an id is decimal digits.
    const std::string text = t.text(row, col);
    const double v = t.number(row, col);
    const size_t sign = text[0] == '-' ? 1 : 0;
    const bool digits = text.size() > sign && text.size() <= sign + 10 &&
                        std::all_of(text.begin() + static_cast<long>(sign), text.end(),
                                    [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    {
        t.fail(row, col,
               "'" + shownValue(text) +
                   mrpt::format("' is not an integer of decimal digits in [%ld, %ld]", lo, hi));
    }
    return static_cast<long>(v);
}

/** The table of the file at `path`, or of `in` (standing for `path` in messages) if given. */
CsvTable openTable(std::istream* in, const std::string& path,
                   const std::vector<std::string>& required,
                   const std::vector<std::string>& optional)
{
    return in != nullptr ? CsvTable::FromStream(*in, path, required, optional)
                         : CsvTable::FromFile(path, required, optional);
}

}  // namespace detail

namespace
{
/** Forward speed `v` and yaw rate `w` held for `dt` from `p`: the exact arc. */
mrpt::math::TPose2D integrate(const mrpt::math::TPose2D& p, double v, double w, double dt)
{
    const double dphi = w * dt;
    mrpt::math::TPose2D q = p;
    if (std::abs(dphi) < 1e-9)
    {
        q.x += v * dt * std::cos(p.phi + 0.5 * dphi);
        q.y += v * dt * std::sin(p.phi + 0.5 * dphi);
    }
    else
    {
        const double r = v / w;
        q.x += r * (std::sin(p.phi + dphi) - std::sin(p.phi));
        q.y -= r * (std::cos(p.phi + dphi) - std::cos(p.phi));
    }
    q.phi = mrpt::math::wrapToPi(p.phi + dphi);
    return q;
}

/** A time cell [s]: within +-kMaxImportTime_s, else refused with the unit it looks like. */
double timeCell(const CsvTable& t, size_t row, const std::string& col)
{
    const double v = t.number(row, col);
    if (std::abs(v) > kMaxImportTime_s)
    {
        t.fail(row, col,
               "time " + detail::timeText(v) +
                   " is beyond +-1e11 s (3170 years): are the times in " +
                   DatasetImport::likelyTimeUnit(std::abs(v) / 2e9) +
                   "? semloc-import takes seconds (e.g. since 1970)");
    }
    return v;
}

/** One detection row (the label is not empty). */
TSemanticDetection detectionRow(const CsvTable& t, size_t r)
{
    TSemanticDetection d;
    d.label = t.text(r, "label");
    if (const std::string p = labelProblem(d.label); !p.empty())
    {
        t.fail(r, "label", p);
    }
    d.range_m = boundedCell(t, r, "range_m", kMaxWorldCoordinate_m, "m");
    if (d.range_m < 0)
    {
        t.fail(r, "range_m", "range " + detail::shortestText(d.range_m) + " is negative");
    }
    d.bearing_rad = t.number(r, "bearing_rad");
    if (std::abs(d.bearing_rad) > M_PI)
    {
        t.fail(r, "bearing_rad",
               "bearing " + detail::shortestText(d.bearing_rad) +
                   " is outside [-pi, pi]: are the bearings in degrees? semloc-import takes "
                   "radians in [-pi, pi]");
    }
    d.confidence = t.numberOr(r, "confidence", 1.0);
    if (!(d.confidence >= 0 && d.confidence <= 1))
    {
        t.fail(r, "confidence",
               "confidence " + shownValue(t.text(r, "confidence")) + " is not in [0, 1]");
    }
    d.object_id = t.empty(r, "id") ? -1
                                   : static_cast<int32_t>(integerCell(
                                         t, r, "id", -1, std::numeric_limits<int32_t>::max()));
    if (d.object_id == 0)
    {
        t.fail(r, "id", "id 0: object ids are positive (-1 or empty: unknown)");
    }
    return d;
}

/** Checks that a row marking an empty scan has no other cell. */
void checkEmptyScanRow(const CsvTable& t, size_t r)
{
    for (const char* c : {"range_m", "bearing_rad", "id", "confidence"})
    {
        if (!t.empty(r, c))
        {
            t.fail(r, c,
                   "a row without a label marks a scan with no detections and has no other "
                   "cell but t");
        }
    }
}

/** Within `tol` of each other (an absolute tolerance). */
bool near(double a, double b, double tol = 1e-6)
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
                                   const std::string& consequence)
{
    std::vector<size_t> kept;
    size_t differing = 0, firstLine = 0, dropped = 0;
    for (size_t r = 0; r < t.rows(); r++)
    {
        size_t last = r;
        while (last + 1 < t.rows() && t.number(last + 1, "t") == t.number(r, "t"))
        {
            last++;
        }
        for (size_t d = r; d < last; d++, dropped++)
        {
            if (!same(d, last))
            {
                firstLine = differing++ == 0 ? t.line(d) : firstLine;
            }
        }
        kept.push_back(last);
        r = last;
    }
    repeated += dropped;
    if (stats != nullptr && differing > 0)
    {
        stats->warnings.push_back(mrpt::format(
            "%s: %zu of the %zu repeated times hold another %s than their last row (the first "
            "on line %zu): the last is kept%s",
            what.c_str(), differing, dropped, reading.c_str(), firstLine, consequence.c_str()));
    }
    return kept;
}

/** Checks an odometry file's columns; true for poses (t,x,y,phi), false for speeds (t,v,w). */
bool odometryHasPoses(const CsvTable& t, const std::string& path)
{
    const bool poses = t.has("x") || t.has("y") || t.has("phi");
    const std::vector<std::string> columns =
        poses ? std::vector<std::string>{"x", "y", "phi"} : std::vector<std::string>{"v", "w"};
    for (const auto& c : columns)
    {
        if (!t.has(c))
        {
            THROW_EXCEPTION(
                mrpt::format("%s:%zu: missing column '%s' (odometry is t,x,y,phi "
                             "or t,v,w)",
                             path.c_str(), t.headerLine(), c.c_str()));
        }
    }
    if (poses && (t.has("v") || t.has("w")))
    {
        THROW_EXCEPTION(
            mrpt::format("%s:%zu: column '%s': odometry is t,x,y,phi or t,v,w, not both",
                         path.c_str(), t.headerLine(), t.has("v") ? "v" : "w"));
    }
    return poses;
}

/** A pose row's heading (wrapped to [-pi, pi]). */
double headingCell(const CsvTable& t, size_t r)
{
    return mrpt::math::wrapToPi(boundedCell(t, r, "phi", kMaxImportHeading_rad, "rad"));
}

/** Whether pose rows a and b of `t` hold one pose (to the micrometre and microradian). */
bool samePose(const CsvTable& t, size_t a, size_t b)
{
    return near(t.number(a, "x"), t.number(b, "x")) && near(t.number(a, "y"), t.number(b, "y")) &&
           near(mrpt::math::wrapToPi(headingCell(t, a) - headingCell(t, b)), 0);
}

/** Whether a detection time `time` is of the scan that began at `first`. */
bool inScan(double first, double time, double window_s)
{
    // To the microsecond: times since 1970 carry ~0.2 us of rounding.
    return time == first || (window_s > 0 && time - first <= window_s + 1e-6);
}

/** Warnings when grouping within `window_s` may have joined two scans: `repeatingId` grouped
 *  scans hold one id twice (the first on line `line`), or the scans are less than 5 windows
 *  apart (median). */
void warnGrouping(const std::vector<DetectionScan>& scans, double window_s, size_t repeatingId,
                  size_t line, const std::string& path, TDatasetImportStats& stats)
{
    const std::string what = "detections '" + path + "'";
    const std::string w = detail::shortestText(window_s);
    if (repeatingId > 0)
    {
        stats.warnings.push_back(mrpt::format(
            "%s: %zu %s within --scan-window-s %s s %s one id twice (the first on line %zu): "
            "are they readings of two scans? a shorter window keeps them apart",
            what.c_str(), repeatingId, repeatingId == 1 ? "scan grouped" : "scans grouped",
            w.c_str(), repeatingId == 1 ? "holds" : "hold", line));
    }
    std::vector<double> dt;
    for (size_t k = 1; k < scans.size(); k++)
    {
        dt.push_back(scans[k].t - scans[k - 1].t);
    }
    if (dt.empty())
    {
        return;
    }
    std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
    const double median = dt[dt.size() / 2];
    if (median < 5 * window_s)
    {
        stats.warnings.push_back(mrpt::format(
            "%s: the scans are %s s apart (median), less than 5 times --scan-window-s %s s: "
            "readings of different scans may have been grouped into one",
            what.c_str(), detail::timeText(median).c_str(), w.c_str()));
    }
}
}  // namespace

void TDatasetImportOptions::check() const
{
    auto bad = [](const std::string& opt, double v, const std::string& what)
    { THROW_EXCEPTION(opt + " " + detail::shortestText(v) + ": must be " + what); };
    if (!(maxRange_m > 0 && maxRange_m <= kMaxWorldCoordinate_m))
    {
        bad("--max-range-m", maxRange_m, "a finite number in (0, 1e7] [m]");
    }
    if (!(fov_deg > 0 && fov_deg <= 360))
    {
        bad("--fov-deg", fov_deg, "in (0, 360] [deg]");
    }
    if (!(maxStep_s > 0 && maxStep_s <= 1e6))
    {
        bad("--max-step-s", maxStep_s, "in (0, 1e6] [s]");
    }
    if (!(margin_m >= 0 && margin_m <= kMaxWorldCoordinate_m))
    {
        bad("--margin-m", margin_m, "a finite number in [0, 1e7] [m]");
    }
    if (!(scanWindow_s >= 0 && scanWindow_s <= 1))
    {
        bad("--scan-window-s", scanWindow_s, "in [0, 1] [s]");
    }
    if (!(gtMaxGap_s >= 0 && gtMaxGap_s <= 1e6))
    {
        bad("--gt-max-gap-s", gtMaxGap_s, "in [0, 1e6] [s] (0: the default)");
    }
    const auto& p = sensorPose;
    if (!(std::abs(p.x) <= 1000 && std::abs(p.y) <= 1000 && std::isfinite(p.phi)))
    {
        THROW_EXCEPTION("--sensor-pose: x and y must be finite and within 1000 m of the vehicle");
    }
}

mrpt::math::TPose2D OdometryTrack::at(double time) const
{
    ASSERT_(!t.empty() && time >= t.front() && time <= t.back());
    size_t i = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
    if (i >= t.size())
    {
        return pose.back();
    }
    const size_t a = i - 1;
    const double f = (time - t[a]) / (t[i] - t[a]);
    const auto& p = pose[a];
    const auto& q = pose[i];
    return {p.x + f * (q.x - p.x), p.y + f * (q.y - p.y),
            mrpt::math::wrapToPi(p.phi + f * mrpt::math::wrapToPi(q.phi - p.phi))};
}

static OdometryTrack odometryOf(std::istream* in, const std::string& path,
                                TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t"}, {"x", "y", "phi", "v", "w"});
    const bool poses = odometryHasPoses(t, path);
    t.checkIncreasing("t", false);
    for (size_t r = 0; r < t.rows(); r++)  // every row, also those a later one replaces
    {
        timeCell(t, r, "t");
        if (poses)
        {
            positionCell(t, r, "x");
            positionCell(t, r, "y");
            headingCell(t, r);
        }
        else
        {
            boundedCell(t, r, "v", kMaxImportSpeed_mps, "m/s");
            boundedCell(t, r, "w", kMaxImportYawRate_radps, "rad/s");
        }
    }
    auto same = [&](size_t a, size_t b)
    {
        return poses ? samePose(t, a, b)
                     : near(t.number(a, "v"), t.number(b, "v")) &&
                           near(t.number(a, "w"), t.number(b, "w"));
    };
    size_t repeated = 0;
    const auto kept = lastOfEachTime(t, same, repeated, stats, "odometry '" + path + "'",
                                     poses ? "pose" : "speed", ", the others held for no time");
    if (stats != nullptr)
    {
        stats->odometryRepeatedTimes += repeated;
    }
    if (kept.size() < 2)
    {
        THROW_EXCEPTION("'" + path +
                        "' holds fewer than 2 odometry rows of distinct times: no motion to "
                        "import");
    }
    OdometryTrack odo;
    mrpt::math::TPose2D p(0, 0, 0);
    for (size_t k = 0; k < kept.size(); k++)
    {
        const size_t r = kept[k];
        odo.t.push_back(t.number(r, "t"));
        if (poses)
        {
            p = {t.number(r, "x"), t.number(r, "y"), headingCell(t, r)};
        }
        else if (k > 0)
        {
            // The speeds of the last row of the previous time, held until this one.
            const size_t q = kept[k - 1];
            p = integrate(p, t.number(q, "v"), t.number(q, "w"), odo.t[k] - odo.t[k - 1]);
            if (std::abs(p.x) > kMaxWorldCoordinate_m || std::abs(p.y) > kMaxWorldCoordinate_m)
            {
                t.fail(r, "t",
                       "the speeds integrated to this row's time reach (" +
                           detail::shortestText(p.x) + ", " + detail::shortestText(p.y) +
                           ") m, beyond the world's bound of +-1e7 m");
            }
        }
        odo.pose.push_back(p);
    }
    return odo;
}

static std::vector<DetectionScan> detectionsOf(std::istream* in, const std::string& path,
                                               double scanWindow_s, TDatasetImportStats* stats)
{
    const auto t =
        openTable(in, path, {"t", "label", "range_m", "bearing_rad"}, {"id", "confidence"});
    t.checkIncreasing("t", false);
    std::vector<DetectionScan> scans;
    bool markedEmpty = false;  // the current scan has a row without a label
    bool repeatsId = false;    // the current scan has a grouped row repeating an id
    size_t grouped = 0, repeatingId = 0, repeatLine = 0;
    for (size_t r = 0; r < t.rows(); r++)
    {
        const double time = timeCell(t, r, "t");
        if (time == 0)
        {
            t.fail(r, "t",
                   "time 0 is MRPT's 'no timestamp': shift the times (e.g. to seconds "
                   "since 1970)");
        }
        if (scans.empty() || !inScan(scans.back().t, time, scanWindow_s))
        {
            scans.push_back({time, {}});
            markedEmpty = repeatsId = false;
        }
        const bool later = time != scans.back().t, emptyRow = t.empty(r, "label");
        grouped += later ? 1 : 0;
        if (emptyRow)
        {
            checkEmptyScanRow(t, r);
        }
        else
        {
            const auto d = detectionRow(t, r);
            auto& dets = scans.back().detections;
            if (later && !repeatsId && d.object_id > 0 &&
                std::any_of(dets.begin(), dets.end(),
                            [&](const TSemanticDetection& e)
                            { return e.object_id == d.object_id; }))
            {
                repeatsId = true;
                repeatLine = repeatingId++ == 0 ? t.line(r) : repeatLine;
            }
            dets.push_back(d);
        }
        if ((emptyRow && !scans.back().detections.empty()) || (!emptyRow && markedEmpty))
        {
            t.fail(r, "label",
                   "the scan at time " + detail::timeText(scans.back().t) +
                       " is marked empty (a row without a label) and has detections");
        }
        markedEmpty = markedEmpty || emptyRow;
    }
    if (scans.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no scans");
    }
    if (stats != nullptr && grouped > 0)
    {
        stats->detectionsGrouped += grouped;
        stats->scanWindow_s = scanWindow_s;
        warnGrouping(scans, scanWindow_s, repeatingId, repeatLine, path, *stats);
    }
    return scans;
}

static std::vector<GroundTruthRow> groundTruthOf(std::istream* in, const std::string& path,
                                                 TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t", "x", "y", "phi"});
    t.checkIncreasing("t", false);
    for (size_t r = 0; r < t.rows(); r++)  // every row, also those a later one replaces
    {
        timeCell(t, r, "t");
        positionCell(t, r, "x");
        positionCell(t, r, "y");
        headingCell(t, r);
    }
    size_t repeated = 0;
    const auto kept = lastOfEachTime(
        t, [&](size_t a, size_t b) { return samePose(t, a, b); }, repeated, stats,
        "ground truth '" + path + "'", "pose", "");
    if (stats != nullptr)
    {
        stats->groundTruthRepeatedTimes += repeated;
    }
    std::vector<GroundTruthRow> rows;
    for (const size_t r : kept)
    {
        rows.push_back({t.number(r, "t"), t.number(r, "x"), t.number(r, "y"), headingCell(t, r)});
    }
    if (rows.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no ground-truth rows");
    }
    return rows;
}

OdometryTrack DatasetImport::readOdometry(const std::string& path, TDatasetImportStats* stats)
{
    return odometryOf(nullptr, path, stats);
}

std::vector<DetectionScan> DatasetImport::readDetections(const std::string& path,
                                                         double scanWindow_s,
                                                         TDatasetImportStats* stats)
{
    return detectionsOf(nullptr, path, scanWindow_s, stats);
}

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(const std::string& path,
                                                           TDatasetImportStats* stats)
{
    return groundTruthOf(nullptr, path, stats);
}

OdometryTrack DatasetImport::readOdometry(std::istream& in, const std::string& name)
{
    return odometryOf(&in, name, nullptr);
}

std::vector<DetectionScan> DatasetImport::readDetections(std::istream& in, const std::string& name)
{
    return detectionsOf(&in, name, kDefaultScanWindow_s, nullptr);
}

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(std::istream& in,
                                                           const std::string& name)
{
    return groundTruthOf(&in, name, nullptr);
}

}  // namespace semloc

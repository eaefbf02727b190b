/* semloc — DatasetImport's detections reader: the detections CSV file of semloc-import
 * (docs/tools.md, "semloc-import"), its scans per sensor, side-scan and bearing-only rows. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <istream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "dataset/CsvTable.h"
#include "dataset/ImportCells.h"
#include "io/Text.h"

namespace semloc
{
using detail::boundedCell;
using detail::CsvTable;
using detail::inScan;
using detail::integerCell;
using detail::openTable;

namespace
{
/** The bearing of a side-scan row's `side` cell: +pi/2 to port (`port`, `left`), -pi/2 to
 *  starboard (`starboard`, `right`), in any case. */
double sideBearing(const CsvTable& t, size_t r)
{
    std::string side = t.text(r, "side");
    std::transform(side.begin(), side.end(), side.begin(),
                   [](char c)
                   { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; });
    if (side == "port" || side == "left")
    {
        return M_PI / 2;
    }
    if (side == "starboard" || side == "right")
    {
        return -M_PI / 2;
    }
    t.fail(r, "side",
           "'" + shownValue(t.text(r, "side")) +
               "' is no side: port or left (bearing +pi/2), starboard or right (-pi/2), or empty");
}

/** A detection row's bearing: its side's, or its `bearing_rad` within [-pi, pi]. */
double bearingCell(const CsvTable& t, size_t r)
{
    if (!t.empty(r, "side"))
    {
        if (!t.empty(r, "bearing_rad"))
        {
            t.fail(r, "bearing_rad",
                   "a side-scan row (side '" + shownValue(t.text(r, "side")) +
                       "') has its bearing from its side: bearing_rad must be empty");
        }
        return sideBearing(t, r);
    }
    const double b = t.number(r, "bearing_rad");
    if (std::abs(b) > M_PI)
    {
        t.fail(r, "bearing_rad",
               "bearing " + detail::shortestText(b) +
                   " is outside [-pi, pi]: are the bearings in degrees? semloc-import takes "
                   "radians in [-pi, pi]");
    }
    return b;
}

/** One detection row (the label is not empty); an empty range: a bearing-only detection. */
TSemanticDetection detectionRow(const CsvTable& t, size_t r)
{
    TSemanticDetection d;
    d.label = t.text(r, "label");
    if (const std::string p = labelProblem(d.label); !p.empty())
    {
        t.fail(r, "label", p);
    }
    d.range_m = t.empty(r, "range_m") ? std::numeric_limits<double>::quiet_NaN()
                                      : boundedCell(t, r, "range_m", kMaxWorldCoordinate_m, "m");
    if (d.range_m < 0)
    {
        t.fail(r, "range_m", "range " + detail::shortestText(d.range_m) + " is negative");
    }
    d.bearing_rad = bearingCell(t, r);
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

/** Checks that a row marking an empty scan has no other cell (but its sensor). */
void checkEmptyScanRow(const CsvTable& t, size_t r)
{
    for (const char* c : {"range_m", "bearing_rad", "id", "confidence", "side"})
    {
        if (!t.empty(r, c))
        {
            t.fail(r, c,
                   "a row without a label marks a scan with no detections and has no other "
                   "cell but t (and sensor)");
        }
    }
}

/** A row's sensor label: its `sensor` cell, kDefaultImportSensor when empty or absent. */
std::string sensorCell(const CsvTable& t, size_t r)
{
    std::string s = t.text(r, "sensor");
    if (s.empty())
    {
        return kDefaultImportSensor;
    }
    if (const std::string p = labelProblem(s); !p.empty())
    {
        t.fail(r, "sensor", "sensor " + p);
    }
    return s;
}

/** The median of `v` (not empty), reordering it. */
double median(std::vector<double>& v)
{
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

/** Warnings when grouping within `window_s` may have joined two scans: `repeatingId` grouped
 *  scans hold one id twice (the first on line `line`), or a sensor's scans are less than 5
 *  windows apart (the median over every sensor's consecutive scans). */
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
    std::map<std::string, double> last;  // each sensor's last scan time
    for (const auto& s : scans)
    {
        if (const auto it = last.find(s.sensor); it != last.end())
        {
            dt.push_back(s.t - it->second);
        }
        last[s.sensor] = s.t;
    }
    if (dt.empty())
    {
        return;
    }
    const double m = median(dt);
    if (m < 5 * window_s)
    {
        stats.warnings.push_back(mrpt::format(
            "%s: the scans are %s s apart (median), less than 5 times --scan-window-s %s s: "
            "readings of different scans may have been grouped into one",
            what.c_str(), detail::timeText(m).c_str(), w.c_str()));
    }
}

/** The scan a sensor's rows are collecting. */
struct OpenScan
{
    size_t index = 0;          // in the scans
    bool markedEmpty = false;  // it has a row without a label
    bool repeatsId = false;    // it has a grouped row repeating an id
};

/** The scans of a detections table, and what warnGrouping() needs. */
struct ScanGrouping
{
    std::vector<DetectionScan> scans;
    std::map<std::string, OpenScan> open;  // by sensor
    size_t grouped = 0, repeatingId = 0, repeatLine = 0;

    /** Adds row `r` of `t` at `time` to its sensor's scan (a new one past the window). */
    void add(const CsvTable& t, size_t r, double time, double window_s)
    {
        const std::string sensor = sensorCell(t, r);
        auto it = open.find(sensor);
        if (it == open.end() || !inScan(scans[it->second.index].t, time, window_s))
        {
            scans.push_back({time, {}, sensor});
            it = open.insert_or_assign(sensor, OpenScan{scans.size() - 1}).first;
        }
        OpenScan& o = it->second;
        DetectionScan& scan = scans[o.index];
        const bool later = time != scan.t, emptyRow = t.empty(r, "label");
        grouped += later ? 1 : 0;
        if (emptyRow)
        {
            checkEmptyScanRow(t, r);
        }
        else
        {
            const auto d = detectionRow(t, r);
            auto& dets = scan.detections;
            if (later && !o.repeatsId && d.object_id > 0 &&
                std::any_of(dets.begin(), dets.end(),
                            [&](const TSemanticDetection& e)
                            { return e.object_id == d.object_id; }))
            {
                o.repeatsId = true;
                repeatLine = repeatingId++ == 0 ? t.line(r) : repeatLine;
            }
            dets.push_back(d);
        }
        if ((emptyRow && !scan.detections.empty()) || (!emptyRow && o.markedEmpty))
        {
            t.fail(r, "label",
                   "the scan at time " + detail::timeText(scan.t) +
                       (sensor == kDefaultImportSensor ? std::string() : " of sensor " + sensor) +
                       " is marked empty (a row without a label) and has detections");
        }
        o.markedEmpty = o.markedEmpty || emptyRow;
    }
};
}  // namespace

static std::vector<DetectionScan> detectionsOf(std::istream* in, const std::string& path,
                                               double scanWindow_s, TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t", "label", "range_m", "bearing_rad"},
                             {"id", "confidence", "sensor", "side"});
    t.checkIncreasing("t", false);
    ScanGrouping g;
    for (size_t r = 0; r < t.rows(); r++)
    {
        g.add(t, r, detail::stampCell(t, r), scanWindow_s);
    }
    if (g.scans.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no scans");
    }
    if (stats != nullptr && g.grouped > 0)
    {
        stats->detectionsGrouped += g.grouped;
        stats->scanWindow_s = scanWindow_s;
        warnGrouping(g.scans, scanWindow_s, g.repeatingId, g.repeatLine, path, *stats);
    }
    return std::move(g.scans);
}

std::vector<DetectionScan> DatasetImport::readDetections(const std::string& path,
                                                         double scanWindow_s,
                                                         TDatasetImportStats* stats)
{
    return detectionsOf(nullptr, path, scanWindow_s, stats);
}

std::vector<DetectionScan> DatasetImport::readDetections(std::istream& in, const std::string& name)
{
    return detectionsOf(&in, name, kDefaultScanWindow_s, nullptr);
}

}  // namespace semloc

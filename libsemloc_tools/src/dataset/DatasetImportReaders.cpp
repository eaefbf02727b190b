/* semloc — DatasetImport's readers: the odometry and ground-truth CSV files of semloc-import
 * (docs/tools.md, "semloc-import"), and the cells the readers share (the detections are read
 * in DatasetImportDetections.cpp, the depth, heading and fixes in DatasetImportReadings.cpp). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <istream>
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

double stampCell(const CsvTable& t, size_t row)
{
    const double time = timeCell(t, row, "t");
    if (time == 0)
    {
        t.fail(row, "t",
               "time 0 is MRPT's 'no timestamp': shift the times (e.g. to seconds "
               "since 1970)");
    }
    return time;
}

double headingValueCell(const CsvTable& t, size_t row, const std::string& col)
{
    return mrpt::math::wrapToPi(boundedCell(t, row, col, kMaxImportHeading_rad, "rad"));
}

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

}  // namespace detail

namespace
{
using detail::lastOfEachTime;
using detail::near;
using detail::timeCell;

/** Forward speed `v` and yaw rate `w` held for `dt` from `p`: the exact arc. With a speed to
 *  port `vy` (a DVL's body-frame velocities; 0: the arithmetic of the speeds' form), the arc
 *  the vehicle crabs along: dx = (v (sin p1 - sin p0) + vy (cos p1 - cos p0)) / w, dy = (v
 *  (cos p0 - cos p1) + vy (sin p1 - sin p0)) / w, p1 = p0 + w dt (a straight line for
 *  |w dt| < 1e-9). */
mrpt::math::TPose2D integrate(const mrpt::math::TPose2D& p, double v, double vy, double w,
                              double dt)
{
    const double dphi = w * dt;
    mrpt::math::TPose2D q = p;
    if (vy != 0)
    {
        const double p0 = p.phi, p1 = p.phi + dphi;
        if (std::abs(dphi) < 1e-9)
        {
            const double c = std::cos(p0 + 0.5 * dphi), s = std::sin(p0 + 0.5 * dphi);
            q.x += (v * c - vy * s) * dt;
            q.y += (v * s + vy * c) * dt;
        }
        else
        {
            q.x += (v * (std::sin(p1) - std::sin(p0)) + vy * (std::cos(p1) - std::cos(p0))) / w;
            q.y += (v * (std::cos(p0) - std::cos(p1)) + vy * (std::sin(p1) - std::sin(p0))) / w;
        }
    }
    else if (std::abs(dphi) < 1e-9)
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

/** The three forms of an odometry file. */
enum class OdometryForm
{
    Poses,       // t,x,y,phi
    Speeds,      // t,v,w
    Velocities,  // t,vx,vy,w
};

/** The form of an odometry file's columns; throws naming the header line and the column for a
 *  column missing or one of another form. */
OdometryForm odometryForm(const CsvTable& t, const std::string& path)
{
    const bool poses = t.has("x") || t.has("y") || t.has("phi");
    const bool dvl = !poses && (t.has("vx") || t.has("vy"));
    const OdometryForm form = poses ? OdometryForm::Poses
                              : dvl ? OdometryForm::Velocities
                                    : OdometryForm::Speeds;
    const std::vector<std::string> columns = poses ? std::vector<std::string>{"x", "y", "phi"}
                                             : dvl ? std::vector<std::string>{"vx", "vy", "w"}
                                                   : std::vector<std::string>{"v", "w"};
    for (const auto& c : columns)
    {
        if (!t.has(c))
        {
            THROW_EXCEPTION(
                mrpt::format("%s:%zu: missing column '%s' (odometry is t,x,y,phi, t,v,w or "
                             "t,vx,vy,w)",
                             path.c_str(), t.headerLine(), c.c_str()));
        }
    }
    for (const char* c : {"v", "w", "vx", "vy"})
    {
        if (t.has(c) && std::find(columns.begin(), columns.end(), c) == columns.end())
        {
            THROW_EXCEPTION(mrpt::format(
                "%s:%zu: column '%s': odometry is t,x,y,phi, t,v,w or t,vx,vy,w, one form, not "
                "several%s",
                path.c_str(), t.headerLine(), c, dvl ? " (the DVL's forward speed is vx)" : ""));
        }
    }
    return form;
}

/** The speed columns of an odometry file of `form` (not poses): forward, to port ("" for the
 *  speeds' form), yaw rate. */
std::vector<std::string> speedColumns(OdometryForm form)
{
    return form == OdometryForm::Velocities ? std::vector<std::string>{"vx", "vy", "w"}
                                            : std::vector<std::string>{"v", "", "w"};
}

/** A pose row's heading (wrapped to [-pi, pi]). */
double headingCell(const CsvTable& t, size_t r)
{
    return detail::headingValueCell(t, r, "phi");
}

/** Whether pose rows a and b of `t` hold one pose (to the micrometre and microradian). */
bool samePose(const CsvTable& t, size_t a, size_t b)
{
    return near(t.number(a, "x"), t.number(b, "x")) && near(t.number(a, "y"), t.number(b, "y")) &&
           near(mrpt::math::wrapToPi(headingCell(t, a) - headingCell(t, b)), 0);
}

}  // namespace

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

namespace
{
/** Checks every row's cells of an odometry table of `form`, also those a later one replaces. */
void checkOdometryCells(const CsvTable& t, OdometryForm form)
{
    const auto speeds = speedColumns(form);
    for (size_t r = 0; r < t.rows(); r++)
    {
        timeCell(t, r, "t");
        if (form == OdometryForm::Poses)
        {
            positionCell(t, r, "x");
            positionCell(t, r, "y");
            headingCell(t, r);
            continue;
        }
        for (size_t c = 0; c < 2; c++)
        {
            if (!speeds[c].empty())
            {
                boundedCell(t, r, speeds[c], kMaxImportSpeed_mps, "m/s");
            }
        }
        boundedCell(t, r, "w", kMaxImportYawRate_radps, "rad/s");
    }
}

/** The poses of the rows `kept` of an odometry table of `form`: its own, or its speeds (each
 *  row's held until the next) integrated from (0, 0, 0). */
OdometryTrack odometryTrack(const CsvTable& t, OdometryForm form, const std::vector<size_t>& kept)
{
    const auto speeds = speedColumns(form);
    OdometryTrack odo;
    mrpt::math::TPose2D p(0, 0, 0);
    for (size_t k = 0; k < kept.size(); k++)
    {
        const size_t r = kept[k];
        odo.t.push_back(t.number(r, "t"));
        if (form == OdometryForm::Poses)
        {
            p = {t.number(r, "x"), t.number(r, "y"), headingCell(t, r)};
        }
        else if (k > 0)
        {
            // The speeds of the last row of the previous time, held until this one.
            const size_t q = kept[k - 1];
            const double vy = speeds[1].empty() ? 0.0 : t.number(q, speeds[1]);
            p = integrate(p, t.number(q, speeds[0]), vy, t.number(q, "w"), odo.t[k] - odo.t[k - 1]);
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
}  // namespace

static OdometryTrack odometryOf(std::istream* in, const std::string& path,
                                TDatasetImportStats* stats)
{
    const auto t = openTable(in, path, {"t"}, {"x", "y", "phi", "v", "w", "vx", "vy"});
    const OdometryForm form = odometryForm(t, path);
    t.checkIncreasing("t", false);
    checkOdometryCells(t, form);
    const auto speeds = speedColumns(form);
    auto same = [&](size_t a, size_t b)
    {
        if (form == OdometryForm::Poses)
        {
            return samePose(t, a, b);
        }
        return std::all_of(speeds.begin(), speeds.end(),
                           [&](const std::string& c)
                           { return c.empty() || near(t.number(a, c), t.number(b, c)); });
    };
    size_t repeated = 0;
    const char* reading = form == OdometryForm::Poses        ? "pose"
                          : form == OdometryForm::Velocities ? "velocity"
                                                             : "speed";
    const auto kept = lastOfEachTime(t, same, repeated, stats, "odometry '" + path + "'", reading,
                                     ", the others held for no time");
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
    return odometryTrack(t, form, kept);
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
    rows.reserve(kept.size());
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

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(const std::string& path,
                                                           TDatasetImportStats* stats)
{
    return groundTruthOf(nullptr, path, stats);
}

OdometryTrack DatasetImport::readOdometry(std::istream& in, const std::string& name)
{
    return odometryOf(&in, name, nullptr);
}

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(std::istream& in,
                                                           const std::string& name)
{
    return groundTruthOf(&in, name, nullptr);
}

}  // namespace semloc

/* semloc — DatasetImport's readers: the odometry, detections, ground-truth and landmarks CSV
 * files of semloc-import (docs/tools.md, "semloc-import"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/io/DatasetImport.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <istream>
#include <iterator>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "io/CsvTable.h"
#include "io/Text.h"

namespace semloc
{
using detail::CsvTable;

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

/** A cell that must be a whole number in [lo, hi]. */
long integerCell(const CsvTable& t, size_t row, const std::string& col, long lo, long hi)
{
    const double v = t.number(row, col);
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    {
        t.fail(row, col,
               "'" + t.text(row, col) + mrpt::format("' is not an integer in [%ld, %ld]", lo, hi));
    }
    return static_cast<long>(v);
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
    d.range_m = t.number(r, "range_m");
    if (d.range_m < 0)
    {
        t.fail(r, "range_m", "range " + detail::shortestText(d.range_m) + " is negative");
    }
    d.bearing_rad = t.number(r, "bearing_rad");
    if (std::abs(d.bearing_rad) > 4 * M_PI)
    {
        t.fail(r, "bearing_rad", "bearing " + t.text(r, "bearing_rad") + " is beyond +-4 pi");
    }
    d.confidence = t.numberOr(r, "confidence", 1.0);
    if (!(d.confidence >= 0 && d.confidence <= 1))
    {
        t.fail(r, "confidence", "confidence " + t.text(r, "confidence") + " is not in [0, 1]");
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

/** The table a reader reads: the file `path`, or the text of `in` (if not null) named `path`. */
CsvTable table(std::istream* in, const std::string& path, const std::vector<std::string>& required,
               const std::vector<std::string>& optional = {})
{
    if (!in)
    {
        return CsvTable::FromFile(path, required, optional);
    }
    if (!*in)
    {
        THROW_EXCEPTION("cannot read '" + path + "'");
    }
    const std::string text{std::istreambuf_iterator<char>(*in), std::istreambuf_iterator<char>()};
    return CsvTable::FromText(text, path, required, optional);
}

/** Checks that the positions [m] in `columns` of row `r` lie within the world's coordinate
 *  bound: the import interpolates and differences positions, which beyond it could overflow. */
void checkPositions(const CsvTable& t, size_t r, std::initializer_list<const char*> columns)
{
    for (const char* c : columns)
    {
        if (!(std::abs(t.number(r, c)) <= kMaxWorldCoordinate_m))
        {
            t.fail(r, c, "position " + t.text(r, c) + " is beyond +-1e7 m (the world's bound)");
        }
    }
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

static OdometryTrack odometryOf(std::istream* in, const std::string& path)
{
    const auto t = table(in, path, {"t"}, {"x", "y", "phi", "v", "w"});
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
    t.checkIncreasing("t", true);
    if (t.rows() < 2)
    {
        THROW_EXCEPTION("'" + path + "' holds fewer than 2 odometry rows: no motion to import");
    }
    OdometryTrack odo;
    mrpt::math::TPose2D p(0, 0, 0);
    for (size_t r = 0; r < t.rows(); r++)
    {
        odo.t.push_back(t.number(r, "t"));
        if (poses)
        {
            checkPositions(t, r, {"x", "y"});
            p = {t.number(r, "x"), t.number(r, "y"), mrpt::math::wrapToPi(t.number(r, "phi"))};
        }
        else if (r > 0)
        {
            p = integrate(p, t.number(r - 1, "v"), t.number(r - 1, "w"), odo.t[r] - odo.t[r - 1]);
            if (!(std::abs(p.x) <= kMaxWorldCoordinate_m && std::abs(p.y) <= kMaxWorldCoordinate_m))
            {
                t.fail(r - 1, "v",
                       "these speeds, held to the next row, move the pose to (" +
                           detail::shortestText(p.x) + ", " + detail::shortestText(p.y) +
                           "), beyond +-1e7 m (the world's bound)");
            }
        }
        odo.pose.push_back(p);
    }
    if (!poses)
    {
        (void)t.number(t.rows() - 1, "v");  // the last row's speeds are checked too
        (void)t.number(t.rows() - 1, "w");
    }
    return odo;
}

static std::vector<DetectionScan> detectionsOf(std::istream* in, const std::string& path)
{
    const auto t = table(in, path, {"t", "label", "range_m", "bearing_rad"}, {"id", "confidence"});
    t.checkIncreasing("t", false);
    std::vector<DetectionScan> scans;
    bool markedEmpty = false;  // the current scan has a row without a label
    for (size_t r = 0; r < t.rows(); r++)
    {
        const double time = t.number(r, "t");
        if (time == 0)
        {
            t.fail(r, "t",
                   "time 0 is MRPT's 'no timestamp': shift the times (e.g. to seconds "
                   "since 1970)");
        }
        if (scans.empty() || scans.back().t != time)
        {
            scans.push_back({time, {}});
            markedEmpty = false;
        }
        const bool emptyRow = t.empty(r, "label");
        if (emptyRow)
        {
            checkEmptyScanRow(t, r);
        }
        else
        {
            scans.back().detections.push_back(detectionRow(t, r));
        }
        if ((emptyRow && !scans.back().detections.empty()) || (!emptyRow && markedEmpty))
        {
            t.fail(r, "label",
                   "the scan at time " + t.text(r, "t") +
                       " is marked empty (a row without a label) and has detections");
        }
        markedEmpty = markedEmpty || emptyRow;
    }
    if (scans.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no scans");
    }
    return scans;
}

static std::vector<GroundTruthRow> groundTruthOf(std::istream* in, const std::string& path)
{
    const auto t = table(in, path, {"t", "x", "y", "phi"});
    t.checkIncreasing("t", true);
    std::vector<GroundTruthRow> rows;
    for (size_t r = 0; r < t.rows(); r++)
    {
        checkPositions(t, r, {"x", "y"});
        rows.push_back({t.number(r, "t"), t.number(r, "x"), t.number(r, "y"),
                        mrpt::math::wrapToPi(t.number(r, "phi"))});
    }
    if (rows.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no ground-truth rows");
    }
    return rows;
}

static std::vector<ImportedLandmark> landmarksOf(std::istream* in, const std::string& path)
{
    const auto t = table(in, path, {"id", "label", "x", "y"}, {"sigma_x_m", "sigma_y_m"});
    std::vector<ImportedLandmark> out;
    std::map<long, size_t> lineOfId;
    for (size_t r = 0; r < t.rows(); r++)
    {
        ImportedLandmark l;
        const long id = integerCell(t, r, "id", 1, std::numeric_limits<int32_t>::max());
        if (const auto it = lineOfId.find(id); it != lineOfId.end())
        {
            t.fail(r, "id", mrpt::format("duplicate id %ld (first on line %zu)", id, it->second));
        }
        lineOfId[id] = t.line(r);
        l.object.id = static_cast<int>(id);
        l.object.label = t.text(r, "label");
        if (const std::string p = labelProblem(l.object.label); !p.empty())
        {
            t.fail(r, "label", p);
        }
        l.object.shape = ShapeType::Point;
        l.object.center = {t.number(r, "x"), t.number(r, "y")};
        for (auto [col, sigma] :
             {std::pair{"sigma_x_m", &l.sigma_x_m}, {"sigma_y_m", &l.sigma_y_m}})
        {
            *sigma = t.numberOr(r, col, std::numeric_limits<double>::quiet_NaN());
            if (*sigma < 0 || *sigma > kMaxWorldCoordinate_m)
            {
                t.fail(r, col, "a standard deviation must be in [0, 1e7] [m]");
            }
        }
        const bool hasX = !std::isnan(l.sigma_x_m), hasY = !std::isnan(l.sigma_y_m);
        if (hasX != hasY)
        {
            t.fail(r, hasX ? "sigma_x_m" : "sigma_y_m",
                   std::string("given without ") + (hasX ? "sigma_y_m" : "sigma_x_m") +
                       ": give both standard deviations or neither");
        }
        // The world's position uncertainty is isotropic: the one of the same total variance.
        l.object.sigma_m =
            hasX ? std::sqrt(0.5 * (l.sigma_x_m * l.sigma_x_m + l.sigma_y_m * l.sigma_y_m)) : 0.0;
        out.push_back(l);
    }
    if (out.empty())
    {
        THROW_EXCEPTION("'" + path + "' holds no landmarks");
    }
    return out;
}

OdometryTrack DatasetImport::readOdometry(const std::string& path)
{
    return odometryOf(nullptr, path);
}

std::vector<DetectionScan> DatasetImport::readDetections(const std::string& path)
{
    return detectionsOf(nullptr, path);
}

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(const std::string& path)
{
    return groundTruthOf(nullptr, path);
}

std::vector<ImportedLandmark> DatasetImport::readLandmarks(const std::string& path)
{
    return landmarksOf(nullptr, path);
}

OdometryTrack DatasetImport::readOdometry(std::istream& in, const std::string& name)
{
    return odometryOf(&in, name);
}

std::vector<DetectionScan> DatasetImport::readDetections(std::istream& in, const std::string& name)
{
    return detectionsOf(&in, name);
}

std::vector<GroundTruthRow> DatasetImport::readGroundTruth(std::istream& in,
                                                           const std::string& name)
{
    return groundTruthOf(&in, name);
}

std::vector<ImportedLandmark> DatasetImport::readLandmarks(std::istream& in,
                                                           const std::string& name)
{
    return landmarksOf(&in, name);
}

}  // namespace semloc

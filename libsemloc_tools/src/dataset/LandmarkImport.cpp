/* semloc — LandmarkImport: MRPT landmark datasets to semantic datasets. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/system/datetime.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/InputFile.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/Text.h"

namespace semloc
{
namespace
{
/** The shortest text that reads back as `v`. */
constexpr auto num = detail::shortestText;

/** Numeric columns of each data line of a text file; `minCols` enforced per line. */
std::vector<std::pair<size_t, std::vector<double>>> readRows(const std::string& path,
                                                             size_t minCols)
{
    (void)checkInputFile(path, "landmark file", InputKind::Text);
    std::ifstream f(path);
    if (!f)
    {
        THROW_EXCEPTION("cannot open '" + path + "' for reading");
    }
    std::vector<std::pair<size_t, std::vector<double>>> rows;
    std::string line;
    for (size_t n = 1; std::getline(f, line); n++)
    {
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '%' || line[b] == '#')
        {
            continue;
        }
        std::istringstream ss(line);
        std::vector<double> cols;
        std::string tok;
        while (ss >> tok)
        {
            char* end = nullptr;
            const double v = std::strtod(tok.c_str(), &end);
            if (end == tok.c_str() || *end != '\0' || !std::isfinite(v))
            {
                THROW_EXCEPTION(mrpt::format("'%s' line %u: '%s' is not a finite number",
                                             path.c_str(), static_cast<unsigned>(n), tok.c_str()));
            }
            cols.push_back(v);
        }
        if (cols.size() < minCols)
        {
            THROW_EXCEPTION(mrpt::format("'%s' line %u: expected at least %u columns, got %u",
                                         path.c_str(), static_cast<unsigned>(n),
                                         static_cast<unsigned>(minCols),
                                         static_cast<unsigned>(cols.size())));
        }
        rows.emplace_back(n, std::move(cols));
    }
    return rows;
}

void checkLabel(const std::string& label)
{
    if (const std::string p = labelProblem(label); !p.empty())
    {
        THROW_EXCEPTION("--label: " + p);
    }
}

void checkMargin(double margin_m)
{
    if (!(margin_m >= 0 && margin_m <= kMaxWorldCoordinate_m))
    {
        THROW_EXCEPTION("--margin " + num(margin_m) + ": must be a finite number in [0, " +
                        num(kMaxWorldCoordinate_m) + "] [m] (world coordinates lie within +-" +
                        num(kMaxWorldCoordinate_m) + " m)");
    }
}
}  // namespace

void LandmarkImport::checkOptions(const std::string& label, double margin_m)
{
    checkLabel(label);
    checkMargin(margin_m);
}

CObservationSemantic LandmarkImport::toSemantic(const mrpt::obs::CObservationBearingRange& obs,
                                                const std::string& label)
{
    CObservationSemantic s;
    s.sensorLabel = "SEMANTIC";
    s.timestamp = obs.timestamp;
    s.sensorPose = obs.sensorLocationOnRobot;
    s.maxRange_m = obs.maxSensorDistance;
    s.fov_rad = obs.fieldOfView_yaw > 0 ? static_cast<double>(obs.fieldOfView_yaw) : 2 * M_PI;
    for (const auto& m : obs.sensedData)
    {
        TSemanticDetection d;
        d.label = label;
        d.range_m = m.range;
        d.bearing_rad = m.yaw;
        d.confidence = 1.0;
        d.object_id = m.landmarkID >= 0 ? m.landmarkID : -1;
        s.detections.push_back(d);
    }
    return s;
}

size_t LandmarkImport::convertRawlog(mrpt::obs::CRawlog& log, const std::string& label)
{
    checkLabel(label);
    size_t n = 0;
    for (size_t i = 0; i < log.size(); i++)
    {
        if (log.getType(i) != mrpt::obs::CRawlog::etSensoryFrame)
        {
            continue;
        }
        auto sf = log.getAsObservations(i);
        for (auto& o : *sf)
        {
            if (const auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o))
            {
                o = std::make_shared<CObservationSemantic>(toSemantic(*br, label));
                n++;
            }
        }
    }
    return n;
}

std::vector<WorldObject> LandmarkImport::readLandmarks(const std::string& path,
                                                       const std::string& label)
{
    checkLabel(label);
    std::vector<WorldObject> out;
    for (const auto& [line, cols] : readRows(path, 4))
    {
        WorldObject o;
        const double id = cols.back();
        if (id != std::floor(id) || id < 0 || id > 2e9)
        {
            THROW_EXCEPTION(mrpt::format("'%s' line %u: last column must be a landmark id",
                                         path.c_str(), static_cast<unsigned>(line)));
        }
        o.id = static_cast<int>(id);
        o.label = label;
        o.shape = ShapeType::Point;
        o.center = {cols[0], cols[1]};
        o.z = cols[2];
        out.push_back(o);
    }
    bool hasZero = false;
    for (const auto& o : out)
    {
        hasZero |= (o.id == 0);
    }
    if (hasZero)
    {
        THROW_EXCEPTION("'" + path +
                        "': landmark id 0 found; semloc object ids must be positive (renumber "
                        "the landmarks from 1)");
    }
    return out;
}

std::vector<mrpt::math::TPose2D> LandmarkImport::readPath(const std::string& path)
{
    std::vector<mrpt::math::TPose2D> out;
    for (const auto& [line, cols] : readRows(path, 4))
    {
        (void)line;
        out.emplace_back(cols[0], cols[1], cols[3]);
    }
    return out;
}

World LandmarkImport::makeWorld(const std::vector<WorldObject>& landmarks,
                                const std::vector<mrpt::math::TPose2D>& path, double margin_m,
                                const std::string& name)
{
    checkMargin(margin_m);
    World w;
    w.name = name;
    bool first = true;
    auto grow = [&](double x, double y)
    {
        if (first)
        {
            w.bounds = {x, x, y, y};
            first = false;
        }
        w.bounds.x_min = std::min(w.bounds.x_min, x);
        w.bounds.x_max = std::max(w.bounds.x_max, x);
        w.bounds.y_min = std::min(w.bounds.y_min, y);
        w.bounds.y_max = std::max(w.bounds.y_max, y);
    };
    for (const auto& o : landmarks)
    {
        grow(o.center.x, o.center.y);
    }
    for (const auto& p : path)
    {
        grow(p.x, p.y);
    }
    if (first)
    {
        THROW_EXCEPTION("no landmarks and no path: cannot make a world");
    }
    w.bounds.x_min -= margin_m;
    w.bounds.x_max += margin_m;
    w.bounds.y_min -= margin_m;
    w.bounds.y_max += margin_m;
    const double reach =
        std::max({-w.bounds.x_min, w.bounds.x_max, -w.bounds.y_min, w.bounds.y_max});
    if (reach > kMaxWorldCoordinate_m)
    {
        THROW_EXCEPTION("--margin " + num(margin_m) + ": the world's bounds (x " +
                        num(w.bounds.x_min) + " .. " + num(w.bounds.x_max) + ", y " +
                        num(w.bounds.y_min) + " .. " + num(w.bounds.y_max) +
                        ") would reach beyond +-" + num(kMaxWorldCoordinate_m) +
                        " m, the bound of world coordinates");
    }
    w.objects = landmarks;
    // What the world loader would refuse is refused here, before anything is written.
    try
    {
        (void)World::FromText(w.toYamlText(), name);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("the world of the landmarks and the path would not load: " +
                        errorMessage(e));
    }
    return w;
}

std::vector<double> LandmarkImport::frameTimes(const mrpt::obs::CRawlog& log)
{
    std::vector<double> t;
    for (size_t i = 0; i < log.size(); i++)
    {
        if (log.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
        {
            const auto sf = log.getAsObservations(i);
            t.push_back(sf->size() ? mrpt::Clock::toDouble((*sf->begin())->timestamp) : 0.0);
        }
    }
    return t;
}

void LandmarkImport::writeGroundTruth(const std::vector<double>& times,
                                      const std::vector<mrpt::math::TPose2D>& path,
                                      const std::string& outPath)
{
    if (path.size() < times.size())
    {
        THROW_EXCEPTION(mrpt::format("robot path has %u rows but the rawlog has %u sensory frames",
                                     static_cast<unsigned>(path.size()),
                                     static_cast<unsigned>(times.size())));
    }
    std::vector<GroundTruthRow> rows;
    rows.reserve(times.size());
    for (size_t i = 0; i < times.size(); i++)
    {
        rows.push_back({times[i], path[i].x, path[i].y, path[i].phi});
    }
    GroundTruthFile::Write(rows, outPath);  // its errors name the file and the reason
}

}  // namespace semloc

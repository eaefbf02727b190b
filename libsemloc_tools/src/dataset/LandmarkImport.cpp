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
#include <functional>
#include <sstream>
#include <utility>

#include "io/Text.h"
#include "world/WorldStream.h"

namespace semloc
{
namespace
{
/** The shortest text that reads back as `v`. */
constexpr auto num = detail::shortestText;

/** Calls `row(line, words)` for each data line of the text file `path` (blank-separated
 *  words; blank lines and lines starting with % or # skipped), one line in memory at a time;
 *  returns how many there were. */
size_t forEachRow(const std::string& path,
                  const std::function<void(size_t, const std::vector<std::string>&)>& row)
{
    (void)checkInputFile(path, "landmark file", InputKind::Text);
    std::ifstream f(path);
    if (!f)
    {
        THROW_EXCEPTION("cannot open '" + path + "' for reading");
    }
    std::string line;
    std::vector<std::string> words;
    size_t rows = 0;
    for (size_t n = 1; std::getline(f, line); n++)
    {
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '%' || line[b] == '#')
        {
            continue;
        }
        words.clear();
        std::istringstream ss(line);
        for (std::string w; ss >> w;)
        {
            words.push_back(std::move(w));
        }
        row(n, words);
        rows++;
    }
    return rows;
}

/** The numbers of a data line's words (each a finite number, at least `minCols`). */
void rowNumbers(const std::string& path, size_t n, const std::vector<std::string>& words,
                size_t minCols, std::vector<double>& cols)
{
    cols.clear();
    for (const auto& w : words)
    {
        char* end = nullptr;
        const double v = std::strtod(w.c_str(), &end);
        if (end == w.c_str() || *end != '\0' || !std::isfinite(v))
        {
            THROW_EXCEPTION(mrpt::format("'%s' line %zu: '%s' is not a finite number", path.c_str(),
                                         n, w.c_str()));
        }
        cols.push_back(v);
    }
    if (cols.size() < minCols)
    {
        THROW_EXCEPTION(mrpt::format("'%s' line %zu: expected at least %zu columns, got %zu",
                                     path.c_str(), n, minCols, cols.size()));
    }
}

/** A landmark id: decimal digits (as simul-landmarks writes it) of a value in [0, 2e9];
 *  `0x10`, `1e3` or `16.0`, which read as numbers, are refused. */
int landmarkId(const std::string& path, size_t n, const std::string& word)
{
    const bool digits =
        !word.empty() && word.size() <= 10 &&
        std::all_of(word.begin(), word.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || std::stoll(word) > 2000000000LL)
    {
        THROW_EXCEPTION(
            mrpt::format("'%s' line %zu: last column must be a landmark id: '%s' is "
                         "not an integer of decimal digits in [0, 2000000000]",
                         path.c_str(), n, shownValue(word).c_str()));
    }
    return static_cast<int>(std::stoll(word));
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

/** A world named `name` without objects: bounds = box of the `count` centres and the path,
 *  grown by `margin_m`; throws "--margin M: ..." if they would reach beyond
 *  kMaxWorldCoordinate_m. */
World worldAround(size_t count, const std::function<mrpt::math::TPoint2D(size_t)>& centre,
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
    for (size_t i = 0; i < count; i++)
    {
        const auto c = centre(i);
        grow(c.x, c.y);
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
    return w;
}

/** What the world loader would refuse is refused here, before anything is written (read back
 *  as the text streams: beyond the world, memory for its ids and centres). */
void checkLoads(const World& w, const std::string& name, const WorldObjectList* objects)
{
    try
    {
        detail::checkReadsBack(w, name, objects);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("the world of the landmarks and the path would not load: " +
                        errorMessage(e));
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

LandmarkSet LandmarkImport::readLandmarkSet(const std::string& path, const std::string& label)
{
    checkLabel(label);
    // Counted first: the landmarks are stored once, without the copies of a growing vector.
    LandmarkSet out;
    out.reserve(forEachRow(path, [](size_t, const std::vector<std::string>&) {}));
    std::vector<double> cols;
    bool hasZero = false;
    forEachRow(path,
               [&](size_t n, const std::vector<std::string>& words)
               {
                   rowNumbers(path, n, words, 4, cols);
                   const int id = landmarkId(path, n, words.back());
                   hasZero |= id == 0;
                   out.add(id, label, cols[0], cols[1], cols[2]);
               });
    if (hasZero)
    {
        THROW_EXCEPTION("'" + path +
                        "': landmark id 0 found; semloc object ids must be positive (renumber "
                        "the landmarks from 1)");
    }
    return out;
}

std::vector<WorldObject> LandmarkImport::readLandmarks(const std::string& path,
                                                       const std::string& label)
{
    const LandmarkSet set = readLandmarkSet(path, label);
    std::vector<WorldObject> out;
    out.reserve(set.size());
    for (size_t i = 0; i < set.size(); i++)
    {
        out.push_back(set.object(i));
    }
    return out;
}

std::vector<mrpt::math::TPose2D> LandmarkImport::readPath(const std::string& path)
{
    std::vector<mrpt::math::TPose2D> out;
    std::vector<double> cols;
    forEachRow(path,
               [&](size_t n, const std::vector<std::string>& words)
               {
                   rowNumbers(path, n, words, 4, cols);
                   out.emplace_back(cols[0], cols[1], cols[3]);
               });
    return out;
}

World LandmarkImport::makeWorld(std::vector<WorldObject> landmarks,
                                const std::vector<mrpt::math::TPose2D>& path, double margin_m,
                                const std::string& name)
{
    World w = worldAround(
        landmarks.size(), [&](size_t i) { return landmarks[i].center; }, path, margin_m, name);
    w.objects = std::move(landmarks);
    checkLoads(w, name, nullptr);
    return w;
}

World LandmarkImport::makeWorldFrame(const LandmarkSet& landmarks,
                                     const std::vector<mrpt::math::TPose2D>& path, double margin_m,
                                     const std::string& name)
{
    World w = worldAround(
        landmarks.size(),
        [&](size_t i) { return mrpt::math::TPoint2D(landmarks[i].x, landmarks[i].y); }, path,
        margin_m, name);
    const WorldObjectList list = landmarks.objectList();
    checkLoads(w, name, &list);
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

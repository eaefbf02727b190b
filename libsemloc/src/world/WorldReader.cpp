/* semloc — the world-file reader: YAML text -> World, checked strictly (docs/design.md,
 * "World file"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/InputFile.h>
#include <semloc/observation/Labels.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "world/ObjectShape.h"
#include "world/WorldFileValues.h"
#include "world/WorldStream.h"
#include "world/YamlSyntax.h"

namespace semloc
{
namespace
{
using detail::checkKeys;
using detail::findKey;
using detail::requireKey;
using detail::scalarText;
using detail::toCoordinate;
using detail::toNumber;
using detail::toPoint;
using detail::Where;
using mrpt::math::TPoint2D;
using node_t = detail::WorldNode;
using map_t = detail::WorldMap;

/** A polygon's area centroid; fails if it is self-intersecting or has zero area. */
void finishPolygon(WorldObject& o, const Where& w)
{
    const auto& p = o.points;
    const size_t n = p.size();
    double a2 = 0, cx = 0, cy = 0;
    for (size_t i = 0; i < n; i++)
    {
        const auto& u = p[i];
        const auto& v = p[(i + 1) % n];
        const double c = u.x * v.y - v.x * u.y;
        a2 += c;
        cx += (u.x + v.x) * c;
        cy += (u.y + v.y) * c;
    }
    for (size_t i = 0; i < n; i++)
    {
        for (size_t j = i + 1; j < n; j++)
        {
            const bool adjacent = (j == i + 1) || (i == 0 && j == n - 1);
            if (adjacent)
            {
                continue;
            }
            if (detail::segmentsTouch(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]))
            {
                w.fail("points", "polygon is self-intersecting (edges " + std::to_string(i) +
                                     " and " + std::to_string(j) + ")");
            }
        }
    }
    if (std::abs(a2) < 1e-12)
    {
        w.fail("points", "polygon has zero area");
    }
    o.center = {cx / (3 * a2), cy / (3 * a2)};
}

/** A box's 4 corners (counter-clockwise) from its centre, sides and yaw. */
void finishBox(WorldObject& o)
{
    const double c = std::cos(o.yaw), s = std::sin(o.yaw);
    const double hx = 0.5 * o.size_x, hy = 0.5 * o.size_y;
    const double corners[4][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    o.points.clear();
    for (const auto& k : corners)
    {
        o.points.emplace_back(o.center.x + c * k[0] - s * k[1], o.center.y + s * k[0] + c * k[1]);
    }
}

/** `id` (a positive integer, then named in `w`'s messages) and `label` of an object. */
void readIdentity(const map_t& m, Where& w, WorldObject& o)
{
    o.id = detail::toInt(requireKey(m, "id", w), w, "id");
    w.object += " (id " + std::to_string(o.id) + ")";
    if (o.id <= 0)
    {
        w.fail("id", "must be a positive integer");
    }
    o.label = scalarText(requireKey(m, "label", w), w, "label");
    if (const std::string problem = labelProblem(o.label); !problem.empty())
    {
        w.fail("label", problem);
    }
}

void readBox(const map_t& m, const Where& w, WorldObject& o)
{
    checkKeys(
        m,
        {"id", "label", "shape", "z", "center", "size", "yaw_deg", "sigma_m", "p_exist", "classes"},
        w);
    o.shape = ShapeType::Box;
    o.center = toPoint(requireKey(m, "center", w), w, "center");
    const auto sz = toPoint(requireKey(m, "size", w), w, "size");
    o.size_x = sz.x;
    o.size_y = sz.y;
    if (o.size_x <= 0 || o.size_y <= 0)
    {
        w.fail("size", "both sides must be > 0");
    }
    if (const auto* y = findKey(m, "yaw_deg"))
    {
        o.yaw = toNumber(*y, w, "yaw_deg") * M_PI / 180.0;
    }
    finishBox(o);
    o.extent_m = std::hypot(0.5 * o.size_x, 0.5 * o.size_y);
}

void readCylinder(const map_t& m, const Where& w, WorldObject& o)
{
    checkKeys(m, {"id", "label", "shape", "z", "center", "radius", "sigma_m", "p_exist", "classes"},
              w);
    o.shape = ShapeType::Cylinder;
    o.center = toPoint(requireKey(m, "center", w), w, "center");
    o.radius = toCoordinate(requireKey(m, "radius", w), w, "radius");
    if (o.radius <= 0)
    {
        w.fail("radius", "must be > 0");
    }
    o.extent_m = o.radius;
}

void readPolygon(const map_t& m, const Where& w, WorldObject& o)
{
    checkKeys(m, {"id", "label", "shape", "z", "points", "sigma_m", "p_exist", "classes"}, w);
    o.shape = ShapeType::Polygon;
    const auto& pts = requireKey(m, "points", w);
    if (!pts.isSequence() || pts.asSequence().size() < 3)
    {
        w.fail("points", "expected a list of at least 3 points [[x, y], ...]");
    }
    for (const auto& p : pts.asSequence())
    {
        o.points.push_back(toPoint(p, w, "points"));
    }
    finishPolygon(o, w);
    for (const auto& p : o.points)
    {
        o.extent_m = std::max(o.extent_m, std::hypot(p.x - o.center.x, p.y - o.center.y));
    }
}

void readPoint(const map_t& m, const Where& w, WorldObject& o)
{
    checkKeys(
        m, {"id", "label", "shape", "z", "center", "extent_m", "sigma_m", "p_exist", "classes"}, w);
    o.shape = ShapeType::Point;
    o.center = toPoint(requireKey(m, "center", w), w, "center");
    if (const auto* e = findKey(m, "extent_m"))
    {
        o.extent_m = toCoordinate(*e, w, "extent_m");
        if (o.extent_m < 0)
        {
            w.fail("extent_m", "must be >= 0");
        }
    }
}

/** The optional keys of how sure the map is of the object: `sigma_m`, `p_exist`, `classes`. */
void readUncertainty(const map_t& m, const Where& w, WorldObject& o)
{
    if (const auto* s = findKey(m, "sigma_m"))
    {
        o.sigma_m = toCoordinate(*s, w, "sigma_m");
        if (o.sigma_m < 0)
        {
            w.fail("sigma_m", "must be >= 0");
        }
    }
    if (const auto* p = findKey(m, "p_exist"))
    {
        o.p_exist = toNumber(*p, w, "p_exist");
        if (!(o.p_exist > 0 && o.p_exist <= 1))
        {
            w.fail("p_exist", "must be in (0, 1]");
        }
    }
    const auto* c = findKey(m, "classes");
    if (c == nullptr)
    {
        return;
    }
    if (!c->isMap() || c->asMap().empty())
    {
        w.fail("classes", "expected a map {label: probability, ...}");
    }
    for (const auto& kv : c->asMap())
    {
        o.classes.emplace_back(kv.first.as<std::string>(), toNumber(kv.second, w, "classes"));
    }
    std::sort(o.classes.begin(), o.classes.end());
    if (const std::string problem = classesProblem(o.classes, o.label); !problem.empty())
    {
        w.fail("classes", problem);
    }
}

/** objects[index]: identity, `z`, then the keys of its shape. */
WorldObject parseObject(const node_t& n, size_t index, const std::string& file)
{
    Where w{file, "objects[" + std::to_string(index) + "]"};
    if (!n.isMap())
    {
        w.fail("", "expected a map {id: ..., label: ..., shape: ...}");
    }
    const auto& m = n.asMap();
    WorldObject o;
    readIdentity(m, w, o);
    const std::string shape = scalarText(requireKey(m, "shape", w), w, "shape");
    if (const auto* z = findKey(m, "z"))
    {
        o.z = toCoordinate(*z, w, "z");
    }
    if (shape == "box")
    {
        readBox(m, w, o);
    }
    else if (shape == "cylinder")
    {
        readCylinder(m, w, o);
    }
    else if (shape == "polygon")
    {
        readPolygon(m, w, o);
    }
    else if (shape == "point")
    {
        readPoint(m, w, o);
    }
    else
    {
        w.fail("shape", "unknown shape '" + shape + "' (expected box, cylinder, polygon or point)");
    }
    readUncertainty(m, w, o);
    return o;
}

WorldBounds readBounds(const node_t& b, const std::string& file, const Where& top)
{
    if (!b.isMap())
    {
        top.fail("bounds", "expected {x_min, x_max, y_min, y_max}");
    }
    const Where wb{file, "bounds"};
    checkKeys(b.asMap(), {"x_min", "x_max", "y_min", "y_max"}, wb);
    WorldBounds bounds;
    bounds.x_min = toCoordinate(requireKey(b.asMap(), "x_min", wb), wb, "x_min");
    bounds.x_max = toCoordinate(requireKey(b.asMap(), "x_max", wb), wb, "x_max");
    bounds.y_min = toCoordinate(requireKey(b.asMap(), "y_min", wb), wb, "y_min");
    bounds.y_max = toCoordinate(requireKey(b.asMap(), "y_max", wb), wb, "y_max");
    if (!(bounds.x_min < bounds.x_max) || !(bounds.y_min < bounds.y_max))
    {
        top.fail("bounds", "empty area: need x_min < x_max and y_min < y_max");
    }
    return bounds;
}

/** beacons[index]: `id` (a non-negative integer), `x`, `y`, optional `z`. */
WorldBeacon parseBeacon(const node_t& n, size_t index, const std::string& file)
{
    Where w{file, "beacons[" + std::to_string(index) + "]"};
    if (!n.isMap())
    {
        w.fail("", "expected a map {id: ..., x: ..., y: ...}");
    }
    const auto& m = n.asMap();
    WorldBeacon b;
    b.id = detail::toInt(requireKey(m, "id", w), w, "id");
    w.object += " (id " + std::to_string(b.id) + ")";
    checkKeys(m, {"id", "x", "y", "z"}, w);
    if (b.id < 0)
    {
        w.fail("id", "must be a non-negative integer");
    }
    b.x = toCoordinate(requireKey(m, "x", w), w, "x");
    b.y = toCoordinate(requireKey(m, "y", w), w, "y");
    if (const auto* z = findKey(m, "z"))
    {
        b.z = toCoordinate(*z, w, "z");
    }
    return b;
}

/** What the checks of the objects need of one (with a sink, which takes the object). */
struct PlacedObject
{
    int id = 0;
    ShapeType shape = ShapeType::Point;
    TPoint2D center{0, 0};
};

/** The elements of `objects:` and `beacons:`, parsed one by one as the YAML parser hands them
 *  over: the parsed ones in file order, and the first that failed (its exception; those after
 *  it are not parsed). The checks that span elements (unique ids, centres in the bounds,
 *  which may come later in the file) are made when the whole file is read, in file order, so
 *  the first error is the one a whole-document reading finds. */
struct Streamed
{
    Streamed(const std::string& f, const detail::ObjectSink* s) : file(f), sink(s) {}

    const std::string& file;
    const detail::ObjectSink* sink = nullptr;
    std::vector<WorldObject> objects;  // without a sink
    std::vector<PlacedObject> placed;  // with a sink
    size_t objectCount = 0;
    std::exception_ptr objectError;  // objects[objectCount]'s
    std::vector<WorldBeacon> beacons;
    std::exception_ptr beaconError;  // beacons[beacons.size()]'s

    void take(const std::string& key, size_t index, const node_t& n)
    {
        try
        {
            if (key == "beacons" && !beaconError)
            {
                beacons.push_back(parseBeacon(n, index, file));
            }
            else if (key == "objects" && !objectError)
            {
                takeObject(parseObject(n, index, file), index);
            }
        }
        catch (...)
        {
            (key == "beacons" ? beaconError : objectError) = std::current_exception();
        }
    }

    void takeObject(WorldObject&& o, size_t index)
    {
        objectCount++;
        if (!sink)
        {
            objects.push_back(std::move(o));
            return;
        }
        placed.push_back({o.id, o.shape, o.center});
        (*sink)(std::move(o), index);
    }
};

/** The streamed objects' checks in file order (the first failing parse last of all, where it
 *  stopped): unique ids, centres inside the bounds. */
template <typename Elements>
void checkObjects(const Elements& objects, const Streamed& st, const World& world)
{
    const size_t repeated = detail::firstRepeatedId(objects);
    for (size_t i = 0; i < objects.size(); i++)
    {
        const auto& o = objects[i];
        const Where w{st.file,
                      "objects[" + std::to_string(i) + "] (id " + std::to_string(o.id) + ")"};
        if (i == repeated)
        {
            w.fail("id", "duplicate id " + std::to_string(o.id));
        }
        if (!world.bounds.contains(o.center.x, o.center.y))
        {
            w.fail(o.shape == ShapeType::Polygon ? "points" : "center",
                   "object centre is outside bounds");
        }
    }
    if (st.objectError)
    {
        std::rethrow_exception(st.objectError);
    }
}

/** The objects, in file order, into `world` (whose bounds are read): unique ids, centres
 *  inside the bounds (`objs` is the document's `objects:`, its elements in `st`). */
void readObjects(const node_t& objs, const Where& top, World& world, Streamed& st)
{
    if (objs.isNullNode())
    {
        return;  // "objects:" with nothing after it: an empty world is allowed.
    }
    if (!objs.isSequence())
    {
        top.fail("objects", "expected a list of objects");
    }
    if (st.sink)
    {
        checkObjects(st.placed, st, world);
        return;
    }
    checkObjects(st.objects, st, world);
    world.objects = std::move(st.objects);
}

/** The optional acoustic beacons, in file order, with unique ids (anywhere: a beacon may be
 *  moored outside the area particles may occupy); `list` is the document's `beacons:`, its
 *  elements in `st`. */
std::vector<WorldBeacon> readBeacons(const node_t& list, const Where& top, Streamed& st)
{
    std::vector<WorldBeacon> beacons;
    if (list.isNullNode())
    {
        return beacons;  // "beacons:" with nothing after it: none
    }
    if (!list.isSequence())
    {
        top.fail("beacons", "expected a list of beacons [{id: ..., x: ..., y: ...}, ...]");
    }
    const size_t repeated = detail::firstRepeatedId(st.beacons);
    for (size_t i = 0; i < st.beacons.size(); i++)
    {
        if (i == repeated)
        {
            const Where w{st.file, "beacons[" + std::to_string(i) + "] (id " +
                                       std::to_string(st.beacons[i].id) + ")"};
            w.fail("id", "duplicate id " + std::to_string(st.beacons[i].id));
        }
    }
    if (st.beaconError)
    {
        std::rethrow_exception(st.beaconError);
    }
    return std::move(st.beacons);
}

/** The simulated vehicle follows the waypoints: a path of zero length, or one through an
 *  object (whose inside is not free space: the true pose would weigh zero), is refused. */
void checkTrajectory(const World& world, const WorldTrajectory& tr, const Where& wt)
{
    const auto& p = tr.waypoints;
    auto wp = [&](size_t i)
    { return "waypoints[" + std::to_string(i) + "] " + detail::pointText(p[i]); };
    auto obj = [&](int k)
    {
        const auto& o = world.objects[static_cast<size_t>(k)];
        return mrpt::format("objects[%d] (id %d, %s)", k, o.id, shapeName(o.shape));
    };
    bool moves = false;
    for (size_t i = 0; i < p.size(); i++)
    {
        moves |= p[i].x != p[0].x || p[i].y != p[0].y;
        if (const int k = world.firstObjectOnSegment(p[i], p[i]); k >= 0)
        {
            wt.fail("waypoints", wp(i) + " is inside " + obj(k));
        }
    }
    if (!moves)
    {
        wt.fail("waypoints", "the trajectory has zero length (every waypoint is " +
                                 detail::pointText(p[0]) + ")");
    }
    for (size_t i = 0; i + 1 < p.size(); i++)
    {
        if (const int k = world.firstObjectOnSegment(p[i], p[i + 1]); k >= 0)
        {
            wt.fail("waypoints",
                    "the leg from " + wp(i) + " to " + wp(i + 1) + " passes through " + obj(k));
        }
    }
}

/** The optional trajectory of a world whose bounds and objects are read. */
WorldTrajectory readTrajectory(const node_t& t, const std::string& file, const Where& top,
                               const World& world)
{
    const Where wt{file, "trajectory"};
    if (!t.isMap())
    {
        top.fail("trajectory", "expected {speed_mps, waypoints}");
    }
    checkKeys(t.asMap(), {"speed_mps", "waypoints"}, wt);
    WorldTrajectory tr;
    if (const auto* s = findKey(t.asMap(), "speed_mps"))
    {
        tr.speed_mps = toNumber(*s, wt, "speed_mps");
    }
    if (tr.speed_mps <= 0)
    {
        wt.fail("speed_mps", "must be > 0");
    }
    const auto& wp = requireKey(t.asMap(), "waypoints", wt);
    if (!wp.isSequence() || wp.asSequence().size() < 2)
    {
        wt.fail("waypoints", "expected at least 2 points [[x, y], ...]");
    }
    for (const auto& p : wp.asSequence())
    {
        const auto q = toPoint(p, wt, "waypoints");
        if (!world.bounds.contains(q.x, q.y))
        {
            wt.fail("waypoints", "waypoint outside bounds");
        }
        tr.waypoints.push_back(q);
    }
    checkTrajectory(world, tr, wt);
    return tr;
}

World parseWorld(const node_t& doc, const std::string& file, Streamed& st)
{
    const Where top{file, ""};
    if (!doc.isMap())
    {
        top.fail("", "expected a YAML map with keys name, bounds, objects");
    }
    const auto& m = doc.asMap();
    checkKeys(m, {"name", "bounds", "objects", "beacons", "trajectory"}, top);
    World world;
    world.source = file;
    if (const auto* n = findKey(m, "name"))
    {
        world.name = scalarText(*n, top, "name");
    }
    world.bounds = readBounds(requireKey(m, "bounds", top), file, top);
    readObjects(requireKey(m, "objects", top), top, world, st);
    if (const auto* b = findKey(m, "beacons"))
    {
        world.beacons = readBeacons(*b, top, st);
    }
    if (const auto* t = findKey(m, "trajectory"))
    {
        ASSERTMSG_(!st.sink, "a world with a trajectory is read with its objects");
        world.trajectory = readTrajectory(*t, file, top, world);
    }
    return world;
}
}  // namespace

namespace detail
{
World readWorld(TextSource& source, const std::string& sourceName, const ObjectSink* sink)
{
    if (const size_t line = detail::firstNonUtf8Line(source))
    {
        THROW_EXCEPTION(
            mrpt::format("world file '%s': line %zu: not UTF-8 text", sourceName.c_str(), line));
    }
    source.rewind();
    Streamed st{sourceName, sink};
    YamlElementSink elements;
    elements.keys = {"objects", "beacons"};
    elements.take = [&](const std::string& key, size_t index, const node_t& n)
    { st.take(key, index, n); };
    node_t doc;
    const YamlRead read = [&](char* buf, size_t n) { return source.read(buf, n); };
    if (const std::string err = detail::parseYaml(read, doc, &elements); !err.empty())
    {
        THROW_EXCEPTION("world file '" + sourceName + "': " + err);
    }
    return parseWorld(doc, sourceName, st);
}
}  // namespace detail

World World::FromText(const std::string& yamlText, const std::string& sourceName)
{
    detail::StringSource source(yamlText);
    return detail::readWorld(source, sourceName);
}

World World::FromFile(const std::string& path)
{
    // A regular file within the cap (checkInputFile), read as it is parsed: a world of a
    // million objects is never held as text.
    (void)checkInputFile(path, "world file", InputKind::World);
    detail::FileSource source(path);
    return detail::readWorld(source, path);
}

}  // namespace semloc

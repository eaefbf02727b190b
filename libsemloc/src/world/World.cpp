/* semloc — World: loading and validating world YAML files. */
#include <mrpt/containers/yaml.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/Labels.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "io/Text.h"
#include "world/Geometry2D.h"
#include "world/YamlSyntax.h"

namespace semloc
{
namespace
{
/** 1-based line of the first byte sequence that is not UTF-8 (overlong forms and surrogates
 *  are not told apart), or 0 if there is none. YAML text must be Unicode, and libfyaml (MRPT's
 *  YAML parser) loops forever on some invalid bytes (found by tests/fuzz/fuzz_world). */
size_t firstNonUtf8Line(const std::string& text)
{
    size_t line = 1;
    for (size_t i = 0; i < text.size();)
    {
        const auto c = static_cast<unsigned char>(text[i]);
        const size_t len = c < 0x80           ? 1
                           : (c >> 5) == 0x6  ? 2
                           : (c >> 4) == 0xE  ? 3
                           : (c >> 3) == 0x1E ? 4
                                              : 0;
        if (len == 0 || i + len > text.size())
        {
            return line;
        }
        for (size_t k = 1; k < len; k++)
        {
            if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2)
            {
                return line;
            }
        }
        line += c == '\n' ? 1 : 0;
        i += len;
    }
    return 0;
}

using mrpt::containers::yaml;
using node_t = mrpt::containers::yaml::node_t;
using mrpt::math::TPoint2D;
/** The shortest text that reads back as `v`. */
constexpr auto num = detail::shortestText;

/** Where in the file a value is: composes the prefix of every error message. */
struct Where
{
    const std::string& file;
    std::string object;  // e.g. "objects[3] (id 7)", empty at top level

    [[noreturn]] void fail(const std::string& key, const std::string& what) const
    {
        std::string msg = "world file '" + file + "': ";
        if (!object.empty())
        {
            msg += object + ": ";
        }
        if (!key.empty())
        {
            msg += "key '" + key + "': ";
        }
        THROW_EXCEPTION(msg + what);
    }
};

std::string scalarText(const node_t& n, const Where& w, const std::string& key)
{
    if (!n.isScalar())
    {
        w.fail(key, "expected a scalar value, got a " + n.typeName());
    }
    try
    {
        return n.as<std::string>();
    }
    catch (const std::exception&)
    {
        // Programmatically built documents hold typed scalars.
        std::ostringstream ss;
        ss.precision(17);
        ss << n.as<double>();
        return ss.str();
    }
}

double toNumber(const node_t& n, const Where& w, const std::string& key)
{
    const std::string s = scalarText(n, w, key);
    const char* b = s.data();
    const char* e = s.data() + s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(*b)))
    {
        ++b;
    }
    while (e > b && std::isspace(static_cast<unsigned char>(e[-1])))
    {
        --e;
    }
    if (b < e && *b == '+')
    {
        ++b;
    }
    double v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e || b == e)
    {
        std::string l(b, e);
        std::transform(l.begin(), l.end(), l.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        if (l == ".inf" || l == "-.inf" || l == ".nan")
        {
            w.fail(key, "'" + s + "' is not a finite number");
        }
        w.fail(key, "'" + s + "' is not a number");
    }
    if (!std::isfinite(v))
    {
        w.fail(key, "'" + s + "' is not a finite number");
    }
    return v;
}

int toInt(const node_t& n, const Where& w, const std::string& key)
{
    const double v = toNumber(n, w, key);
    if (v != std::floor(v) || std::abs(v) > 2e9)
    {
        w.fail(key, "expected an integer, got '" + scalarText(n, w, key) + "'");
    }
    return static_cast<int>(v);
}

/** A coordinate or length: a finite number within +-kMaxWorldCoordinate_m. */
double toCoordinate(const node_t& n, const Where& w, const std::string& key)
{
    const double v = toNumber(n, w, key);
    if (std::abs(v) > kMaxWorldCoordinate_m)
    {
        w.fail(key, mrpt::format("'%s' is outside [-%g, %g] m, the bound of world coordinates",
                                 scalarText(n, w, key).c_str(), kMaxWorldCoordinate_m,
                                 kMaxWorldCoordinate_m));
    }
    return v;
}

TPoint2D toPoint(const node_t& n, const Where& w, const std::string& key)
{
    if (!n.isSequence() || n.asSequence().size() != 2)
    {
        w.fail(key, "expected a point [x, y]");
    }
    const auto& s = n.asSequence();
    return {toCoordinate(s[0], w, key), toCoordinate(s[1], w, key)};
}

const node_t& requireKey(const yaml::map_t& m, const std::string& key, const Where& w)
{
    for (const auto& kv : m)
    {
        if (kv.first.as<std::string>() == key)
        {
            return kv.second;
        }
    }
    w.fail(key, "missing required key");
}

const node_t* findKey(const yaml::map_t& m, const std::string& key)
{
    for (const auto& kv : m)
    {
        if (kv.first.as<std::string>() == key)
        {
            return &kv.second;
        }
    }
    return nullptr;
}

void checkKeys(const yaml::map_t& m, const std::set<std::string>& allowed, const Where& w)
{
    for (const auto& kv : m)
    {
        const auto k = kv.first.as<std::string>();
        if (!allowed.count(k))
        {
            std::string list;
            for (const auto& a : allowed)
            {
                list += (list.empty() ? "" : ", ") + a;
            }
            w.fail(k, "unknown key (allowed here: " + list + ")");
        }
    }
}

double cross(const TPoint2D& o, const TPoint2D& a, const TPoint2D& b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

bool onSegment(const TPoint2D& p, const TPoint2D& a, const TPoint2D& b)
{
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

/** True if closed segments [a,b] and [c,d] share at least one point. */
bool segmentsTouch(const TPoint2D& a, const TPoint2D& b, const TPoint2D& c, const TPoint2D& d)
{
    const double d1 = cross(c, d, a), d2 = cross(c, d, b);
    const double d3 = cross(a, b, c), d4 = cross(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    {
        return true;
    }
    return (d1 == 0 && onSegment(a, c, d)) || (d2 == 0 && onSegment(b, c, d)) ||
           (d3 == 0 && onSegment(c, a, b)) || (d4 == 0 && onSegment(d, a, b));
}

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
            if (segmentsTouch(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]))
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

WorldObject parseObject(const node_t& n, size_t index, const std::string& file)
{
    Where w{file, "objects[" + std::to_string(index) + "]"};
    if (!n.isMap())
    {
        w.fail("", "expected a map {id: ..., label: ..., shape: ...}");
    }
    const auto& m = n.asMap();
    WorldObject o;
    o.id = toInt(requireKey(m, "id", w), w, "id");
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
    const std::string shape = scalarText(requireKey(m, "shape", w), w, "shape");
    if (const auto* z = findKey(m, "z"))
    {
        o.z = toCoordinate(*z, w, "z");
    }
    if (shape == "box")
    {
        checkKeys(m, {"id", "label", "shape", "z", "center", "size", "yaw_deg"}, w);
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
    else if (shape == "cylinder")
    {
        checkKeys(m, {"id", "label", "shape", "z", "center", "radius"}, w);
        o.shape = ShapeType::Cylinder;
        o.center = toPoint(requireKey(m, "center", w), w, "center");
        o.radius = toCoordinate(requireKey(m, "radius", w), w, "radius");
        if (o.radius <= 0)
        {
            w.fail("radius", "must be > 0");
        }
        o.extent_m = o.radius;
    }
    else if (shape == "polygon")
    {
        checkKeys(m, {"id", "label", "shape", "z", "points"}, w);
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
    else if (shape == "point")
    {
        checkKeys(m, {"id", "label", "shape", "z", "center", "extent_m"}, w);
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
    else
    {
        w.fail("shape", "unknown shape '" + shape + "' (expected box, cylinder, polygon or point)");
    }
    return o;
}

/** `[x, y]` of `p`, each the shortest text that reads back as it. */
std::string pt(const TPoint2D& p)
{
    return "[" + num(p.x) + ", " + num(p.y) + "]";
}

/** The simulated vehicle follows the waypoints: a path of zero length, or one through an
 *  object (whose inside is not free space: the true pose would weigh zero), is refused. */
void checkTrajectory(const World& world, const WorldTrajectory& tr, const Where& wt)
{
    const auto& p = tr.waypoints;
    auto wp = [&](size_t i) { return "waypoints[" + std::to_string(i) + "] " + pt(p[i]); };
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
        wt.fail("waypoints", "the trajectory has zero length (every waypoint is " + pt(p[0]) + ")");
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

World parseWorld(const node_t& doc, const std::string& file)
{
    const Where top{file, ""};
    if (!doc.isMap())
    {
        top.fail("", "expected a YAML map with keys name, bounds, objects");
    }
    const auto& m = doc.asMap();
    checkKeys(m, {"name", "bounds", "objects", "trajectory"}, top);
    World world;
    world.source = file;
    if (const auto* n = findKey(m, "name"))
    {
        world.name = scalarText(*n, top, "name");
    }

    const auto& b = requireKey(m, "bounds", top);
    if (!b.isMap())
    {
        top.fail("bounds", "expected {x_min, x_max, y_min, y_max}");
    }
    const Where wb{file, "bounds"};
    checkKeys(b.asMap(), {"x_min", "x_max", "y_min", "y_max"}, wb);
    world.bounds.x_min = toCoordinate(requireKey(b.asMap(), "x_min", wb), wb, "x_min");
    world.bounds.x_max = toCoordinate(requireKey(b.asMap(), "x_max", wb), wb, "x_max");
    world.bounds.y_min = toCoordinate(requireKey(b.asMap(), "y_min", wb), wb, "y_min");
    world.bounds.y_max = toCoordinate(requireKey(b.asMap(), "y_max", wb), wb, "y_max");
    if (!(world.bounds.x_min < world.bounds.x_max) || !(world.bounds.y_min < world.bounds.y_max))
    {
        top.fail("bounds", "empty area: need x_min < x_max and y_min < y_max");
    }

    const auto& objs = requireKey(m, "objects", top);
    if (objs.isNullNode())
    {
        // "objects:" with nothing after it: an empty world is allowed.
    }
    else if (!objs.isSequence())
    {
        top.fail("objects", "expected a list of objects");
    }
    else
    {
        std::set<int> ids;
        size_t i = 0;
        for (const auto& on : objs.asSequence())
        {
            WorldObject o = parseObject(on, i, file);
            const Where w{file,
                          "objects[" + std::to_string(i) + "] (id " + std::to_string(o.id) + ")"};
            if (!ids.insert(o.id).second)
            {
                w.fail("id", "duplicate id " + std::to_string(o.id));
            }
            if (!world.bounds.contains(o.center.x, o.center.y))
            {
                w.fail(o.shape == ShapeType::Polygon ? "points" : "center",
                       "object centre is outside bounds");
            }
            world.objects.push_back(std::move(o));
            i++;
        }
    }

    if (const auto* t = findKey(m, "trajectory"))
    {
        const Where wt{file, "trajectory"};
        if (!t->isMap())
        {
            top.fail("trajectory", "expected {speed_mps, waypoints}");
        }
        checkKeys(t->asMap(), {"speed_mps", "waypoints"}, wt);
        WorldTrajectory tr;
        if (const auto* s = findKey(t->asMap(), "speed_mps"))
        {
            tr.speed_mps = toNumber(*s, wt, "speed_mps");
        }
        if (tr.speed_mps <= 0)
        {
            wt.fail("speed_mps", "must be > 0");
        }
        const auto& wp = requireKey(t->asMap(), "waypoints", wt);
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
        world.trajectory = std::move(tr);
    }
    return world;
}

/** `s` as a YAML scalar that reads back as the string `s` in a flow map or a block: as it is
 *  if it is a plain word of ASCII letters, digits and `_` (then `-./+`), else double-quoted,
 *  with escapes for `"`, `\\`, control characters and what YAML would not keep as text (the
 *  C1 controls, its line breaks U+0085, U+2028 and U+2029, U+FEFF, U+FFFE and U+FFFF). */
std::string yamlString(const std::string& s)
{
    bool plain = !s.empty() && s != "null" && s != "Null" && s != "NULL";
    for (size_t i = 0; plain && i < s.size(); i++)
    {
        const char c = s[i];
        plain = std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                (i > 0 && std::strchr("-./+", c) != nullptr);
    }
    if (plain)
    {
        return s;
    }
    std::string q = "\"";
    for (size_t i = 0; i < s.size(); i++)
    {
        const auto c = static_cast<unsigned char>(s[i]);
        const auto byte = [&](size_t k)
        { return i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0u; };
        // The code point of a 2- or 3-byte UTF-8 sequence at i (the text is valid UTF-8).
        unsigned code = 0;
        size_t len = 1;
        if ((c >> 5) == 0x6)
        {
            code = ((c & 0x1Fu) << 6) | (byte(1) & 0x3Fu);
            len = 2;
        }
        else if ((c >> 4) == 0xE)
        {
            code = ((c & 0x0Fu) << 12) | ((byte(1) & 0x3Fu) << 6) | (byte(2) & 0x3Fu);
            len = 3;
        }
        if (c == '"' || c == '\\')
        {
            q += '\\';
            q += static_cast<char>(c);
        }
        else if (c < 0x20 || c == 0x7F)
        {
            q += mrpt::format("\\x%02X", c);
        }
        else if ((code >= 0x80 && code <= 0x9F) || code == 0x2028 || code == 0x2029 ||
                 code == 0xFEFF || code == 0xFFFE || code == 0xFFFF)
        {
            q += mrpt::format("\\u%04X", code);
            i += len - 1;
        }
        else
        {
            q += static_cast<char>(c);
        }
    }
    return q + "\"";
}

}  // namespace

const char* shapeName(ShapeType s)
{
    switch (s)
    {
        case ShapeType::Box:
            return "box";
        case ShapeType::Cylinder:
            return "cylinder";
        case ShapeType::Polygon:
            return "polygon";
        case ShapeType::Point:
            return "point";
    }
    return "?";
}

World World::FromText(const std::string& yamlText, const std::string& sourceName)
{
    if (const size_t line = firstNonUtf8Line(yamlText))
    {
        THROW_EXCEPTION(
            mrpt::format("world file '%s': line %zu: not UTF-8 text", sourceName.c_str(), line));
    }
    node_t doc;
    if (const std::string err = detail::parseYaml(yamlText, doc); !err.empty())
    {
        THROW_EXCEPTION("world file '" + sourceName + "': " + err);
    }
    return parseWorld(doc, sourceName);
}

World World::FromFile(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
    {
        THROW_EXCEPTION("world file '" + path + "': cannot open for reading");
    }
    std::stringstream ss;
    ss << f.rdbuf();
    if (f.bad())
    {
        THROW_EXCEPTION("world file '" + path + "': read error");
    }
    return FromText(ss.str(), path);
}

std::string World::toYamlText() const
{
    std::ostringstream o;
    if (!name.empty())
    {
        o << "name: " << yamlString(name) << "\n";
    }
    o << "bounds: {x_min: " << num(bounds.x_min) << ", x_max: " << num(bounds.x_max)
      << ", y_min: " << num(bounds.y_min) << ", y_max: " << num(bounds.y_max) << "}\n";
    o << "objects:" << (objects.empty() ? " []" : "") << "\n";
    for (const auto& ob : objects)
    {
        o << "  - {id: " << ob.id << ", label: " << yamlString(ob.label)
          << ", shape: " << shapeName(ob.shape);
        switch (ob.shape)
        {
            case ShapeType::Box:
                o << ", center: " << pt(ob.center) << ", size: [" << num(ob.size_x) << ", "
                  << num(ob.size_y) << "], yaw_deg: " << num(ob.yaw * 180.0 / M_PI);
                break;
            case ShapeType::Cylinder:
                o << ", center: " << pt(ob.center) << ", radius: " << num(ob.radius);
                break;
            case ShapeType::Polygon:
            {
                o << ", points: [";
                for (size_t i = 0; i < ob.points.size(); i++)
                {
                    o << (i ? ", " : "") << pt(ob.points[i]);
                }
                o << "]";
                break;
            }
            case ShapeType::Point:
                o << ", center: " << pt(ob.center);
                if (ob.extent_m > 0)
                {
                    o << ", extent_m: " << num(ob.extent_m);
                }
                break;
        }
        if (ob.z != 0)
        {
            o << ", z: " << num(ob.z);
        }
        o << "}\n";
    }
    if (trajectory)
    {
        o << "trajectory:\n  speed_mps: " << num(trajectory->speed_mps) << "\n  waypoints: [";
        for (size_t i = 0; i < trajectory->waypoints.size(); i++)
        {
            o << (i ? ", " : "") << pt(trajectory->waypoints[i]);
        }
        o << "]\n";
    }
    return o.str();
}

void World::saveToFile(const std::string& path) const
{
    // What semloc writes, semloc reads back: the text must load, with the same name and the
    // same objects (ids, labels, shapes; numbers are written exactly).
    const std::string text = toYamlText();
    try
    {
        const World back = World::FromText(text, path);
        bool same = back.name == name && back.objects.size() == objects.size();
        for (size_t i = 0; same && i < objects.size(); i++)
        {
            const auto &a = objects[i], &b = back.objects[i];
            same = a.id == b.id && a.label == b.label && a.shape == b.shape;
        }
        if (!same)
        {
            THROW_EXCEPTION("it reads back as another world");
        }
    }
    catch (const std::exception& e)
    {
        std::string why = errorMessage(e);
        const std::string prefix = "world file '" + path + "': ";
        if (why.compare(0, prefix.size(), prefix) == 0)
        {
            why.erase(0, prefix.size());
        }
        THROW_EXCEPTION("not writing world file '" + path +
                        "': semloc could not read it back: " + why);
    }
    errno = 0;
    std::ofstream f(path, std::ios::binary);
    if (!f)
    {
        THROW_EXCEPTION("cannot write world file '" + path + "': " + std::strerror(errno));
    }
    f << text;
    f.close();
    if (!f)
    {
        THROW_EXCEPTION("cannot write world file '" + path +
                        "': " + (errno ? std::strerror(errno) : "write error"));
    }
}

int World::indexOfId(int id) const
{
    for (size_t i = 0; i < objects.size(); i++)
    {
        if (objects[i].id == id)
        {
            return static_cast<int>(i);
        }
    }
    return -1;
}

// ------------------------------------------------------------------ geometry

namespace
{
/** True if p is inside the object's exact shape or on its boundary. */
bool insideObject(const WorldObject& o, const TPoint2D& p)
{
    const double dx = p.x - o.center.x, dy = p.y - o.center.y;
    if (dx * dx + dy * dy > o.extent_m * o.extent_m * (1 + 1e-12) + 1e-18)
    {
        return false;
    }
    switch (o.shape)
    {
        case ShapeType::Box:
        {
            // In the box frame (rotate by -yaw).
            const double c = std::cos(o.yaw), s = std::sin(o.yaw);
            const double u = c * dx + s * dy, v = -s * dx + c * dy;
            return std::abs(u) <= 0.5 * o.size_x + 1e-12 && std::abs(v) <= 0.5 * o.size_y + 1e-12;
        }
        case ShapeType::Cylinder:
            return true;  // within extent_m == radius
        case ShapeType::Polygon:
            return detail::pointInPolygon(p, o.points);
        case ShapeType::Point:
            return false;
    }
    return false;
}

/** Maximum number of rejection-sampling draws in sampleFreePose(). */
constexpr int kMaxFreeDraws = 100000;

/** Distance from p to the closed segment [a, b]. */
double pointSegmentDistance(const TPoint2D& p, const TPoint2D& a, const TPoint2D& b)
{
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    const double u =
        len2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - (a.x + u * ex), p.y - (a.y + u * ey));
}

/** Cells i of a raster axis (origin v0, side c, n cells) with floor((lo - v0) / c) <= i <=
 *  floor((hi - v0) / c), clamped to [0, n); false if there is none. */
bool cellSpan(double lo, double hi, double v0, double c, size_t n, size_t& i0, size_t& i1)
{
    const double a = std::floor((lo - v0) / c), b = std::floor((hi - v0) / c);
    const double last = static_cast<double>(n) - 1;
    if (!(b >= 0) || !(a <= last) || !(a <= b))
    {
        return false;
    }
    i0 = static_cast<size_t>(std::max(a, 0.0));
    i1 = static_cast<size_t>(std::min(b, last));
    return true;
}
}  // namespace

int World::cylinderSides(double radius_m, double tolerance_m)
{
    ASSERTMSG_(tolerance_m > 0 && std::isfinite(tolerance_m),
               "World::cylinderSides: the tolerance must be a finite number > 0");
    ASSERTMSG_(radius_m > 0 && std::isfinite(radius_m),
               "World::cylinderSides: the radius must be a finite number > 0");
    constexpr int kMinSides = 6, kMaxSides = 65536;
    const double ratio = tolerance_m / radius_m;
    if (ratio >= 1)
    {
        return kMinSides;  // the sagitta of any n >= 2 is at most r
    }
    // r (1 - cos(pi / n)) <= tol  <=>  n >= pi / acos(1 - tol / r)
    const double nReal = M_PI / std::acos(1 - ratio);
    if (!(nReal <= kMaxSides))
    {
        THROW_EXCEPTION(mrpt::format(
            "World::cylinderSides: tolerance %g m is too small for radius %g m (needs more "
            "than %d sides)",
            tolerance_m, radius_m, kMaxSides));
    }
    int n = std::max(kMinSides, static_cast<int>(std::ceil(nReal)));
    while (n < kMaxSides && radius_m * (1 - std::cos(M_PI / n)) > tolerance_m)
    {
        n++;  // guards the rounding of acos
    }
    return n;
}

std::vector<TPoint2D> World::outlinePolygon(const WorldObject& o, double cylinderTolerance_m)
{
    switch (o.shape)
    {
        case ShapeType::Box:
        case ShapeType::Polygon:
            return o.points;
        case ShapeType::Cylinder:
        {
            const int n = cylinderSides(o.radius, cylinderTolerance_m);
            std::vector<TPoint2D> p;
            p.reserve(static_cast<size_t>(n));
            for (int k = 0; k < n; k++)
            {
                const double a = 2 * M_PI * k / n;
                p.emplace_back(o.center.x + o.radius * std::cos(a),
                               o.center.y + o.radius * std::sin(a));
            }
            return p;
        }
        case ShapeType::Point:
            break;
    }
    return {};
}

std::vector<mrpt::math::TSegment2D> World::outlineSegments(double cylinderTolerance_m) const
{
    std::vector<mrpt::math::TSegment2D> segs;
    for (const auto& o : objects)
    {
        const auto poly = outlinePolygon(o, cylinderTolerance_m);
        for (size_t i = 0; i < poly.size(); i++)
        {
            segs.emplace_back(poly[i], poly[(i + 1) % poly.size()]);
        }
    }
    return segs;
}

bool World::isFree(double x, double y) const
{
    if (!bounds.contains(x, y))
    {
        return false;
    }
    const TPoint2D p(x, y);
    for (const auto& o : objects)
    {
        if (insideObject(o, p))
        {
            return false;
        }
    }
    return true;
}

mrpt::math::TPose2D World::sampleFreePose(mrpt::random::CRandomGenerator& rng) const
{
    for (int i = 0; i < kMaxFreeDraws; i++)
    {
        const double x = rng.drawUniform(bounds.x_min, bounds.x_max);
        const double y = rng.drawUniform(bounds.y_min, bounds.y_max);
        if (isFree(x, y))
        {
            return {x, y, rng.drawUniform(-M_PI, M_PI)};
        }
    }
    THROW_EXCEPTION(mrpt::format(
        "world '%s': no free space: none of %d uniform draws inside bounds fell outside "
        "every object outline",
        (source.empty() ? name : source).c_str(), kMaxFreeDraws));
}

int World::firstObjectOnSegment(const TPoint2D& a, const TPoint2D& b) const
{
    for (size_t k = 0; k < objects.size(); k++)
    {
        const auto& o = objects[k];
        if (o.shape == ShapeType::Point)
        {
            continue;
        }
        // The shape lies in the disc of radius extent_m around the centre (insideObject).
        const double d = pointSegmentDistance(o.center, a, b);
        if (d * d > o.extent_m * o.extent_m * (1 + 1e-12) + 1e-18)
        {
            continue;
        }
        bool touches = o.shape == ShapeType::Cylinder || insideObject(o, a) || insideObject(o, b);
        for (size_t i = 0; !touches && i < o.points.size(); i++)
        {
            touches = segmentsTouch(a, b, o.points[i], o.points[(i + 1) % o.points.size()]);
        }
        if (touches)
        {
            return static_cast<int>(k);
        }
    }
    return -1;
}

std::vector<uint8_t> World::freeRaster(double x0, double y0, double cell_m, size_t nx,
                                       size_t ny) const
{
    ASSERTMSG_(cell_m > 0 && std::isfinite(cell_m) && std::isfinite(x0) && std::isfinite(y0),
               "World::freeRaster: the origin must be finite and the cell a finite number > 0");
    std::vector<uint8_t> free(nx * ny, 1);
    if (free.empty())
    {
        return free;
    }
    auto cellIndex = [&](size_t i, size_t j) { return i + j * nx; };
    struct Run
    {
        size_t i0, i1;
    };
    std::vector<std::vector<Run>> rows;
    for (const auto& o : objects)
    {
        if (o.shape == ShapeType::Point)
        {
            continue;
        }
        // The margin by which cells are widened: far above the rounding of a cell lookup
        // ((x - x0) / cell) and of the exact tests' tolerances (relative 1e-12), so that a
        // point that is not free never looks up a cell marked free.
        const double m = 1e-4 + 1e-11 * (std::abs(o.center.x) + std::abs(o.center.y) + o.extent_m +
                                         std::abs(x0) + std::abs(y0));
        const double pad = 2 * m;
        if (o.shape == ShapeType::Cylinder || o.points.size() < 3)
        {
            // Every cell whose widened box meets the disc of radius r + m (an outline
            // without its points: the disc of its extent).
            const double R =
                (o.shape == ShapeType::Cylinder ? o.radius : o.extent_m) * (1 + 1e-12) + m;
            size_t j0 = 0, j1 = 0;
            if (!cellSpan(o.center.y - R - pad, o.center.y + R + pad, y0, cell_m, ny, j0, j1))
            {
                continue;
            }
            for (size_t j = j0; j <= j1; j++)
            {
                const double b0 = y0 + static_cast<double>(j) * cell_m - m;
                const double b1 = y0 + static_cast<double>(j + 1) * cell_m + m;
                const double dy = std::max({0.0, b0 - o.center.y, o.center.y - b1});
                if (dy > R)
                {
                    continue;
                }
                const double hw = std::sqrt(R * R - dy * dy);
                size_t i0 = 0, i1 = 0;
                if (cellSpan(o.center.x - hw - pad, o.center.x + hw + pad, x0, cell_m, nx, i0, i1))
                {
                    std::fill(free.begin() + static_cast<ptrdiff_t>(cellIndex(i0, j)),
                              free.begin() + static_cast<ptrdiff_t>(cellIndex(i1, j) + 1), 0);
                }
            }
            continue;
        }
        // Box or polygon: the cells its edges touch (per row, the x extent of each edge
        // within the row's widened band), then per row each run of untouched cells of the
        // bounding box is wholly inside or wholly outside: one exact test of a cell centre.
        const auto& poly = o.points;
        double xmin = poly[0].x, xmax = xmin, ymin = poly[0].y, ymax = ymin;
        for (const auto& p : poly)
        {
            xmin = std::min(xmin, p.x);
            xmax = std::max(xmax, p.x);
            ymin = std::min(ymin, p.y);
            ymax = std::max(ymax, p.y);
        }
        size_t bi0 = 0, bi1 = 0, bj0 = 0, bj1 = 0;
        if (!cellSpan(xmin - pad, xmax + pad, x0, cell_m, nx, bi0, bi1) ||
            !cellSpan(ymin - pad, ymax + pad, y0, cell_m, ny, bj0, bj1))
        {
            continue;
        }
        rows.assign(bj1 - bj0 + 1, {});
        for (size_t e = 0; e < poly.size(); e++)
        {
            const auto& a = poly[e];
            const auto& b = poly[(e + 1) % poly.size()];
            size_t j0 = 0, j1 = 0;
            if (!cellSpan(std::min(a.y, b.y) - pad, std::max(a.y, b.y) + pad, y0, cell_m, ny, j0,
                          j1))
            {
                continue;
            }
            for (size_t j = std::max(j0, bj0); j <= std::min(j1, bj1); j++)
            {
                const double lo = y0 + static_cast<double>(j) * cell_m - pad;
                const double hi = y0 + static_cast<double>(j + 1) * cell_m + pad;
                double xa = std::min(a.x, b.x), xb = std::max(a.x, b.x);
                if (a.y != b.y)
                {
                    const double ta = (lo - a.y) / (b.y - a.y), tb = (hi - a.y) / (b.y - a.y);
                    const double t0 = std::max(0.0, std::min(ta, tb));
                    const double t1 = std::min(1.0, std::max(ta, tb));
                    if (t0 > t1)
                    {
                        continue;
                    }
                    const double u0 = a.x + t0 * (b.x - a.x), u1 = a.x + t1 * (b.x - a.x);
                    xa = std::min(u0, u1);
                    xb = std::max(u0, u1);
                }
                size_t i0 = 0, i1 = 0;
                if (cellSpan(xa - pad, xb + pad, x0, cell_m, nx, i0, i1))
                {
                    rows[j - bj0].push_back({i0, i1});
                }
            }
        }
        for (size_t j = bj0; j <= bj1; j++)
        {
            auto& runs = rows[j - bj0];
            std::sort(runs.begin(), runs.end(),
                      [](const Run& l, const Run& r) { return l.i0 < r.i0; });
            const double cy = y0 + (static_cast<double>(j) + 0.5) * cell_m;
            size_t next = bi0;  // first cell of the row not yet classified
            auto untouched = [&](size_t from, size_t to)  // cells [from, to] of row j
            {
                const double cx = x0 + (static_cast<double>(from) + 0.5) * cell_m;
                if (from <= to && insideObject(o, TPoint2D(cx, cy)))
                {
                    std::fill(free.begin() + static_cast<ptrdiff_t>(cellIndex(from, j)),
                              free.begin() + static_cast<ptrdiff_t>(cellIndex(to, j) + 1), 0);
                }
            };
            for (const auto& r : runs)
            {
                if (r.i0 > next)
                {
                    untouched(next, std::min(r.i0 - 1, bi1));
                }
                std::fill(free.begin() + static_cast<ptrdiff_t>(cellIndex(r.i0, j)),
                          free.begin() + static_cast<ptrdiff_t>(cellIndex(r.i1, j) + 1), 0);
                next = std::max(next, r.i1 + 1);
            }
            if (next <= bi1)
            {
                untouched(next, bi1);
            }
        }
    }
    return free;
}

mrpt::maps::COccupancyGridMap2D World::makeOccupancyGrid(double resolution_m) const
{
    ASSERTMSG_(resolution_m > 0 && std::isfinite(resolution_m),
               "World::makeOccupancyGrid: resolution must be a finite number > 0");
    {
        const double w = bounds.x_max - bounds.x_min, h = bounds.y_max - bounds.y_min;
        const double cells = (std::ceil(w / resolution_m) + 1) * (std::ceil(h / resolution_m) + 1);
        const auto maxCells = static_cast<double>(kMaxOccupancyGridCells);
        if (!(cells <= maxCells))
        {
            // The resolution r at which (w / r + 1) (h / r + 1) = maxCells, a little coarser.
            const double a = w * h, bq = w + h, c = 1 - maxCells;
            const double u = (-bq + std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
            THROW_EXCEPTION(mrpt::format(
                "world '%s': an occupancy grid over its bounds x [%g, %g], y [%g, %g] at "
                "resolution %g m would have %.3g cells, more than the %zu allowed: use a "
                "resolution of %.3g m or coarser",
                (source.empty() ? name : source).c_str(), bounds.x_min, bounds.x_max, bounds.y_min,
                bounds.y_max, resolution_m, cells, kMaxOccupancyGridCells, 1.001 / u));
        }
    }
    mrpt::maps::COccupancyGridMap2D grid;
    grid.setSize(static_cast<float>(bounds.x_min), static_cast<float>(bounds.x_max),
                 static_cast<float>(bounds.y_min), static_cast<float>(bounds.y_max),
                 static_cast<float>(resolution_m), 1.0f);
    const double gx0 = grid.getXMin(), gy0 = grid.getYMin(), res = grid.getResolution();
    const int nx = static_cast<int>(grid.getSizeX()), ny = static_cast<int>(grid.getSizeY());
    // Cells are tested slightly inflated: MRPT maps coordinates to cells in float, so a
    // point within ~1e-5 m of a cell border may land in either neighbour.
    constexpr double kInflate_m = 5e-5;
    auto clampIdx = [](double v, int n)
    { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
    for (const auto& o : objects)
    {
        const auto poly = outlinePolygon(o);
        if (poly.empty())
        {
            continue;
        }
        double xmin = o.center.x - o.extent_m, xmax = o.center.x + o.extent_m;
        double ymin = o.center.y - o.extent_m, ymax = o.center.y + o.extent_m;
        for (const auto& p : poly)
        {
            xmin = std::min(xmin, p.x);
            xmax = std::max(xmax, p.x);
            ymin = std::min(ymin, p.y);
            ymax = std::max(ymax, p.y);
        }
        const int ix0 = clampIdx((xmin - kInflate_m - gx0) / res, nx);
        const int ix1 = clampIdx((xmax + kInflate_m - gx0) / res, nx);
        const int iy0 = clampIdx((ymin - kInflate_m - gy0) / res, ny);
        const int iy1 = clampIdx((ymax + kInflate_m - gy0) / res, ny);
        for (int iy = iy0; iy <= iy1; iy++)
        {
            const double cy0 = gy0 + iy * res;
            for (int ix = ix0; ix <= ix1; ix++)
            {
                const double cx0 = gx0 + ix * res;
                bool occupied = insideObject(o, TPoint2D(cx0 + 0.5 * res, cy0 + 0.5 * res));
                for (size_t i = 0; !occupied && i < poly.size(); i++)
                {
                    const auto& a = poly[i];
                    const auto& b = poly[(i + 1) % poly.size()];
                    occupied = detail::segmentTouchesBox(a.x, a.y, b.x, b.y, cx0 - kInflate_m,
                                                         cy0 - kInflate_m, cx0 + res + kInflate_m,
                                                         cy0 + res + kInflate_m);
                }
                if (occupied)
                {
                    grid.setCell(ix, iy, 0.0f);
                }
            }
        }
    }
    return grid;
}

}  // namespace semloc

/* semloc — the world-file writer: World -> YAML text that the reader reads back as the same
 * world (docs/design.md, "World file"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>
#include <vector>

#include "io/Text.h"
#include "world/WorldFileValues.h"
#include "world/WorldStream.h"

namespace semloc
{
namespace
{
/** The shortest text that reads back as `v`. */
constexpr auto num = detail::shortestText;
constexpr auto pt = detail::pointText;

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

/** One object as a flow map: `{id: .., label: .., shape: .., <its shape's keys>[, z: ..]}`,
 *  then sigma_m, p_exist and classes when not their defaults. */
void writeObject(std::ostream& o, const WorldObject& ob)
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
    if (ob.sigma_m != 0)
    {
        o << ", sigma_m: " << num(ob.sigma_m);
    }
    if (ob.p_exist != 1)
    {
        o << ", p_exist: " << num(ob.p_exist);
    }
    if (!ob.classes.empty())
    {
        o << ", classes: {";
        for (size_t i = 0; i < ob.classes.size(); i++)
        {
            o << (i ? ", " : "") << yamlString(ob.classes[i].first) << ": "
              << num(ob.classes[i].second);
        }
        o << "}";
    }
    o << "}\n";
}

/** The lines before the `objects` objects: name, bounds, `objects:`. */
void writeHeader(std::ostream& o, const World& w, size_t objects)
{
    if (!w.name.empty())
    {
        o << "name: " << yamlString(w.name) << "\n";
    }
    o << "bounds: {x_min: " << num(w.bounds.x_min) << ", x_max: " << num(w.bounds.x_max)
      << ", y_min: " << num(w.bounds.y_min) << ", y_max: " << num(w.bounds.y_max) << "}\n";
    o << "objects:" << (objects == 0 ? " []" : "") << "\n";
}

void writeBeacon(std::ostream& o, const WorldBeacon& b)
{
    o << "  - {id: " << b.id << ", x: " << num(b.x) << ", y: " << num(b.y);
    if (b.z != 0)
    {
        o << ", z: " << num(b.z);
    }
    o << "}\n";
}

void writeTrajectory(std::ostream& o, const WorldTrajectory& t)
{
    o << "trajectory:\n  speed_mps: " << num(t.speed_mps) << "\n  waypoints: [";
    for (size_t i = 0; i < t.waypoints.size(); i++)
    {
        o << (i ? ", " : "") << pt(t.waypoints[i]);
    }
    o << "]\n";
}

/** Bytes of text WorldTextSource makes at a time (whole lines). */
constexpr size_t kTextPiece = size_t{1} << 16;

/** `what` of a read-back that failed, without the "world file 'PATH': " the reader puts
 *  first. */
std::string readBackError(const std::exception& e, const std::string& path)
{
    std::string why = errorMessage(e);
    const std::string prefix = "world file '" + path + "': ";
    if (why.compare(0, prefix.size(), prefix) == 0)
    {
        why.erase(0, prefix.size());
    }
    return why;
}
}  // namespace

namespace detail
{
bool WorldTextSource::nextLines()
{
    std::ostringstream o;
    while (static_cast<size_t>(o.tellp()) < kTextPiece && m_part < 4)
    {
        if (m_part == 0)
        {
            writeHeader(o, m_world, objectCount());
            m_part = 1;
        }
        else if (m_part == 1 && m_item < objectCount())
        {
            writeObject(o, m_objects ? m_objects->at(m_item) : m_world.objects[m_item]);
            m_item++;
        }
        else if (m_part == 1)
        {
            o << (m_world.beacons.empty() ? "" : "beacons:\n");
            m_part = 2;
            m_item = 0;
        }
        else if (m_part == 2 && m_item < m_world.beacons.size())
        {
            writeBeacon(o, m_world.beacons[m_item++]);
        }
        else
        {
            if (m_part == 2 && m_world.trajectory)
            {
                writeTrajectory(o, *m_world.trajectory);
            }
            m_part = 4;
        }
    }
    m_line = o.str();
    m_at = 0;
    return !m_line.empty();
}

size_t WorldTextSource::objectCount() const
{
    return m_objects ? m_objects->count : m_world.objects.size();
}

size_t WorldTextSource::read(char* buf, size_t n)
{
    if (m_at == m_line.size() && !nextLines())
    {
        return 0;
    }
    const size_t k = std::min(n, m_line.size() - m_at);
    std::copy_n(m_line.data() + m_at, k, buf);
    m_at += k;
    return k;
}

void WorldTextSource::rewind()
{
    m_part = 0;
    m_item = 0;
    m_line.clear();
    m_at = 0;
}

void checkReadsBack(const World& world, const std::string& sourceName,
                    const WorldObjectList* objects)
{
    // What semloc writes, semloc reads back: the text must load, with the same name and the
    // same objects (ids, labels, shapes) and beacons (ids; numbers are written exactly).
    ASSERTMSG_(!objects || world.objects.empty(), "a world with objects and an object list");
    WorldTextSource text(world, objects);
    const size_t count = objects ? objects->count : world.objects.size();
    bool same = true;
    size_t read = 0;
    const ObjectSink compare = [&](WorldObject&& b, size_t i)
    {
        if (same && i < count)
        {
            const WorldObject a = objects ? objects->at(i) : world.objects[i];
            same = a.id == b.id && a.label == b.label && a.shape == b.shape;
        }
        same = same && i < count;
        read++;
    };
    // A trajectory's check needs the objects: such a world (a simulator's, small) is read
    // back whole.
    const World back = readWorld(text, sourceName, world.trajectory ? nullptr : &compare);
    for (size_t i = 0; world.trajectory && i < back.objects.size(); i++)
    {
        compare(WorldObject(back.objects[i]), i);
    }
    same = same && back.name == world.name && read == count &&
           back.beacons.size() == world.beacons.size();
    for (size_t i = 0; same && i < world.beacons.size(); i++)
    {
        same = back.beacons[i].id == world.beacons[i].id;
    }
    if (!same)
    {
        THROW_EXCEPTION("it reads back as another world");
    }
}
}  // namespace detail

namespace
{
/** World::saveToFile(): read back as it is made, then written as it is made. */
void saveWorldFile(const World& w, const std::string& path, const WorldObjectList* objects)
{
    try
    {
        detail::checkReadsBack(w, path, objects);
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("not writing world file '" + path +
                        "': semloc could not read it back: " + readBackError(e, path));
    }
    errno = 0;
    std::ofstream f(path, std::ios::binary);
    if (!f)
    {
        THROW_EXCEPTION("cannot write world file '" + path + "': " + std::strerror(errno));
    }
    detail::WorldTextSource lines(w, objects);
    std::vector<char> buf(kTextPiece);
    for (size_t n; f && (n = lines.read(buf.data(), buf.size())) > 0;)
    {
        f.write(buf.data(), static_cast<std::streamsize>(n));
    }
    f.close();
    if (!f)
    {
        THROW_EXCEPTION("cannot write world file '" + path +
                        "': " + (errno ? std::strerror(errno) : "write error"));
    }
}
}  // namespace

std::string World::toYamlText() const
{
    detail::WorldTextSource lines(*this);
    std::string text;
    char buf[kTextPiece];
    for (size_t n; (n = lines.read(buf, sizeof buf)) > 0;)
    {
        text.append(buf, n);
    }
    return text;
}

void World::saveToFile(const std::string& path) const
{
    saveWorldFile(*this, path, nullptr);
}

void World::saveToFile(const std::string& path, const WorldObjectList& list) const
{
    ASSERTMSG_(objects.empty(),
               "World::saveToFile: the world has objects of its own and an object list");
    saveWorldFile(*this, path, &list);
}

}  // namespace semloc

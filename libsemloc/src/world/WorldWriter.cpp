/* semloc — the world-file writer: World -> YAML text that the reader reads back as the same
 * world (docs/design.md, "World file"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/world/World.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>

#include "io/Text.h"
#include "world/WorldFileValues.h"

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
}  // namespace

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
        writeObject(o, ob);
    }
    if (!beacons.empty())
    {
        o << "beacons:\n";
        for (const auto& b : beacons)
        {
            o << "  - {id: " << b.id << ", x: " << num(b.x) << ", y: " << num(b.y);
            if (b.z != 0)
            {
                o << ", z: " << num(b.z);
            }
            o << "}\n";
        }
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
    // same objects (ids, labels, shapes) and beacons (ids; numbers are written exactly).
    const std::string text = toYamlText();
    try
    {
        const World back = World::FromText(text, path);
        bool same = back.name == name && back.objects.size() == objects.size() &&
                    back.beacons.size() == beacons.size();
        for (size_t i = 0; same && i < beacons.size(); i++)
        {
            same = back.beacons[i].id == beacons[i].id;
        }
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

}  // namespace semloc

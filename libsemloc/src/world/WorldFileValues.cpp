/* semloc — the values of a world file read strictly (docs/design.md, "World file"). */
#include "world/WorldFileValues.h"

#include <mrpt/core/format.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

#include "io/Text.h"

namespace semloc::detail
{
using mrpt::math::TPoint2D;

std::string scalarText(const WorldNode& n, const Where& w, const std::string& key)
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

double toNumber(const WorldNode& n, const Where& w, const std::string& key)
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

int toInt(const WorldNode& n, const Where& w, const std::string& key)
{
    const double v = toNumber(n, w, key);
    if (v != std::floor(v) || std::abs(v) > 2e9)
    {
        w.fail(key, "expected an integer, got '" + scalarText(n, w, key) + "'");
    }
    return static_cast<int>(v);
}

/** A coordinate or length: a finite number within +-kMaxWorldCoordinate_m. */
double toCoordinate(const WorldNode& n, const Where& w, const std::string& key)
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

TPoint2D toPoint(const WorldNode& n, const Where& w, const std::string& key)
{
    if (!n.isSequence() || n.asSequence().size() != 2)
    {
        w.fail(key, "expected a point [x, y]");
    }
    const auto& s = n.asSequence();
    return {toCoordinate(s[0], w, key), toCoordinate(s[1], w, key)};
}

const WorldNode& requireKey(const WorldMap& m, const std::string& key, const Where& w)
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

const WorldNode* findKey(const WorldMap& m, const std::string& key)
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

void checkKeys(const WorldMap& m, const std::set<std::string>& allowed, const Where& w)
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

std::string pointText(const TPoint2D& p)
{
    return "[" + shortestText(p.x) + ", " + shortestText(p.y) + "]";
}
}  // namespace semloc::detail

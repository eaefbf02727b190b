/* semloc — the values of a world file: where a value is (the prefix of every error message),
 * scalars, numbers, coordinates and points read strictly, keys required and allowed, and the
 * text of a point (private; docs/design.md, "World file"). */
#pragma once

#include <mrpt/containers/yaml.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/TPoint2D.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace semloc::detail
{
using WorldNode = mrpt::containers::yaml::node_t;
using WorldMap = mrpt::containers::yaml::map_t;

/** Where in the file a value is: composes the prefix of every error message. */
struct Where
{
    const std::string& file;
    std::string object;  // e.g. "objects[3] (id 7)", empty at top level

    /** Throws "world file '<file>': [<object>: ][key '<key>': ]<what>". */
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

/** The text of a scalar (a typed scalar of a document built in code: its %.17g text). */
std::string scalarText(const WorldNode& n, const Where& w, const std::string& key);
/** A finite number (blanks around and a leading '+' allowed). */
double toNumber(const WorldNode& n, const Where& w, const std::string& key);
/** An integer within +-2e9. */
int toInt(const WorldNode& n, const Where& w, const std::string& key);
/** A coordinate or length: a finite number within +-kMaxWorldCoordinate_m. */
double toCoordinate(const WorldNode& n, const Where& w, const std::string& key);
/** A point [x, y] of two coordinates. */
mrpt::math::TPoint2D toPoint(const WorldNode& n, const Where& w, const std::string& key);

/** The value of `key` in `m`; fails "missing required key" without it. */
const WorldNode& requireKey(const WorldMap& m, const std::string& key, const Where& w);
/** The value of `key` in `m`, or nullptr. */
const WorldNode* findKey(const WorldMap& m, const std::string& key);
/** Fails on the first key of `m` (in the map's order) that is not in `allowed`. */
void checkKeys(const WorldMap& m, const std::set<std::string>& allowed, const Where& w);

/** Index of the first element whose id an earlier element has (SIZE_MAX if none): the
 *  duplicates a set of ids filled in file order finds first, in memory for 16 bytes an
 *  element. */
template <typename Elements>
size_t firstRepeatedId(const Elements& elements)
{
    std::vector<std::pair<int, size_t>> byId;
    byId.reserve(elements.size());
    for (size_t i = 0; i < elements.size(); i++)
    {
        byId.emplace_back(elements[i].id, i);
    }
    std::sort(byId.begin(), byId.end());
    size_t first = std::numeric_limits<size_t>::max();
    for (size_t k = 1; k < byId.size(); k++)
    {
        if (byId[k].first == byId[k - 1].first)
        {
            first = std::min(first, byId[k].second);
        }
    }
    return first;
}

/** `[x, y]` of `p`, each the shortest text that reads back as it. */
std::string pointText(const mrpt::math::TPoint2D& p);
}  // namespace semloc::detail

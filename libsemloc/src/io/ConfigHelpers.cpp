/* semloc — strict ini value parsing. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/filesystem.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <typeindex>
#include <utility>

#include "io/Text.h"

namespace semloc::config
{
namespace
{
using detail::shortestText;
using detail::trim;

using detail::kUtf8Bom;

[[noreturn]] void fail(const std::string& section, const std::string& key, const std::string& what)
{
    THROW_EXCEPTION("ini [" + shownValue(section) + "] " + shownValue(key) + ": " + what);
}

bool readRaw(const mrpt::config::CConfigFileBase& c, const std::string& section,
             const std::string& key, std::string& out)
{
    if (!c.keyExists(section, key))
    {
        return false;
    }
    out = trim(c.read_string(section, key, "", false));
    return true;
}

/** `text` with every line ended by LF: CRLF and a CR alone (old Mac files) are line ends for
 *  MRPT's ini reader too. */
std::string lfLineEnds(const std::string& text)
{
    std::string out;
    out.reserve(text.size());
    for (size_t i = 0; i < text.size(); i++)
    {
        const bool crlf = text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n';
        if (!crlf)
        {
            out += text[i] == '\r' ? '\n' : text[i];
        }
    }
    return out;
}
}  // namespace

void readDouble(const mrpt::config::CConfigFileBase& c, const std::string& section,
                const std::string& key, double& value, double lo, double hi)
{
    std::string s;
    if (!readRaw(c, section, key, s))
    {
        return;
    }
    const char* b = s.data();
    if (!s.empty() && s[0] == '+')
    {
        ++b;
    }
    double v = 0;
    const auto r = std::from_chars(b, s.data() + s.size(), v);
    if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
    {
        fail(section, key, "'" + shownValue(s) + "' is not a number");
    }
    if (!std::isfinite(v))
    {
        fail(section, key, "'" + shownValue(s) + "' is not a finite number");
    }
    if (v < lo || v > hi)
    {
        fail(section, key,
             "value " + shownValue(s) + " is out of range [" + shortestText(lo) + ", " +
                 shortestText(hi) + "]");
    }
    value = v;
}

void readDoubles(const mrpt::config::CConfigFileBase& c, const std::string& section,
                 const std::string& key, std::vector<double>& values, size_t maxCount, double lo,
                 double hi)
{
    std::string s;
    if (!readRaw(c, section, key, s))
    {
        return;
    }
    std::vector<double> out;
    std::istringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
    {
        // Each item as a key of its own, so that it gets readDouble's checks and messages.
        mrpt::config::CConfigFileMemory one;
        one.write(section, key, trim(item));
        double v = 0;
        readDouble(one, section, key, v, lo, hi);
        out.push_back(v);
    }
    if (out.empty() || s.back() == ',')
    {
        fail(section, key, "'" + shownValue(s) + "' is not a list of numbers (a, b, ...)");
    }
    if (out.size() > maxCount)
    {
        fail(section, key,
             "'" + shownValue(s) + "' has " + std::to_string(out.size()) + " values: at most " +
                 std::to_string(maxCount));
    }
    values = out;
}

void readInt(const mrpt::config::CConfigFileBase& c, const std::string& section,
             const std::string& key, int& value, int lo, int hi)
{
    std::string s;
    if (!readRaw(c, section, key, s))
    {
        return;
    }
    long long v = 0;
    const char* b = s.data();
    if (!s.empty() && s[0] == '+')
    {
        ++b;
    }
    const auto r = std::from_chars(b, s.data() + s.size(), v);
    if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
    {
        fail(section, key, "'" + shownValue(s) + "' is not an integer");
    }
    if (v < lo || v > hi)
    {
        fail(section, key,
             "value " + shownValue(s) + " is out of range [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]");
    }
    value = static_cast<int>(v);
}

void readBool(const mrpt::config::CConfigFileBase& c, const std::string& section,
              const std::string& key, bool& value)
{
    std::string s;
    if (!readRaw(c, section, key, s))
    {
        return;
    }
    std::string l = s;
    std::transform(l.begin(), l.end(), l.begin(),
                   [](unsigned char ch) { return std::tolower(ch); });
    if (l == "true" || l == "1" || l == "yes" || l == "on")
    {
        value = true;
    }
    else if (l == "false" || l == "0" || l == "no" || l == "off")
    {
        value = false;
    }
    else
    {
        fail(section, key, "'" + shownValue(s) + "' is not a boolean (true/false)");
    }
}

void readChoice(const mrpt::config::CConfigFileBase& c, const std::string& section,
                const std::string& key, std::string& value, const std::vector<std::string>& choices)
{
    std::string s;
    if (!readRaw(c, section, key, s))
    {
        return;
    }
    if (std::find(choices.begin(), choices.end(), s) == choices.end())
    {
        std::string list;
        for (const auto& ch : choices)
        {
            list += (list.empty() ? "" : ", ") + ch;
        }
        fail(section, key, "'" + shownValue(s) + "' is not one of: " + list);
    }
    value = s;
}

namespace
{
/** MRPT's reader expands `${VAR}`, `$env{VAR}` and `$eval{EXPR}` and throws, naming neither
 *  the file nor its line, on one that is not closed on its line: named here. */
void rejectUnclosedExpansion(const std::string& content, const std::string& file, size_t n)
{
    for (size_t p = content.find('$'); p != std::string::npos; p = content.find('$', p + 1))
    {
        const auto brace = content.find('{', p);
        const bool opens = brace != std::string::npos &&
                           (brace == p + 1 || content.compare(p, brace - p, "$env") == 0 ||
                            content.compare(p, brace - p, "$eval") == 0);
        if (opens && content.find('}', brace) == std::string::npos)
        {
            THROW_EXCEPTION(mrpt::format(
                "%s:%zu: '%s' opens MRPT's %s{...} without its closing '}' on the line",
                file.c_str(), n, shownValue(content).c_str(),
                content.substr(p, brace - p).c_str()));
        }
    }
}
}  // namespace

void checkIniText(const std::string& text, const std::string& file)
{
    // MRPT's ini reader (SimpleIni) matches sections and keys regardless of ASCII case.
    auto lower = [](std::string s)
    {
        std::transform(s.begin(), s.end(), s.begin(),
                       [](unsigned char ch) { return std::tolower(ch); });
        return s;
    };
    // Per section (lower case): its name as first written and the first line of each key.
    std::map<std::string, std::pair<std::string, std::map<std::string, size_t>>> sections;
    auto* current = &sections[""];
    std::istringstream in(lfLineEnds(text));
    std::string line;
    for (size_t n = 1; std::getline(in, line); n++)
    {
        if (n == 1 && line.compare(0, 3, kUtf8Bom) == 0)
        {
            line.erase(0, 3);  // a byte-order mark: MRPT skips it too
        }
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == ';' || line[b] == '#' || line[b] == '%' ||
            line[b] == '@' || line.compare(b, 2, "//") == 0)
        {
            continue;
        }
        const auto e = line.find_last_not_of(" \t\r");
        const std::string content = line.substr(b, e - b + 1);
        const bool section = content.front() == '[' && content.back() == ']' && content.size() > 2;
        const auto eq = content.find('=');
        const bool keyValue = content.front() != '[' && eq != std::string::npos && eq > 0;
        if (!section && !keyValue)
        {
            THROW_EXCEPTION(mrpt::format("%s:%zu: '%s' is neither a [section] nor key = value",
                                         file.c_str(), n, shownValue(content).c_str()));
        }
        rejectUnclosedExpansion(content, file, n);
        if (section)
        {
            const std::string name = trim(content.substr(1, content.size() - 2));
            current = &sections[lower(name)];
            if (current->first.empty())
            {
                current->first = name;
            }
            continue;
        }
        const std::string key = trim(content.substr(0, eq));
        const auto [it, added] = current->second.emplace(lower(key), n);
        if (!added)
        {
            THROW_EXCEPTION(mrpt::format(
                "%s:%zu: [%s] %s: set twice (also on line %zu; MRPT would silently use the "
                "last value): keep one",
                file.c_str(), n, shownValue(current->first).c_str(), shownValue(key).c_str(),
                it->second));
        }
    }
}

void rejectUnknownKeys(const mrpt::config::CConfigFileBase& c, const std::string& section,
                       const std::vector<std::string>& known)
{
    std::vector<std::string> keys;
    c.getAllKeys(section, keys);
    for (auto k : keys)
    {
        k = trim(k);
        if (std::find(known.begin(), known.end(), k) == known.end())
        {
            std::string list;
            for (const auto& kn : known)
            {
                list += (list.empty() ? "" : ", ") + kn;
            }
            fail(section, k, "unknown key (known keys: " + list + ")");
        }
    }
}

std::string iniFileOf(const mrpt::config::CConfigFileBase& source)
{
    if (const auto* f = dynamic_cast<const mrpt::config::CConfigFile*>(&source))
    {
        return f->getAssociatedFile();
    }
    if (const auto* m = dynamic_cast<const IniFileInMemory*>(&source))
    {
        return m->path();
    }
    return {};
}

namespace
{
/** `file` joined to the directory of the ini `origin`. */
std::string nextToIni(const std::string& origin, const std::string& file)
{
    // MRPT 2.5's extractFileDirectory() drops the trailing separator: join explicitly.
    const std::string dir = mrpt::system::extractFileDirectory(origin);
    return mrpt::system::pathJoin({dir.empty() ? "." : dir, file});
}
}  // namespace

namespace
{
/** The files `source` was read from: an IniFileInMemory's file and its bases, a CConfigFile's
 *  file, or none. */
std::vector<std::string> iniFilesOf(const mrpt::config::CConfigFileBase& source)
{
    if (const auto* m = dynamic_cast<const IniFileInMemory*>(&source))
    {
        return m->files();
    }
    if (std::string f = iniFileOf(source); !f.empty())
    {
        return {f};
    }
    return {};
}
}  // namespace

std::string resolveNextToIni(const mrpt::config::CConfigFileBase& source, const std::string& file)
{
    if (file.empty() || file[0] == '/' || mrpt::system::fileExists(file))
    {
        return file;
    }
    for (const auto& origin : iniFilesOf(source))
    {
        std::string joined = nextToIni(origin, file);
        if (mrpt::system::fileExists(joined))
        {
            return joined;
        }
    }
    return file;
}

std::string missingFileMessage(const mrpt::config::CConfigFileBase& source,
                               const std::string& written)
{
    std::string m = "file '" + written + "' does not exist";
    const auto origins = iniFilesOf(source);
    if (!written.empty() && written[0] != '/' && !origins.empty())
    {
        m += " (tried";
        for (size_t i = 0; i < origins.size(); i++)
        {
            m += std::string(i == 0 ? " '" : ", '") + nextToIni(origins[i], written) +
                 "' next to " + (i == 0 ? "the ini '" : "its base '") + origins[i] + "'";
        }
        m += " and '" + written + "' from the working directory)";
    }
    return m;
}

std::vector<std::string> keysOf(const mrpt::config::CLoadableOptions& o, const std::string& variant)
{
    // Once per class and variant: saving the options to list their keys costs more than the
    // rest of a load.
    static std::mutex mutex;
    static std::map<std::pair<std::type_index, std::string>, std::vector<std::string>> known;
    const std::lock_guard<std::mutex> lock(mutex);
    const auto id = std::make_pair(std::type_index(typeid(o)), variant);
    if (const auto it = known.find(id); it != known.end())
    {
        return it->second;
    }
    mrpt::config::CConfigFileMemory mem;
    o.saveToConfigFile(mem, "s");
    std::vector<std::string> keys;
    mem.getAllKeys("s", keys);
    for (auto& k : keys)
    {
        k = trim(k);  // MRPT pads keys to align the written columns
    }
    known.emplace(id, keys);
    return keys;
}

}  // namespace semloc::config

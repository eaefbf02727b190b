/* semloc — an ini's text with keys set in place, each with its comment: semloc-calibrate's
 * output (private). */
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/Text.h"

namespace semloc
{
struct TCalibrationFit;
}

namespace semloc::detail
{
inline std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

/** The section a line opens ("" when it opens none). */
inline std::string sectionOf(const std::string& line)
{
    const std::string t = trim(line);
    return t.size() >= 2 && t.front() == '[' && t.back() == ']' ? trim(t.substr(1, t.size() - 2))
                                                                : std::string();
}

/** The key a line sets ("" for a comment, a blank line or a section). */
inline std::string keyOf(const std::string& line)
{
    const std::string t = trim(line);
    const auto eq = t.find('=');
    if (t.empty() || t[0] == '#' || t[0] == ';' || t[0] == '[' || t.rfind("//", 0) == 0 ||
        eq == std::string::npos)
    {
        return "";
    }
    return trim(t.substr(0, eq));
}

/** A value as the calibrated ini writes it: 4 significant digits. */
inline std::string number(double v)
{
    std::ostringstream s;
    s << std::setprecision(4) << v;
    return s.str();
}

/** The line `key = value // comment`, aligned as semloc's inis are. */
inline std::string keyLine(const std::string& key, const std::string& value,
                           const std::string& comment)
{
    std::string k = key;
    k.resize(std::max<size_t>(key.size() + 1, 24), ' ');  // a blank before "=" always
    std::string v = value + " ";  // MRPT reads "//" as a comment only after a blank
    v.resize(std::max<size_t>(v.size(), 10), ' ');
    return k + "= " + v + (comment.empty() ? "" : "// " + comment);
}

/** The base's lines, with `key` of `section` set (replaced where the base has it, else added
 *  at the end of the section, or in a new section at the end). */
class IniText
{
public:
    IniText(const std::string& text, std::string name) : m_name(std::move(name))
    {
        std::istringstream in(text);
        for (std::string line; std::getline(in, line);)
        {
            m_lines.push_back(line);
        }
    }
    void set(const std::string& section, const std::string& key, const std::string& value,
             const std::string& comment)
    {
        std::string cur;
        size_t found = m_lines.size(), lastInSection = m_lines.size();
        bool inSection = false;
        for (size_t i = 0; i < m_lines.size(); i++)
        {
            if (const std::string s = sectionOf(m_lines[i]); !s.empty())
            {
                inSection = lower(s) == lower(section);
                cur = s;
            }
            if (!inSection)
            {
                continue;
            }
            if (!trim(m_lines[i]).empty())
            {
                lastInSection = i;
            }
            if (lower(keyOf(m_lines[i])) == lower(key))
            {
                if (found < m_lines.size())
                {
                    std::string msg = "ini '" + m_name + "': line ";
                    msg += std::to_string(i + 1);
                    msg += ": [" + section;
                    msg += "] " + key;
                    msg += ": set twice (first on line " + std::to_string(found + 1);
                    msg += ")";
                    throw std::runtime_error(msg);
                }
                found = i;
            }
        }
        const std::string line = keyLine(key, value, comment);
        if (found < m_lines.size())
        {
            m_lines[found] = line;
        }
        else if (lastInSection < m_lines.size())
        {
            m_lines.insert(m_lines.begin() + static_cast<std::ptrdiff_t>(lastInSection + 1), line);
        }
        else
        {
            m_lines.emplace_back("");
            m_lines.push_back("[" + section + "]");
            m_lines.push_back(line);
        }
    }
    /** Adds the comment line "// `comment`" at the end of `section`; false when the text has
     *  no such section. */
    bool note(const std::string& section, const std::string& comment)
    {
        size_t last = m_lines.size();
        bool inSection = false;
        for (size_t i = 0; i < m_lines.size(); i++)
        {
            if (const std::string s = sectionOf(m_lines[i]); !s.empty())
            {
                inSection = lower(s) == lower(section);
            }
            if (inSection && !trim(m_lines[i]).empty())
            {
                last = i;
            }
        }
        if (last == m_lines.size())
        {
            return false;
        }
        m_lines.insert(m_lines.begin() + static_cast<std::ptrdiff_t>(last + 1), "// " + comment);
        return true;
    }
    std::string text() const
    {
        std::string out;
        for (const auto& l : m_lines)
        {
            out += l + "\n";
        }
        return out;
    }

private:
    std::string m_name;
    std::vector<std::string> m_lines;
};

/** The comment of a fit in the calibrated ini: "calibrated: n = 120, +/- 0.02 (95 %), METHOD",
 *  or why it is not the fit as made (clamped, widened). */
std::string fitComment(const TCalibrationFit& f);

}  // namespace semloc::detail

/* semloc — the comma-separated lists of Benchmark's ini files (private). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <sstream>
#include <string>
#include <vector>

#include "io/Text.h"

namespace semloc::detail
{
/** The items of a comma-separated list, trimmed. */
inline std::vector<std::string> splitList(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        out.push_back(trim(item));
    }
    return out;
}

/** A comma-separated list of names or files, each without blanks; `key` names errors. */
inline std::vector<std::string> readList(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s, const std::string& key)
{
    const std::string text = c.read_string(s, key, "");
    auto out = splitList(text);
    for (const auto& v : out)
    {
        if (v.empty() || v.find_first_of(" \t") != std::string::npos)
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s] %s: '%s' is not a comma-separated list of names or ini files", s.c_str(),
                key.c_str(), text.c_str()));
        }
    }
    return out;
}

/** The items joined by commas. */
inline std::string joinList(const std::vector<std::string>& v)
{
    std::string s;
    for (const auto& x : v)
    {
        s += (s.empty() ? "" : ",") + x;
    }
    return s;
}
}  // namespace semloc::detail

/* semloc — writing ini values that read back bit-exactly (private). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

#include "io/Text.h"

namespace semloc::detail
{
/** Writes `value` in the shortest fixed-point text that reads back as the same double (MRPT's own
 *  write() keeps 6 digits, so an effective configuration would not reproduce its run). */
inline void writeExact(mrpt::config::CConfigFileBase& c, const std::string& section,
                       const std::string& key, double value, const std::string& comment)
{
    c.write(section, key, fixedText(value), 24, 24, comment);
}

/** Writes `values` comma-separated, each as writeExact() writes a number; "0" for none. */
inline void writeExactList(mrpt::config::CConfigFileBase& c, const std::string& section,
                           const std::string& key, const std::vector<double>& values,
                           const std::string& comment)
{
    std::string text;
    for (const double v : values)
    {
        text += (text.empty() ? "" : ", ") + fixedText(v);
    }
    c.write(section, key, text.empty() ? std::string("0") : text, 24, 24, comment);
}

/** Writes a text value with its comment, or without the comment when the value is empty or
 *  holds "//": MRPT reads `key = // comment` back as "// comment", and takes no inline comment
 *  from a value whose first "//" follows no blank (`/data//run.rawlog // the dataset` reads back
 *  whole) (both found by tests/fuzz/fuzz_ini). */
inline void writeText(mrpt::config::CConfigFileBase& c, const std::string& section,
                      const std::string& key, const std::string& value, const std::string& comment)
{
    if (value.empty() || value.find("//") != std::string::npos)
    {
        c.write(section, key, value);
    }
    else
    {
        c.write(section, key, value, 24, 24, comment);
    }
}

}  // namespace semloc::detail

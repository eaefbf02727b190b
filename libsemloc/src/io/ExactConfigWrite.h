/* semloc — writing ini values that read back bit-exactly (private). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <charconv>
#include <string>

namespace semloc::detail
{
/** Writes `value` in the shortest fixed-point text that reads back as the same double (MRPT's own
 *  write() keeps 6 digits, so an effective configuration would not reproduce its run). */
inline void writeExact(mrpt::config::CConfigFileBase& c, const std::string& section,
                       const std::string& key, double value, const std::string& comment)
{
    char buf[400];  // fixed notation of any double fits
    const auto r = std::to_chars(buf, buf + sizeof(buf), value, std::chars_format::fixed);
    c.write(section, key, std::string(buf, r.ptr), 24, 24, comment);
}

/** Writes a text value with its comment, or without the comment when the value is empty: MRPT
 *  reads `key = // comment` back as "// comment" (found by tests/fuzz/fuzz_ini). */
inline void writeText(mrpt::config::CConfigFileBase& c, const std::string& section,
                      const std::string& key, const std::string& value, const std::string& comment)
{
    if (value.empty())
    {
        c.write(section, key, value);
    }
    else
    {
        c.write(section, key, value, 24, 24, comment);
    }
}

}  // namespace semloc::detail

/* semloc — trimming and number text shared by the readers and writers (private). */
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace semloc::detail
{
/** The UTF-8 byte-order mark some editors put at the start of a text file; the readers of
 *  text files (ini, CSV) skip it. */
inline constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";

/** `s` without the blanks, tabs, CRs and LFs at either end. */
inline std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
    {
        return {};
    }
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

/** An ini value as MRPT returns it, trimmed the way a user reads it: without the blanks and
 *  tabs in front, nor the blanks, tabs and CR (of a CRLF line) at the end. */
inline std::string trimValue(std::string s)
{
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t\r") + 1);
    return s;
}

/** The shortest text that reads back as `v` ("nan", "inf", "-inf" if not finite). */
inline std::string shortestText(double v)
{
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, r.ptr);
}

/** The shortest fixed-point text (no exponent) that reads back as `v`. */
inline std::string fixedText(double v)
{
    char buf[400];  // fixed notation of any double fits
    const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed);
    return std::string(buf, r.ptr);
}

/** A time [s] as every message of the importers writes it: fixed-point, the shortest text
 *  that reads back (1700000000.25), or the shortest text with an exponent from 1e15 on
 *  (1.7e+18), where fixed-point would print digits that mean nothing. */
inline std::string timeText(double t)
{
    return std::abs(t) < 1e15 ? fixedText(t) : shortestText(t);
}

}  // namespace semloc::detail

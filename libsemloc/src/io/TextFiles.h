/* semloc — small text-file helpers shared by the writers (private). */
#pragma once

#include <mrpt/core/exceptions.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

namespace semloc::detail
{
/** Writes `text` to `path` (replacing it); throws "cannot write 'PATH': REASON" on any
 *  error. */
inline void writeFile(const std::string& path, const std::string& text)
{
    errno = 0;
    std::ofstream f(path, std::ios::binary);
    f << text;
    f.close();
    if (!f)
    {
        const int e = errno;
        THROW_EXCEPTION("cannot write '" + path + "': " + (e ? std::strerror(e) : "write error"));
    }
}

/** `s` as one POSIX shell word (single-quoted). */
inline std::string shellQuoted(const std::string& s)
{
    std::string out = "'";
    for (const char c : s)
    {
        out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
    }
    return out + "'";
}

}  // namespace semloc::detail

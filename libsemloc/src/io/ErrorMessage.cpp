/* semloc — errorMessage(): user-facing text of an exception. */
#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace semloc
{
namespace
{
/** Length of the valid UTF-8 sequence (2 to 4 bytes) of a printable character beyond ASCII at
 *  the start of `s`, or 0 (invalid, a C1 control, or a character that prints nothing). */
size_t printableUtf8(std::string_view s)
{
    const auto b = [&](size_t i) { return static_cast<unsigned char>(s[i]); };
    const unsigned char c = b(0);
    const size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
    if (n == 0 || n > s.size())
    {
        return 0;
    }
    unsigned cp = c & (0xFFu >> (n + 1));
    for (size_t i = 1; i < n; i++)
    {
        if ((b(i) & 0xC0) != 0x80)
        {
            return 0;
        }
        cp = (cp << 6) | (b(i) & 0x3Fu);
    }
    const unsigned minimum[] = {0, 0, 0x80, 0x800, 0x10000};
    const bool invisible = cp < 0xA0 || cp == 0xAD || cp == 0xFEFF ||
                           (cp >= 0x200B && cp <= 0x200F) || (cp >= 0x2028 && cp <= 0x202E) ||
                           (cp >= 0x2060 && cp <= 0x2069);
    const bool valid = cp >= minimum[n] && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
    return valid && !invisible ? n : 0;
}
/** `full` without MRPT's frame lines ("==== ... ===="), labels ("Message:", "Location:") and
 *  call-stack backtrace: for an exception whose text MRPT put after "Location:" (a
 *  std::exception it wrapped), which leaves "Message:" empty. */
std::string withoutBacktrace(const std::string& full)
{
    std::istringstream in(full);
    std::string out;
    for (std::string line; std::getline(in, line);)
    {
        if (line.rfind("Call stack", 0) == 0)
        {
            break;
        }
        for (const char* label : {"Message:", "Location:"})
        {
            if (line.rfind(label, 0) == 0)
            {
                line.erase(0, std::string(label).size());
            }
        }
        const auto b = line.find_first_not_of(' ');
        if (b == std::string::npos || line.rfind("====", b) == b)
        {
            continue;
        }
        out += (out.empty() ? "" : "\n") + line.substr(b);
    }
    return out.empty() ? full : out;
}
}  // namespace

std::string shownValue(std::string_view value)
{
    std::string out;
    size_t shown = 0;  // characters written
    for (size_t i = 0; i < value.size();)
    {
        const auto c = static_cast<unsigned char>(value[i]);
        std::string piece;
        size_t used = 1;
        if (c >= 0x20 && c < 0x7F)
        {
            piece.assign(1, static_cast<char>(c));
        }
        else if (const size_t n = c >= 0x80 ? printableUtf8(value.substr(i)) : 0; n > 0)
        {
            piece.assign(value.substr(i, n));
            used = n;
        }
        else
        {
            char esc[8];
            std::snprintf(esc, sizeof(esc), "\\x%02X", c);
            piece = esc;
        }
        const size_t width = used > 1 ? 1 : piece.size();  // a UTF-8 character: one
        if (shown + width > kMaxShownValue)
        {
            return out + "\u2026";
        }
        out += piece;
        shown += width;
        i += used;
    }
    return out;
}

std::string errorMessage(const std::exception& e)
{
    std::string full = mrpt::exception_to_str(e);
    if (const char* dbg = std::getenv("SEMLOC_DEBUG"); dbg && std::string(dbg) == "1")
    {
        return full;
    }
    // MRPT formats each level as "Message:  <text>\nLocation: ...\nCall stack backtrace: ...".
    std::istringstream in(full);
    std::string line, out;
    for (bool inMessage = false; std::getline(in, line);)
    {
        if (line.rfind("Message:", 0) == 0)
        {
            const auto b = line.find_first_not_of(' ', 8);
            out += (out.empty() ? "" : "\n") + (b == std::string::npos ? "" : line.substr(b));
            inMessage = true;
        }
        else if (line.rfind("Location:", 0) == 0 || line.rfind("Call stack", 0) == 0 ||
                 line.rfind("====", 0) == 0)
        {
            inMessage = false;
        }
        else if (inMessage && !line.empty())
        {
            out += "\n" + line;  // multi-line messages
        }
    }
    return out.empty() ? withoutBacktrace(full) : out;
}

}  // namespace semloc

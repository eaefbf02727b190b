/* semloc — errorMessage(): user-facing text of an exception. */
#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>

#include <cstdlib>
#include <sstream>

namespace semloc
{
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
    return out.empty() ? std::string(e.what()) : out;
}

}  // namespace semloc

/* semloc — a temporary directory of a job, removed with it (also by the interrupt watchdog). */
#pragma once

#include <mrpt/core/exceptions.h>
#include <semloc/io/Interrupt.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

namespace semloc::detail
{
/** A new directory `<dir>/<prefix>XXXXXX`, registered for the interrupt watchdog and removed
 *  with everything in it at the end of the scope. */
class TemporaryDirectory
{
public:
    TemporaryDirectory(const std::filesystem::path& dir, const std::string& prefix)
    {
        std::string name = (dir / (prefix + "XXXXXX")).string();
        const InterruptExitDeferral defer;  // created and registered as one step
        if (!::mkdtemp(name.data()))
        {
            THROW_EXCEPTION("cannot create a temporary directory in '" + dir.string() +
                            "': " + std::strerror(errno));
        }
        m_path = name;
        registerTemporaryPath(m_path);
    }
    ~TemporaryDirectory()
    {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
        unregisterTemporaryPath(m_path);
    }
    TemporaryDirectory(const TemporaryDirectory&) = delete;
    TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
    /** `file` inside the directory. */
    std::string path(const std::string& file) const
    {
        return (std::filesystem::path(m_path) / file).string();
    }

private:
    std::string m_path;
};
}  // namespace semloc::detail

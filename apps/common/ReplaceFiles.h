/* semloc tools — output files written under temporary names and renamed together. */
#pragma once

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/Interrupt.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace semloc::apps
{
/** `write()` writes every file of `outputs` as `<file>.tmp`; then all are renamed onto the
 *  outputs, or on an error (Ctrl-C too) the temporary files are removed and the outputs stay
 *  as they were. */
inline void replaceAll(const std::vector<std::string>& outputs, const std::function<void()>& write)
{
    for (const auto& f : outputs)
    {
        semloc::registerTemporaryPath(f + ".tmp");
    }
    try
    {
        write();
        if (semloc::interruptRequested())
        {
            throw semloc::Interrupted();
        }
    }
    catch (...)
    {
        for (const auto& f : outputs)
        {
            std::remove((f + ".tmp").c_str());
            semloc::unregisterTemporaryPath(f + ".tmp");
        }
        throw;
    }
    const semloc::InterruptExitDeferral whole;  // all renamed, or none
    for (const auto& f : outputs)
    {
        if (std::rename((f + ".tmp").c_str(), f.c_str()) != 0)
        {
            THROW_EXCEPTION(mrpt::format("cannot rename '%s.tmp' to '%s': %s", f.c_str(), f.c_str(),
                                         std::strerror(errno)));
        }
        semloc::unregisterTemporaryPath(f + ".tmp");
    }
}

}  // namespace semloc::apps

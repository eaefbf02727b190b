/* semloc tools — the main() every tool shares. */
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <semloc/ErrorMessage.h>
#include <semloc/Interrupt.h>

#include <iostream>

namespace semloc::apps
{
/** Parses the command line and calls `run()`: exit 0 on success and after --help/--version,
 *  1 on any error, printed as "<tool>: <message>" (SEMLOC_DEBUG=1 adds MRPT's details), 130
 *  when a job that installed semloc::installInterruptHandlers() stopped at Ctrl-C. */
template <typename RUN>
int runMain(TCLAP::CmdLine& cmd, int argc, char** argv, const char* tool, RUN&& run)
{
    try
    {
        if (!cmd.parse(argc, argv))
        {
            return 0;  // --help or --version was printed
        }
        run();
        return 0;
    }
    catch (const semloc::Interrupted& e)
    {
        std::cerr << tool << ": " << e.what() << "\n";
        return 130;  // as a shell reports a process ended by SIGINT
    }
    catch (const std::exception& e)
    {
        std::cerr << tool << ": " << semloc::errorMessage(e) << "\n";
        return 1;
    }
}

}  // namespace semloc::apps

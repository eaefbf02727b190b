/* semloc tools — the main() every tool shares. */
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>

#include <cstdint>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

namespace semloc::apps
{
/** TCLAP's standard output that remembers a parse error: MRPT's TCLAP prints it and returns
 *  false from CmdLine::parse(), as after --help, instead of exiting with status 1. */
class ParseErrorFlag : public TCLAP::StdOutput
{
public:
    bool failed = false;
    void failure(TCLAP::CmdLineInterface& c, TCLAP::ArgException& e) override
    {
        failed = true;
        TCLAP::StdOutput::failure(c, e);
    }
};

/** A --seed option's value as the ini keys `seed` take it, 0..2^31-1 (a negative one must
 *  not wrap around); throws naming the option otherwise. */
inline uint32_t seedOption(long long v)
{
    if (v < 0 || v > std::numeric_limits<int>::max())
    {
        throw std::invalid_argument("--seed must be in [0, " +
                                    std::to_string(std::numeric_limits<int>::max()) + "]");
    }
    return static_cast<uint32_t>(v);
}

/** Parses the command line (taking over its TCLAP output) and calls `run()`: exit 0 on
 *  success and after --help/--version, 1 on any error (a bad command line included), printed
 *  as "<tool>: <message>" (SEMLOC_DEBUG=1 adds MRPT's details; TCLAP's own format for the
 *  command line), 130 at Ctrl-C or SIGTERM (semloc::installInterruptHandlers(), installed
 *  before `run()`: nothing is left behind). */
template <typename RUN>
int runMain(TCLAP::CmdLine& cmd, int argc, char** argv, const char* tool, RUN&& run)
{
    // Ours replaces TCLAP's own output, which `cmd` then no longer frees; `output` outlives
    // `cmd`, which keeps a pointer to it.
    static ParseErrorFlag output;
    if (cmd.getOutput() != &output)
    {
        delete cmd.getOutput();
        cmd.setOutput(&output);
    }
    try
    {
        if (!cmd.parse(argc, argv))
        {
            return output.failed ? 1 : 0;  // a parse error, or --help / --version printed
        }
        // Ctrl-C from the start: while the inputs are read, nothing is written yet and the
        // watchdog ends the process; later a job stops at its next check (exit 130 always).
        semloc::installInterruptHandlers(tool);
        run();
        semloc::markRunComplete();
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

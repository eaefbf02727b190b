/* semloc — runGnuplot: a gnuplot script run in a staged output directory. */
#include "io/Gnuplot.h"

#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace semloc::detail
{
void runGnuplot(const StagedDirectory& out, const std::string& script,
                const std::vector<std::string>& outputs)
{
    const std::string log = out.path(script + ".log");
    int rc = 0;
    try
    {
        rc = runChildProcess({"gnuplot", script}, log, out.path(""));
    }
    catch (const Interrupted&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION(errorMessage(e) + " (is the Debian package gnuplot-nox installed?)");
    }
    bool drawn = true;
    for (const auto& file : outputs)
    {
        drawn = drawn && std::filesystem::exists(out.path(file));
    }
    if (rc != 0 || !drawn)
    {
        std::ifstream f(log);
        std::stringstream msg;
        msg << f.rdbuf();
        THROW_EXCEPTION("gnuplot failed on " + script + " (it " + waitStatusText(rc) +
                        "): " + msg.str());
    }
    std::filesystem::remove(log);
}
}  // namespace semloc::detail

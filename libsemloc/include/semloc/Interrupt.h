/* semloc — stopping a long job cleanly (Ctrl-C). */
#pragma once

#include <stdexcept>

namespace semloc
{
/** Thrown by a long job (Benchmark::run) that saw interruptRequested(): the job stopped
 *  before writing its outputs, and its staging directory is removed as the exception
 *  unwinds. */
class Interrupted : public std::runtime_error
{
public:
    Interrupted();
};

/** Asks the running jobs to stop at their next check (async-signal-safe: a signal handler,
 *  a GUI's stop button or another thread may call it). */
void requestInterrupt() noexcept;
/** True once requestInterrupt() was called and until clearInterrupt(). */
bool interruptRequested() noexcept;
void clearInterrupt() noexcept;

/** Makes SIGINT and SIGTERM call requestInterrupt() (the tools do this). A second signal
 *  gets the default action: the process ends at once. Installed without SA_RESTART, so a
 *  blocking wait returns and the job sees the request. */
void installInterruptHandlers();

}  // namespace semloc

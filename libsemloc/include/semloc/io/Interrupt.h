/* semloc — stopping a long job cleanly (Ctrl-C): the request its loops check. The signal
 * handlers and the watchdog of the tools are in libsemloc_tools (semloc/io/ProcessControl.h). */
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

/** How many times clearInterrupt() has been called (async-signal-safe): whoever watches a
 *  request (the tools' watchdog) tells by it that the request it saw was handled and cleared,
 *  even when a new one followed. */
unsigned interruptGeneration() noexcept;

}  // namespace semloc

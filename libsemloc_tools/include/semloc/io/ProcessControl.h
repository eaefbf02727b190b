/* semloc — a tool's process at Ctrl-C: the signal handlers that request the interrupt
 * (semloc/io/Interrupt.h), the watchdog that ends a job that does not stop by itself, what it
 * removes and ends, and the child processes the tools run. */
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace semloc
{
/** Makes SIGINT and SIGTERM call requestInterrupt() (the tools do this). The handler stays in
 *  place: a second signal makes the watchdog end the process at once, with the same cleanup
 *  (children ended, temporary paths removed); more signals change nothing. Installed without
 *  SA_RESTART, so a blocking wait returns and the job sees the request.
 *
 *  It also starts a watchdog thread (once per process): a job that has not returned within
 *  kInterruptGracePeriod_s of the first signal (or at once after a second one) (a step inside MRPT
 * that has no check, such as KLD sampling) is ended by the watchdog, unless clearInterrupt() was
 * called meanwhile. It kills the registered child processes (SIGKILL, and waits for them), removes
 * the registered temporary paths, prints "<tool>: interrupted; no output written" (`tool`: a string
 * that lives as long as the process, such as a literal; the program's name when null) and ends the
 * process with _exit(130). */
void installInterruptHandlers(const char* tool = nullptr);

/** The job has returned with its outputs in place (a tool calls it when its job returns):
 *  a signal from then on (while the process exits, which may take a while under a leak
 *  checker) no longer turns the finished run into an interrupted one: the watchdog ends the
 *  process with 0 and no message. Blocks while the watchdog is already ending the process
 *  (which then ends with 130, nothing of the job having been reported). */
void markRunComplete() noexcept;

/** How long the watchdog lets a job stop by itself after the first signal [s]. */
constexpr double kInterruptGracePeriod_s = 1.0;

/** The registry of what the watchdog removes or ends (thread-safe; none of these may be
 *  called from a signal handler). A writer registers a temporary file or directory before
 *  creating it and unregisters it once it is renamed into place or removed; the watchdog
 *  removes the registered paths recursively (a path that no longer exists is skipped). A
 *  path registered twice must be unregistered twice. */
void registerTemporaryPath(const std::string& path);
void unregisterTemporaryPath(const std::string& path);
/** A child process that the watchdog kills (SIGKILL) and waits for before removing the
 *  temporary paths (so that it cannot write them again). */
void registerChildProcess(pid_t pid);
void unregisterChildProcess(pid_t pid);

/** While one exists, the watchdog does not end the process (it waits): for a short sequence
 *  that must not be cut in the middle, such as the renames that put an output in place, or
 *  a child's start and registration. Once the watchdog has begun ending the process, a new
 *  one blocks until the process ends. */
class InterruptExitDeferral
{
public:
    InterruptExitDeferral();
    ~InterruptExitDeferral();
    InterruptExitDeferral(const InterruptExitDeferral&) = delete;
    InterruptExitDeferral& operator=(const InterruptExitDeferral&) = delete;
};

/** A wait status (waitpid) in words: "exited with status 2", "was killed by signal 9
 *  (SIGKILL)". */
std::string waitStatusText(int status);

/** Runs `argv` (argv[0] looked up on the PATH), with standard input from /dev/null and
 *  standard output and error into `logPath` (created or truncated), in `workDir` (empty: the
 *  current directory), and waits for it; returns its wait status. The child is registered
 *  for the watchdog while it runs. At an interrupt request the child is ended (SIGTERM, then
 *  SIGKILL), waited for, and Interrupted is thrown; a child that ends while an interrupt is
 *  requested (Ctrl-C reaches the whole process group) also throws Interrupted. Throws naming
 *  argv[0] if it cannot be started. */
int runChildProcess(const std::vector<std::string>& argv, const std::string& logPath,
                    const std::string& workDir = {});

}  // namespace semloc

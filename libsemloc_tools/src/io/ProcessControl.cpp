/* semloc — a tool's process at Ctrl-C: the signal handlers, the watchdog that ends a job that
 * does not stop by itself, its registry, and the child processes the tools run. */
#include <errno.h>
#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <poll.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <thread>

extern char** environ;

namespace semloc
{
namespace
{
/** Set by a second signal, with the interruptGeneration() it came in: the watchdog cleans up
 *  and ends the process without the grace period, unless clearInterrupt() was called since. */
std::atomic<bool> g_urgent{false};
std::atomic<unsigned> g_urgentGeneration{0};
/** The write end of the watchdog's self-pipe (-1 until installInterruptHandlers()). */
std::atomic<int> g_wakeFd{-1};
std::atomic<const char*> g_tool{nullptr};
static_assert(std::atomic<bool>::is_always_lock_free, "used from a signal handler");
static_assert(std::atomic<unsigned>::is_always_lock_free, "used from a signal handler");
static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");

/** A second signal came since the last clearInterrupt(). */
bool urgent()
{
    return g_urgent.load() && g_urgentGeneration.load() == interruptGeneration();
}

/** What the watchdog removes and ends. Never destroyed (the watchdog may use it while the
 *  process exits). */
struct Registry
{
    std::mutex mutex;
    std::vector<std::string> paths;
    std::vector<pid_t> children;
    int deferrals = 0;
    bool exiting = false;   // exit() has begun (the tool printed its own message)
    bool complete = false;  // the job returned, its outputs in place (markRunComplete)
};

Registry& registry()
{
    static Registry* r = new Registry;  // NOLINT(cppcoreguidelines-owning-memory): see above
    return *r;
}

void onSignal(int /*sig*/)
{
    const int savedErrno = errno;
    // A second Ctrl-C or SIGTERM ends the process at once, but through the watchdog's cleanup:
    // the handler stays in place (a default action would leave the temporary paths behind).
    if (interruptRequested())
    {
        g_urgentGeneration.store(interruptGeneration());
        g_urgent.store(true);
    }
    requestInterrupt();
    const int fd = g_wakeFd.load();
    if (fd >= 0)
    {
        const char c = 1;
        [[maybe_unused]] const ssize_t n = ::write(fd, &c, 1);
    }
    errno = savedErrno;
}

void sleepMs(int ms)
{
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

/** Write all of `s` to standard error (async-signal-safe calls only). */
void writeStderr(const std::string& s)
{
    size_t done = 0;
    while (done < s.size())
    {
        const ssize_t n = ::write(STDERR_FILENO, s.data() + done, s.size() - done);
        if (n < 0 && errno == EINTR)
        {
            continue;
        }
        if (n <= 0)
        {
            return;
        }
        done += static_cast<size_t>(n);
    }
}

/** Kills the registered children, removes the registered paths, reports and ends the
 *  process. Runs on the watchdog thread. */
[[noreturn]] void endProcess()
{
    Registry& r = registry();
    std::unique_lock<std::mutex> lock(r.mutex);
    while (r.deferrals > 0)
    {
        lock.unlock();
        sleepMs(10);
        lock.lock();
    }
    // From here the mutex stays held: registering, unregistering, a new deferral and exit()
    // wait until _exit.
    for (const pid_t pid : r.children)
    {
        ::kill(pid, SIGKILL);
    }
    for (const pid_t pid : r.children)
    {
        // Wait until it is gone, without reaping it (WNOWAIT: the job's own waitpid still
        // finds it), at most 2 s (a process in uninterruptible sleep).
        for (int i = 0; i < 200; i++)
        {
            siginfo_t info = {};
            const int rc =
                ::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT);
            if ((rc == 0 && info.si_pid == pid) || (rc < 0 && errno == ECHILD))
            {
                break;
            }
            sleepMs(10);
        }
    }
    // The job's threads may still be writing into a staging directory: retry until it is gone.
    for (auto it = r.paths.rbegin(); it != r.paths.rend(); ++it)
    {
        for (int i = 0; i < 50; i++)
        {
            std::error_code ec;
            std::filesystem::remove_all(*it, ec);
            if (!std::filesystem::exists(std::filesystem::symlink_status(*it, ec)))
            {
                break;
            }
            sleepMs(10);
        }
    }
    if (r.complete)
    {
        ::_exit(0);  // the job had finished: its outputs are in place
    }
    if (!r.exiting)
    {
        const char* tool = g_tool.load();
        writeStderr(std::string(::isatty(STDERR_FILENO) ? "\n" : "") +
                    (tool ? tool : program_invocation_short_name) +
                    ": interrupted; no output written\n");
    }
    ::_exit(130);  // as a shell reports a process ended by SIGINT
}

void watchdog(int fd)
{
    for (;;)
    {
        char c = 0;
        const ssize_t n = ::read(fd, &c, 1);
        if (n < 0 && errno == EINTR)
        {
            continue;
        }
        if (n <= 0)
        {
            return;
        }
        const unsigned generation = interruptGeneration();
        const auto until = std::chrono::steady_clock::now() +
                           std::chrono::duration<double>(kInterruptGracePeriod_s);
        auto standDown = [&]
        { return !interruptRequested() || interruptGeneration() != generation; };
        while (std::chrono::steady_clock::now() < until && !standDown() && !urgent())
        {
            sleepMs(10);
        }
        if (standDown() && !urgent())
        {
            // The job stopped and cleared the request (a library user, a test): wait for the
            // next signal, forgetting the bytes of this one.
            pollfd p = {fd, POLLIN, 0};
            while (::poll(&p, 1, 0) > 0 && ::read(fd, &c, 1) > 0)
            {
            }
            continue;
        }
        endProcess();
    }
}

void markExiting()
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);  // waits while the watchdog ends it
    r.exiting = true;
}

void startWatchdog()
{
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
    {
        THROW_EXCEPTION(std::string("cannot create the interrupt watchdog's pipe: ") +
                        std::strerror(errno));
    }
    // The watchdog never takes the signals: a blocked waitpid() in the job's thread returns
    // with EINTR.
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    ::pthread_sigmask(SIG_BLOCK, &block, &old);
    // Returns once the thread runs: from then on it waits in read() and holds no lock, so a
    // fork() by the job (semloc-benchmark's runs) never copies a lock it held mid-start
    // (a thread's start allocates; AddressSanitizer's allocator has no fork handler, and its
    // child would wait forever on that lock).
    std::atomic<bool> running{false};
    std::thread(
        [fd = fds[0], &running]
        {
            running.store(true);
            watchdog(fd);
        })
        .detach();
    while (!running.load())
    {
        std::this_thread::yield();
    }
    ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
    g_wakeFd.store(fds[1]);
    std::atexit(markExiting);
}
}  // namespace

void markRunComplete() noexcept
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);  // waits while the watchdog ends it
    r.complete = true;
}

void installInterruptHandlers(const char* tool)
{
    if (tool)
    {
        g_tool.store(tool);
    }
    static std::once_flag once;
    std::call_once(once, startWatchdog);
    struct sigaction sa = {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sigaddset(&sa.sa_mask, SIGINT);
    sigaddset(&sa.sa_mask, SIGTERM);
    sa.sa_flags = 0;  // no SA_RESTART: waitpid() returns EINTR
    ::sigaction(SIGINT, &sa, nullptr);
    ::sigaction(SIGTERM, &sa, nullptr);
}

// ------------------------------------------------------------------ the registry

void registerTemporaryPath(const std::string& path)
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    r.paths.push_back(path);
}

void unregisterTemporaryPath(const std::string& path)
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    const auto it = std::find(r.paths.rbegin(), r.paths.rend(), path);
    if (it != r.paths.rend())
    {
        r.paths.erase(std::next(it).base());
    }
}

void registerChildProcess(pid_t pid)
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    r.children.push_back(pid);
}

void unregisterChildProcess(pid_t pid)
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    const auto it = std::find(r.children.begin(), r.children.end(), pid);
    if (it != r.children.end())
    {
        r.children.erase(it);
    }
}

InterruptExitDeferral::InterruptExitDeferral()
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    r.deferrals++;
}

InterruptExitDeferral::~InterruptExitDeferral()
{
    Registry& r = registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    r.deferrals--;
}

// ------------------------------------------------------------------ child processes

std::string waitStatusText(int status)
{
    if (WIFEXITED(status))
    {
        return "exited with status " + std::to_string(WEXITSTATUS(status));
    }
    if (WIFSIGNALED(status))
    {
        const int sig = WTERMSIG(status);
        const char* abbrev = ::sigabbrev_np(sig);
        return "was killed by signal " + std::to_string(sig) +
               (abbrev ? " (SIG" + std::string(abbrev) + ")" : std::string());
    }
    return "ended with wait status " + std::to_string(status);
}

namespace
{
/** How a child is started: stdin from /dev/null, stdout and stderr to the log (opened before
 *  the change of directory: a relative log path is ours), in `workDir` if given, with no
 *  signal blocked and SIGINT, SIGTERM and SIGPIPE at their defaults. */
class SpawnSettings
{
public:
    SpawnSettings(const std::string& logPath, const std::string& workDir)
    {
        ::posix_spawn_file_actions_init(&m_actions);
        ::posix_spawnattr_init(&m_attr);
        ::posix_spawn_file_actions_addopen(&m_actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
        ::posix_spawn_file_actions_addopen(&m_actions, STDOUT_FILENO, logPath.c_str(),
                                           O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::posix_spawn_file_actions_adddup2(&m_actions, STDOUT_FILENO, STDERR_FILENO);
        if (!workDir.empty())
        {
            ::posix_spawn_file_actions_addchdir_np(&m_actions, workDir.c_str());
        }
        sigset_t none, defaults;
        sigemptyset(&none);
        sigemptyset(&defaults);
        sigaddset(&defaults, SIGINT);
        sigaddset(&defaults, SIGTERM);
        sigaddset(&defaults, SIGPIPE);
        ::posix_spawnattr_setsigmask(&m_attr, &none);
        ::posix_spawnattr_setsigdefault(&m_attr, &defaults);
        ::posix_spawnattr_setflags(&m_attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    }
    ~SpawnSettings()
    {
        ::posix_spawn_file_actions_destroy(&m_actions);
        ::posix_spawnattr_destroy(&m_attr);
    }
    SpawnSettings(const SpawnSettings&) = delete;
    SpawnSettings& operator=(const SpawnSettings&) = delete;

    /** posix_spawnp's result: 0, or the error number. */
    int spawn(pid_t& pid, std::vector<char*>& args) const
    {
        return ::posix_spawnp(&pid, args[0], &m_actions, &m_attr, args.data(), environ);
    }

private:
    posix_spawn_file_actions_t m_actions{};
    posix_spawnattr_t m_attr{};
};

/** Starts the child and registers it, as one step for the watchdog; its pid. Throws
 *  Interrupted if an interrupt was requested before, or the reason it could not start. */
pid_t startChild(const std::vector<std::string>& argv, const std::string& logPath,
                 const std::string& workDir)
{
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (const auto& a : argv)
    {
        args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);

    pid_t pid = -1;
    int rc = 0;
    bool interruptedBefore = false;
    {
        const SpawnSettings settings(logPath, workDir);
        // Started and registered as one step for the watchdog.
        const InterruptExitDeferral defer;
        interruptedBefore = interruptRequested();
        if (!interruptedBefore)
        {
            rc = settings.spawn(pid, args);
            if (rc == 0)
            {
                registerChildProcess(pid);
            }
        }
    }
    if (interruptedBefore)
    {
        throw Interrupted();
    }
    if (rc != 0)
    {
        THROW_EXCEPTION("cannot run '" + argv[0] + "': " + std::strerror(rc));
    }
    return pid;
}

/** Waits for the child to end and unregisters it; its wait status. Polled rather than
 *  blocked on: the signal may be delivered to another thread. On an interrupt the child gets
 *  SIGTERM, then SIGKILL after 300 ms, and Interrupted is thrown once it has ended. */
int waitForChild(pid_t pid, const std::string& program)
{
    int status = 0;
    bool ended = false;
    std::chrono::steady_clock::time_point termSent;
    for (;;)
    {
        const pid_t w = ::waitpid(pid, &status, WNOHANG);
        if (w == pid)
        {
            break;
        }
        if (w < 0 && errno != EINTR)
        {
            const int err = errno;
            unregisterChildProcess(pid);
            THROW_EXCEPTION("waiting for '" + program + "' failed: " + std::strerror(err));
        }
        if (interruptRequested())
        {
            if (!ended)
            {
                ended = true;
                termSent = std::chrono::steady_clock::now();
                ::kill(pid, SIGTERM);
            }
            else if (std::chrono::steady_clock::now() - termSent > std::chrono::milliseconds(300))
            {
                ::kill(pid, SIGKILL);
            }
        }
        sleepMs(5);
    }
    unregisterChildProcess(pid);
    if (ended || interruptRequested())
    {
        throw Interrupted();
    }
    return status;
}
}  // namespace

int runChildProcess(const std::vector<std::string>& argv, const std::string& logPath,
                    const std::string& workDir)
{
    ASSERTMSG_(!argv.empty(), "runChildProcess: no program");
    return waitForChild(startChild(argv, logPath, workDir), argv[0]);
}

}  // namespace semloc

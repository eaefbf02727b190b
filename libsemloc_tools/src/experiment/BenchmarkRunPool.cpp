/* semloc — Benchmark's run pool: child processes, their run files, their failures. */
#include "experiment/BenchmarkRunPool.h"

#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "io/TextFiles.h"

namespace semloc::detail
{
namespace
{
/** Why a run failed: its error message, else how its process ended (the signal named) and
 *  the end of what it printed (its log). */
std::string runFailure(const std::string& scenario, int run, int status, const std::string& error,
                       const std::string& logPath)
{
    std::string s = (scenario.empty() ? std::string() : "scenario '" + scenario + "', ") +
                    mrpt::format("run %d (seed %d) failed: ", run, run);
    if (!error.empty())
    {
        return s + error;
    }
    s += "its process " + waitStatusText(status);
    std::ifstream f(logPath);
    std::stringstream log;
    log << f.rdbuf();
    std::string tail = log.str();
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' '))
    {
        tail.pop_back();
    }
    constexpr size_t kTail = 2000;
    if (tail.size() > kTail)
    {
        tail = "..." + tail.substr(tail.size() - kTail);
    }
    return tail.empty() ? s + " (it printed nothing)" : s + "; the end of its output:\n" + tail;
}

/** The pool of runInChildProcesses(): the running children and the first failure. */
class RunPool
{
public:
    RunPool(const RunFiles& files, int first, int last, size_t jobs, const std::string& scenario,
            const std::function<std::vector<Benchmark::TRunResult>(int)>& runOne,
            const std::function<void(size_t, size_t)>& progress)
        : m_files(files),
          m_runs(last - first + 1),
          m_last(last),
          m_next(first),
          m_jobs(jobs),
          m_scenario(scenario),
          m_runOne(runOne),
          m_progress(progress)
    {
    }

    /** Every run, then the failure or Interrupted thrown. */
    void runAll();

private:
    /** A new run may start (none failed, no Ctrl-C, runs left). */
    bool moreRuns() const { return m_next <= m_last && m_failure.empty() && !m_interrupted; }
    /** Starts `run` in a child process. */
    void start(int run);
    /** The child process of `run`: runs it, writes its file, exits. */
    [[noreturn]] void child(int run) const;
    /** Takes note of a child's end and result, else of what the running ones told
     *  (readNotes) before a tenth of a second's wait. */
    void reap();
    /** The new lines of the notes of `run` (runNote), each kind reported once. */
    void readNotes(int run);

    const RunFiles& m_files;
    const int m_runs;  // how many: first..last
    const int m_last;
    int m_next;
    const size_t m_jobs;
    const std::string& m_scenario;
    const std::function<std::vector<Benchmark::TRunResult>(int)>& m_runOne;
    const std::function<void(size_t, size_t)>& m_progress;
    std::map<pid_t, int> m_children;
    std::map<int, size_t> m_notesSeen;  // per run: the lines of its notes read
    std::set<std::string> m_toldKinds;
    std::string m_failure;
    size_t m_done = 0;
    bool m_interrupted = false;
};

void RunPool::runAll()
{
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    if (m_progress)
    {
        m_progress(0, static_cast<size_t>(m_runs));
    }
    // Ctrl-C (installInterruptHandlers): no new run, the running ones ended, then Interrupted;
    // the staging directory goes with the exception.
    while (moreRuns() || !m_children.empty())
    {
        if (interruptRequested() && !m_interrupted)
        {
            m_interrupted = true;
            for (const auto& c : m_children)
            {
                ::kill(c.first, SIGTERM);
            }
            continue;
        }
        if (moreRuns() && m_children.size() < m_jobs)
        {
            start(m_next++);
            continue;
        }
        reap();
    }
    if (m_interrupted)
    {
        throw Interrupted();
    }
    if (!m_failure.empty())
    {
        THROW_EXCEPTION(m_failure);
    }
}

void RunPool::start(int run)
{
    pid_t pid = -1;
    int forkErrno = 0;
    {
        const InterruptExitDeferral defer;  // started and registered as one step
        pid = ::fork();
        forkErrno = errno;
        if (pid > 0)
        {
            registerChildProcess(pid);
        }
    }
    if (pid < 0)
    {
        m_failure = std::string("cannot start run ") + std::to_string(run) +
                    ": fork failed: " + std::strerror(forkErrno);
        return;
    }
    if (pid == 0)
    {
        child(run);
    }
    m_children[pid] = run;
}

void RunPool::child(int run) const
{
    // The run ends at Ctrl-C or the parent's SIGTERM (its outputs are not kept).
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    // MRPT's warnings (e.g. re-initializations, counted in results.csv) go to the run's log,
    // not over the progress bar.
    const int log = ::open(m_files.path(run, "log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log >= 0)
    {
        ::dup2(log, STDOUT_FILENO);
        ::dup2(log, STDERR_FILENO);
        ::close(log);
    }
    int rc = 0;
    runNotesTo(m_files.path(run, "note"));
    try
    {
        writeFile(m_files.path(run, "txt"), runFileText(m_runOne(run), run, m_files.inputs()));
    }
    catch (const std::exception& e)
    {
        std::ofstream(m_files.path(run, "err")) << errorMessage(e);
        rc = 1;
    }
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    ::_exit(rc);  // no destructors: the staging directory is the parent's
}

void RunPool::readNotes(int run)
{
    std::ifstream f(m_files.path(run, "note"));
    size_t& seen = m_notesSeen[run];
    size_t line = 0;
    for (std::string text; std::getline(f, text); line++)
    {
        if (f.eof() || line < seen)
        {
            continue;  // a line being written, or one already read
        }
        seen = line + 1;
        const auto tab = text.find('\t');
        if (tab != std::string::npos && m_toldKinds.insert(text.substr(0, tab)).second)
        {
            reportWarning(text.substr(tab + 1));
        }
    }
}

void RunPool::reap()
{
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid == 0)
    {
        // Every run still running: what they tell so far, then a tenth of a second.
        for (const auto& c : m_children)
        {
            readNotes(c.second);
        }
        const timespec tenth{0, 100000000};
        ::nanosleep(&tenth, nullptr);
        return;
    }
    if (pid < 0)
    {
        if (errno == EINTR)
        {
            return;  // a signal: the loop looks at interruptRequested()
        }
        THROW_EXCEPTION(std::string("waiting for the runs failed: ") + std::strerror(errno));
    }
    const auto it = m_children.find(pid);
    if (it == m_children.end())
    {
        return;
    }
    const int run = it->second;
    m_children.erase(it);
    unregisterChildProcess(pid);
    readNotes(run);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    {
        std::ifstream f(m_files.path(run, "err"));
        std::stringstream msg;
        msg << f.rdbuf();
        if (m_failure.empty())
        {
            m_failure = runFailure(m_scenario, run, status, msg.str(), m_files.path(run, "log"));
        }
    }
    m_done++;
    if (m_progress)
    {
        m_progress(m_done, static_cast<size_t>(m_runs));
    }
}

/** The note file of the run of this child process (runNotesTo), empty in the parent. */
std::string& notesPath()
{
    static std::string path;
    return path;
}
}  // namespace

void runNotesTo(const std::string& path)
{
    notesPath() = path;
}

void runNote(const std::string& kind, const std::string& text)
{
    if (notesPath().empty())
    {
        reportWarning(text);  // a run of this process: told at once
        return;
    }
    std::ofstream(notesPath(), std::ios::app) << kind << '\t' << text << '\n' << std::flush;
}

void runInChildProcesses(const RunFiles& files, int first, int last, size_t jobs,
                         const std::string& scenario,
                         const std::function<std::vector<Benchmark::TRunResult>(int)>& runOne,
                         const std::function<void(size_t, size_t)>& progress)
{
    ASSERTMSG_(first >= 1 && first <= last, "runInChildProcesses: no run");
    RunPool(files, first, last, jobs, scenario, runOne, progress).runAll();
}

}  // namespace semloc::detail

/* semloc — Benchmark's run pool: every run in a child process, its results handed back to
 * the parent in a run file (private). */
#pragma once

#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace semloc::detail
{
/** The files of the runs, in one directory: `run_NNNNNN.txt` (the results, runFileText()),
 *  `.err` (the run's error message), `.log` (what its process printed) and `.note` (what it
 *  told while it ran, runNote()). */
class RunFiles
{
public:
    explicit RunFiles(std::string dir) : m_dir(std::move(dir)) {}
    /** The directory. */
    const std::string& dir() const { return m_dir; }
    /** The file of `run` with extension `ext`. */
    std::string path(int run, const char* ext) const
    {
        return m_dir + mrpt::format("/run_%06d.%s", run, ext);
    }

private:
    std::string m_dir;
};

/** Where runNote() writes in this (child) process: the run's `.note` file. */
void runNotesTo(const std::string& path);
/** A note of the running run (ClosedLoopNote: one line `kind<TAB>text`), which the parent
 *  reads while the run goes on and reports once per kind (reportWarning); without a note
 *  file (a run in the calling process), reported at once. */
void runNote(const std::string& kind, const std::string& text);
/** Benchmark::SetWarningReporter()'s reporter, told `text` (nothing without one). */
void reportWarning(const std::string& text);

/** A run's results as its run file holds them: per variant and control "V <variant> <control>
 *  <particles> <threads> <wall_s> <reinitializations> <decisions> <decision_wall_s>
 *  <decision_filter_steps> <max_decision_filter_steps> <stuck_decisions> <n>" then n
 *  step lines and the detector's bound "B <n> ..."; doubles printed with 17 digits read
 *  back bit-exactly, so the parent's metrics equal the child's. */
std::string runFileText(const std::vector<Benchmark::TRunResult>& results);

/** The results of run `run` read back from its run file (metrics and scenario not set). */
std::vector<Benchmark::TRunResult> readRunFile(const std::string& path, int run);

/** Runs `runOne(run)` for run = first..last, each in a child process (fork(), no exec), at
 *  most `jobs` at once, writing its run file (or its error) in `files`; `progress(done, n)`
 *  (n runs) at the start and after each run; the runs' notes (runNote()) reported as they
 *  come, once per kind. The first failure stops new runs and is thrown once
 * the running ones ended, naming `scenario` (if not empty), the run and its error or how its
 *  process ended; Ctrl-C (installInterruptHandlers) ends the running ones and throws
 *  Interrupted. */
void runInChildProcesses(const RunFiles& files, int first, int last, size_t jobs,
                         const std::string& scenario,
                         const std::function<std::vector<Benchmark::TRunResult>(int)>& runOne,
                         const std::function<void(size_t, size_t)>& progress);

/** Copies the run files of runs 1..runs into `files` from `dirs` (each a shard's run
 *  directory, RunFiles' names; Benchmark::Merge() has checked that each run is in exactly
 *  one). Throws naming the run whose file is in none. */
void gatherRunFiles(const std::vector<std::string>& dirs, int runs, const RunFiles& files);

}  // namespace semloc::detail

/* semloc — Benchmark's run pool: every run in a child process, its results handed back to
 * the parent in a run file (private). */
#pragma once

#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace semloc::detail
{
/** The files of the runs, in one directory: `run_NNNNNN.txt` (the results, runFileText()),
 *  `.err` (the run's error message), `.log` (what its process printed) and `.note` (what it
 *  told while it ran, runNote()); `inputs` is the benchmark's digest (Benchmark::digest())
 *  each run file carries. */
class RunFiles
{
public:
    RunFiles(std::string dir, std::string inputs)
        : m_dir(std::move(dir)), m_inputs(std::move(inputs))
    {
    }
    /** The directory. */
    const std::string& dir() const { return m_dir; }
    /** The benchmark's digest. */
    const std::string& inputs() const { return m_inputs; }
    /** The file of `run` with extension `ext`. */
    std::string path(int run, const char* ext) const
    {
        return m_dir + mrpt::format("/run_%06d.%s", run, ext);
    }

private:
    std::string m_dir, m_inputs;
};

/** The (variant, control) of each result of a run, in the order of the run's results. */
using RunSeries = std::vector<std::pair<std::string, std::string>>;

/** Where runNote() writes in this (child) process: the run's `.note` file. */
void runNotesTo(const std::string& path);
/** A note of the running run (ClosedLoopNote: one line `kind<TAB>text`), which the parent
 *  reads while the run goes on and reports once per kind (reportWarning); without a note
 *  file (a run in the calling process), reported at once. */
void runNote(const std::string& kind, const std::string& text);
/** Benchmark::SetWarningReporter()'s reporter, told `text` (nothing without one). */
void reportWarning(const std::string& text);

/** The largest run file readRunFile() reads [bytes]. */
constexpr uint64_t kMaxRunFileBytes = uint64_t(1) << 30;

/** A run's results as its run file holds them: a header comment, `run <run>`, `inputs
 *  <inputs>` (the benchmark's digest), then per variant and control "V <variant> <control>
 *  <particles> <threads> <wall_s> <reinitializations> <decisions> <decision_wall_s>
 *  <decision_filter_steps> <max_decision_filter_steps> <stuck_decisions> <n>", n step lines and the
 * detector's bound "B <n> ...", and last `content <digest>`: the FNV-1a digest of every byte before
 * that line (detail::fnv1a), which seals the file. Doubles are printed with 17 digits and read back
 * bit-exactly, so the parent's metrics equal the child's. */
std::string runFileText(const std::vector<Benchmark::TRunResult>& results, int run,
                        const std::string& inputs);

/** The results of run `run` read back from its run file `path` (metrics and scenario not
 *  set). Refused with one line naming `path` (and the line, where there is one): not a regular
 *  file (a symbolic link, a FIFO, a device), larger than kMaxRunFileBytes, not a run file, a
 *  content digest that is not its content's (a file changed after its run wrote it), the
 *  results of another run or of another benchmark (its `inputs` digest is not `inputs`), a
 *  line that does not read, other results than the run's `series`. */
std::vector<Benchmark::TRunResult> readRunFile(const std::string& path, int run,
                                               const std::string& inputs, const RunSeries& series);

/** The bytes of the file `path` (`what` names it in the errors) through semloc's one reader
 *  of inputs (readInputFile: a regular file of at most `maxBytes`), and not a symbolic link:
 *  semloc-benchmark reads only the files it wrote. */
std::string readBoundedFile(const std::string& path, uint64_t maxBytes, const std::string& what);

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

}  // namespace semloc::detail

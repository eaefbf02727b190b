/* semloc — the outputs of a localization run: steps.csv and summary.yaml (docs/design.md,
 * "Output contract of semloc-localize") (private). */
#pragma once

#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>

#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace semloc::detail
{
/** steps.csv: one row per step, numbers in their shortest round-trip text, empty cells for
 *  unknown values. */
std::string stepsCsv(const std::vector<TStepRecord>& records);

/** steps.csv written row by row while the run goes (stepsCsv's text). */
class StepsCsv
{
public:
    /** Writes the header to `path`. */
    explicit StepsCsv(const std::string& path);
    /** The row of `r`. */
    void add(const TStepRecord& r);
    /** Closes the file; throws naming it if a write failed. */
    void finish();

private:
    std::string m_path;
    std::ofstream m_out;
};

/** summary.yaml of the run `res` configured by `o`; unknown values are `null`. */
std::string summaryYaml(const LocalizationExperiment::TResult& res,
                        const LocalizationExperiment::TOptions& o);

/** particles.csv, written while the run goes (a cloud of 10^4 particles over 10^3 steps
 *  is hundreds of MB): `step,t,x,y,phi,weight` with each step's weights normalized to sum
 *  to 1, for step 0, every N-th step and the last one. */
class ParticlesCsv
{
public:
    /** Writes the header to `path`; `every` >= 1. */
    ParticlesCsv(const std::string& path, size_t every);
    /** The cloud after step `r.step`, written if that step is due. */
    void step(const TStepRecord& r, const CParallelMonteCarloLocalization2D& pdf);
    /** After the last step `last`: its cloud (unless written), then the file is closed;
     *  throws naming the file if a write failed. */
    void finish(const TStepRecord& last, const CParallelMonteCarloLocalization2D& pdf);

private:
    void write(const TStepRecord& r, const CParallelMonteCarloLocalization2D& pdf);
    std::string m_path;
    std::ofstream m_out;
    size_t m_every;
    std::optional<size_t> m_lastWritten;
};

}  // namespace semloc::detail

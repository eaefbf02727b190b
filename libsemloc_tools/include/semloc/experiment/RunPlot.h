/* semloc — the figures of one semloc-localize run: the world with the true path, the estimate
 * and particle clouds; error and spread over time; an animated GIF of the particles. */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <semloc/experiment/RunMetrics.h>
#include <semloc/plot/FigureWarning.h>
#include <semloc/world/World.h>

#include <optional>
#include <string>
#include <vector>

namespace semloc
{
/** A semloc-localize output directory read back and drawn with gnuplot (semloc-plot-run).
 *
 *  Reads `steps.csv`, `summary.yaml` (variant, convergence step), `config.ini` (`map_file`)
 *  and, when present, `particles.csv` (`--save-particles`); the world is the run's map file
 *  when it is a world YAML, or a file given instead (otherwise no objects are drawn and the
 *  view spans the paths and clouds). Every file error names the file and line. */
class RunPlot
{
public:
    /** A particle cloud of one step, thinned to at most kMaxCloudPoints particles. */
    struct Cloud
    {
        size_t step = 0;
        std::vector<mrpt::math::TPoint2D> points;
    };
    /** Particles kept of each saved step (evenly through the file's rows). */
    static constexpr size_t kMaxCloudPoints = 2000;

    /** What save() draws. */
    struct TOptions
    {
        /** Steps whose clouds run.png shows; each must be a step of particles.csv. Empty:
         *  the first saved step, the first saved at or after convergence, and the last. */
        std::vector<size_t> cloudSteps;
        /** Draw run.gif (needs particles.csv). */
        bool gif = true;
        /** Width of run.png and error.png [px], 300..6000. */
        int widthPx = 900;
        /** Width of run.gif [px], 200..3000. */
        int gifWidthPx = 600;
        /** Most frames of run.gif (saved steps taken evenly), 2..2000. */
        size_t maxGifFrames = 200;
    };

    /** Reads the run in `runDir`; `worldFile` (a world YAML) replaces its map file. */
    static RunPlot FromDirectory(const std::string& runDir, const std::string& worldFile = {});

    /** Writes `outDir` (a new directory or a previous output of semloc, replaced as a whole,
     *  never half-written): run.png, error.png, run.gif (with particles and `o.gif`), the
     *  gnuplot script run.gp and its data (world.dat, track.dat, clouds.dat), so a figure can
     *  be restyled by hand. A figure gnuplot cannot draw (or every figure, without gnuplot)
     *  is left out and returned as a warning: the other outputs are written all the same.
     *  semloc::Interrupted at an interrupt request. */
    std::vector<TFigureWarning> save(const std::string& outDir, const TOptions& o) const;

    /** The run's steps (steps.csv). */
    const std::vector<TStepRecord>& records() const { return m_records; }
    /** The saved clouds in step order (empty without particles.csv). */
    const std::vector<Cloud>& clouds() const { return m_clouds; }
    /** The step of convergence (summary.yaml), if the run converged. */
    std::optional<size_t> convergenceStep() const { return m_convergenceStep; }
    /** The world drawn. */
    const World& world() const { return m_world; }

private:
    std::string m_runDir, m_worldFile, m_variant;
    std::vector<TStepRecord> m_records;
    std::vector<Cloud> m_clouds;
    std::optional<size_t> m_convergenceStep;
    World m_world;
    std::vector<std::string> inputFiles() const;
    std::vector<size_t> chooseCloudSteps(const TOptions& o) const;
    std::string script(const TOptions& o, const std::vector<size_t>& shown) const;
    std::string errorScript(const TOptions& o, long convergenceStep) const;
    std::string gifScript(const TOptions& o, bool groundTruth, long convergenceStep) const;
    std::string cloudsData() const;
};

}  // namespace semloc

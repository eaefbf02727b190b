/* semloc — RunPlot: the figures of a run (run.png, error.png, run.gif) drawn by gnuplot. */
#include <mrpt/core/exceptions.h>
#include <semloc/experiment/RunPlot.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/plot/WorldPlot.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "experiment/RunFigures.h"
#include "io/Text.h"
#include "io/TextFiles.h"
#include "plot/Gnuplot.h"

namespace semloc
{
namespace
{
using detail::gnuplotQuoted;

const char* kCloudColours[] = {"#1f77b4", "#9467bd", "#ff7f0e", "#17becf", "#e377c2", "#8c564b"};

/** Height for `width` keeping the world's aspect, plus room for the key and colour box. */
int heightFor(const World& w, int width)
{
    const auto& b = w.bounds;
    const double h = width * (b.y_max - b.y_min) / (b.x_max - b.x_min);
    return static_cast<int>(std::clamp(h, 0.3 * width, 3.0 * width)) + 110;
}

std::string timeText(const TStepRecord& r, const TStepRecord& first)
{
    return std::isfinite(r.t) && std::isfinite(first.t)
               ? ", t = " + detail::fixedText(std::round((r.t - first.t) * 10) / 10) + " s"
               : std::string();
}

/** "0, 50, 100 ... 430" (all of them when there are at most four). */
std::string savedStepsText(const std::vector<size_t>& saved)
{
    std::string t;
    for (size_t i = 0; i < saved.size(); i++)
    {
        if (saved.size() > 4 && i == 3)
        {
            t += " ... " + std::to_string(saved.back());
            break;
        }
        t += (i ? ", " : "") + std::to_string(saved[i]);
    }
    return t;
}

void checkOptions(const RunPlot::TOptions& o)
{
    if (o.widthPx < 300 || o.widthPx > 6000)
    {
        THROW_EXCEPTION("the figure width must be in [300, 6000] px");
    }
    if (o.gifWidthPx < 200 || o.gifWidthPx > 3000)
    {
        THROW_EXCEPTION("the GIF width must be in [200, 3000] px");
    }
    if (o.maxGifFrames < 2 || o.maxGifFrames > 2000)
    {
        THROW_EXCEPTION("the GIF's frames must be in [2, 2000]");
    }
}
}  // namespace

std::vector<size_t> RunPlot::chooseCloudSteps(const TOptions& o) const
{
    std::vector<size_t> saved;
    for (const auto& c : m_clouds)
    {
        saved.push_back(c.step);
    }
    std::vector<size_t> shown;  // indexes into m_clouds
    if (!o.cloudSteps.empty())
    {
        for (const size_t s : o.cloudSteps)
        {
            const auto it = std::find(saved.begin(), saved.end(), s);
            if (it == saved.end())
            {
                THROW_EXCEPTION("step " + std::to_string(s) +
                                (saved.empty() ? std::string(": the run has no particles.csv "
                                                             "(semloc-localize --save-particles N)")
                                               : " has no particles in particles.csv (saved: " +
                                                     savedStepsText(saved) + ")"));
            }
            shown.push_back(static_cast<size_t>(it - saved.begin()));
        }
        return shown;
    }
    if (saved.empty())
    {
        return shown;
    }
    shown.push_back(0);
    if (m_convergenceStep)
    {
        const auto it = std::lower_bound(saved.begin(), saved.end(), *m_convergenceStep);
        if (it != saved.end())
        {
            shown.push_back(static_cast<size_t>(it - saved.begin()));
        }
    }
    shown.push_back(saved.size() - 1);
    shown.erase(std::unique(shown.begin(), shown.end()), shown.end());
    return shown;
}

std::string RunPlot::cloudsData() const
{
    std::ostringstream o;
    for (const auto& c : m_clouds)
    {
        o << "# step " << c.step << "\n";
        for (const auto& p : c.points)
        {
            o << detail::shortestText(p.x) << ' ' << detail::shortestText(p.y) << '\n';
        }
        o << "\n\n";
    }
    return o.str();
}

std::string RunPlot::script(const TOptions& o, const std::vector<size_t>& shown) const
{
    const bool gt = std::any_of(m_records.begin(), m_records.end(),
                                [](const TStepRecord& r) { return r.gt.has_value(); });
    const long conv = m_convergenceStep ? static_cast<long>(*m_convergenceStep) : -1;
    const std::string name = m_variant.empty() ? std::string("run") : m_variant;
    WorldPlot world(m_world, name + ": true path, estimate and particles");
    std::ostringstream s;
    s << "set terminal pngcairo size " << o.widthPx << "," << heightFor(m_world, o.widthPx)
      << " enhanced font 'Sans,10'\nset output 'run.png'\n";
    s << world.settings() << detail::errorPalette();
    s << "plot " << world.worldLayers("world.dat");
    for (size_t k = 0; k < shown.size(); k++)
    {
        const auto& c = m_clouds[shown[k]];
        s << ", \\\n  'clouds.dat' index " << shown[k] << " with points pt 7 ps 0.25 lc rgb '"
          << kCloudColours[k % 6] << "' title "
          << gnuplotQuoted("particles, step " + std::to_string(c.step));
    }
    s << detail::trackLayers("track.dat", gt, conv) << "\n";
    s << "unset output\n";
    std::string all =
        "# semloc-plot-run: gnuplot run.gp (in this directory) draws the figures again;\n"
        "# gnuplot -e \"figure='error.png'\" run.gp only that one.\n" +
        detail::figureSelector() + detail::figureBlock("run.png", s.str()) +
        detail::figureBlock("error.png", errorScript(o, conv));
    if (o.gif && !m_clouds.empty())
    {
        all += detail::figureBlock("run.gif", gifScript(o, gt, conv));
    }
    return all;
}

std::string RunPlot::errorScript(const TOptions& o, long conv) const
{
    // error.png: error and spread over time (a linear axis where nothing is positive: one
    // particle has no spread; a run without ground truth has no error).
    const std::string name = m_variant.empty() ? std::string("run") : m_variant;
    std::vector<double> err, spread;
    for (const auto& r : m_records)
    {
        err.push_back(r.errXY());
        spread.push_back(std::sqrt(std::max(r.var_xy, 0.0)));
    }
    std::ostringstream s;
    s << "reset\nset terminal pngcairo size " << o.widthPx << "," << o.widthPx * 2 / 3
      << " enhanced font 'Sans,10'\nset output 'error.png'\n";
    s << "set multiplot layout 2,1 title " << gnuplotQuoted(name + ": error and spread")
      << " noenhanced\nset grid\nset xlabel " << gnuplotQuoted(detail::timeAxisLabel(m_records))
      << "\n";
    if (conv >= 0)
    {
        const double t = m_records[conv].t - m_records.front().t;
        const double x = std::isfinite(t) ? t : static_cast<double>(conv);
        s << "set arrow 1 from " << detail::shortestText(x) << ", graph 0 to "
          << detail::shortestText(x)
          << ", graph 1 nohead dt 2 lc rgb '#000000'\nset label 1 'converged' at "
          << detail::shortestText(x) << ", graph 0.92 offset 0.5,0\n";
    }
    s << detail::axisY(err, true, "no ground truth: no error")
      << "set ylabel 'position error [m]'\nplot 'track.dat' using 2:7 with lines lw 1.5 lc rgb "
         "'#d62728' notitle\n"
      << detail::unsetAxisY() << detail::axisY(spread, true, "no spread")
      << "set ylabel 'particle spread sqrt(var_{xy}) [m]'\nplot 'track.dat' using 2:8 with lines "
         "lw 1.5 lc rgb '#1f77b4' notitle\nunset multiplot\nunset output\n";
    return s.str();
}

std::string RunPlot::gifScript(const TOptions& o, bool gt, long conv) const
{
    const std::string name = m_variant.empty() ? std::string("run") : m_variant;
    WorldPlot world(m_world, name);
    std::ostringstream s;
    s << "reset\nset terminal gif animate delay 10 loop 0 optimize size " << o.gifWidthPx << ","
      << heightFor(m_world, o.gifWidthPx) << "\nset output 'run.gif'\n";
    s << world.settings() << detail::errorPalette() << "unset label\n";
    const size_t n = m_clouds.size(), frames = std::min(n, o.maxGifFrames);
    for (size_t f = 0; f < frames; f++)
    {
        const size_t i = frames == 1 ? 0 : f * (n - 1) / (frames - 1);
        const auto& c = m_clouds[i];
        s << "set title "
          << gnuplotQuoted(name + ": step " + std::to_string(c.step) +
                           timeText(m_records[c.step], m_records.front()))
          << " noenhanced\n";
        s << "plot " << world.worldLayers("world.dat") << ", \\\n  'clouds.dat' index " << i
          << " with points pt 7 ps 0.3 lc rgb '#1f77b4' title 'particles'"
          << detail::trackLayers("track.dat", gt, conv, static_cast<long>(c.step)) << "\n";
    }
    s << "unset output\n";
    return s.str();
}

std::vector<TFigureWarning> RunPlot::save(const std::string& outDir, const TOptions& o) const
{
    checkOptions(o);
    const auto shown = chooseCloudSteps(o);
    StagedDirectory out(outDir, inputFiles());
    detail::writeFile(out.path("world.dat"), WorldPlot(m_world).data());
    detail::writeFile(out.path("track.dat"), detail::trackData(m_records));
    detail::writeFile(out.path("clouds.dat"), cloudsData());
    detail::writeFile(out.path("run.gp"), script(o, shown));
    std::vector<std::string> figures = {"run.png", "error.png"};
    if (o.gif && !m_clouds.empty())
    {
        figures.emplace_back("run.gif");
    }
    auto warnings = detail::drawFigures(out, "run.gp", figures);
    if (interruptRequested())
    {
        throw Interrupted();
    }
    out.commit();
    return warnings;
}

}  // namespace semloc

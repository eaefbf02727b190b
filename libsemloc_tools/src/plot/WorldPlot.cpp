/* semloc — WorldPlot: gnuplot script and data for a world figure. */
#include <mrpt/core/exceptions.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/plot/PngText.h>
#include <semloc/plot/WorldPlot.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

#include "io/TemporaryDirectory.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
namespace fs = std::filesystem;
using detail::writeFile;
std::string quoted(const std::string& s)
{
    std::string out = "'";
    for (const char c : s)
    {
        out += (c == '\'') ? std::string("''") : std::string(1, c);  // gnuplot single quotes
    }
    return out + "'";
}

}  // namespace

WorldPlot::WorldPlot(World world, std::string title)
    : m_world(std::move(world)), m_title(std::move(title))
{
}

void WorldPlot::addPath(const std::string& name, std::vector<mrpt::math::TPoint2D> points)
{
    m_paths.push_back({name, std::move(points)});
}

void WorldPlot::addWorldTrajectory()
{
    if (m_world.trajectory)
    {
        addPath("trajectory", m_world.trajectory->waypoints);
    }
}

namespace
{
/** The first line of a data file or script savePng() keeps beside the PNG. */
const char* const kKeptHeader = "# semloc-plot-world: ";
}  // namespace

void WorldPlot::checkPngOutputs(const std::string& pngPath, const std::vector<std::string>& inputs,
                                bool keepScript)
{
    checkOutputFile(pngPath, inputs, isSemlocPng);
    if (keepScript)
    {
        const auto kept = [](const std::string& p) { return fileStartsWith(p, kKeptHeader); };
        checkOutputFile(pngPath + ".dat", inputs, kept);
        checkOutputFile(pngPath + ".gp", inputs, kept);
    }
}

std::string WorldPlot::data() const
{
    // Block 0: outlines (closed polylines separated by blank lines); block 1: point objects;
    // blocks 2..: paths.
    std::ostringstream o;
    o.precision(10);
    o << kKeptHeader << "the data of a world figure\n";
    o << "# outlines\n";
    bool any = false;
    for (const auto& ob : m_world.objects)
    {
        const auto poly = World::outlinePolygon(ob);
        if (poly.empty())
        {
            continue;
        }
        for (const auto& p : poly)
        {
            o << p.x << " " << p.y << "\n";
        }
        o << poly.front().x << " " << poly.front().y << "\n\n";
        any = true;
    }
    if (!any)
    {
        o << "nan nan\n";
    }
    o << "\n\n# point objects\n";
    any = false;
    for (const auto& ob : m_world.objects)
    {
        if (ob.shape == ShapeType::Point)
        {
            o << ob.center.x << " " << ob.center.y << "\n";
            any = true;
        }
    }
    if (!any)
    {
        o << "nan nan\n";
    }
    for (const auto& p : m_paths)
    {
        o << "\n\n# path " << p.name << "\n";
        for (const auto& q : p.points)
        {
            o << q.x << " " << q.y << "\n";
        }
        if (p.points.empty())
        {
            o << "nan nan\n";
        }
    }
    return o.str();
}

std::string WorldPlot::settings() const
{
    const auto& b = m_world.bounds;
    std::ostringstream s;
    s.precision(10);
    s << "set title " << quoted(m_title.empty() ? m_world.name : m_title) << " noenhanced\n";
    s << "set xrange [" << b.x_min << ":" << b.x_max << "]\nset yrange [" << b.y_min << ":"
      << b.y_max << "]\n";
    s << "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n";
    // 5 m blocks, as in the paper's Fig. 1, while they stay readable; gnuplot's own beyond.
    const double span = std::max(b.x_max - b.x_min, b.y_max - b.y_min);
    s << (span <= 120 ? "set xtics 5\nset ytics 5\n" : "set xtics autofreq\nset ytics autofreq\n");
    s << "set grid xtics ytics lc rgb '#dddddd'\n";
    s << "set key outside bottom center horizontal noenhanced\n";
    for (const auto& ob : m_world.objects)
    {
        // Just above the outline's top edge; below its bottom edge at the top border.
        double top = ob.center.y, bottom = ob.center.y;
        for (const auto& p : World::outlinePolygon(ob))
        {
            top = std::max(top, p.y);
            bottom = std::min(bottom, p.y);
        }
        const double y = (top + 1.2 < b.y_max) ? top + 0.7 : bottom - 0.9;
        s << "set label " << quoted(ob.label + " #" + std::to_string(ob.id)) << " at "
          << ob.center.x << "," << y << " center font 'Sans,7' noenhanced\n";
    }
    return s.str();
}

std::string WorldPlot::worldLayers(const std::string& dataPath) const
{
    // Legend entries only for what the world has.
    bool outlines = false, points = false;
    for (const auto& ob : m_world.objects)
    {
        (ob.shape == ShapeType::Point ? points : outlines) = true;
    }
    return quoted(dataPath) + " index 0 with lines lw 2 lc rgb '#333333' " +
           (outlines ? "title 'structures (sonar)'" : "notitle") +
           ", \\\n  '' index 1 with points pt 7 ps 0.8 lc rgb '#cc6600' " +
           (points ? "title 'point objects'" : "notitle");
}

std::string WorldPlot::script(const std::string& dataPath, const std::string& pngPath, int widthPx,
                              int heightPx) const
{
    std::ostringstream s;
    s << kKeptHeader << "the script of a world figure\n";
    s << "set terminal pngcairo size " << widthPx << "," << heightPx
      << " enhanced font 'Sans,10'\n";
    s << "set output " << quoted(pngPath) << "\n";
    s << settings();
    s << "plot " << worldLayers(dataPath);
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf"};
    for (size_t i = 0; i < m_paths.size(); i++)
    {
        s << ", \\\n  '' index " << i + 2 << " with lines lw 1.5 lc rgb '" << colours[i % 6]
          << "' title " << quoted(m_paths[i].name);
    }
    s << "\n";
    return s.str();
}

void WorldPlot::savePng(const std::string& pngPath, int widthPx, int heightPx,
                        bool keepScript) const
{
    // Everything is drawn in a private directory beside the PNG (registered for the interrupt
    // watchdog), and only finished files are renamed out of it.
    const fs::path png = fs::absolute(fs::path(pngPath));
    std::optional<detail::TemporaryDirectory> tmpDir;
    try
    {
        tmpDir.emplace(png.parent_path(), "." + png.filename().string() + ".plot-");
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("cannot write '" + pngPath + "': " + errorMessage(e));
    }
    const detail::TemporaryDirectory& tmp = *tmpDir;
    const std::string tmpPng = tmp.path("plot.png"), dataPath = tmp.path("plot.dat");
    const std::string scriptPath = tmp.path("plot.gp"), logPath = tmp.path("gnuplot.log");
    writeFile(dataPath, data());
    writeFile(scriptPath, script(dataPath, tmpPng, widthPx, heightPx));
    int status = 0;
    try
    {
        status = runChildProcess({"gnuplot", scriptPath}, logPath);
    }
    catch (const Interrupted&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        THROW_EXCEPTION("drawing '" + pngPath + "': " + errorMessage(e) +
                        " (is the Debian package gnuplot-nox installed?)");
    }
    if (status != 0 || !fs::exists(tmpPng))
    {
        std::ifstream logf(logPath);
        std::stringstream log;
        log << logf.rdbuf();
        THROW_EXCEPTION("gnuplot failed drawing '" + pngPath + "' (it " + waitStatusText(status) +
                        "): " + log.str());
    }
    addPngText(tmpPng, "Software", std::string(kPngSoftware) + " (semloc-plot-world)");
    std::vector<std::pair<std::string, std::string>> files = {{tmpPng, pngPath}};
    if (keepScript)
    {
        // The kept script reads the kept data and draws the PNG beside it.
        const std::string keptData = pngPath + ".dat", keptScript = pngPath + ".gp";
        writeFile(tmp.path("kept.gp"), script(keptData, pngPath, widthPx, heightPx));
        files.insert(files.begin(), {{dataPath, keptData}, {tmp.path("kept.gp"), keptScript}});
    }
    std::vector<std::string> outputs;
    for (const auto& f : files)
    {
        outputs.push_back(f.second);
    }
    writeOutputFiles(
        outputs,
        [&](const std::vector<std::string>& temporaries)
        {
            for (size_t i = 0; i < files.size(); i++)
            {
                std::error_code ec;
                fs::rename(files[i].first, temporaries[i], ec);
                if (ec)
                {
                    THROW_EXCEPTION("cannot write '" + files[i].second + "': " + ec.message());
                }
            }
        });
}

}  // namespace semloc

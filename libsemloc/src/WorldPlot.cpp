/* semloc — WorldPlot: gnuplot script and data for a world figure. */
#include <mrpt/core/exceptions.h>
#include <mrpt/system/filesystem.h>
#include <semloc/WorldPlot.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include "TextFiles.h"

namespace semloc
{
namespace
{
using detail::shellQuoted;
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

std::string WorldPlot::data() const
{
    // Block 0: outlines (closed polylines separated by blank lines); block 1: point objects;
    // blocks 2..: paths.
    std::ostringstream o;
    o.precision(10);
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

std::string WorldPlot::script(const std::string& dataPath, const std::string& pngPath, int widthPx,
                              int heightPx) const
{
    const auto& b = m_world.bounds;
    std::ostringstream s;
    s.precision(10);
    s << "set terminal pngcairo size " << widthPx << "," << heightPx
      << " enhanced font 'Sans,10'\n";
    s << "set output " << quoted(pngPath) << "\n";
    s << "set title " << quoted(m_title.empty() ? m_world.name : m_title) << " noenhanced\n";
    s << "set xrange [" << b.x_min << ":" << b.x_max << "]\nset yrange [" << b.y_min << ":"
      << b.y_max << "]\n";
    s << "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n";
    // 5 m blocks, as in the paper's Fig. 1.
    s << "set xtics 5\nset ytics 5\nset grid xtics ytics lc rgb '#dddddd'\n";
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
    s << "plot " << quoted(dataPath)
      << " index 0 with lines lw 2 lc rgb '#333333' title 'structures (sonar)', \\\n";
    s << "  '' index 1 with points pt 7 ps 0.8 lc rgb '#cc6600' title 'point objects'";
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
    const std::string tmpPng = pngPath + ".tmp.png";
    const std::string dataPath = pngPath + ".dat";
    const std::string scriptPath = pngPath + ".gp";
    writeFile(dataPath, data());
    writeFile(scriptPath, script(dataPath, tmpPng, widthPx, heightPx));
    const std::string logPath = pngPath + ".log";
    const std::string cmd =
        "gnuplot " + shellQuoted(scriptPath) + " > " + shellQuoted(logPath) + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream logf(logPath);
    std::stringstream log;
    log << logf.rdbuf();
    std::remove(logPath.c_str());
    if (!keepScript)
    {
        std::remove(dataPath.c_str());
        std::remove(scriptPath.c_str());
    }
    if (rc != 0 || !mrpt::system::fileExists(tmpPng))
    {
        std::remove(tmpPng.c_str());
        THROW_EXCEPTION("gnuplot failed drawing '" + pngPath +
                        "' (is the Debian package gnuplot-nox installed?): " + log.str());
    }
    if (std::rename(tmpPng.c_str(), pngPath.c_str()) != 0)
    {
        std::remove(tmpPng.c_str());
        THROW_EXCEPTION("cannot write '" + pngPath + "'");
    }
}

}  // namespace semloc

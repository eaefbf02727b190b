/* semloc — figures of a world (outlines, labels, paths) drawn by gnuplot. */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <semloc/world/World.h>

#include <string>
#include <vector>

namespace semloc
{
/** A top view of a world: object outlines, their labels and ids, point objects, and any
 *  number of named paths (the trajectory, estimates), rendered to PNG by gnuplot.
 *
 *  gnuplot (Debian package gnuplot-nox) must be on the PATH; the script and data are
 *  written next to the PNG as `<png>.gp` / `<png>.dat` when `keepScript` is set, so a
 *  figure can be restyled by hand. */
class WorldPlot
{
public:
    /** A named polyline drawn over the world. */
    struct Path
    {
        /** Legend entry. */
        std::string name;
        /** Vertices [m]. */
        std::vector<mrpt::math::TPoint2D> points;
    };

    /** A figure of `world`; `title` defaults to the world's name. */
    explicit WorldPlot(World world, std::string title = {});

    /** Adds a path (drawn in insertion order, legend entry `name`). */
    void addPath(const std::string& name, std::vector<mrpt::math::TPoint2D> points);
    /** Adds the world's own trajectory (waypoints) as a path named "trajectory". */
    void addWorldTrajectory();

    /** gnuplot settings of the world's figure (title, ranges, equal axes, tics, object labels),
     *  for a script that draws more over the world. */
    std::string settings() const;
    /** The `plot` clauses of the world (outlines, point objects) reading blocks 0 and 1 of
     *  `dataPath`, a file holding data() (without `plot`, for more clauses after it). */
    std::string worldLayers(const std::string& dataPath) const;

    /** The gnuplot script that draws into `pngPath` reading `dataPath`. */
    std::string script(const std::string& dataPath, const std::string& pngPath, int widthPx,
                       int heightPx) const;
    /** The data file the script reads (gnuplot indexed blocks). */
    std::string data() const;

    /** Checks, before any work, that savePng() may write `pngPath` (and, with `keepScript`,
     *  `<pngPath>.dat` and `<pngPath>.gp`): checkOutputFile's rule, where a previous output is a
     *  PNG semloc drew (isSemlocPng) and a script or data file that starts with semloc's
     *  header. */
    static void checkPngOutputs(const std::string& pngPath, const std::vector<std::string>& inputs,
                                bool keepScript);

    /** Renders to `pngPath` (tagged with a `Software` text entry, isSemlocPng): gnuplot (a child
     * process) draws in a temporary directory beside it, and the finished files are renamed into
     * place. Throws with gnuplot's output if gnuplot is missing or fails; throws
     * semloc::Interrupted at an interrupt request (semloc/io/Interrupt.h), gnuplot ended. Nothing
     * is left behind on any error. */
    void savePng(const std::string& pngPath, int widthPx = 900, int heightPx = 900,
                 bool keepScript = false) const;

private:
    World m_world;
    std::string m_title;
    std::vector<Path> m_paths;
};

}  // namespace semloc

/* semloc — a figure gnuplot could not draw: the tools keep their other outputs and say which
 * figure is missing and why. */
#pragma once

#include <string>
#include <vector>

namespace semloc
{
/** A figure left out of a tool's outputs because gnuplot could not draw it (or is missing):
 *  the results stand without it; the tools print text() on stderr and, where they write a
 *  report.md, figureWarningsMarkdown(). */
struct TFigureWarning
{
    /** The figure's file, relative to the output directory (e.g. `fig_variance.png`). */
    std::string figure;
    /** The script that draws it, relative to the output directory (e.g. `figures.gp`). */
    std::string script;
    /** gnuplot's first error line (e.g. `"figures.gp" line 9: all points y value
     *  undefined!`), or why gnuplot could not be run. */
    std::string error;

    /** "figure fig_variance.png was not drawn (figures.gp): <error>". */
    std::string text() const;
};

/** report.md's section on the figures not drawn: a heading and one line per warning; empty
 *  without warnings. */
std::string figureWarningsMarkdown(const std::vector<TFigureWarning>& warnings);

}  // namespace semloc

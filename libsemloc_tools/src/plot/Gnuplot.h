/* semloc — gnuplot scripts that draw several figures, each drawn by a gnuplot of its own in a
 * staged output directory, so that one figure gnuplot cannot draw leaves the others (private). */
#pragma once

#include <semloc/io/StagedDirectory.h>
#include <semloc/plot/FigureWarning.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** The first line of a script made of figureBlock()s: `gnuplot script` draws every figure,
 *  `gnuplot -e "figure='NAME'" script` only figure NAME. */
std::string figureSelector();

/** `body` (gnuplot commands that draw `figure` and need nothing from the other blocks) as
 *  the block of a script that runs when the script draws every figure or `figure`. */
std::string figureBlock(const std::string& figure, const std::string& body);

/** Draws each file of `figures` by running `gnuplot -e "figure='NAME'" script` (`script` a
 *  file of `out` made of figureSelector() and figureBlock()s) in `out`. A figure gnuplot
 *  cannot draw (it fails, or leaves the file out or empty) is removed and returned as a
 *  warning with gnuplot's first error line; without gnuplot every figure is a warning.
 *  semloc::Interrupted at an interrupt request (gnuplot ended). The logs are removed. */
std::vector<TFigureWarning> drawFigures(const StagedDirectory& out, const std::string& script,
                                        const std::vector<std::string>& figures);

/** The y axis of a panel of `values` (one column of its data): `set logscale y` when
 *  `logScale` and one of them is positive; else a linear axis, with a fixed range [0:1] and
 *  the label `noData` in the middle when none is finite (gnuplot refuses a plot whose every
 *  point is undefined). `set`s only: to be undone with unsetAxisY(). */
std::string axisY(const std::vector<double>& values, bool logScale, const std::string& noData);

/** Undoes axisY(). */
std::string unsetAxisY();
}  // namespace semloc::detail

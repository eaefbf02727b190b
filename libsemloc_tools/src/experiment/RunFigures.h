/* semloc — gnuplot pieces of a run's figures over its world: the track data (true path,
 * estimate, error, spread) and the plot clauses that draw it (private). */
#pragma once

#include <semloc/experiment/RunMetrics.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** Position error at which the estimate's colour saturates to red [m]. */
constexpr double kErrorColourMax_m = 2.0;

/** A string in gnuplot's single quotes. */
std::string gnuplotQuoted(const std::string& s);

/** The track of a run, one row per step: `step t gt_x gt_y est_x est_y err_xy std_xy` (`t` the
 *  seconds since the first step, the step index when the times are unknown; `std_xy` the
 *  square root of var_xy; NaN where unknown). */
std::string trackData(const std::vector<TStepRecord>& records);

/** gnuplot settings of the estimate's colour scale: green (no error) to red
 *  (kErrorColourMax_m or more). */
std::string errorPalette();

/** The `plot` clauses of a track (a file of trackData) over a world, each after a comma: the
 *  true path, the estimate (coloured by its error when there is ground truth, else blue) and
 *  the convergence point (row `convergenceRow`, none if negative); rows after `lastRow` are
 *  not drawn (negative: all). */
std::string trackLayers(const std::string& trackFile, bool groundTruth, long convergenceRow,
                        long lastRow = -1);

/** The time axis of a run's records: "t [s]" or "step" (no times). */
std::string timeAxisLabel(const std::vector<TStepRecord>& records);

}  // namespace semloc::detail

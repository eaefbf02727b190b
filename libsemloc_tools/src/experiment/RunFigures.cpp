/* semloc — the track of a run as gnuplot data and plot clauses. */
#include "experiment/RunFigures.h"

#include <cmath>
#include <sstream>

#include "io/Text.h"

namespace semloc::detail
{
namespace
{
/** A number for gnuplot: shortest round-trip text, NaN for unknown values. */
std::string gp(double v)
{
    return std::isfinite(v) ? shortestText(v) : std::string("NaN");
}

bool haveTimes(const std::vector<TStepRecord>& records)
{
    for (const auto& r : records)
    {
        if (!std::isfinite(r.t))
        {
            return false;
        }
    }
    return !records.empty();
}
}  // namespace

std::string gnuplotQuoted(const std::string& s)
{
    std::string out = "'";
    for (const char c : s)
    {
        out += (c == '\'') ? std::string("''") : std::string(1, c);
    }
    return out + "'";
}

std::string trackData(const std::vector<TStepRecord>& records)
{
    const bool times = haveTimes(records);
    std::ostringstream o;
    o << "# step t gt_x gt_y est_x est_y err_xy std_xy\n";
    for (const auto& r : records)
    {
        const double t = times ? r.t - records.front().t : static_cast<double>(r.step);
        o << r.step << ' ' << gp(t) << ' ' << gp(r.gt ? r.gt->x : NAN) << ' '
          << gp(r.gt ? r.gt->y : NAN) << ' ' << gp(r.est.x) << ' ' << gp(r.est.y) << ' '
          << gp(r.errXY()) << ' ' << gp(std::sqrt(std::max(r.var_xy, 0.0))) << '\n';
    }
    return o.str();
}

std::string errorPalette()
{
    return "set palette defined (0 '#1a9850', 0.25 '#91cf60', 0.5 '#fee08b', 0.75 '#fc8d59', "
           "1 '#d73027')\nset cbrange [0:" +
           shortestText(kErrorColourMax_m) +
           "]\nset cblabel 'position error of the estimate [m]'\n";
}

std::string trackLayers(const std::string& trackFile, bool groundTruth, long convergenceRow,
                        long lastRow)
{
    const std::string file = gnuplotQuoted(trackFile);
    const std::string rows = lastRow >= 0 ? " every ::0::" + std::to_string(lastRow) : "";
    std::string s;
    if (groundTruth)
    {
        s += ", \\\n  " + file + rows +
             " using 3:4 with lines lw 1.5 dt 2 lc rgb '#000000' title 'true path'";
        s += ", \\\n  " + file + rows +
             " using 5:6:7 with lines lw 1.5 lc palette title 'estimate (colour: error)'";
    }
    else
    {
        s += ", \\\n  " + file + rows +
             " using 5:6 with lines lw 1.5 lc rgb '#1f77b4' title 'estimate'";
    }
    if (convergenceRow >= 0 && (lastRow < 0 || convergenceRow <= lastRow))
    {
        const std::string r = std::to_string(convergenceRow);
        s += ", \\\n  " + file + " every ::" + r + "::" + r +
             " using 5:6 with points pt 6 ps 2.5 lw 2 lc rgb '#000000' title 'converged'";
    }
    return s;
}

std::string timeAxisLabel(const std::vector<TStepRecord>& records)
{
    return haveTimes(records) ? "time since the first step [s]" : "step";
}

}  // namespace semloc::detail

/* semloc — semloc-calibrate's report: the fits as a markdown page with gnuplot figures. */
#include <mrpt/core/exceptions.h>
#include <semloc/calibration/SensorCalibration.h>

#include <cmath>
#include <sstream>

#include "io/Gnuplot.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
using detail::writeFile;

/** residuals_range.dat, residuals_bearing.dat, detection.dat (range, detected), odometry.dat
 *  (d, |dphi|, |e_xy|, |e_phi| in deg). */
void writeData(const TCalibrationResult& r, const StagedDirectory& out)
{
    const auto& s = r.samples;
    std::ostringstream rr, rb, det, odo;
    rr << "# range_residual_m\n";
    for (double v : s.rangeResiduals_m)
    {
        rr << v << "\n";
    }
    rb << "# bearing_residual_deg\n";
    for (double v : s.bearingResiduals_deg)
    {
        rb << v << "\n";
    }
    det << "# range_m detected\n";
    for (size_t i = 0; i < s.visibleRanges_m.size(); i++)
    {
        det << s.visibleRanges_m[i] << " " << s.visibleDetected[i] << "\n";
    }
    odo << "# d_m abs_dphi_rad abs_err_xy_m abs_err_phi_deg\n";
    for (size_t i = 0; i < s.odomDist_m.size(); i++)
    {
        odo << s.odomDist_m[i] << " " << s.odomTurn_rad[i] << " " << s.odomErrXY_m[i] << " "
            << s.odomErrPhi_rad[i] * 180 / M_PI << "\n";
    }
    writeFile(out.path("residuals_range.dat"), rr.str());
    writeFile(out.path("residuals_bearing.dat"), rb.str());
    writeFile(out.path("detection.dat"), det.str());
    writeFile(out.path("odometry.dat"), odo.str());
}

std::string script(const TCalibrationResult& r)
{
    const double sr = r.sigma_range_m.value, sb = r.sigma_bearing_deg.value;
    const double R = r.maxRange_m > 0 ? r.maxRange_m : 1.0;
    std::ostringstream g;
    g << "# semloc-calibrate: the report's figures (gnuplot figures.gp)\n"
      << "set terminal pngcairo size 1000,420 noenhanced\nset grid\n"
      << "bin(x, w) = w * floor(x / w) + w / 2\n"
      << "set output 'fig_residuals.png'\nset multiplot layout 1,2\n"
      << "sr = " << sr << "\nsb = " << sb << "\nnr = " << r.samples.rangeResiduals_m.size()
      << "\nnb = " << r.samples.bearingResiduals_deg.size() << "\nwr = sr / 4.0\nwb = sb / 4.0\n"
      << "set xlabel 'range residual [m]'\nset ylabel 'detections'\n"
      << "plot [-4*sr:4*sr] 'residuals_range.dat' u (bin($1, wr)):(1) smooth freq w boxes t "
         "'matched', nr * wr / (sr * sqrt(2*pi)) * exp(-0.5 * (x / sr)**2) lw 2 t 'fit'\n"
      << "set xlabel 'bearing residual [deg]'\n"
      << "plot [-4*sb:4*sb] 'residuals_bearing.dat' u (bin($1, wb)):(1) smooth freq w boxes t "
         "'matched', nb * wb / (sb * sqrt(2*pi)) * exp(-0.5 * (x / sb)**2) lw 2 t 'fit'\n"
      << "unset multiplot\n"
      << "set output 'fig_detection.png'\nset xlabel 'range [m]'\n"
      << "set ylabel 'detected share of in-view objects'\nset yrange [0:1.05]\n"
      << "plot 'detection.dat' u (bin($1, " << R / 10 << ")):2 smooth unique w lp t 'data', "
      << r.p_detect_near.value << " + (" << r.p_detect_far.value << " - " << r.p_detect_near.value
      << ") * x / " << R << " lw 2 t 'fitted P_D(r)'\n"
      << "set autoscale y\nset output 'fig_odometry.png'\nset multiplot layout 1,2\n"
      << "set xlabel 'distance travelled in a step [m]'\nset ylabel '|position error| [m]'\n"
      << "plot 'odometry.dat' u 1:3 pt 7 ps 0.4 t 'steps', (" << r.minStdXY.value << " + "
      << r.a1.value << " * x) * sqrt(pi/2) lw 2 t 'fitted mean (no turn)'\n"
      << "set ylabel '|heading error| [deg]'\n"
      << "plot 'odometry.dat' u 1:4 pt 7 ps 0.4 t 'steps', (" << r.minStdPHI.value << " + "
      << r.a3.value << " * x) * sqrt(2/pi) lw 2 t 'fitted mean (no turn)'\n"
      << "unset multiplot\n";
    return g.str();
}

/** `text` for a markdown table cell: its `|` escaped. */
std::string cell(const std::string& text)
{
    std::string out;
    for (const char c : text)
    {
        out += (c == '|') ? std::string("\\|") : std::string(1, c);
    }
    return out;
}

std::string row(const char* key, const TCalibrationFit& f)
{
    std::ostringstream s;
    s << "| `" << key << "` | " << f.value << " | ±" << f.ci95 << " | " << f.n << " | "
      << cell(f.method) << " |\n";
    return s.str();
}

std::string markdown(const TCalibrationResult& r)
{
    std::ostringstream m;
    m << "# semloc-calibrate: the fitted noise\n\n"
      << r.scans << " semantic scans: " << r.matched << " detections matched an in-view object "
      << "of their label, " << r.misread << " one of their label at its bearing but outside its "
      << "range gate (misread range), " << r.confused << " one of another label, " << r.clutter
      << " none (clutter); " << r.increments << " odometry increments.\n\n"
      << "| key | value | 95 % | n | fit |\n| --- | --- | --- | --- | --- |\n"
      << row("sigma_range_m", r.sigma_range_m) << row("sigma_bearing_deg", r.sigma_bearing_deg)
      << row("p_detect_near", r.p_detect_near) << row("p_detect_far", r.p_detect_far)
      << row("clutter_per_scan", r.clutter_per_scan) << row("p_confusion", r.p_confusion)
      << row("p_range_outlier", r.p_range_outlier) << row("a1", r.a1) << row("a2", r.a2)
      << row("a3", r.a3) << row("a4", r.a4) << row("minStdXY", r.minStdXY)
      << row("minStdPHI", r.minStdPHI)
      << row("heading drift [deg/min]", r.heading_drift_deg_per_min) << "\nThe heading "
      << (r.headingDrifts ? "drifts: the calibrated ini turns the drift state on "
                            "([MotionModel] heading_drift_walk_deg_per_min)."
                          : "does not drift measurably: the drift state stays off.")
      << "\n"
      << "\n![residuals](fig_residuals.png)\n\n![detection](fig_detection.png)\n\n"
      << "![odometry](fig_odometry.png)\n";
    return m.str();
}
}  // namespace

void SensorCalibration::WriteReport(const TCalibrationResult& r, const StagedDirectory& out)
{
    writeData(r, out);
    writeFile(out.path("figures.gp"), script(r));
    writeFile(out.path("report.md"), markdown(r));
    detail::runGnuplot(out, "figures.gp",
                       {"fig_residuals.png", "fig_detection.png", "fig_odometry.png"});
}

}  // namespace semloc

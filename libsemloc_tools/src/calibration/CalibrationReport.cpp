/* semloc — semloc-calibrate's report: the fits as a markdown page with gnuplot figures. */
#include <mrpt/core/exceptions.h>
#include <semloc/calibration/SensorCalibration.h>

#include <cmath>
#include <sstream>

#include "io/TextFiles.h"
#include "plot/Gnuplot.h"

namespace semloc
{
namespace
{
using detail::writeFile;

/** residuals_range.dat, residuals_bearing.dat, detection.dat (range, detected, off axis),
 *  detection_outer.dat (its rows more than half way to the edge of the view), odometry.dat
 *  (d, |dphi|, |e_xy|, |e_phi| in deg). */
void writeData(const TCalibrationResult& r, const StagedDirectory& out)
{
    const auto& s = r.samples;
    std::ostringstream rr, rb, det, outer, odo;
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
    det << "# range_m detected off_axis (|bearing| / half the field of view)\n";
    outer << "# range_m detected off_axis, off_axis > 0.5\n";
    for (size_t i = 0; i < s.visibleRanges_m.size(); i++)
    {
        const double off = i < s.visibleOffAxis.size() ? s.visibleOffAxis[i] : 0.0;
        std::ostringstream row;
        row << s.visibleRanges_m[i] << " " << s.visibleDetected[i] << " " << off << "\n";
        det << row.str();
        if (off > 0.5)
        {
            outer << row.str();
        }
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
    writeFile(out.path("detection_outer.dat"), outer.str());
    writeFile(out.path("odometry.dat"), odo.str());
}

/** A panel with nothing to show but `why` (gnuplot refuses a plot without a defined point). */
std::string emptyPanel(const std::string& why)
{
    return "set label 99 '" + why +
           "' at graph 0.5, graph 0.5 center\nplot [0:1][0:1] NaN notitle\nunset label 99\n";
}

/** fig_residuals.png: the residual histograms with the fitted normal densities. */
std::string residualsFigure(const TCalibrationResult& r)
{
    const double sr = r.sigma_range_m.value, sb = r.sigma_bearing_deg.value;
    std::ostringstream g;
    g << "set output 'fig_residuals.png'\nset multiplot layout 1,2\n";
    g << "set xlabel 'range residual [m]'\nset ylabel 'detections'\n";
    if (r.samples.rangeResiduals_m.empty() || !(sr > 0) || !std::isfinite(sr))
    {
        g << emptyPanel("no range residual to fit");
    }
    else
    {
        g << "sr = " << sr << "\nnr = " << r.samples.rangeResiduals_m.size() << "\nwr = sr / 4.0\n"
          << "plot [-4*sr:4*sr] 'residuals_range.dat' u (bin($1, wr)):(1) smooth freq w boxes t "
             "'matched', nr * wr / (sr * sqrt(2*pi)) * exp(-0.5 * (x / sr)**2) lw 2 t 'fit'\n";
    }
    g << "set xlabel 'bearing residual [deg]'\n";
    if (r.samples.bearingResiduals_deg.empty() || !(sb > 0) || !std::isfinite(sb))
    {
        g << emptyPanel("no bearing residual to fit");
    }
    else
    {
        g << "sb = " << sb << "\nnb = " << r.samples.bearingResiduals_deg.size()
          << "\nwb = sb / 4.0\n"
          << "plot [-4*sb:4*sb] 'residuals_bearing.dat' u (bin($1, wb)):(1) smooth freq w boxes t "
             "'matched', nb * wb / (sb * sqrt(2*pi)) * exp(-0.5 * (x / sb)**2) lw 2 t 'fit'\n";
    }
    g << "unset multiplot\nunset output\n";
    return g.str();
}

/** fig_detection.png: the detected share of the objects in view against their range (all,
 *  and those in the outer half of the field of view), the fitted P_D on the axis and at the
 *  edge. */
std::string detectionFigure(const TCalibrationResult& r)
{
    const double R = r.maxRange_m > 0 ? r.maxRange_m : 1.0;
    std::ostringstream g;
    g << "set output 'fig_detection.png'\nset xlabel 'range [m]'\n"
      << "set ylabel 'detected share of in-view objects'\nset yrange [0:1.05]\n";
    if (r.samples.visibleRanges_m.empty())
    {
        g << emptyPanel("no object in view");
    }
    else
    {
        const auto line = [&](double factor)
        {
            std::ostringstream l;
            l << factor << " * (" << r.p_detect_near.value << " + (" << r.p_detect_far.value
              << " - " << r.p_detect_near.value << ") * x / " << R << ")";
            return l.str();
        };
        g << "plot 'detection.dat' u (bin($1, " << R / 10 << ")):2 smooth unique w lp t 'data', "
          << "'detection_outer.dat' u (bin($1, " << R / 10 << ")):2 smooth unique "
          << "w lp t 'data, outer half of the view', " << line(1) << " lw 2 t 'fitted P_D, axis', "
          << line(r.p_detect_edge_ratio.value) << " lw 2 t 'fitted P_D, edge'\n";
    }
    g << "set autoscale y\nunset output\n";
    return g.str();
}

/** fig_odometry.png: the odometry errors against the distance travelled. */
std::string odometryFigure(const TCalibrationResult& r)
{
    std::ostringstream g;
    g << "set output 'fig_odometry.png'\nset multiplot layout 1,2\n"
      << "set xlabel 'distance travelled in a step [m]'\nset ylabel '|position error| [m]'\n";
    if (r.samples.odomDist_m.empty())
    {
        g << emptyPanel("no odometry increment") << "set ylabel '|heading error| [deg]'\n"
          << emptyPanel("no odometry increment");
    }
    else
    {
        g << "plot 'odometry.dat' u 1:3 pt 7 ps 0.4 t 'steps', (" << r.minStdXY.value << " + "
          << r.a1.value << " * x) * sqrt(pi/2) lw 2 t 'fitted mean (no turn)'\n"
          << "set ylabel '|heading error| [deg]'\n"
          << "plot 'odometry.dat' u 1:4 pt 7 ps 0.4 t 'steps', (" << r.minStdPHI.value << " + "
          << r.a3.value << " * x) * sqrt(2/pi) lw 2 t 'fitted mean (no turn)'\n";
    }
    g << "unset multiplot\nunset output\n";
    return g.str();
}

std::string script(const TCalibrationResult& r)
{
    std::ostringstream g;
    g << "# semloc-calibrate: the report's figures (gnuplot figures.gp; gnuplot -e\n"
      << "# \"figure='fig_odometry.png'\" figures.gp draws only that one)\n"
      << detail::figureSelector() << "set terminal pngcairo size 1000,420 noenhanced\nset grid\n"
      << "bin(x, w) = w * floor(x / w) + w / 2\n"
      << detail::figureBlock("fig_residuals.png", residualsFigure(r))
      << detail::figureBlock("fig_detection.png", detectionFigure(r))
      << detail::figureBlock("fig_odometry.png", odometryFigure(r));
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
    std::string how = f.method;
    if (f.status == TCalibrationFit::Status::Clamped)
    {
        std::ostringstream c;
        c << "clamped into the filter's range: fitted " << f.fitted << " (" << f.why << "); "
          << f.method;
        how = c.str();
    }
    if (f.status == TCalibrationFit::Status::TooLittleData)
    {
        s << "| `" << key << "` | not fitted | | " << f.n << " | "
          << cell("too little data (" + f.why + "): the base ini's value written") << " |\n";
        return s.str();
    }
    s << "| `" << key << "` | " << f.value << " | ±" << f.ci95 << " | " << f.n << " | " << cell(how)
      << " |\n";
    return s.str();
}

/** The consistency stage's trials as a table (empty when it did not run). */
std::string consistencyMarkdown(const TCalibrationResult& r)
{
    const auto& c = r.consistency;
    if (c.trials.empty())
    {
        return "";
    }
    std::ostringstream m;
    m << "\n## Consistency\n\nThe filter run on this run from its own start, against its "
         "ground truth, with the detector sigmas and the motion noise widened and the "
         "likelihood tempered (one run per seed per row); written: the row in bold ("
      << (c.consistent ? "the consistent one of the lowest error"
                       : "none reached the share asked "
                         "for: the most steps inside")
      << "). NEES inside: the share of the steps whose pose NEES is within its 95 % bound ("
      << 100 * c.minInsideShare
      << " % asked for, less two standard errors over the steps: a filter exactly that "
         "consistent falls below it in half of its runs).\n\n"
      << "| detector sigmas | motion noise | likelihood tempering | NEES inside [%] | mean NEES | "
         "mean error [m] | converged |\n| --- | --- | --- | --- | --- | --- | --- |\n";
    for (size_t i = 0; i < c.trials.size(); i++)
    {
        const auto& t = c.trials[i];
        const std::string b = i == c.chosen ? "**" : "";
        m << "| " << b << "x" << t.sensorScale << b << " | " << b << "x" << t.motionScale << b
          << " | " << b << "x" << t.temper << b << " | " << 100 * t.insideShare << " | "
          << t.neesMean << " | " << t.meanErr_m << " | " << t.converged << " of " << t.runs
          << " |\n";
    }
    return m.str();
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
      << row("p_detect_edge_ratio", r.p_detect_edge_ratio)
      << row("clutter_per_scan", r.clutter_per_scan) << row("p_confusion", r.p_confusion)
      << row("p_range_outlier", r.p_range_outlier)
      << row("lookalike_persistence", r.lookalike_persistence) << row("a1", r.a1) << row("a2", r.a2)
      << row("a3", r.a3) << row("a4", r.a4) << row("minStdXY", r.minStdXY)
      << row("minStdPHI", r.minStdPHI)
      << row("heading drift [deg/min]", r.heading_drift_deg_per_min)
      << row("odometry_delay_s", r.odometry_delay_s) << "\nThe heading "
      << (r.headingDrifts ? "drifts: the calibrated ini turns the drift state on "
                            "([MotionModel] heading_drift_walk_deg_per_min)."
                          : "does not drift measurably: the drift state stays off.")
      << " The odometry's increments err by " << r.odomHeadingRms_deg
      << " deg RMS in heading as they come";
    if (r.odometry_delay_s.value > 0)
    {
        m << ", " << r.odomHeadingRmsDelayed_deg
          << " re-cut by the delay (the vehicle follows its odometry late: [MotionModel] "
             "odometry_delay_s).";
    }
    else
    {
        m << "; no delay lowers that significantly.";
    }
    m << "\n\n## Bias and map offset\n\n";
    std::istringstream bias(SensorCalibration::BiasText(r));
    for (std::string line; std::getline(bias, line);)
    {
        m << "- " << line << "\n";
    }
    m << consistencyMarkdown(r);
    const auto warnings = SensorCalibration::Warnings(r);
    m << "\n## Warnings\n\n" << (warnings.empty() ? "None.\n" : "");
    for (const auto& w : warnings)
    {
        m << "- " << w << "\n";
    }
    m << "\n![residuals](fig_residuals.png)\n\n![detection](fig_detection.png)\n\n"
      << "![odometry](fig_odometry.png)\n";
    return m.str();
}
}  // namespace

std::vector<TFigureWarning> SensorCalibration::WriteReport(const TCalibrationResult& r,
                                                           const StagedDirectory& out)
{
    writeData(r, out);
    writeFile(out.path("figures.gp"), script(r));
    auto warnings = detail::drawFigures(
        out, "figures.gp", {"fig_residuals.png", "fig_detection.png", "fig_odometry.png"});
    writeFile(out.path("report.md"), markdown(r) + figureWarningsMarkdown(warnings));
    return warnings;
}

}  // namespace semloc

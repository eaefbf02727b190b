/* semloc tests — the bad inputs of semloc-plot-run in docs/bad-input.md's table, and the
 * figures gnuplot cannot draw (semloc-plot-run, semloc-benchmark, semloc-calibrate: a warning,
 * every other output written). Each case writes its input in a fresh directory and returns the
 * tool's command line (test_BadInput.cpp runs it and checks the row). */
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{
namespace
{
/** A three-step run in `d`/run (steps.csv, summary.yaml, config.ini, particles.csv of steps 0
 *  and 2 with `particles` as its rows) and semloc-plot-run's command line on it. */
std::vector<std::string> plotRun(const fs::path& d, const std::string& particles,
                                 const std::vector<std::string>& extra = {})
{
    const fs::path run = d / "run";
    fs::create_directories(run);
    writeText(run / ".semloc-output", "");
    writeText(run / "steps.csv",
              "step,t,gt_x,gt_y,gt_phi,est_x,est_y,est_phi,err_xy,err_phi,var_xy,ess,n_particles,"
              "update_us\n"
              "0,0,1,1,0,2,2,0,1.41,0,4,1,2,10\n1,1,2,1,0,2,1,0,0,0,1,1,2,10\n"
              "2,2,3,1,0,3,1,0,0,0,0.5,1,2,10\n");
    writeText(run / "summary.yaml", "variant: \"semantic\"\nconvergence_step: 1\n");
    writeText(run / "config.ini", "[LocalizationExperiment]\nmap_file = \n");
    writeText(run / "particles.csv", "step,t,x,y,phi,weight\n" + particles);
    std::vector<std::string> argv = {"semloc-plot-run", run.string(), "-o",
                                     (d / "figures").string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return argv;
}

const std::string kParticles = "0,0,1,1,0,0.5\n0,0,2,2,0,0.5\n2,2,3,1,0,0.5\n2,2,3,1.1,0,0.5\n";
}  // namespace

Cases runPlotCases()
{
    return {
        {"plot-run-out-is-run",
         [](const fs::path& d)
         {
             auto a = plotRun(d, kParticles);
             a[3] = (d / "run").string();
             return a;
         }},
        {"plot-run-not-a-run",
         [](const fs::path& d)
         {
             auto a = plotRun(d, kParticles);
             fs::remove(d / "run" / "steps.csv");
             return a;
         }},
        {"plot-run-particles-bad-cell", [](const fs::path& d)
         { return plotRun(d, "0,0,1,1,0,0.5\n0,0,abc,2,0,0.5\n2,2,3,1,0,0.5\n"); }},
        {"plot-run-particles-unknown-step",
         [](const fs::path& d) { return plotRun(d, "0,0,1,1,0,1\n5,5,1,1,0,1\n"); }},
        {"plot-run-steps-not-saved",
         [](const fs::path& d) {
             return plotRun(d, kParticles, {"--steps", "0,1"});
         }},
    };
}

void gnuplotRefusing(const fs::path& d, const std::string& figure)
{
    std::string real;
    std::istringstream path(std::getenv("PATH") ? std::getenv("PATH") : "");
    for (std::string dir; real.empty() && std::getline(path, dir, ':');)
    {
        if (!dir.empty() && ::access((dir + "/gnuplot").c_str(), X_OK) == 0)
        {
            real = dir + "/gnuplot";
        }
    }
    const fs::path bin = d / "fake-bin";
    fs::create_directories(bin);
    // The tools run `gnuplot -e "figure='NAME'" SCRIPT`.
    writeText(bin / "gnuplot", "#!/bin/sh\ncase \"$2\" in *\"'" + figure +
                                   "'\"*) echo \"\\\"$3\\\" line 1: this gnuplot refuses " +
                                   figure + "\"; exit 1 ;; esac\nexec '" + real + "' \"$@\"\n");
    fs::permissions(bin / "gnuplot", fs::perms::owner_all);
}

Cases figureCases()
{
    return {
        {"plot-run-figure-not-drawn",
         [](const fs::path& d)
         {
             gnuplotRefusing(d, "error.png");
             return plotRun(d, kParticles);
         }},
        {"benchmark-figure-not-drawn",
         [](const fs::path& d)
         {
             gnuplotRefusing(d, "fig_variance.png");
             writeText(d / "bench.ini",
                       "[Benchmark]\nruns = 1\nmax_steps = 10\nparticles = 100\n"
                       "variants = " +
                           kSrc + "/config/localize/semantic.ini\nsimulate_ini = " + kSrc +
                           "/config/simulate/simulate.ini\noutput_dir = out\n");
             return std::vector<std::string>{"semloc-benchmark", (d / "bench.ini").string()};
         }},
        {"calibrate-figure-not-drawn",
         [](const fs::path& d)
         {
             gnuplotRefusing(d, "fig_detection.png");
             auto a = calibrate(d, 100, "semantic", "out.ini");
             a.insert(a.end(), {"--report", (d / "report").string()});
             return a;
         }},
    };
}

}  // namespace semloc::test::bad_input

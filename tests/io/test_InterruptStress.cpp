/* semloc tests — two Ctrl-C at random moments (the second while the first is being handled, as
 * `timeout -s INT` or an impatient user sends them) to semloc-localize, semloc-benchmark,
 * semloc-import and semloc-plot-run, 20 times each: every time the tool either finished (exit
 * 0, its outputs complete) or stopped (exit 130, nothing written), and no staging directory,
 * temporary file or process of its group is left. The moments come from a fixed seed. */
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "TestHelpers.h"
#include "io/InterruptHelpers.h"

namespace
{
using namespace semloc::test::interrupt;

constexpr int kTries = 20;

/** The processes (not zombies) whose process group is `pgid`. */
std::vector<pid_t> groupMembers(pid_t pgid)
{
    std::vector<pid_t> members;
    for (const auto& e : fs::directory_iterator("/proc"))
    {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos)
        {
            continue;
        }
        std::ifstream f(e.path() / "stat");
        std::string stat;
        std::getline(f, stat);
        const auto close = stat.rfind(')');
        if (close == std::string::npos)
        {
            continue;
        }
        std::istringstream rest(stat.substr(close + 2));
        char state = 0;
        long ppid = 0, pgrp = 0;
        rest >> state >> ppid >> pgrp;
        if (pgrp == pgid && state != 'Z')
        {
            members.push_back(static_cast<pid_t>(std::stol(name)));
        }
    }
    return members;
}

/** The entries under `d` that are not in `before` and not under one of `outputs`. */
std::vector<std::string> leftovers(const fs::path& d, const std::set<std::string>& before,
                                   const std::vector<std::string>& outputs)
{
    std::vector<std::string> found;
    for (const auto& name : listing(d))
    {
        const std::string top = fs::path(name).begin()->string();
        if (before.count(name) == 0 &&
            std::find(outputs.begin(), outputs.end(), top) == outputs.end())
        {
            found.push_back(name);
        }
    }
    return found;
}

/** Runs `argv` in `d` once to the end (its duration: the window of the signals), then
 *  `kTries` times signalled twice at random moments (the first within the window, the second
 *  within 0.1 s after it; every other try to the whole process group, as a terminal's
 *  Ctrl-C); checks each outcome and that nothing is left; `outputs` (relative to `d`) are
 *  removed after a try that finished. */
void stress(const std::vector<std::string>& argv, const fs::path& d,
            const std::vector<std::string>& outputs, std::mt19937& rng)
{
    const auto before = listing(d);
    const auto t0 = std::chrono::steady_clock::now();
    const Tool whole = start(argv, d);
    int wholeStatus = 0;
    ASSERT_EQ(::waitpid(whole.pid, &wholeStatus, 0), whole.pid);
    const double window_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(WIFEXITED(wholeStatus) && WEXITSTATUS(wholeStatus) == 0) << readText(whole.err);
    for (const auto& o : outputs)
    {
        ASSERT_TRUE(fs::exists(d / o)) << o;
        fs::remove_all(d / o);
    }
    std::uniform_real_distribution<double> first(0.0, window_s), second(0.0, 0.1);
    int stopped = 0;
    for (int k = 0; k < kTries; k++)
    {
        SCOPED_TRACE("try " + std::to_string(k));
        const bool group = k % 2 == 1;
        const Tool t = start(argv, d);
        std::this_thread::sleep_for(std::chrono::duration<double>(first(rng)));
        ::kill(group ? -t.pid : t.pid, SIGINT);
        std::this_thread::sleep_for(std::chrono::duration<double>(second(rng)));
        ::kill(group ? -t.pid : t.pid, SIGINT);
        int status = 0;
        const bool ended =
            waitUntil([&] { return ::waitpid(t.pid, &status, WNOHANG) == t.pid; }, kLatency_s);
        if (!ended)
        {
            ::kill(-t.pid, SIGKILL);
            ::waitpid(t.pid, &status, 0);
        }
        ASSERT_TRUE(ended) << "still running " << kLatency_s << " s after the signals";
        // A signal before main() installed the handlers (the process loading its libraries)
        // ends it by the default action, before it could write anything: a stop too.
        const bool early = WIFSIGNALED(status) && WTERMSIG(status) == SIGINT;
        ASSERT_TRUE(WIFEXITED(status) || early) << "ended by a signal: wait status " << status;
        const int rc = early ? 130 : WEXITSTATUS(status);
        ASSERT_TRUE(rc == 0 || rc == 130) << "exit " << rc << ": " << readText(t.err);
        stopped += rc == 130 ? 1 : 0;
        // Whatever a killed child was doing, nothing of the tool's group may outlive it.
        EXPECT_TRUE(waitUntil([&] { return groupMembers(t.pid).empty(); }, 2.0))
            << groupMembers(t.pid).size() << " process(es) of its group left";
        const auto left = leftovers(d, before, rc == 0 ? outputs : std::vector<std::string>());
        EXPECT_TRUE(left.empty()) << "left behind: " << left.front();
        for (const auto& o : outputs)
        {
            if (rc == 130)
            {
                EXPECT_FALSE(fs::exists(d / o)) << o << " written although stopped";
            }
            else
            {
                EXPECT_TRUE(fs::exists(d / o)) << o << " missing although finished";
            }
            fs::remove_all(d / o);
        }
        if (::testing::Test::HasFailure())
        {
            return;
        }
    }
    EXPECT_GE(stopped, kTries / 4) << "the signals missed the runs: most finished first";
}

/** A simulated dataset of `steps` steps in `d`/ds.rawlog (and its ground truth). */
void simulateDataset(const fs::path& d, int steps)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate.ini");
    o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
    o.simulation.max_steps = steps;
    semloc::Simulator sim(o);
    sim.writeDataset(sim.run(), (d / "ds.rawlog").string());
}
}  // namespace

TEST(InterruptStress, LocalizeTwoSignalsLeaveNothing)
{
    const fs::path d = freshDir("stress_localize");
    simulateDataset(d, 60);
    std::mt19937 rng(1);
    stress({kBin + "/semloc-localize", kSrc + "/config/localize/semantic.ini", "ds.rawlog", "-o",
            "out", "--save-particles", "1", "-q"},
           d, {"out"}, rng);
}

TEST(InterruptStress, BenchmarkTwoSignalsLeaveNothing)
{
    const fs::path d = freshDir("stress_benchmark");
    std::ofstream(d / "bench.ini")
        << "[Benchmark]\nruns = 4\njobs = 2\nparticles = 500\nvariants = " << kSrc
        << "/config/localize/semantic.ini\nsimulate_ini = " << kSrc
        << "/config/simulate/simulate.ini\noutput_dir = out\n";
    std::mt19937 rng(2);
    stress({kBin + "/semloc-benchmark", "bench.ini"}, d, {"out"}, rng);
}

TEST(InterruptStress, ImportTwoSignalsLeaveNothing)
{
    const fs::path d = freshDir("stress_import");
    // A long dataset (10 Hz odometry, 1 Hz scans, 20 000 s), so that the signals land inside.
    {
        std::ofstream odo(d / "odom.csv"), det(d / "det.csv"), gt(d / "gt.csv");
        odo << "t,x,y,phi\n";
        det << "t,label,range_m,bearing_rad,id\n";
        gt << "t,x,y,phi\n";
        for (int k = 0; k <= 200000; k++)
        {
            const double t = 1.7e9 + 0.1 * k, x = 0.05 * k;
            odo << std::to_string(t) << ',' << x << ",0,0\n";
            gt << std::to_string(t) << ',' << x << ",0,0\n";
            if (k % 10 == 0)
            {
                det << std::to_string(t) << ",buoy,5,0.1,1\n";
            }
        }
        std::ofstream(d / "lm.csv") << "id,label,x,y\n1,buoy,5,0.5\n";
    }
    std::mt19937 rng(3);
    stress({kBin + "/semloc-import", "-o", "run.rawlog", "--odometry", "odom.csv", "--detections",
            "det.csv", "--ground-truth", "gt.csv", "--landmarks", "lm.csv"},
           d, {"run.rawlog", "run_gt.txt", "run_world.yaml"}, rng);
}

TEST(InterruptStress, PlotRunTwoSignalsLeaveNothing)
{
    const fs::path d = freshDir("stress_plot_run");
    simulateDataset(d, 60);
    const Tool loc = start({kBin + "/semloc-localize", kSrc + "/config/localize/semantic.ini",
                            "ds.rawlog", "-o", "run", "--save-particles", "1", "-n", "2000", "-q"},
                           d);
    int status = 0;
    ASSERT_EQ(::waitpid(loc.pid, &status, 0), loc.pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readText(loc.err);
    std::mt19937 rng(4);
    stress({kBin + "/semloc-plot-run", "run", "-o", "figs"}, d, {"figs"}, rng);
}

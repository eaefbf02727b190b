/* semloc tests — Ctrl-C and SIGTERM end a tool promptly wherever its time goes: status 130,
 * nothing written and no temporary left, no child process left running. The tools are run
 * in their own process group, busy in a long step (MRPT's KLD sampling, a likelihood-field
 * cache, gnuplot drawing a large world), and signalled; the exit must come within
 * kLatency_s of the signal. The watchdog of semloc/io/ProcessControl.h is tested in-process
 * (death tests). */
#include <fcntl.h>
#include <gtest/gtest.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/simulator/Simulator.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "TestHelpers.h"
#include "io/InterruptHelpers.h"

namespace fs = std::filesystem;

namespace
{
using namespace semloc::test::interrupt;

/** Runs `argv` in `d` until it has installed its handlers and `settle_s` more, signals it,
 *  and checks: exit 130 within kLatency_s with "<tool>: interrupted; no output written",
 *  and `d` as it was. */
void expectInterrupted(const std::vector<std::string>& argv, const fs::path& d, int sig, bool group,
                       double settle_s)
{
    SCOPED_TRACE(std::string(strsignal(sig)) + (group ? " to the process group" : ""));
    const auto before = listing(d);
    const Tool t = start(argv, d);
    ASSERT_TRUE(waitUntil([&] { return catchesSignals(t.pid) || !alive(t.pid); }, 300));
    std::this_thread::sleep_for(std::chrono::duration<double>(settle_s));
    ASSERT_TRUE(alive(t.pid)) << "the tool ended before the signal: " << readText(t.err);
    double took = 0;
    const auto status = signalAndWait(t, sig, group, &took);
    ASSERT_TRUE(status.has_value()) << "still running " << kLatency_s << " s after the signal";
    EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 130)
        << "wait status " << *status << "; stderr: " << readText(t.err);
    const std::string tool = fs::path(argv[0]).filename().string();
    EXPECT_NE(readText(t.err).find(tool + ": interrupted; no output written"), std::string::npos)
        << readText(t.err);
    EXPECT_EQ(listing(d), before) << "an output or a temporary was left";
    EXPECT_LT(took, kLatency_s);
}
}  // namespace

// ------------------------------------------------------------------ the tools

TEST(Interrupt, LocalizeStopsInsideKLDSampling)
{
    // KLD sampling with a huge maximum and tiny bins draws particles for minutes inside
    // MRPT's prediction step, which has no check: the watchdog ends the process.
    const fs::path d = freshDir("kld");
    writeDataset(d);
    writeConfig(d / "kld.ini", "semantic.ini",
                {{"map_file", kSrc + "/maps/paper_50x50.yaml"},
                 {"particles_count", "1000"},
                 {"resamplingMethod", "0"},
                 {"adaptiveSampleSize", "1"},
                 {"heading_drift_walk_deg_per_min", "0"},  // MRPT's KLD carries no rates
                 {"KLD_binSize_XY", "0.0001"},
                 {"KLD_binSize_PHI_deg", "0.001"},
                 {"KLD_maxSampleSize", "100000000"}});
    const std::vector<std::string> argv = {
        kBin + "/semloc-localize", "kld.ini", "ds.rawlog", "-o", "out", "-q"};
    expectInterrupted(argv, d, SIGINT, false, 0.5);
    expectInterrupted(argv, d, SIGTERM, false, 0.5);
    expectInterrupted(argv, d, SIGINT, true, 0.5);
}

TEST(Interrupt, LocalizeStopsWhileFillingTheLikelihoodFieldCache)
{
    // grid_lf on a 560 x 560 m world with 2 threads: the likelihood-field cache of 31 million
    // cells is filled before the first step (15 s on the reference machine).
    const fs::path d = freshDir("grid_cache");
    writeDataset(d);
    std::string world = readText(kSrc + "/maps/paper_50x50.yaml");
    const std::string bounds = "bounds: {x_min: 0, x_max: 50, y_min: 0, y_max: 50}";
    ASSERT_NE(world.find(bounds), std::string::npos);
    world.replace(world.find(bounds), bounds.size(),
                  "bounds: {x_min: 0, x_max: 560, y_min: 0, y_max: 560}");
    std::ofstream(d / "world.yaml") << world;
    writeConfig(d / "grid.ini", "grid_lf.ini",
                {{"map_file", (d / "world.yaml").string()}, {"particles_count", "1000"}});
    const std::vector<std::string> argv = {
        kBin + "/semloc-localize", "grid.ini", "ds.rawlog", "-o", "out", "-q", "--threads", "2"};
    expectInterrupted(argv, d, SIGINT, false, 0.3);
    expectInterrupted(argv, d, SIGTERM, false, 0.3);
}

TEST(Interrupt, SecondSignalEndsAtOnceAndLeavesNothing)
{
    const fs::path d = freshDir("second");
    writeDataset(d);
    writeConfig(d / "kld.ini", "semantic.ini",
                {{"map_file", kSrc + "/maps/paper_50x50.yaml"},
                 {"resamplingMethod", "0"},
                 {"adaptiveSampleSize", "1"},
                 {"heading_drift_walk_deg_per_min", "0"},  // MRPT's KLD carries no rates
                 {"KLD_binSize_XY", "0.0001"},
                 {"KLD_binSize_PHI_deg", "0.001"},
                 {"KLD_maxSampleSize", "100000000"}});
    const auto before = listing(d);
    // --save-particles: the staging directory holds a file being written.
    const Tool t = start(
        {kBin + "/semloc-localize", "kld.ini", "ds.rawlog", "-o", "out", "--save-particles", "1"},
        d);
    ASSERT_TRUE(waitUntil([&] { return catchesSignals(t.pid) || !alive(t.pid); }, 300));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // inside KLD sampling
    ASSERT_EQ(::kill(t.pid, SIGINT), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    // The handler stays in place: the second signal goes through the same cleanup.
    ASSERT_TRUE(catchesSignals(t.pid) || !alive(t.pid));
    double took = 0;
    const auto status = signalAndWait(t, SIGINT, false, &took);
    ASSERT_TRUE(status.has_value());
    EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 130) << *status;
    EXPECT_NE(readText(t.err).find("semloc-localize: interrupted; no output written"),
              std::string::npos)
        << readText(t.err);
    EXPECT_EQ(listing(d), before) << "a staging directory or an output was left";
    EXPECT_LT(took, semloc::kInterruptGracePeriod_s) << "the second signal waited for the first's";
}

TEST(Interrupt, PlotWorldEndsGnuplotAndLeavesNothing)
{
    // 20000 labelled objects keep gnuplot busy for many seconds.
    const fs::path d = freshDir("plot");
    {
        std::ofstream w(d / "big.yaml");
        w << "name: big\nbounds: {x_min: 0, x_max: 1000, y_min: 0, y_max: 1000}\nobjects:\n";
        for (int i = 0; i < 20000; i++)
        {
            w << "  - {id: " << i + 1 << ", label: pillar, shape: cylinder, center: ["
              << 5 + (i % 140) * 7 << ", " << 5 + (i / 140) * 7 << "], radius: 0.5}\n";
        }
    }
    const auto before = listing(d);
    for (const auto& [sig, group] : std::vector<std::pair<int, bool>>{
             {SIGINT, true}, {SIGINT, false}, {SIGTERM, false}, {SIGTERM, true}})
    {
        SCOPED_TRACE(std::string(strsignal(sig)) + (group ? " to the process group" : ""));
        const Tool t =
            start({kBin + "/semloc-plot-world", "big.yaml", "-o", "big.png", "--keep-script"}, d);
        std::vector<pid_t> gnuplot;
        ASSERT_TRUE(waitUntil(
            [&]
            {
                gnuplot = childrenOf(t.pid, "gnuplot", true);
                return !gnuplot.empty() || !alive(t.pid);
            },
            300));
        ASSERT_EQ(gnuplot.size(), 1u) << readText(t.err);
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        ASSERT_TRUE(alive(gnuplot[0])) << "gnuplot ended before the signal";
        const auto status = signalAndWait(t, sig, group);
        ASSERT_TRUE(status.has_value()) << "still running " << kLatency_s << " s after the signal";
        EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 130)
            << "wait status " << *status << "; stderr: " << readText(t.err);
        EXPECT_NE(readText(t.err).find("semloc-plot-world: interrupted; no output written"),
                  std::string::npos)
            << readText(t.err);
        EXPECT_FALSE(alive(gnuplot[0])) << "gnuplot left running";
        if (alive(gnuplot[0]))
        {
            ::kill(gnuplot[0], SIGKILL);
        }
        EXPECT_EQ(listing(d), before) << "an output or a temporary was left";
    }
}

TEST(Interrupt, BenchmarkNamesTheSignalThatKilledARun)
{
    const fs::path d = freshDir("bench_killed");
    std::ofstream(d / "bench.ini") << "[Benchmark]\nsimulate_ini = " << kSrc
                                   << "/config/simulate/simulate.ini\nvariants = " << kSrc
                                   << "/config/localize/semantic.ini\noutput_dir = out\nruns = 1\n"
                                      "jobs = 1\nparticles = 2000\n";
    const auto before = listing(d);
    const Tool t = start({kBin + "/semloc-benchmark", "bench.ini"}, d);
    std::vector<pid_t> runs;
    ASSERT_TRUE(waitUntil(
        [&]
        {
            runs = childrenOf(t.pid);
            return !runs.empty() || !alive(t.pid);
        },
        300));
    ASSERT_EQ(runs.size(), 1u) << readText(t.err);
    ASSERT_EQ(::kill(runs[0], SIGKILL), 0);
    int status = 0;
    ASSERT_TRUE(
        waitUntil([&] { return ::waitpid(t.pid, &status, WNOHANG) == t.pid; }, kLatency_s * 10));
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
    EXPECT_NE(
        readText(t.err).find("run 1 (seed 1) failed: its process was killed by signal 9 (SIGKILL)"),
        std::string::npos)
        << readText(t.err);
    EXPECT_EQ(listing(d), before);
}

// ------------------------------------------------------------------ the watchdog, in-process

namespace
{
/** A child process that would run for a long time. */
pid_t startSleeper()
{
    pid_t pid = -1;
    const char* argv[] = {"sleep", "1000", nullptr};
    EXPECT_EQ(posix_spawnp(&pid, "sleep", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
    return pid;
}
}  // namespace

TEST(InterruptDeathTest, WatchdogRemovesTheRegisteredPathsAndEndsTheChildren)
{
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const fs::path d = freshDir("watchdog");
    const fs::path pidFile = d.string() + ".logs/sleeper";
    EXPECT_EXIT(
        {
            semloc::installInterruptHandlers("watchdog-test");
            fs::create_directories(d / "staging/sub");
            std::ofstream(d / "staging/sub/file") << "x";
            std::ofstream(d / "file.tmp") << "x";
            std::ofstream(d / "kept") << "x";
            semloc::registerTemporaryPath((d / "staging").string());
            semloc::registerTemporaryPath((d / "file.tmp").string());
            semloc::registerTemporaryPath((d / "never-created").string());
            const pid_t sleeper = startSleeper();
            semloc::registerChildProcess(sleeper);
            std::ofstream(pidFile) << sleeper;
            std::raise(SIGINT);
            for (;;)
            {
                std::this_thread::sleep_for(std::chrono::seconds(1));  // a step without checks
            }
        },
        ::testing::ExitedWithCode(130), "watchdog-test: interrupted; no output written");
    EXPECT_EQ(listing(d), std::set<std::string>({"kept"}));
    const pid_t sleeper = std::stoi(readText(pidFile));
    EXPECT_FALSE(alive(sleeper));
}

TEST(InterruptDeathTest, ASignalAfterTheRunCompletedEndsItWithZero)
{
    // The tool's job returned with its outputs in place; two signals while the process exits
    // (a leak checker may take a while there): it ends with 0, not as an interrupted run.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            semloc::installInterruptHandlers("watchdog-test");
            semloc::markRunComplete();
            std::raise(SIGINT);
            std::raise(SIGINT);
            for (;;)
            {
                std::this_thread::sleep_for(std::chrono::seconds(1));  // exit's slow part
            }
        },
        ::testing::ExitedWithCode(0), "^$");
}

TEST(InterruptDeathTest, WatchdogWaitsForADeferralAndStandsDownWhenTheJobClears)
{
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const fs::path d = freshDir("deferral");
    EXPECT_EXIT(
        {
            semloc::installInterruptHandlers("watchdog-test");
            // A job that handles the request and clears it: the watchdog does nothing.
            std::raise(SIGINT);
            semloc::clearInterrupt();
            std::this_thread::sleep_for(std::chrono::milliseconds(1500));
            std::ofstream(d / "survived") << "x";
            // A sequence that must not be cut: the watchdog ends the process after it only.
            semloc::installInterruptHandlers("watchdog-test");
            std::raise(SIGTERM);
            {
                const semloc::InterruptExitDeferral defer;
                std::this_thread::sleep_for(std::chrono::milliseconds(1500));
                std::ofstream(d / "completed") << "x";
            }
            for (;;)
            {
                std::this_thread::sleep_for(std::chrono::seconds(1));
            }
        },
        ::testing::ExitedWithCode(130), "watchdog-test: interrupted; no output written");
    EXPECT_EQ(listing(d), std::set<std::string>({"completed", "survived"}));
}

TEST(InterruptDeathTest, AForkRightAfterTheHandlersCopiesNoLockOfTheWatchdog)
{
    // semloc-benchmark forks its runs without exec. A fork while the watchdog thread was still
    // starting (a thread's start allocates) copied the allocator's lock it held into the child,
    // which then waited forever on its first allocation (AddressSanitizer's allocator has no
    // fork handler; without the handshake in installInterruptHandlers, 3 of 200 such children
    // hung under ASan, forked 0.46-0.84 ms after it returned). Fresh processes that fork 0 to
    // 1 ms after the handlers are installed: every child allocates in every size class and
    // exits.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    for (int i = 0; i < 50; i++)
    {
        EXPECT_EXIT(
            {
                semloc::installInterruptHandlers("fork-test");
                const auto until =
                    std::chrono::steady_clock::now() + std::chrono::microseconds(20 * i);
                while (std::chrono::steady_clock::now() < until)
                {
                }
                const pid_t pid = ::fork();
                if (pid == 0)
                {
                    std::vector<std::string> v;
                    for (int k = 0; k < 4000; k++)
                    {
                        v.emplace_back(static_cast<size_t>(k % 1000), 'x');
                    }
                    ::_exit(v.size() == 4000 ? 0 : 1);
                }
                int status = 0;
                if (!waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, 10))
                {
                    ::kill(pid, SIGKILL);
                    std::fprintf(stderr, "the forked child hung\n");
                    std::_Exit(3);
                }
                std::_Exit(WIFEXITED(status) ? WEXITSTATUS(status) : 4);
            },
            ::testing::ExitedWithCode(0), "")
            << "process " << i;
    }
}

TEST(Interrupt, WaitStatusNamesTheSignal)
{
    EXPECT_EQ(semloc::waitStatusText(9), "was killed by signal 9 (SIGKILL)");
    EXPECT_EQ(semloc::waitStatusText(2 << 8), "exited with status 2");
}

TEST(Interrupt, ChildProcessEndsAtARequest)
{
    // A request while the child runs: it is ended and waited for, and Interrupted thrown.
    const fs::path d = freshDir("child");
    std::thread stop(
        []
        {
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            semloc::requestInterrupt();
        });
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_THROW(semloc::runChildProcess({"sleep", "1000"}, (d / "log").string()),
                 semloc::Interrupted);
    stop.join();
    semloc::clearInterrupt();
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              kLatency_s);
    // The status of a normal run; a program that does not exist is an error naming it.
    EXPECT_EQ(semloc::runChildProcess({"sh", "-c", "echo hi; exit 3"}, (d / "log").string()),
              3 << 8);
    EXPECT_EQ(readText(d / "log"), "hi\n");
    try
    {
        semloc::runChildProcess({"semloc-no-such-program"}, (d / "log").string());
        ADD_FAILURE() << "no exception";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("cannot run 'semloc-no-such-program'"),
                  std::string::npos)
            << e.what();
    }
}

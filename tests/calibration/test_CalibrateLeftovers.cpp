/* semloc tests — what a killed job leaves behind: semloc-calibrate's consistency stage works in
 * a temporary directory (`$TMPDIR/semloc-calibrate-XXXXXX`) that a kill -9 leaves; the next
 * run removes those that no live process holds (each job holds a lock in its own while it
 * lives: detail::TemporaryDirectory), and keeps the others. */
#include <fcntl.h>
#include <gtest/gtest.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/simulator/Simulator.h>
#include <signal.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "TestHelpers.h"
#include "io/TemporaryDirectory.h"

extern char** environ;

namespace fs = std::filesystem;
using semloc::detail::kTemporaryLockFile;

namespace
{
const std::string kSrc = SEMLOC_SOURCE_DIR;
const std::string kPrefix = "semloc-calibrate-";

/** A directory `dir`/`name` holding a lock file (`lockFile`, empty: none) and a file. */
fs::path leftover(const fs::path& dir, const std::string& name, const std::string& lockFile)
{
    fs::path p = dir / name;
    fs::create_directories(p / "run");
    std::ofstream(p / "run" / "steps.csv") << "step\n";
    if (!lockFile.empty())
    {
        std::ofstream(p / lockFile) << "";
    }
    return p;
}

/** The lock of `dir`'s lock file, held by this process while the object lives (as a live
 *  job holds its own). */
class HeldLock
{
public:
    explicit HeldLock(const fs::path& dir)
        : m_fd(::open((dir / kTemporaryLockFile).c_str(), O_RDONLY | O_CLOEXEC))
    {
        EXPECT_GE(m_fd, 0);
        EXPECT_EQ(::flock(m_fd, LOCK_EX | LOCK_NB), 0);
    }
    ~HeldLock() { ::close(m_fd); }
    HeldLock(const HeldLock&) = delete;
    HeldLock& operator=(const HeldLock&) = delete;

private:
    int m_fd;
};

/** True when some process holds the lock of `dir`'s lock file. */
bool lockHeld(const fs::path& dir)
{
    const int fd = ::open((dir / kTemporaryLockFile).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
        return false;
    }
    const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
    ::close(fd);
    return held;
}

/** The entries of `dir` whose name starts with `prefix`. */
std::vector<std::string> withPrefix(const fs::path& dir, const std::string& prefix)
{
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
    {
        if (e.path().filename().string().rfind(prefix, 0) == 0)
        {
            out.push_back(e.path().string());
        }
    }
    return out;
}

/** A simulated run of the paper's world in `dir` (data.rawlog and its ground truth) and a
 *  base ini with 1000 particles (base.ini): a consistency stage of a few seconds. */
void writeDataset(const fs::path& dir, int steps)
{
    semloc::TSimulatorOptions o;
    o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
    o.simulation.seed = 5;
    o.simulation.max_steps = steps;
    const semloc::Simulator sim(o);
    sim.writeDataset(sim.run(), (dir / "data.rawlog").string());
    std::ofstream(dir / "base.ini")
        << semloc::test::withKeys(semloc::test::resolvedIni(kSrc + "/config/localize/semantic.ini"),
                                  "semantic.ini", {{"particles_count", "1000"}});
}

/** semloc-calibrate on the dataset of `dir`, with TMPDIR=`tmp` and `seeds` consistency
 *  seeds, started (not waited for); its process id. */
pid_t startCalibrate(const fs::path& dir, const fs::path& tmp, int seeds)
{
    const std::string rawlog = (dir / "data.rawlog").string();
    std::vector<std::string> args = {std::string(SEMLOC_BIN_DIR) + "/semloc-calibrate",
                                     rawlog,
                                     "--world",
                                     kSrc + "/maps/paper_50x50.yaml",
                                     "--ground-truth",
                                     semloc::GroundTruthFile::PathFor(rawlog),
                                     "--base",
                                     (dir / "base.ini").string(),
                                     "-o",
                                     (dir / "out.ini").string(),
                                     "--consistency-seeds",
                                     std::to_string(seeds)};
    std::vector<std::string> env = {"TMPDIR=" + tmp.string()};
    for (char** e = environ; *e != nullptr; e++)
    {
        if (std::string(*e).rfind("TMPDIR=", 0) != 0)
        {
            env.emplace_back(*e);
        }
    }
    std::vector<char*> argv, envp;
    for (auto& a : args)
    {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    for (auto& e : env)
    {
        envp.push_back(e.data());
    }
    envp.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, (dir / "calibrate.log").c_str(),
                                     O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = -1;
    EXPECT_EQ(posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data()), 0);
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

/** The exit status of `pid` once it ends (-1: ended by a signal). */
int waitFor(pid_t pid)
{
    int status = 0;
    EXPECT_EQ(::waitpid(pid, &status, 0), pid);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST(CalibrateLeftovers, StaleDirectoriesAreRemovedHeldOnesKept)
{
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "calibrate_leftovers_sweep";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path stale = leftover(dir, "job-stale", kTemporaryLockFile);
    const fs::path live = leftover(dir, "job-live", kTemporaryLockFile);
    const fs::path fresh = leftover(dir, "job-fresh", "");
    const fs::path old = leftover(dir, "job-old", "");
    fs::last_write_time(old, fs::file_time_type::clock::now() - std::chrono::minutes(20));
    // A lock being taken (its file not yet under its name): the directory is not stale.
    const fs::path taking = leftover(dir, "job-taking", std::string(kTemporaryLockFile) + ".new");
    const fs::path other = leftover(dir, "other-stale", kTemporaryLockFile);
    const fs::path target = leftover(dir, "elsewhere", kTemporaryLockFile);
    fs::create_directory_symlink(target, dir / "job-link");
    {
        const HeldLock holding(live);
        const semloc::detail::TemporaryDirectory tmp(dir, "job-");
        // What it removed and kept.
        EXPECT_FALSE(fs::exists(stale)) << "a directory whose lock nobody holds";
        EXPECT_FALSE(fs::exists(old)) << "a directory without a lock, unchanged for 20 min";
        EXPECT_TRUE(fs::exists(live / "run" / "steps.csv")) << "held by a live process";
        EXPECT_TRUE(fs::exists(fresh / "run" / "steps.csv")) << "without a lock, but new";
        EXPECT_TRUE(fs::exists(taking / "run" / "steps.csv"));
        EXPECT_TRUE(fs::exists(other / "run" / "steps.csv")) << "another prefix";
        EXPECT_TRUE(fs::is_symlink(dir / "job-link"));
        EXPECT_TRUE(fs::exists(target / "run" / "steps.csv")) << "a link is not followed";
        // Its own directory is held while it lives, and removed with it.
        const fs::path own = fs::path(tmp.path("x")).parent_path();
        EXPECT_TRUE(lockHeld(own));
        EXPECT_EQ(semloc::detail::removeStaleTemporaryDirectories(dir, "job-"), 0u);
        EXPECT_TRUE(fs::exists(own));
        ASSERT_EQ(withPrefix(dir, "job-").size(), 5u);  // live, fresh, taking, link, own
    }
    EXPECT_EQ(withPrefix(dir, "job-").size(), 4u) << "its own directory was not removed";
    // Once its owner is gone, a held directory is stale.
    EXPECT_EQ(semloc::detail::removeStaleTemporaryDirectories(dir, "job-"), 1u);
    EXPECT_FALSE(fs::exists(live));
    if (!HasFailure())
    {
        fs::remove_all(dir);
    }
}

TEST(CalibrateLeftovers, AKilledRunsTemporaryDirectoryIsRemovedByTheNextRun)
{
    const fs::path dir = fs::path(SEMLOC_TEST_OUT) / "calibrate_leftovers_kill";
    const fs::path tmp = dir / "tmp";
    fs::remove_all(dir);
    fs::create_directories(tmp);
    writeDataset(dir, 400);
    // kill -9 in the consistency stage, once its first setting is written (after the lock).
    const pid_t pid = startCalibrate(dir, tmp, 3);
    ASSERT_GT(pid, 0);
    fs::path killed;
    for (int status = 0; killed.empty();)
    {
        for (const auto& p : withPrefix(tmp, kPrefix))
        {
            killed = fs::exists(fs::path(p) / "trial.ini") ? fs::path(p) : killed;
        }
        if (killed.empty() && ::waitpid(pid, &status, WNOHANG) == pid)
        {
            FAIL() << "semloc-calibrate ended before its consistency stage was seen:\n"
                   << semloc::test::readText(dir / "calibrate.log");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    EXPECT_EQ(waitFor(pid), -1);
    ASSERT_TRUE(fs::exists(killed)) << "nothing handles a kill -9: the directory stays";
    EXPECT_FALSE(fs::exists(dir / "out.ini"));
    // Another job's, alive.
    const fs::path live = leftover(tmp, kPrefix + "live", kTemporaryLockFile);
    const HeldLock holding(live);

    // The next run removes the killed run's directory, not the live one, nor leaves its own.
    const pid_t next = startCalibrate(dir, tmp, 1);
    ASSERT_EQ(waitFor(next), 0) << semloc::test::readText(dir / "calibrate.log");
    EXPECT_TRUE(fs::exists(dir / "out.ini"));
    EXPECT_FALSE(fs::exists(killed)) << killed;
    EXPECT_TRUE(fs::exists(live / "run" / "steps.csv"));
    EXPECT_EQ(withPrefix(tmp, kPrefix), std::vector<std::string>{live.string()});
    if (!HasFailure())
    {
        fs::remove_all(dir);
    }
}

/* semloc tests — running a tool in its own process group, signalling it and checking what it
 * left: the helpers of the interrupt tests. */
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <semloc/simulator/Simulator.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
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

extern char** environ;

namespace semloc::test::interrupt
{
namespace fs = std::filesystem;

const std::string kSrc = SEMLOC_SOURCE_DIR;
inline const std::string kBin = SEMLOC_BIN_DIR;
/** The bound on the time from the signal to the exit (generous: the watchdog's grace period
 *  is 1 s). */
constexpr double kLatency_s = 5.0;

using semloc::test::readText;

/** A fresh directory for one case, and a sibling for the tool's stdout/stderr. */
inline fs::path freshDir(const std::string& name)
{
    fs::path d = fs::path(SEMLOC_TEST_OUT) / "interrupt" / name;
    fs::remove_all(d);
    fs::create_directories(d);
    fs::remove_all(d.string() + ".logs");
    fs::create_directories(d.string() + ".logs");
    return d;
}

/** Every name under `d` (hidden ones included), relative. */
inline std::set<std::string> listing(const fs::path& d)
{
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(d))
    {
        names.insert(fs::relative(e.path(), d).string());
    }
    return names;
}

/** A tool started in its own process group (pgid = pid), in `cwd`, with its output in
 *  `<cwd>.logs/`. */
struct Tool
{
    pid_t pid = -1;
    fs::path out, err;
};

inline Tool start(const std::vector<std::string>& argv, const fs::path& cwd)
{
    Tool t;
    t.out = cwd.string() + ".logs/stdout";
    t.err = cwd.string() + ".logs/stderr";
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (const auto& a : argv)
    {
        args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawnattr_t at;
    posix_spawn_file_actions_init(&fa);
    posix_spawnattr_init(&at);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, t.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, t.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
    posix_spawnattr_setpgroup(&at, 0);
    posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP);
    const int rc = posix_spawn(&t.pid, args[0], &fa, &at, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&at);
    EXPECT_EQ(rc, 0) << argv[0];
    return t;
}

/** Waits at most `limit_s` for `pred`; false on time-out. */
inline bool waitUntil(const std::function<bool()>& pred, double limit_s)
{
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
    while (!pred())
    {
        if (std::chrono::steady_clock::now() > end)
        {
            return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
}

/** `pid`'s /proc/<pid>/status field `key` ("" if none). */
inline std::string procStatus(pid_t pid, const std::string& key)
{
    std::ifstream f("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(f, line);)
    {
        if (line.rfind(key + ":", 0) == 0)
        {
            return line.substr(key.size() + 1);
        }
    }
    return "";
}

/** True once the process catches SIGINT and SIGTERM: the tool has installed its handlers
 *  (semloc::installInterruptHandlers), i.e. it has started its job. */
inline bool catchesSignals(pid_t pid)
{
    const std::string mask = procStatus(pid, "SigCgt");
    if (mask.empty())
    {
        return false;
    }
    const unsigned long long bits = std::stoull(mask, nullptr, 16);
    return (bits & (1ull << (SIGINT - 1))) && (bits & (1ull << (SIGTERM - 1)));
}

/** True while `pid` exists and is not a zombie. */
inline bool alive(pid_t pid)
{
    std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(f, stat);
    const auto close = stat.rfind(')');
    return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] != 'Z';
}

/** The live children of `parent` (and their descendants when `deep`) whose command name is
 *  `comm` (any when empty). */
inline std::vector<pid_t> childrenOf(pid_t parent, const std::string& comm = {}, bool deep = false)
{
    std::vector<pid_t> kids;
    for (const auto& e : fs::directory_iterator("/proc"))
    {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos)
        {
            continue;
        }
        const pid_t pid = std::stoi(name);
        const std::string ppid = procStatus(pid, "PPid");
        if (ppid.empty() || std::stoi(ppid) != parent || !alive(pid))
        {
            continue;
        }
        std::string c = procStatus(pid, "Name");
        c.erase(0, c.find_first_not_of(" \t"));
        if (comm.empty() || c == comm)
        {
            kids.push_back(pid);
        }
        if (deep)
        {
            const auto more = childrenOf(pid, comm, true);
            kids.insert(kids.end(), more.begin(), more.end());
        }
    }
    return kids;
}

/** Sends `sig` to the tool (its process group when `group`) and waits for its exit:
 *  the wait status, or nothing if it is still running kLatency_s later (then killed). */
inline std::optional<int> signalAndWait(const Tool& t, int sig, bool group, double* took = nullptr)
{
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(group ? ::kill(-t.pid, sig) : ::kill(t.pid, sig), 0);
    int status = 0;
    const bool ended =
        waitUntil([&] { return ::waitpid(t.pid, &status, WNOHANG) == t.pid; }, kLatency_s);
    if (took)
    {
        *took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    if (!ended)
    {
        ::kill(-t.pid, SIGKILL);
        ::waitpid(t.pid, &status, 0);
        return std::nullopt;
    }
    return status;
}

/** A short simulated dataset of the paper's world, in `d`. */
inline void writeDataset(const fs::path& d)
{
    auto o = semloc::TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate.ini");
    o.simulation.world_file = kSrc + "/maps/paper_50x50.yaml";
    o.simulation.max_steps = 6;
    semloc::Simulator sim(o);
    sim.writeDataset(sim.run(), (d / "ds.rawlog").string());
}

/** `config/localize/<name>` with each `key = value` of `set` replacing the line of that key. */
inline void writeConfig(const fs::path& to, const std::string& name,
                        const std::vector<std::pair<std::string, std::string>>& set)
{
    std::istringstream in(resolvedIni(kSrc + "/config/localize/" + name));
    std::ofstream out(to);
    for (std::string line; std::getline(in, line);)
    {
        for (const auto& [k, v] : set)
        {
            const auto eq = line.find('=');
            if (eq != std::string::npos && line.rfind(k, 0) == 0 &&
                line.find_first_not_of(' ', k.size()) == eq)
            {
                line = k;
                line += " = ";
                line += v;
            }
        }
        out << line << "\n";
    }
}

}  // namespace semloc::test::interrupt

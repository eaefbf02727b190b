/* semloc tests — a tool run as a child process, its exit status and peak memory measured. */
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

extern char** environ;

namespace semloc::test
{
/** Runs `args` (args[0] a path), stdout and stderr to `log`; returns the exit status (-1: did
 *  not exit normally) and sets `maxRss_MiB` to its peak resident set (wait4's ru_maxrss). */
inline int runMeasured(std::vector<std::string> args, const std::filesystem::path& log,
                       double& maxRss_MiB)
{
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& s : args)
    {
        argv.push_back(s.data());
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0)
    {
        return -1;
    }
    int status = 0;
    rusage ru{};
    if (wait4(pid, &status, 0, &ru) != pid)
    {
        return -1;
    }
    maxRss_MiB = static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace semloc::test

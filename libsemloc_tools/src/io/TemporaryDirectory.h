/* semloc — a temporary directory of a job, removed with it (also by the interrupt watchdog,
 * and by a later job when the process was killed). */
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace semloc::detail
{
/** The file of a TemporaryDirectory whose lock (flock) its owner holds while it lives. */
constexpr const char* kTemporaryLockFile = ".semloc-lock";

/** A new directory `<dir>/<prefix>XXXXXX`, registered for the interrupt watchdog, locked while
 *  the object lives (kTemporaryLockFile inside it) and removed with everything in it at the
 *  end of the scope. The constructor first removes the directories `<dir>/<prefix>*` that no
 *  running process holds (left by a process that was killed, kill -9, which no handler
 *  sees): removeStaleTemporaryDirectories. */
class TemporaryDirectory
{
public:
    TemporaryDirectory(const std::filesystem::path& dir, const std::string& prefix);
    ~TemporaryDirectory();
    TemporaryDirectory(const TemporaryDirectory&) = delete;
    TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
    /** `file` inside the directory. */
    std::string path(const std::string& file) const
    {
        return (std::filesystem::path(m_path) / file).string();
    }

private:
    std::string m_path;
    int m_lockFd = -1;
};

/** Removes the directories `<dir>/<prefix>*` that no running process holds: nobody holds the
 *  lock of their kTemporaryLockFile, or they have none (a process killed before it made it,
 *  an older semloc) and were last changed more than ten minutes ago. Symbolic links are left,
 *  and so is what cannot be removed (another user's); the number removed. */
size_t removeStaleTemporaryDirectories(const std::filesystem::path& dir, const std::string& prefix);
}  // namespace semloc::detail

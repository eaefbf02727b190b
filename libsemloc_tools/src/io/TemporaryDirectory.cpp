/* semloc — TemporaryDirectory: a job's scratch directory, locked while the job lives. */
#include "io/TemporaryDirectory.h"

#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <semloc/io/ProcessControl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace semloc::detail
{
namespace fs = std::filesystem;

namespace
{
/** How long a directory without its lock file must have been left unchanged to be taken for
 *  a stale one (its owner makes the file right after the directory). */
constexpr auto kLocklessAge = std::chrono::minutes(10);

/** True when no running process holds the directory `dir` (removeStaleTemporaryDirectories). */
bool isStale(const fs::path& dir)
{
    const int fd = ::open((dir / kTemporaryLockFile).c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0)
    {
        if (errno != ENOENT)
        {
            return false;  // not ours to judge (another user's)
        }
        std::error_code ec;
        const auto written = fs::last_write_time(dir, ec);
        return !ec && fs::file_time_type::clock::now() - written > kLocklessAge;
    }
    const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
    ::close(fd);
    return free;
}
}  // namespace

size_t removeStaleTemporaryDirectories(const fs::path& dir, const std::string& prefix)
{
    size_t removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    {
        const std::string name = it->path().filename().string();
        std::error_code st;
        if (name.rfind(prefix, 0) == 0 && !it->is_symlink(st) && it->is_directory(st) &&
            isStale(it->path()))
        {
            std::error_code rm;
            fs::remove_all(it->path(), rm);
            removed += rm ? 0 : 1;
        }
    }
    return removed;
}

TemporaryDirectory::TemporaryDirectory(const fs::path& dir, const std::string& prefix)
{
    removeStaleTemporaryDirectories(dir, prefix);  // left by a job that was killed
    std::string name = (dir / (prefix + "XXXXXX")).string();
    {
        const InterruptExitDeferral defer;  // created and registered as one step
        if (!::mkdtemp(name.data()))
        {
            THROW_EXCEPTION("cannot create a temporary directory in '" + dir.string() +
                            "': " + std::strerror(errno));
        }
        m_path = name;
        registerTemporaryPath(m_path);
    }
    // The lock is taken on the file under another name, which is then renamed: a later job
    // never finds the lock file unlocked while this one lives.
    const std::string taking = path(std::string(kTemporaryLockFile) + ".new");
    m_lockFd = ::open(taking.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (m_lockFd < 0 || ::flock(m_lockFd, LOCK_EX | LOCK_NB) != 0 ||
        ::rename(taking.c_str(), path(kTemporaryLockFile).c_str()) != 0)
    {
        const int err = errno;
        if (m_lockFd >= 0)
        {
            ::close(m_lockFd);
        }
        std::error_code ec;
        fs::remove_all(m_path, ec);
        unregisterTemporaryPath(m_path);
        THROW_EXCEPTION("cannot lock the temporary directory '" + m_path +
                        "': " + std::strerror(err));
    }
}

TemporaryDirectory::~TemporaryDirectory()
{
    std::error_code ec;
    fs::remove_all(m_path, ec);
    ::close(m_lockFd);
    unregisterTemporaryPath(m_path);
}
}  // namespace semloc::detail

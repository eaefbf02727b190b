/* semloc — lockOutput(): one writer per output, the second one refused at once. */
#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/OutputPaths.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

namespace semloc
{
namespace fs = std::filesystem;

namespace
{
/** The locks this process holds: lock file -> descriptor; `owner` is the process that took
 *  them (a child forked by semloc-benchmark inherits the descriptors, never the removal). */
struct THeldLocks
{
    std::mutex mutex;
    std::map<std::string, int> fds;
    pid_t owner = 0;
};

THeldLocks& held()
{
    static auto* locks = new THeldLocks;  // never destroyed: used by the exit handler
    return *locks;
}

/** At exit, the lock files of the process that took them are removed while still locked (a
 *  process waiting on one sees it gone and takes a new one). */
void removeHeldLockFiles()
{
    auto& h = held();
    const std::lock_guard<std::mutex> guard(h.mutex);
    if (h.owner != ::getpid())
    {
        return;
    }
    for (const auto& [path, fd] : h.fds)
    {
        ::unlink(path.c_str());
        ::close(fd);
    }
    h.fds.clear();
}

/** FNV-1a, 64 bits: the lock file's name from the output's path. */
uint64_t fnv1a(const std::string& s)
{
    uint64_t h = 1469598103934665603ull;
    for (const unsigned char c : s)
    {
        h = (h ^ c) * 1099511628211ull;
    }
    return h;
}

/** The directory of the lock files, made private to the user (0700) on first use. */
fs::path lockDirectory()
{
    std::error_code ec;
    fs::path tmp = fs::temp_directory_path(ec);
    if (ec)
    {
        tmp = "/tmp";
    }
    fs::path dir = tmp / mrpt::format("semloc-locks-%u", static_cast<unsigned>(::getuid()));
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
    {
        THROW_EXCEPTION("cannot create the directory of output locks '" + dir.string() +
                        "': " + std::strerror(errno));
    }
    struct stat st = {};
    if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::getuid())
    {
        THROW_EXCEPTION("the directory of output locks '" + dir.string() +
                        "' is not a directory of this user's: remove it");
    }
    return dir;
}

/** The process id written in a held lock file, or 0. */
long holderOf(int fd)
{
    char text[32] = {};
    const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
    return n > 0 ? std::strtol(text, nullptr, 10) : 0;
}

/** True when `fd` is still the file at `path` (not removed or replaced by its last holder). */
bool stillAt(int fd, const std::string& path)
{
    struct stat a = {}, b = {};
    return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev &&
           a.st_ino == b.st_ino;
}
}  // namespace

void lockOutput(const std::string& output)
{
    const std::string target = resolvedOutputPath(output);
    const fs::path dir = lockDirectory();
    const std::string lock =
        (dir / mrpt::format("%016llx.lock", static_cast<unsigned long long>(fnv1a(target))))
            .string();
    auto& h = held();
    const std::lock_guard<std::mutex> guard(h.mutex);
    if (h.owner != ::getpid())
    {
        h.fds.clear();  // a forked child: its parent holds these
        h.owner = ::getpid();
        static const bool registered = std::atexit(removeHeldLockFiles) == 0;
        (void)registered;
    }
    if (h.fds.count(lock) != 0)
    {
        return;  // this process holds it already
    }
    for (;;)
    {
        const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
        if (fd < 0)
        {
            THROW_EXCEPTION(mrpt::format("cannot lock the output '%s' ('%s'): %s", output.c_str(),
                                         lock.c_str(), std::strerror(errno)));
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
        {
            const long pid = holderOf(fd);
            ::close(fd);
            THROW_EXCEPTION(mrpt::format(
                "output '%s' is in use by process %ld (another semloc tool writing it): wait "
                "for it to end or choose another output",
                output.c_str(), pid));
        }
        if (!stillAt(fd, lock))
        {
            ::close(fd);  // its holder removed it as we opened it: take a new one
            continue;
        }
        const std::string text = std::to_string(::getpid()) + "\n" + target + "\n";
        if (::ftruncate(fd, 0) != 0 ||
            ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
        {
            ::close(fd);
            THROW_EXCEPTION(mrpt::format("cannot lock the output '%s' ('%s'): %s", output.c_str(),
                                         lock.c_str(), std::strerror(errno)));
        }
        h.fds[lock] = fd;
        return;
    }
}

}  // namespace semloc

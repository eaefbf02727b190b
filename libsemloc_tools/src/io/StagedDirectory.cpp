/* semloc — StagedDirectory: write beside, rename at the end. */
#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/io/StagedDirectory.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <vector>

namespace semloc
{
namespace fs = std::filesystem;

namespace
{
/** mkdtemp() on `<dir>/<prefix>XXXXXX`, with the permissions the umask gives a new
 *  directory (mkdtemp's are 0700). */
std::string makeUniqueDir(const fs::path& dir, const std::string& prefix)
{
    std::string tmpl = (dir / (prefix + "XXXXXX")).string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data()) ||
        ::chmod(buf.data(), static_cast<mode_t>(directoryModeFromUmask())) != 0)
    {
        THROW_EXCEPTION("cannot create a directory in '" + dir.string() +
                        "': " + std::strerror(errno));
    }
    return std::string(buf.data());
}

/** How old a staging directory without its marker must be to be taken for a stale one (its
 *  owner creates the marker right after the directory). */
constexpr auto kMarkerlessStagingAge = std::chrono::minutes(10);

/** True when no running process owns the staging directory `dir`: nobody holds the lock on
 *  its marker (a run holds it from the marker's creation to its end), or it has no marker and
 *  is older than kMarkerlessStagingAge. */
bool isStale(const fs::path& dir)
{
    const int fd = ::open((dir / kOutputMarker).c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0)
    {
        std::error_code ec;
        const auto written = fs::last_write_time(dir, ec);
        return !ec && fs::file_time_type::clock::now() - written > kMarkerlessStagingAge;
    }
    const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
    ::close(fd);
    return free;
}
}  // namespace

size_t removeStaleStagingDirectories(const std::string& target)
{
    const fs::path t = fs::absolute(fs::path(target)).lexically_normal();
    const std::string prefix = "." + t.filename().string() + ".staging-";
    size_t removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(t.parent_path(), ec), end; !ec && it != end; it.increment(ec))
    {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) == 0 && it->is_directory(ec) && !it->is_symlink(ec) &&
            isStale(it->path()))
        {
            std::error_code rm;
            fs::remove_all(it->path(), rm);
            removed += rm ? 0 : 1;
        }
    }
    return removed;
}

StagedDirectory::StagedDirectory(const std::string& target, const std::vector<std::string>& inputs)
    : m_target(target)
{
    checkOutputDirectory(target, inputs);
    // Through a symbolic link: the output replaces what the link points at, and the link stays.
    const fs::path t = resolvedOutputPath(target);
    std::error_code ec;
    fs::create_directories(t.parent_path(), ec);
    if (ec)
    {
        THROW_EXCEPTION("cannot create '" + t.parent_path().string() + "': " + ec.message());
    }
    m_target = t.string();
    removeStaleStagingDirectories(m_target);  // left by a run that was killed
    {
        const InterruptExitDeferral whole;  // never an unregistered staging directory
        m_staging = makeUniqueDir(t.parent_path(), "." + t.filename().string() + ".staging-");
        registerTemporaryPath(m_staging);  // removed if the process is ended at Ctrl-C
    }
    // The marker's lock, held until the end of the run, tells a later run that this staging
    // directory is not stale.
    m_lockFd = ::open(path(kOutputMarker).c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (m_lockFd < 0 || ::flock(m_lockFd, LOCK_EX | LOCK_NB) != 0)
    {
        fs::remove_all(m_staging, ec);
        unregisterTemporaryPath(m_staging);
        THROW_EXCEPTION("cannot write in '" + t.parent_path().string() +
                        "': " + std::strerror(errno));
    }
}

StagedDirectory::~StagedDirectory()
{
    if (m_lockFd >= 0)
    {
        ::close(m_lockFd);
    }
    if (!m_committed)
    {
        std::error_code ec;
        fs::remove_all(m_staging, ec);
    }
    unregisterTemporaryPath(m_staging);
}

std::string StagedDirectory::path(const std::string& file) const
{
    return (fs::path(m_staging) / file).string();
}

void StagedDirectory::commit()
{
    ASSERTMSG_(!m_committed, "StagedDirectory committed twice");
    // Ctrl-C's watchdog waits: a previous output is never left under its hidden name.
    const InterruptExitDeferral whole;
    // The target may have changed during the run: the rule is checked again.
    checkOutputDirectory(m_target);
    std::error_code ec;
    std::string old;
    if (fs::exists(m_target))
    {
        // Keep the previous output until the new one is in place.
        const fs::path t(m_target);
        old = makeUniqueDir(t.parent_path(), "." + t.filename().string() + ".old-");
        fs::remove(old);
        fs::rename(m_target, old, ec);
        if (ec)
        {
            THROW_EXCEPTION("cannot replace '" + m_target + "': " + ec.message());
        }
    }
    fs::rename(m_staging, m_target, ec);
    if (ec)
    {
        if (!old.empty())
        {
            std::error_code ec2;
            fs::rename(old, m_target, ec2);
        }
        THROW_EXCEPTION("cannot create '" + m_target + "': " + ec.message());
    }
    m_committed = true;
    if (!old.empty())
    {
        fs::remove_all(old, ec);
    }
}

}  // namespace semloc

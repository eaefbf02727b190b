/* semloc — StagedDirectory: write beside, rename at the end. */
#include <mrpt/core/exceptions.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/StagedDirectory.h>
#include <sys/stat.h>

#include <cerrno>
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
}  // namespace

StagedDirectory::StagedDirectory(const std::string& target, const std::vector<std::string>& inputs)
    : m_target(target)
{
    checkOutputDirectory(target, inputs);
    fs::path t = fs::absolute(fs::path(target)).lexically_normal();
    if (!t.has_filename())
    {
        t = t.parent_path();
    }
    std::error_code ec;
    fs::create_directories(t.parent_path(), ec);
    if (ec)
    {
        THROW_EXCEPTION("cannot create '" + t.parent_path().string() + "': " + ec.message());
    }
    m_target = t.string();
    {
        const InterruptExitDeferral whole;  // never an unregistered staging directory
        m_staging = makeUniqueDir(t.parent_path(), "." + t.filename().string() + ".staging-");
        registerTemporaryPath(m_staging);  // removed if the process is ended at Ctrl-C
    }
    std::ofstream marker(path(kOutputMarker));
    if (!marker)
    {
        fs::remove_all(m_staging, ec);
        unregisterTemporaryPath(m_staging);
        THROW_EXCEPTION("cannot write in '" + t.parent_path().string() +
                        "': " + std::strerror(errno));
    }
}

StagedDirectory::~StagedDirectory()
{
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

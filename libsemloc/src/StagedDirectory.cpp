/* semloc — StagedDirectory: write beside, rename at the end. */
#include <mrpt/core/exceptions.h>
#include <semloc/StagedDirectory.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace semloc
{
namespace fs = std::filesystem;

namespace
{
/** mkdtemp() on `<dir>/<prefix>XXXXXX`. */
std::string makeUniqueDir(const fs::path& dir, const std::string& prefix)
{
    std::string tmpl = (dir / (prefix + "XXXXXX")).string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data()))
    {
        THROW_EXCEPTION("cannot create a directory in '" + dir.string() + "'");
    }
    return std::string(buf.data());
}
}  // namespace

StagedDirectory::StagedDirectory(const std::string& target) : m_target(target)
{
    if (target.empty())
    {
        THROW_EXCEPTION("empty output directory name");
    }
    fs::path t = fs::absolute(fs::path(target)).lexically_normal();
    if (!t.has_filename())
    {
        t = t.parent_path();
    }
    if (fs::exists(t) && !fs::is_directory(t))
    {
        THROW_EXCEPTION("output '" + target + "' exists and is not a directory");
    }
    std::error_code ec;
    fs::create_directories(t.parent_path(), ec);
    if (ec)
    {
        THROW_EXCEPTION("cannot create '" + t.parent_path().string() + "': " + ec.message());
    }
    m_target = t.string();
    m_staging = makeUniqueDir(t.parent_path(), "." + t.filename().string() + ".staging-");
}

StagedDirectory::~StagedDirectory()
{
    if (!m_committed)
    {
        std::error_code ec;
        fs::remove_all(m_staging, ec);
    }
}

std::string StagedDirectory::path(const std::string& file) const
{
    return (fs::path(m_staging) / file).string();
}

void StagedDirectory::commit()
{
    ASSERTMSG_(!m_committed, "StagedDirectory committed twice");
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

/* semloc — OutputPaths: refuse any output location that could destroy a user's files. */
#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>

namespace semloc
{
namespace fs = std::filesystem;

const char* const kOutputMarker = ".semloc-output";

namespace
{
/** `p` made absolute, normal, with the symbolic links of its existing part resolved. */
fs::path resolved(const std::string& p)
{
    std::error_code ec;
    fs::path a = fs::absolute(fs::path(p), ec);
    if (ec)
    {
        THROW_EXCEPTION("cannot resolve the path '" + p + "': " + ec.message());
    }
    fs::path c = fs::weakly_canonical(a, ec);
    c = (ec ? a : c).lexically_normal();
    if (!c.has_filename() && c.has_parent_path() && c != c.root_path())
    {
        c = c.parent_path();  // "out/" as "out"
    }
    return c;
}

/** True when `inner` is `outer` or lies below it (both resolved). */
bool within(const fs::path& outer, const fs::path& inner)
{
    auto o = outer.begin(), i = inner.begin();
    for (; o != outer.end(); ++o, ++i)
    {
        if (o->empty())
        {
            continue;  // a trailing separator
        }
        if (i == inner.end() || *o != *i)
        {
            return false;
        }
    }
    return true;
}

bool isEmptyDirectory(const fs::path& d, const std::string& shown)
{
    std::error_code ec;
    const bool empty = fs::directory_iterator(d, ec) == fs::directory_iterator();
    if (ec)
    {
        THROW_EXCEPTION("output directory '" + shown + "': cannot list it: " + ec.message());
    }
    return empty;
}
}  // namespace

void checkOutputDirectory(const std::string& dir, const std::vector<std::string>& inputs)
{
    if (dir.empty())
    {
        THROW_EXCEPTION("empty output directory name");
    }
    const fs::path t = resolved(dir);
    std::error_code ec;
    const auto st = fs::status(t, ec);
    if (fs::exists(st) && !fs::is_directory(st))
    {
        THROW_EXCEPTION("output directory '" + dir + "' exists and is not a directory");
    }
    if (within(t, resolved(fs::current_path().string())))
    {
        THROW_EXCEPTION("output directory '" + dir +
                        "' is or contains the working directory; semloc replaces an output "
                        "directory as a whole: name a new directory");
    }
    for (const auto& in : inputs)
    {
        if (!in.empty() && within(t, resolved(in)))
        {
            THROW_EXCEPTION(
                mrpt::format("output directory '%s' contains the input '%s'; semloc "
                             "replaces an output directory as a whole: name a new "
                             "directory",
                             dir.c_str(), in.c_str()));
        }
    }
    if (fs::is_directory(st) && !fs::exists(t / kOutputMarker, ec) && !isEmptyDirectory(t, dir))
    {
        THROW_EXCEPTION("output directory '" + dir +
                        "' exists and was not written by semloc (it has no " +
                        std::string(kOutputMarker) +
                        " file); semloc replaces an output directory as a whole, and only its "
                        "own: name a new directory or remove this one yourself");
    }
    lockOutput(dir);
}

void checkOutputFile(const std::string& file, const std::vector<std::string>& inputs,
                     const std::function<bool(const std::string&)>& isPreviousOutput)
{
    if (file.empty())
    {
        THROW_EXCEPTION("empty output file name");
    }
    ASSERTMSG_(isPreviousOutput != nullptr, "checkOutputFile: no test of a previous output");
    const fs::path f = resolvedOutputPath(file);
    std::error_code ec;
    const auto st = fs::status(f, ec);
    if (fs::is_directory(st))
    {
        THROW_EXCEPTION("output file '" + file + "' is a directory");
    }
    if (fs::exists(st) && !fs::is_regular_file(st))
    {
        THROW_EXCEPTION("output file '" + file + "' exists and is not a regular file");
    }
    for (const auto& in : inputs)
    {
        if (!in.empty() && (resolved(in) == f || fs::equivalent(f, in, ec)))
        {
            THROW_EXCEPTION(
                mrpt::format("output file '%s' is the input '%s'", file.c_str(), in.c_str()));
        }
    }
    const fs::path parent = f.parent_path();
    if (!fs::is_directory(parent, ec))
    {
        THROW_EXCEPTION("output file '" + file + "': the directory '" + parent.string() +
                        (fs::exists(parent, ec) ? "' is not a directory" : "' does not exist"));
    }
    if (fs::exists(st) && !isPreviousOutput(f.string()))
    {
        THROW_EXCEPTION("output file '" + file +
                        "' exists and is not a previous output of this kind written by semloc; "
                        "semloc does not replace it: choose another output name or remove it "
                        "yourself");
    }
    lockOutput(file);
}

std::string resolvedOutputPath(const std::string& path)
{
    if (path.empty())
    {
        THROW_EXCEPTION("empty output name");
    }
    std::error_code ec;
    fs::path a = fs::absolute(fs::path(path), ec).lexically_normal();
    if (!a.has_filename() && a.has_parent_path() && a != a.root_path())
    {
        a = a.parent_path();  // "out/" as "out"
    }
    if (fs::is_symlink(fs::symlink_status(a, ec)))
    {
        const fs::path target = fs::canonical(a, ec);
        if (ec)
        {
            THROW_EXCEPTION("output '" + path + "' is a symbolic link to '" +
                            fs::read_symlink(a, ec).string() +
                            "', which does not exist: semloc writes through a link, not over it");
        }
        return target.string();
    }
    const fs::path parent = fs::weakly_canonical(a.parent_path(), ec);
    return ec ? a.string() : (parent / a.filename()).string();
}

namespace
{
/** A temporary file beside `target` (`.<name>.tmp-XXXXXX`, mode 0666 under the umask),
 *  created empty, registered for the interrupt watchdog and locked (flock) until it is closed:
 *  a later run takes an unlocked one for a killed run's leftover. */
class LockedTemporary
{
public:
    explicit LockedTemporary(const fs::path& target)
    {
        std::string name =
            (target.parent_path() / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
        const InterruptExitDeferral defer;  // created and registered as one step
        m_fd = ::mkostemp(name.data(), O_CLOEXEC);
        if (m_fd < 0)
        {
            THROW_EXCEPTION("cannot write in '" + target.parent_path().string() +
                            "': " + std::strerror(errno));
        }
        m_path = name;
        registerTemporaryPath(m_path);
        ::flock(m_fd, LOCK_EX | LOCK_NB);
        ::fchmod(m_fd, static_cast<mode_t>(0666u & directoryModeFromUmask()));
    }
    ~LockedTemporary()
    {
        if (!m_renamed)
        {
            std::error_code ec;
            fs::remove(m_path, ec);
        }
        unregisterTemporaryPath(m_path);
        ::close(m_fd);
    }
    LockedTemporary(const LockedTemporary&) = delete;
    LockedTemporary& operator=(const LockedTemporary&) = delete;

    const std::string& path() const { return m_path; }
    void renameTo(const fs::path& target)
    {
        if (::rename(m_path.c_str(), target.c_str()) != 0)
        {
            THROW_EXCEPTION("cannot write '" + target.string() + "': " + std::strerror(errno));
        }
        m_renamed = true;
    }

private:
    std::string m_path;
    int m_fd = -1;
    bool m_renamed = false;
};

/** Removes the temporary files `.<name>.tmp-*` beside `target` whose lock no process holds. */
void removeStaleTemporaries(const fs::path& target)
{
    const std::string prefix = "." + target.filename().string() + ".tmp-";
    std::error_code ec;
    for (fs::directory_iterator it(target.parent_path(), ec), end; !ec && it != end;
         it.increment(ec))
    {
        if (it->path().filename().string().rfind(prefix, 0) != 0 || !it->is_regular_file(ec) ||
            it->is_symlink(ec))
        {
            continue;
        }
        const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
        if (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0)
        {
            std::error_code rm;
            fs::remove(it->path(), rm);
        }
        if (fd >= 0)
        {
            ::close(fd);
        }
    }
}
}  // namespace

void writeOutputFiles(const std::vector<std::string>& outputs,
                      const std::function<void(const std::vector<std::string>&)>& write)
{
    std::vector<fs::path> targets;
    std::vector<std::unique_ptr<LockedTemporary>> tmp;
    std::vector<std::string> tmpPaths;
    for (const auto& o : outputs)
    {
        targets.emplace_back(resolvedOutputPath(o));
        removeStaleTemporaries(targets.back());
        tmp.push_back(std::make_unique<LockedTemporary>(targets.back()));
        tmpPaths.push_back(tmp.back()->path());
    }
    write(tmpPaths);
    if (interruptRequested())
    {
        throw Interrupted();  // nothing renamed: the outputs as they were
    }
    const InterruptExitDeferral whole;  // all renamed, or none
    for (size_t i = 0; i < tmp.size(); i++)
    {
        tmp[i]->renameTo(targets[i]);
    }
}

bool fileStartsWith(const std::string& path, const std::string& prefix)
{
    std::ifstream f(path, std::ios::binary);
    std::string head(prefix.size(), '\0');
    f.read(head.data(), static_cast<std::streamsize>(head.size()));
    return f && head == prefix;
}

unsigned directoryModeFromUmask()
{
    // /proc/self/status has the umask without the race of umask(umask(0)).
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
    {
        if (line.rfind("Umask:", 0) == 0)
        {
            return 0777u & ~static_cast<unsigned>(std::stoul(line.substr(6), nullptr, 8));
        }
    }
    const mode_t m = ::umask(0);
    ::umask(m);
    return 0777u & ~static_cast<unsigned>(m);
}

}  // namespace semloc

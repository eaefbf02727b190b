/* semloc — OutputPaths: refuse any output location that could destroy a user's files. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/OutputPaths.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
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
}

void checkOutputFile(const std::string& file, const std::vector<std::string>& inputs,
                     const std::function<bool(const std::string&)>& isPreviousOutput)
{
    if (file.empty())
    {
        THROW_EXCEPTION("empty output file name");
    }
    const fs::path f = resolved(file);
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
    if (fs::exists(st) && isPreviousOutput && !isPreviousOutput(f.string()))
    {
        THROW_EXCEPTION("output file '" + file +
                        "' exists and is not a previous output of this kind; semloc does not "
                        "replace it: choose another output name or remove it yourself");
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

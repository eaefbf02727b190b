/* semloc — checkInputFile() and readInputFile(): every input a regular file within a cap. */
#include <fcntl.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/InputFile.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace semloc
{
namespace
{
constexpr uint64_t kMiB = uint64_t{1} << 20;

/** The kind of a file that is not a regular one, as a message says it. */
const char* notRegular(mode_t mode)
{
    if (S_ISDIR(mode))
    {
        return "is a directory, not a file";
    }
    if (S_ISCHR(mode))
    {
        return "is a character device, not a regular file";
    }
    if (S_ISBLK(mode))
    {
        return "is a block device, not a regular file";
    }
    if (S_ISFIFO(mode))
    {
        return "is a FIFO (a pipe), not a regular file";
    }
    if (S_ISSOCK(mode))
    {
        return "is a socket, not a regular file";
    }
    return S_ISREG(mode) ? nullptr : "is not a regular file";
}

std::string sizeText(uint64_t bytes)
{
    if (bytes >= kMiB && bytes % kMiB == 0)
    {
        return mrpt::format("%llu MiB", static_cast<unsigned long long>(bytes / kMiB));
    }
    return bytes >= kMiB ? mrpt::format("%.1f MiB", static_cast<double>(bytes) / kMiB)
                         : mrpt::format("%llu bytes", static_cast<unsigned long long>(bytes));
}

/** Throws unless `st` is a regular file of at most `cap` bytes. */
uint64_t checkStat(const struct stat& st, const std::string& path, const std::string& what,
                   uint64_t cap)
{
    const std::string name = what + " '" + path + "' ";
    if (const char* why = notRegular(st.st_mode))
    {
        THROW_EXCEPTION(name + why);
    }
    const auto size = static_cast<uint64_t>(st.st_size);
    if (size > cap)
    {
        THROW_EXCEPTION(name + "holds " + sizeText(size) + ", more than the " + sizeText(cap) +
                        " a " + what + " may hold");
    }
    return size;
}

[[noreturn]] void throwErrno(int e, const std::string& path, const std::string& what)
{
    const std::string name = what + " '" + path + "'";
    if (e == ENOENT)
    {
        THROW_EXCEPTION(name + " does not exist");
    }
    if (e == ELOOP)
    {
        THROW_EXCEPTION(name + ": a loop of symbolic links");
    }
    THROW_EXCEPTION("cannot read " + name + ": " + std::strerror(e));
}

/** Closes a descriptor when it goes out of scope. */
struct TFd
{
    int fd;
    ~TFd()
    {
        if (fd >= 0)
        {
            ::close(fd);
        }
    }
};
}  // namespace

uint64_t maxInputBytes(InputKind kind)
{
    switch (kind)
    {
        case InputKind::Config:
            return kMiB * 16;
        case InputKind::World:
            return kMiB * 1024;
        case InputKind::Text:
            return kMiB * 16 * 1024;
        case InputKind::Rawlog:
            return kMiB * 1024 * 1024;
    }
    return 0;
}

uint64_t checkInputFile(const std::string& path, const std::string& what, InputKind kind)
{
    struct stat st = {};
    if (::stat(path.c_str(), &st) != 0)
    {
        throwErrno(errno, path, what);
    }
    return checkStat(st, path, what, maxInputBytes(kind));
}

std::string readInputFile(const std::string& path, const std::string& what, InputKind kind)
{
    return readInputFile(path, what, maxInputBytes(kind));
}

std::string readInputFile(const std::string& path, const std::string& what, uint64_t cap)
{
    // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then refuses it.
    const TFd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
    if (f.fd < 0)
    {
        throwErrno(errno, path, what);
    }
    struct stat st = {};
    if (::fstat(f.fd, &st) != 0)
    {
        throwErrno(errno, path, what);
    }
    const uint64_t size = checkStat(st, path, what, cap);
    std::string bytes;
    bytes.reserve(static_cast<size_t>(size));
    char buffer[1 << 16];
    for (;;)
    {
        const ssize_t n = ::read(f.fd, buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR)
        {
            continue;
        }
        if (n < 0)
        {
            throwErrno(errno, path, what);
        }
        if (n == 0)
        {
            return bytes;
        }
        if (bytes.size() + static_cast<size_t>(n) > cap)
        {
            THROW_EXCEPTION(mrpt::format("%s '%s' grew beyond %s while it was read", what.c_str(),
                                         path.c_str(), sizeText(cap).c_str()));
        }
        bytes.append(buffer, static_cast<size_t>(n));
    }
}

}  // namespace semloc

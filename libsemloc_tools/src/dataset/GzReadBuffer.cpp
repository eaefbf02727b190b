/* semloc — GzReadBuffer: a file read plain or gz-compressed through zlib. */
#include "dataset/GzReadBuffer.h"

#include <mrpt/core/exceptions.h>
#include <semloc/io/InputFile.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>

namespace semloc::detail
{
namespace
{
gzFile gz(void* f)
{
    return static_cast<gzFile>(f);
}
}  // namespace

GzReadBuffer::GzReadBuffer(const std::string& path) : m_path(path)
{
    (void)checkInputFile(path, "CSV file", InputKind::Text);
    errno = 0;
    m_file = gzopen(path.c_str(), "rb");
    if (m_file == nullptr)
    {
        THROW_EXCEPTION("cannot read '" + path +
                        "': " + (errno != 0 ? std::strerror(errno) : "out of memory"));
    }
}

GzReadBuffer::~GzReadBuffer()
{
    gzclose(gz(m_file));
}

GzReadBuffer::int_type GzReadBuffer::underflow()
{
    if (gptr() < egptr())
    {
        return traits_type::to_int_type(*gptr());
    }
    const int n = gzread(gz(m_file), m_buf, sizeof(m_buf));
    int err = Z_OK;
    const char* msg = gzerror(gz(m_file), &err);
    // At the end of a truncated stream zlib reports Z_BUF_ERROR ("unexpected end of file").
    if (n < 0 || (err != Z_OK && err != Z_STREAM_END))
    {
        if (err == Z_ERRNO)
        {
            throw Damaged(std::string("read error: ") + std::strerror(errno));
        }
        std::string why = msg != nullptr ? msg : "error";
        if (why.rfind(m_path + ": ", 0) == 0)
        {
            why.erase(0, m_path.size() + 2);  // zlib's message begins with the path
        }
        throw Damaged("the gz-compressed data is damaged or cut short (zlib: " + why + ")");
    }
    if (n == 0)
    {
        return traits_type::eof();
    }
    setg(m_buf, m_buf, m_buf + n);
    return traits_type::to_int_type(*gptr());
}

}  // namespace semloc::detail

/* semloc — writing gz-compressed rawlogs with errors that name the file and the reason. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/RawlogWriter.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <limits>

namespace semloc
{
namespace
{
gzFile gz(void* f)
{
    return static_cast<gzFile>(f);
}
}  // namespace

GzOutputFile::GzOutputFile(const std::string& path, int compressLevel) : m_path(path)
{
    ASSERTMSG_(compressLevel >= 0 && compressLevel <= 9,
               "GzOutputFile: the compression level must be in [0, 9]");
    errno = 0;
    const std::string mode = "wb" + std::to_string(compressLevel);
    m_file = gzopen(path.c_str(), mode.c_str());
    if (m_file == nullptr)
    {
        fail(errno, errno ? nullptr : "out of memory");
    }
}

GzOutputFile::~GzOutputFile()
{
    if (m_file != nullptr)
    {
        gzclose(gz(m_file));
    }
}

void GzOutputFile::fail(int errnum, const char* zlibMessage) const
{
    const std::string why = zlibMessage != nullptr ? zlibMessage
                            : errnum != 0          ? std::strerror(errnum)
                                                   : "write error";
    THROW_EXCEPTION("cannot write '" + m_path + "': " + why);
}

void GzOutputFile::close()
{
    if (m_file == nullptr)
    {
        return;
    }
    errno = 0;
    const int rc = gzclose(gz(m_file));
    m_file = nullptr;
    if (rc != Z_OK)
    {
        const int e = errno;
        fail(e, rc == Z_ERRNO ? nullptr : zError(rc));
    }
}

size_t GzOutputFile::Write(const void* buffer, size_t count)
{
    if (m_file == nullptr)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "': the file is closed");
    }
    const auto* p = static_cast<const char*>(buffer);
    for (size_t left = count; left > 0;)
    {
        const auto n =
            static_cast<unsigned>(std::min<size_t>(left, std::numeric_limits<int>::max() / 2));
        errno = 0;
        if (gzwrite(gz(m_file), p, n) != static_cast<int>(n))
        {
            const int e = errno;
            int zerr = Z_OK;
            const char* msg = gzerror(gz(m_file), &zerr);
            fail(e, zerr == Z_ERRNO ? nullptr : msg);
        }
        p += n;
        left -= n;
    }
    m_written += count;
    return count;
}

size_t GzOutputFile::Read(void*, size_t)
{
    THROW_EXCEPTION("GzOutputFile: cannot read from an output file");
}

uint64_t GzOutputFile::Seek(int64_t, CStream::TSeekOrigin)
{
    THROW_EXCEPTION("GzOutputFile: cannot seek in a compressed output file");
}

uint64_t GzOutputFile::getTotalBytesCount() const
{
    THROW_EXCEPTION("GzOutputFile: the size of a compressed output file is not known");
}

uint64_t GzOutputFile::getPosition() const
{
    return m_written;
}

std::string GzOutputFile::getStreamDescription() const
{
    return "gz file '" + m_path + "'";
}

const char* const kRawlogSignature = "semloc";

void writeRawlogSignature(mrpt::serialization::CArchive& out, const std::string& text)
{
    mrpt::obs::CObservationComment c;
    c.timestamp = INVALID_TIMESTAMP;  // the same bytes for the same dataset
    c.text = std::string(kRawlogSignature) + ": " + text;
    out << c;
}

void saveRawlog(const mrpt::obs::CRawlog& log, const std::string& path, const std::string& tool)
{
    GzOutputFile f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    const std::string comment = log.getCommentText();
    if (comment.rfind(kRawlogSignature, 0) == 0)
    {
        mrpt::obs::CObservationComment c;
        c.text = comment;
        a << c;
    }
    else
    {
        writeRawlogSignature(a, tool + (comment.empty() ? "" : "\n" + comment));
    }
    for (size_t i = 0; i < log.size(); i++)
    {
        a << *log.getAsGeneric(i);
    }
    f.close();
}

}  // namespace semloc

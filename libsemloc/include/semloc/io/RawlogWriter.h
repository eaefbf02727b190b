/* semloc — writing gz-compressed rawlogs with errors that name the file and the reason. */
#pragma once

#include <mrpt/io/CStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

namespace semloc
{
/** An output stream to a gz-compressed file, as MRPT's CFileGZOutputStream writes it (same
 *  bytes), whose every failure throws "cannot write 'PATH': REASON" (e.g. "No space left on
 *  device"): MRPT's stream says only "Cannot write bytes to stream!" and drops the errors of
 *  its last flush on close, so a full disk could leave a truncated rawlog without a word. */
class GzOutputFile : public mrpt::io::CStream
{
public:
    /** Creates or truncates `path`; throws naming it if it cannot be opened.
     *  `compressLevel`: 0 (none) to 9 (best); MRPT's rawlogs use 1. */
    explicit GzOutputFile(const std::string& path, int compressLevel = 1);
    /** Closes the file if close() was not called, ignoring errors: call close() to see them. */
    ~GzOutputFile() override;
    GzOutputFile(const GzOutputFile&) = delete;
    GzOutputFile& operator=(const GzOutputFile&) = delete;

    /** Flushes and closes the file; throws "cannot write 'PATH': REASON" on an error. */
    void close();

    /** Compresses `count` bytes into the file; throws on an error (never a short write). */
    size_t Write(const void* buffer, size_t count) override;
    /** Not available: throws. */
    size_t Read(void* buffer, size_t count) override;
    /** Not available: throws. */
    uint64_t Seek(int64_t offset, CStream::TSeekOrigin origin) override;
    /** Not available: throws. */
    uint64_t getTotalBytesCount() const override;
    /** Uncompressed bytes written so far. */
    uint64_t getPosition() const override;
    /** The path, for MRPT's messages. */
    std::string getStreamDescription() const override;

private:
    [[noreturn]] void fail(int errnum, const char* zlibMessage) const;

    std::string m_path;
    void* m_file = nullptr;  // gzFile
    uint64_t m_written = 0;
};

/** How every rawlog semloc writes begins: its first entry is a CObservationComment whose text
 *  starts with this ("semloc"), so that a tool recognizes its own previous output
 *  (RawlogReader::IsSemlocRawlog) and replaces nothing else. */
extern const char* const kRawlogSignature;

/** Writes the signature comment, `kRawlogSignature` + ": " + `text` (the first entry). */
void writeRawlogSignature(mrpt::serialization::CArchive& out, const std::string& text);

/** Writes `log` to `path` as CRawlog::saveToRawLogFile does (each entry: the same bytes),
 *  after the signature comment (its text: `log`'s comment text if it starts with the
 *  signature, else the signature, `tool` and the comment text); throws "cannot write 'PATH':
 *  REASON" on any error. */
void saveRawlog(const mrpt::obs::CRawlog& log, const std::string& path, const std::string& tool);

}  // namespace semloc

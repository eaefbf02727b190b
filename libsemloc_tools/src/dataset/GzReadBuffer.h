/* semloc — a stream buffer reading a file plain or gz-compressed (private). */
#pragma once

#include <stdexcept>
#include <streambuf>
#include <string>

namespace semloc::detail
{
/** Reads `path` through zlib: a gz-compressed file decompressed, any other file as it is
 *  (zlib reads a file without the gzip header transparently). The constructor throws "cannot
 *  read 'PATH': REASON"; reading a damaged or cut-short compressed stream throws Damaged
 *  (its message names no file: the reader adds the file and the line). */
class GzReadBuffer : public std::streambuf
{
public:
    /** A damaged or truncated compressed stream: "the gz-compressed data is damaged or cut
     *  short (zlib: unexpected end of file)". */
    struct Damaged : std::runtime_error
    {
        using std::runtime_error::runtime_error;
    };

    explicit GzReadBuffer(const std::string& path);
    ~GzReadBuffer() override;
    GzReadBuffer(const GzReadBuffer&) = delete;
    GzReadBuffer& operator=(const GzReadBuffer&) = delete;

protected:
    int_type underflow() override;

private:
    void* m_file = nullptr;  // gzFile
    std::string m_path;
    char m_buf[1 << 16] = {};
};

}  // namespace semloc::detail

/* semloc — world text in pieces: a string's, a file's, and the UTF-8 check of any (see
 * WorldStream.h). */
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <vector>

#include "world/WorldStream.h"

namespace semloc::detail
{
size_t StringSource::read(char* buf, size_t n)
{
    n = std::min(n, m_text.size() - m_at);
    std::copy_n(m_text.data() + m_at, n, buf);
    m_at += n;
    return n;
}

FileSource::FileSource(const std::string& path) : m_path(path), m_file(path, std::ios::binary)
{
    if (!m_file)
    {
        THROW_EXCEPTION("world file '" + path + "': cannot open for reading");
    }
}

size_t FileSource::read(char* buf, size_t n)
{
    m_file.read(buf, static_cast<std::streamsize>(n));
    if (m_file.bad())
    {
        THROW_EXCEPTION("world file '" + m_path + "': read error");
    }
    return static_cast<size_t>(m_file.gcount());
}

void FileSource::rewind()
{
    m_file.clear();
    m_file.seekg(0);
    if (!m_file)
    {
        THROW_EXCEPTION("world file '" + m_path + "': read error");
    }
}

size_t firstNonUtf8Line(TextSource& source)
{
    size_t line = 1, bad = 0;
    size_t pending = 0;  // continuation bytes the sequence being read still needs
    std::vector<char> buf(size_t{1} << 16);
    for (size_t n; (n = source.read(buf.data(), buf.size())) > 0;)
    {
        for (size_t i = 0; i < n && bad == 0; i++)
        {
            const auto c = static_cast<unsigned char>(buf[i]);
            if (pending > 0)
            {
                bad = (c >> 6) != 0x2 ? line : 0;
                pending--;
                continue;
            }
            const size_t len = c < 0x80           ? 1
                               : (c >> 5) == 0x6  ? 2
                               : (c >> 4) == 0xE  ? 3
                               : (c >> 3) == 0x1E ? 4
                                                  : 0;
            bad = len == 0 ? line : 0;
            line += c == '\n' ? 1 : 0;
            pending = len == 0 ? 0 : len - 1;
        }
    }
    return bad != 0 ? bad : pending > 0 ? line : 0;
}

}  // namespace semloc::detail

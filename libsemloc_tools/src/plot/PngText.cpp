/* semloc — PngText: a tEXt chunk added to, and read from, a PNG file. */
#include <mrpt/core/exceptions.h>
#include <semloc/plot/PngText.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <sstream>

namespace semloc
{
const char* const kPngSoftware = "semloc";

namespace
{
constexpr std::array<unsigned char, 8> kPngMagic = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t readBigEndian(const unsigned char* p)
{
    return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

std::string bigEndian(uint32_t v)
{
    return {char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
}

bool hasMagic(const std::string& head)
{
    return head.size() >= kPngMagic.size() &&
           std::equal(kPngMagic.begin(), kPngMagic.end(), head.begin(),
                      [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); });
}
}  // namespace

void addPngText(const std::string& path, const std::string& keyword, const std::string& text)
{
    ASSERTMSG_(!keyword.empty() && keyword.size() < 80, "addPngText: a keyword of 1-79 bytes");
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        bytes = ss.str();
    }
    // IEND is the last chunk: 4 bytes of length 0, "IEND", its CRC.
    const size_t iend = bytes.size() >= 12 ? bytes.size() - 12 : std::string::npos;
    if (!hasMagic(bytes) || iend == std::string::npos || bytes.compare(iend + 4, 4, "IEND") != 0)
    {
        THROW_EXCEPTION("'" + path + "' is not a PNG file (no signature or no IEND chunk)");
    }
    const std::string data = "tEXt" + keyword + std::string(1, '\0') + text;
    const auto crc = static_cast<uint32_t>(
        crc32(0L, reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(data.size())));
    bytes.insert(iend, bigEndian(static_cast<uint32_t>(data.size() - 4)) + data + bigEndian(crc));
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
    if (!out.flush())
    {
        THROW_EXCEPTION("cannot write '" + path + "'");
    }
}

std::optional<std::string> pngText(const std::string& path, const std::string& keyword)
{
    std::ifstream in(path, std::ios::binary);
    std::string head(kPngMagic.size(), '\0');
    if (!in.read(head.data(), static_cast<std::streamsize>(head.size())) || !hasMagic(head))
    {
        return std::nullopt;
    }
    // Each chunk: length (4), type (4), data (length), CRC (4). Only tEXt chunks are read.
    for (unsigned char h[8]; in.read(reinterpret_cast<char*>(h), 8);)
    {
        const uint32_t length = readBigEndian(h);
        const std::string type(reinterpret_cast<const char*>(h + 4), 4);
        if (type == "IEND" || length > (1u << 31))
        {
            break;
        }
        if (type == "tEXt" && length <= (1u << 20))
        {
            std::string data(length, '\0');
            if (!in.read(data.data(), length))
            {
                break;
            }
            const auto nul = data.find('\0');
            if (nul != std::string::npos && data.compare(0, nul, keyword) == 0 &&
                nul == keyword.size())
            {
                return data.substr(nul + 1);
            }
            in.seekg(4, std::ios::cur);
        }
        else
        {
            in.seekg(static_cast<std::streamoff>(length) + 4, std::ios::cur);
        }
    }
    return std::nullopt;
}

bool isSemlocPng(const std::string& path)
{
    const auto s = pngText(path, "Software");
    return s && s->rfind(kPngSoftware, 0) == 0;
}

}  // namespace semloc

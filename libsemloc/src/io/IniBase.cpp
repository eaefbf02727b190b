/* semloc — an ini file that names its base: the base's text with the file's keys laid over it
 * (docs/design.md, "Configuration files"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "io/Text.h"

namespace semloc::config
{
namespace
{
using detail::trim;

/** How deep bases may be chained: far beyond any sensible layering, short of a stack overflow. */
constexpr size_t kMaxBaseDepth = 16;

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    return s;
}

/** The text of `path`; throws naming `file` if it does not exist, is a directory or cannot be
 *  read. */
std::string readText(const std::string& path, const std::string& file)
{
    if (!std::filesystem::exists(path))
    {
        THROW_EXCEPTION(file + " does not exist");
    }
    if (std::filesystem::is_directory(path))
    {
        THROW_EXCEPTION(file + " is a directory, not a file");
    }
    std::ifstream f(path, std::ios::binary);
    std::stringstream text;
    text << f.rdbuf();
    if (!f || f.bad())
    {
        THROW_EXCEPTION("cannot read " + file);
    }
    return text.str();
}

/** One line of an ini text as the overlay sees it. */
struct TLine
{
    std::string text;
    /** Lower-case section of a `[section]` line or of a key's line; empty for a key before any
     *  section. */
    std::string section;
    /** Lower-case key of a `key = value` line, else empty. */
    std::string key;
    bool isSection = false;
};

/** The lines of a text already checked by checkIniText(), classified. */
std::vector<TLine> classify(const std::string& text)
{
    std::vector<TLine> lines;
    std::istringstream in(text);
    std::string section;
    for (std::string line; std::getline(in, line);)
    {
        if (!line.empty() && line.back() == '\r')
        {
            line.pop_back();
        }
        if (lines.empty() && line.compare(0, 3, detail::kUtf8Bom) == 0)
        {
            line.erase(0, 3);
        }
        TLine l{line, section, "", false};
        const std::string content = trim(line);
        const bool comment = content.empty() || content[0] == ';' || content[0] == '#' ||
                             content[0] == '%' || content[0] == '@' ||
                             content.compare(0, 2, "//") == 0;
        if (!comment && content.front() == '[' && content.back() == ']')
        {
            section = lower(trim(content.substr(1, content.size() - 2)));
            l.section = section;
            l.isSection = true;
        }
        else if (!comment && content.find('=') != std::string::npos)
        {
            l.key = lower(trim(content.substr(0, content.find('='))));
        }
        lines.push_back(l);
    }
    return lines;
}

/** A value as MRPT reads it: trimmed, without a `//` comment after a blank. */
std::string valueOf(const std::string& line)
{
    std::string v = line.substr(line.find('=') + 1);
    for (size_t c = v.find("//"); c != std::string::npos; c = v.find("//", c + 2))
    {
        if (c == 0 || v[c - 1] == ' ' || v[c - 1] == '\t')
        {
            v.erase(c);
            break;
        }
    }
    return trim(v);
}

/** `base`'s text with the key lines of `over` laid over it: a key the base sets is replaced
 *  on its line, a new key goes at the end of its section (a new section at the end). */
std::string overlay(const std::vector<TLine>& base, const std::vector<TLine>& over)
{
    std::vector<std::string> out;
    std::map<std::pair<std::string, std::string>, size_t> keyLine;
    std::map<std::string, size_t> sectionEnd;  // the last line of a section's content
    for (const auto& l : base)
    {
        out.push_back(l.text);
        if (!l.key.empty())
        {
            keyLine[{l.section, l.key}] = out.size() - 1;
        }
        if (!l.key.empty() || l.isSection)
        {
            sectionEnd[l.section] = out.size() - 1;
        }
    }
    // Added lines by the base line they follow.
    std::map<size_t, std::vector<std::string>> after;
    std::vector<std::string> front;  // keys before any section the base does not set
    std::vector<std::pair<std::string, std::vector<std::string>>> newSections;
    std::string shownSection;
    for (const auto& l : over)
    {
        if (l.isSection)
        {
            shownSection = trim(l.text);
        }
        if (l.key.empty() || (l.section.empty() && l.key == "base"))
        {
            continue;
        }
        if (const auto it = keyLine.find({l.section, l.key}); it != keyLine.end())
        {
            out[it->second] = l.text;
        }
        else if (const auto end = sectionEnd.find(l.section); end != sectionEnd.end())
        {
            after[end->second].push_back(l.text);
        }
        else if (l.section.empty())
        {
            front.push_back(l.text);
        }
        else
        {
            if (newSections.empty() || newSections.back().first != l.section)
            {
                newSections.push_back({l.section, {shownSection}});
            }
            newSections.back().second.push_back(l.text);
        }
    }
    std::string text;
    for (const auto& f : front)
    {
        text += f + "\n";
    }
    for (size_t i = 0; i < out.size(); i++)
    {
        text += out[i] + "\n";
        if (const auto it = after.find(i); it != after.end())
        {
            for (const auto& a : it->second)
            {
                text += a + "\n";
            }
        }
    }
    for (const auto& [section, lines] : newSections)
    {
        for (const auto& a : lines)
        {
            text += a + "\n";
        }
    }
    return text;
}

/** The base `written` names (next to `from`, else from the working directory), as a path. */
std::string resolveBase(const std::string& from, const std::string& written, size_t lineNo,
                        const std::string& file)
{
    if (written.empty())
    {
        THROW_EXCEPTION(mrpt::format("%s:%zu: base: empty (name the ini this file changes)",
                                     file.c_str(), lineNo));
    }
    // Regular files only: a device or a pipe would be read forever.
    const std::filesystem::path w(written);
    const std::filesystem::path next = std::filesystem::path(from).parent_path() / w;
    if (!w.is_absolute() && std::filesystem::is_regular_file(next))
    {
        return next.lexically_normal().string();
    }
    if (std::filesystem::is_regular_file(w))
    {
        return written;
    }
    if (w.is_absolute())
    {
        THROW_EXCEPTION(
            mrpt::format("%s:%zu: base '%s' is not a file", file.c_str(), lineNo, written.c_str()));
    }
    THROW_EXCEPTION(
        mrpt::format("%s:%zu: base '%s' does not exist (tried '%s' next to it and "
                     "'%s' from the working directory)",
                     file.c_str(), lineNo, written.c_str(),
                     next.lexically_normal().string().c_str(), written.c_str()));
}

std::string resolvedText(const std::string& path, const std::string& kind,
                         std::vector<std::string>& chain)
{
    const std::string file = kind + " '" + path + "'";
    std::string text = readText(path, file);
    checkIniText(text, file);
    const auto lines = classify(text);
    const auto base =
        std::find_if(lines.begin(), lines.end(),
                     [](const TLine& l) { return l.section.empty() && l.key == "base"; });
    const auto canonical = std::filesystem::weakly_canonical(path).string();
    for (const auto& earlier : chain)
    {
        if (std::filesystem::weakly_canonical(earlier).string() == canonical)
        {
            std::string cycle = "the bases of " + kind + " '" + chain.front() + "' form a cycle: ";
            for (const auto& c : chain)
            {
                cycle.append("'").append(c).append("' -> ");
            }
            cycle.append("'").append(path).append("'");
            THROW_EXCEPTION(cycle);
        }
    }
    chain.push_back(path);
    if (base == lines.end())
    {
        return text;
    }
    if (chain.size() > kMaxBaseDepth)
    {
        THROW_EXCEPTION(mrpt::format("%s: more than %zu bases deep", file.c_str(), kMaxBaseDepth));
    }
    const size_t lineNo = static_cast<size_t>(base - lines.begin()) + 1;
    const std::string basePath = resolveBase(path, valueOf(base->text), lineNo, file);
    const std::string baseText = resolvedText(basePath, kind, chain);
    return overlay(classify(baseText), lines);
}
}  // namespace

std::string readIniText(const std::string& path, const std::string& kind,
                        std::vector<std::string>* files)
{
    std::vector<std::string> chain;
    std::string text = resolvedText(path, kind, chain);
    if (files != nullptr)
    {
        *files = chain;
    }
    return text;
}

std::vector<std::string> iniFileAndBases(const std::string& path)
{
    std::vector<std::string> files;
    try
    {
        (void)readIniText(path, "config file", &files);
    }
    catch (const std::exception&)
    {
        files = {path};
    }
    return files;
}

void checkIniFile(const std::string& path, const std::string& kind)
{
    (void)readIniText(path, kind);
}

IniFileInMemory::IniFileInMemory(const std::string& path, const std::string& kind) : m_path(path)
{
    setContent(readIniText(path, kind, &m_files));
}

}  // namespace semloc::config

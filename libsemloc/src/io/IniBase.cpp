/* semloc — an ini file that names its base: the base's text with the file's keys laid over it
 * (docs/design.md, "Configuration files"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/InputFile.h>

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

/** A key semloc moved: its old section and name, its new ones. */
struct TMovedKey
{
    const char* oldSection;
    const char* oldKey;
    const char* section;
    const char* key;
};

/** The recovery keys left [PF_options] (MRPT's) for a section of their own. */
const TMovedKey kMovedKeys[] = {
    {"PF_options", "recovery_trigger", "Recovery", "trigger"},
    {"PF_options", "recovery_alpha_slow", "Recovery", "alpha_slow"},
    {"PF_options", "recovery_alpha_fast", "Recovery", "alpha_fast"},
    {"PF_options", "recovery_evidence_margin", "Recovery", "evidence_margin"},
    {"PF_options", "recovery_evidence_threshold", "Recovery", "evidence_threshold"},
    {"PF_options", "recovery_inject_share", "Recovery", "inject_share"},
    {"PF_options", "recovery_from_detections", "Recovery", "from_detections"},
    {"PF_options", "recovery_injected_weight", "Recovery", "injected_weight"},
};

/** The lines of `lines` (one file's) that hold a moved key under its old name, each with
 *  its move; throws when the file also sets the key under its new name. */
std::map<size_t, const TMovedKey*> oldKeyLines(const std::vector<TLine>& lines,
                                               const std::string& file)
{
    std::map<size_t, const TMovedKey*> moved;
    for (size_t i = 0; i < lines.size(); i++)
    {
        for (const auto& m : kMovedKeys)
        {
            if (lines[i].section != lower(m.oldSection) || lines[i].key != lower(m.oldKey))
            {
                continue;
            }
            moved[i] = &m;
            for (size_t j = 0; j < lines.size(); j++)
            {
                if (lines[j].section == lower(m.section) && lines[j].key == lower(m.key))
                {
                    THROW_EXCEPTION(mrpt::format(
                        "%s:%zu: [%s] %s and line %zu's [%s] %s: the same setting twice; "
                        "keep [%s] %s (the old name is deprecated)",
                        file.c_str(), i + 1, m.oldSection, m.oldKey, j + 1, m.section, m.key,
                        m.section, m.key));
                }
            }
        }
    }
    return moved;
}

/** `lines` (one file's) with every moved key at its new place: `key = <the old line's text
 *  after its '='>` at the end of the new section (a new section at the end if the file has
 *  none), a warning per key. */
std::string moveOldKeys(const std::vector<TLine>& lines, const std::string& file,
                        std::vector<std::string>* warnings)
{
    const auto moved = oldKeyLines(lines, file);
    std::map<std::string, std::vector<std::string>> added;  // new section -> its lines
    for (const auto& [i, m] : moved)
    {
        const std::string& t = lines[i].text;
        added[lower(m->section)].push_back(std::string(m->key) + " " + t.substr(t.find('=')));
        if (warnings)
        {
            warnings->push_back(
                mrpt::format("%s:%zu: [%s] %s is deprecated: write [%s] %s instead (read as that)",
                             file.c_str(), i + 1, m->oldSection, m->oldKey, m->section, m->key));
        }
    }
    std::map<std::string, size_t> sectionEnd;  // the last line of each section's content
    for (size_t i = 0; i < lines.size(); i++)
    {
        if (moved.count(i) == 0 && (lines[i].isSection || !lines[i].key.empty()))
        {
            sectionEnd[lines[i].section] = i;
        }
    }
    std::map<size_t, std::string> after;  // an added section's lines follow its last line
    for (const auto& entry : added)
    {
        if (const auto end = sectionEnd.find(entry.first); end != sectionEnd.end())
        {
            after[end->second] = entry.first;
        }
    }
    std::string text;
    for (size_t i = 0; i < lines.size(); i++)
    {
        if (moved.count(i) == 0)
        {
            text += lines[i].text + "\n";
        }
        if (const auto it = after.find(i); it != after.end())
        {
            for (const auto& a : added[it->second])
            {
                text += a + "\n";
            }
            added.erase(it->second);
        }
    }
    for (const auto& m : kMovedKeys)  // sections the file does not have, in the table's order
    {
        if (const auto it = added.find(lower(m.section)); it != added.end())
        {
            text += std::string("[") + m.section + "]\n";
            for (const auto& a : it->second)
            {
                text += a + "\n";
            }
            added.erase(it);
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
    // The first name that exists is the base, and must be a regular file (checkInputFile):
    // a directory is named as one, a device or a pipe would be read forever.
    const std::filesystem::path w(written);
    const std::filesystem::path next = std::filesystem::path(from).parent_path() / w;
    const std::string at = mrpt::format("%s:%zu: base '%s'", file.c_str(), lineNo, written.c_str());
    std::vector<std::filesystem::path> candidates = {w};
    if (!w.is_absolute())
    {
        candidates.insert(candidates.begin(), next.lexically_normal());
    }
    for (const auto& c : candidates)
    {
        std::error_code ec;
        if (std::filesystem::symlink_status(c, ec).type() == std::filesystem::file_type::not_found)
        {
            continue;
        }
        try
        {
            (void)checkInputFile(c.string(), "config file", InputKind::Config);
        }
        catch (const std::exception& e)
        {
            THROW_EXCEPTION(at + ": " + errorMessage(e));
        }
        return c.string();
    }
    if (w.is_absolute())
    {
        THROW_EXCEPTION(at + " does not exist");
    }
    THROW_EXCEPTION(at + mrpt::format(" does not exist (tried '%s' next to it and '%s' from the "
                                      "working directory)",
                                      next.lexically_normal().string().c_str(), written.c_str()));
}

std::string resolvedText(const std::string& path, const std::string& kind,
                         std::vector<std::string>& chain, std::vector<std::string>* warnings)
{
    const std::string file = kind + " '" + path + "'";
    std::string text = readInputFile(path, kind, InputKind::Config);
    checkIniText(text, file);
    text = moveOldKeys(classify(text), file, warnings);
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
    const std::string baseText = resolvedText(basePath, kind, chain, warnings);
    return overlay(classify(baseText), lines);
}
}  // namespace

std::string readIniText(const std::string& path, const std::string& kind,
                        std::vector<std::string>* files, std::vector<std::string>* warnings)
{
    std::vector<std::string> chain;
    std::string text = resolvedText(path, kind, chain, warnings);
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

std::vector<std::string> movedKeyNames()
{
    std::vector<std::string> names;
    for (const auto& m : kMovedKeys)
    {
        names.push_back(
            mrpt::format("[%s] %s -> [%s] %s", m.oldSection, m.oldKey, m.section, m.key));
    }
    return names;
}

IniFileInMemory::IniFileInMemory(const std::string& path, const std::string& kind) : m_path(path)
{
    setContent(readIniText(path, kind, &m_files, &m_warnings));
}

}  // namespace semloc::config

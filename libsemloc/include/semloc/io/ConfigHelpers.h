/* semloc — strict reading of ini values: every error names the section and key. */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace semloc::config
{
/** The text of the ini file `path` with its bases resolved. A file may name, before its first
 *  section, the ini it changes: `base = FILE` (relative to the file, else to the working
 *  directory). Its text is then the base's (itself resolved) with the file's keys laid over
 *  it: a key the base sets is replaced on its line, a new key goes at the end of its section,
 *  a new section at the end; the `base` line itself is dropped. Each file is checked with
 *  checkIniText(); throws naming `kind`, the file and the line for a missing, unreadable or
 *  bad file, a missing base, a cycle of bases or bases over 16 deep. `files`, if given, gets
 *  the file and its bases, `path` first.
 *
 *  A key semloc moved to another section (movedKeyNames()) is read at its old place too: in
 *  each file, before the overlay, it is moved to its new section and name, and `warnings`,
 *  if given, gets one message naming the file, the line and both names (the old and the
 *  new name in one file is an error). */
std::string readIniText(const std::string& path, const std::string& kind = "config file",
                        std::vector<std::string>* files = nullptr,
                        std::vector<std::string>* warnings = nullptr);

/** The keys semloc moved, "[OLD_SECTION] old_key -> [SECTION] key" each. */
std::vector<std::string> movedKeyNames();

/** The ini file `path` and its bases (readIniText's `files`); just `path` when it cannot be
 *  read (the error is its reader's to report). */
std::vector<std::string> iniFileAndBases(const std::string& path);

/** Throws as readIniText() does if the ini file or one of its bases does not exist, is a
 *  directory, cannot be read or fails checkIniText(). */
void checkIniFile(const std::string& path, const std::string& kind = "config file");

/** Throws "<file>:LINE: ..." (`file` names the text, e.g. "config file 'x.ini'") for
 *  - a line that is neither blank, a comment (`;`, `#`, `//`, `%`), a `[section]`, a
 *    `key = value` nor an MRPT `@` directive: MRPT's parser skips such lines silently, so a
 *    typo would lose a setting without a word;
 *  - a key set twice in one section (MRPT keeps the last value silently). Section and key
 *    names match regardless of ASCII case, as in MRPT. A section may appear more than once:
 *    its keys are merged, as MRPT does.
 *  A UTF-8 byte-order mark at the start of the text is skipped, as MRPT skips it; lines end
 *  with LF, CRLF or a CR alone, as MRPT reads them. */
void checkIniText(const std::string& text, const std::string& file);

/** Reads a finite number in [lo, hi]; keeps `value` when the key is absent.
 *  Throws "ini [section] key: 'text' is not a number" and the like. */
void readDouble(const mrpt::config::CConfigFileBase& c, const std::string& section,
                const std::string& key, double& value, double lo, double hi);

/** The values a numeric key accepts, [lo, hi] (its loader's bounds, for whoever writes it). */
struct TValueRange
{
    double lo = 0;
    double hi = 0;
    /** `v` moved into [lo, hi]. */
    double clamp(double v) const { return v < lo ? lo : (v > hi ? hi : v); }
};

/** readDouble() with the bounds of `range`. */
inline void readDouble(const mrpt::config::CConfigFileBase& c, const std::string& section,
                       const std::string& key, double& value, const TValueRange& range)
{
    readDouble(c, section, key, value, range.lo, range.hi);
}

/** Reads a comma-separated list of 1 to `maxCount` finite numbers, each in [lo, hi]; keeps
 *  `values` when the key is absent. Throws naming [section] key as readDouble() does. */
void readDoubles(const mrpt::config::CConfigFileBase& c, const std::string& section,
                 const std::string& key, std::vector<double>& values, size_t maxCount, double lo,
                 double hi);

/** Reads an integer in [lo, hi]; keeps `value` when the key is absent. */
void readInt(const mrpt::config::CConfigFileBase& c, const std::string& section,
             const std::string& key, int& value, int lo, int hi);

/** Reads a boolean (true/false/1/0/yes/no); keeps `value` when absent. */
void readBool(const mrpt::config::CConfigFileBase& c, const std::string& section,
              const std::string& key, bool& value);

/** Reads a string that must be one of `choices`; keeps `value` when absent. */
void readChoice(const mrpt::config::CConfigFileBase& c, const std::string& section,
                const std::string& key, std::string& value,
                const std::vector<std::string>& choices);

/** Throws if `section` holds a key not in `known` (MRPT ignores unknown keys
 *  silently, which hides typos). */
void rejectUnknownKeys(const mrpt::config::CConfigFileBase& c, const std::string& section,
                       const std::vector<std::string>& known);

/** An ini file's text, its bases resolved (readIniText), held (and changed) in memory; it
 *  remembers the files it came from: relative paths in it resolve next to them, as in the
 *  files themselves (resolveNextToIni). */
class IniFileInMemory : public mrpt::config::CConfigFileMemory
{
public:
    /** The text of `path` and its bases (read here; throws as readIniText() does). */
    explicit IniFileInMemory(const std::string& path, const std::string& kind = "config file");
    /** The file it came from. */
    const std::string& path() const { return m_path; }
    /** The file and its bases, the file first. */
    const std::vector<std::string>& files() const { return m_files; }
    /** The keys found under their deprecated names (readIniText's `warnings`). */
    const std::vector<std::string>& warnings() const { return m_warnings; }

private:
    std::string m_path;
    std::vector<std::string> m_files;
    std::vector<std::string> m_warnings;
};

/** The file `source` was read from (a CConfigFile or an IniFileInMemory), "" if none. */
std::string iniFileOf(const mrpt::config::CConfigFileBase& source);

/** "file 'WRITTEN' does not exist", and when `written` is relative and `source` came from a
 *  file, the paths tried: "(tried 'DIR/WRITTEN' next to the ini 'INI' and 'WRITTEN' from the
 *  working directory)", DIR the ini's directory as given (a symlinked ini's own, not its
 *  target's); with bases, "'DIR2/WRITTEN' next to its base 'BASE'" after the ini's. */
std::string missingFileMessage(const mrpt::config::CConfigFileBase& source,
                               const std::string& written);

/** `file` as given if it exists (or is absolute or empty), else resolved next to the ini
 *  file `source` was read from (a CConfigFile or an IniFileInMemory), then next to each of its
 *  bases, where it exists first: ini files name their maps relative to themselves, as users
 *  expect, while MRPT's own tools resolve from the working directory. */
std::string resolveNextToIni(const mrpt::config::CConfigFileBase& source, const std::string& file);

/** The keys an options struct writes in saveToConfigFile (its complete key set), computed once
 *  per class and `variant`: the keys a class writes must not depend on its values, but may on
 *  a variant the struct names (the simulator's detectors: one struct, a key set per kind). */
std::vector<std::string> keysOf(const mrpt::config::CLoadableOptions& o,
                                const std::string& variant = {});

}  // namespace semloc::config

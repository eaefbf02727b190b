/* semloc — where a tool may write: the rules that keep a user's files safe. */
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace semloc
{
/** The file every output directory semloc writes holds (an empty file). A directory is
 *  replaced as a whole by the next run into it only when it holds this marker. */
extern const char* const kOutputMarker;

/** Checks, before any work, that `dir` may be written as an output directory (replaced as a
 *  whole at the end of the run). Allowed: a path that does not exist, an empty directory, or
 *  a previous output of semloc (it holds kOutputMarker). Refused, with an error naming `dir`
 *  and the reason: anything that is not a directory; a directory semloc did not write; the
 *  working directory or a directory that contains it; a directory that contains (or is) one
 *  of `inputs` (files or directories the run reads; empty entries are ignored). */
void checkOutputDirectory(const std::string& dir, const std::vector<std::string>& inputs = {});

/** Checks, before any work, that `file` may be written (created or replaced). Refused, with
 *  an error naming `file` and the reason: an existing directory; one of `inputs` (the same
 *  file by any name); a missing or non-directory parent; an existing file for which
 *  `isPreviousOutput(path)` is false when that test is given (for files whose names a tool
 *  derives from the one the user gave, so that a file the user never named is replaced
 *  only when it is a previous output of the same kind). */
void checkOutputFile(const std::string& file, const std::vector<std::string>& inputs = {},
                     const std::function<bool(const std::string&)>& isPreviousOutput = nullptr);

/** True when the file at `path` starts with `prefix` (a header semloc writes). */
bool fileStartsWith(const std::string& path, const std::string& prefix);

/** The permissions a new directory gets under the process's umask (0777 & ~umask), read
 *  without changing the umask (safe with other threads running). */
unsigned directoryModeFromUmask();

}  // namespace semloc

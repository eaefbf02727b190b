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

/** Checks, before any work, that `file` may be written (created or replaced): the rule every
 *  tool applies to a single output file. Refused, with an error naming `file` and the reason:
 *  an existing directory; one of `inputs` (the same file by any name); a missing or
 *  non-directory parent; a symbolic link to nothing; an existing file for which
 *  `isPreviousOutput(path)` is false (a file semloc did not write as an output of this kind:
 *  a tool replaces only its own previous outputs, recognized by their content). A symbolic
 *  link is followed: what it points at is checked, and replaced by writeOutputFiles(). */
void checkOutputFile(const std::string& file, const std::vector<std::string>& inputs,
                     const std::function<bool(const std::string&)>& isPreviousOutput);

/** Holds, until the process ends, the lock of the output `output` (a file or a directory,
 *  through its symbolic links): a second process asking for the same output fails at once
 *  with an error naming the holder's process id. checkOutputDirectory() and checkOutputFile()
 *  call it, so every tool holds each of its outputs from its first check, before any work.
 *  The locks are files `semloc-locks-<uid>/<hash of the path>.lock` in the temporary
 *  directory, locked with flock (freed by the kernel when the process ends, however it ends)
 *  and removed at a normal exit. Calling it again for an output it holds does nothing. */
void lockOutput(const std::string& output);

/** Where an output named `path` is written: absolute and normal, through its symbolic links
 *  (a link to nothing is refused, naming it). */
std::string resolvedOutputPath(const std::string& path);

/** The one way semloc writes single output files. Each of `outputs` is written under a unique
 *  temporary name beside the file it replaces (through a symbolic link: beside what the link
 *  points at), locked while the process writes it; `write(temporaries)` gets those names in
 *  the order of `outputs`. Once all are written they are renamed into place together (Ctrl-C
 *  waits for the renames). On an error or an interrupt request the temporary files are removed,
 *  the outputs stay as they were, and the error is rethrown. Temporary files of the same
 *  outputs left by a process that was killed are removed first. Call checkOutputFile() on
 *  each output before any work. */
void writeOutputFiles(const std::vector<std::string>& outputs,
                      const std::function<void(const std::vector<std::string>&)>& write);

/** True when the file at `path` starts with `prefix` (a header semloc writes). */
bool fileStartsWith(const std::string& path, const std::string& prefix);

/** The permissions a new directory gets under the process's umask (0777 & ~umask), read
 *  without changing the umask (safe with other threads running). */
unsigned directoryModeFromUmask();

}  // namespace semloc

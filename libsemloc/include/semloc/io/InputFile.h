/* semloc — the one way a file is read as an input: a regular file within its kind's size cap
 * (docs/bad-input.md, "What the tools read"). */
#pragma once

#include <cstdint>
#include <string>

namespace semloc
{
/** What an input file is read as: names it in messages and sets its size cap. */
enum class InputKind
{
    Config,  ///< an ini file or a base of one: 16 MiB
    World,   ///< a world YAML file: 1 GiB
    Text,    ///< a table read line by line (ground truth, CSV, landmarks, a run's files): 16 GiB
    Rawlog   ///< a rawlog, read entry by entry: 1 TiB
};

/** The largest file of `kind` that is read, in bytes. */
uint64_t maxInputBytes(InputKind kind);

/** Checks that `path`, an input of the kind `what` names in messages ("rawlog", "config file",
 *  ...), may be read: it exists, is a regular file (a symbolic link is followed; a device, a
 *  FIFO, a socket, a directory or a link loop is refused) of at most maxInputBytes(kind)
 *  bytes. Throws one line naming `what` and `path` otherwise. Returns the file's size. */
uint64_t checkInputFile(const std::string& path, const std::string& what, InputKind kind);

/** The bytes of the input file `path`, checked as checkInputFile() does on the file it opens
 *  (not on the name: a file swapped for a FIFO after the check is refused too) and read with
 *  the cap (a file that grows beyond it while read is refused). */
std::string readInputFile(const std::string& path, const std::string& what, InputKind kind);

/** readInputFile() with a cap of `maxBytes` (a kind of file a tool defines itself). */
std::string readInputFile(const std::string& path, const std::string& what, uint64_t maxBytes);

}  // namespace semloc

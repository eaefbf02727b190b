/* semloc — strict YAML reading with libyaml's event parser (private).
 *
 * MRPT's yaml::FromText (libfyaml) reports some syntax errors on the console only and returns
 * the part of the document it could read (an indentation error near the end of a world file,
 * or a plain `-` in a flow map, went unnoticed), keeps the last of a key written twice, fails
 * on an alias without saying where and reads a quoted 'null' as null. libyaml's parser stops
 * at the first error and says where; the document is built here from its events, so one
 * parser decides what the text says. */
#pragma once

#include <mrpt/containers/yaml.h>

#include <cstddef>
#include <functional>
#include <set>
#include <string>

namespace semloc::detail
{
/** Deepest nesting of maps and sequences parseYaml() accepts. */
constexpr size_t kMaxYamlDepth = 64;

/** Reads the YAML document `text` into `doc`, as MRPT's reader shapes it: maps, sequences,
 *  scalars as std::string; a plain empty, `~`, `null`, `Null` or `NULL` scalar is a null
 *  node; each node's marks (0-based line and column) are set. Returns "" on success, else
 *  - "line L, column C: YAML syntax error: <problem> (<context>)" for a syntax error,
 *  - "line L, column C: key 'k' repeated (first on line M): ..." for a map key written twice,
 *  - "line L, column C: YAML alias '*a': ..." for an alias,
 *  - "line L, column C: ..." for a key that is not a scalar, a second document or nesting
 *    deeper than kMaxYamlDepth;
 *  then `doc` is unspecified. An empty text is a null document. */
std::string parseYaml(const std::string& text, mrpt::containers::yaml::node_t& doc);

/** Where parseYaml() reads its text from, in pieces: read() puts up to `n` bytes into `buf`
 *  and returns how many (0 at the end); it may throw. */
using YamlRead = std::function<size_t(char* buf, size_t n)>;

/** The elements of the sequences under some keys of the document's top-level map, handed
 *  over one by one as they are read instead of kept in the document (whose sequence stays
 *  empty), so that a long list never stands as a tree of nodes: `keys` names them,
 *  `take(key, index, node)` receives each element (with its marks) in order. `take` must not
 *  throw. */
struct YamlElementSink
{
    std::set<std::string> keys;
    std::function<void(const std::string& key, size_t index,
                       const mrpt::containers::yaml::node_t& node)>
        take;
};

/** parseYaml() on the text `read` gives, the elements of `sink`'s sequences handed over to
 *  it (none if null); an exception of `read` is thrown as it is. */
std::string parseYaml(const YamlRead& read, mrpt::containers::yaml::node_t& doc,
                      const YamlElementSink* sink = nullptr);
}  // namespace semloc::detail

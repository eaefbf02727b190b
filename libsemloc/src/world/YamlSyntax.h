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
}  // namespace semloc::detail

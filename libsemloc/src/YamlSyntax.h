/* semloc — strict YAML syntax check (private).
 *
 * MRPT's yaml::FromText reports some syntax errors on the console and returns the part of the
 * document it could read (an indentation error near the end of a world file went unnoticed).
 * libyaml's parser stops at the first error and says where; its events are all we need. */
#pragma once

#include <string>

namespace semloc::detail
{
/** "line L, column C: YAML syntax error: <problem> (<context>)" for the first syntax error of
 *  `text`; "" if the whole text is well-formed YAML. */
std::string yamlSyntaxError(const std::string& text);
}  // namespace semloc::detail

/* semloc — the reference of every ini section semloc reads, generated from the options. */
#pragma once

#include <string>

namespace semloc
{
/** Every ini section semloc's classes read, with every key at its default value and a
 *  comment, written by the options structs' own saveToConfigFile(): docs/ini-reference.md
 *  holds this text (a test keeps the two equal), so it never drifts from the code. */
std::string iniReference();

}  // namespace semloc

/* semloc — a text entry in a PNG file: how a tool recognizes a figure it drew. */
#pragma once

#include <optional>
#include <string>

namespace semloc
{
/** The value of the PNG `Software` text entry of every figure semloc writes to a path the user
 *  names ("semloc"): a tool replaces such a file only when it holds this. */
extern const char* const kPngSoftware;

/** Adds a tEXt chunk `keyword` = `text` (Latin-1, keyword 1-79 bytes) before the PNG's IEND
 *  chunk, rewriting the file; throws naming the file if it is not a PNG or cannot be
 *  rewritten. */
void addPngText(const std::string& path, const std::string& keyword, const std::string& text);

/** The text of the first tEXt chunk named `keyword` in the PNG at `path`; empty when the file
 *  is not a readable PNG or has no such chunk. Reads the chunks' headers, not the image. */
std::optional<std::string> pngText(const std::string& path, const std::string& keyword);

/** True when `path` is a PNG whose `Software` text starts with kPngSoftware. */
bool isSemlocPng(const std::string& path);

}  // namespace semloc

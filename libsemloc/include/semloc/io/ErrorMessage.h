/* semloc — the message a user should see for an exception. */
#pragma once

#include <cstddef>
#include <exception>
#include <string>
#include <string_view>

namespace semloc
{
/** The messages of an exception without MRPT's source locations and call-stack dumps
 *  (mrpt::exception_to_str shows those, which help developers, not users). Nested MRPT
 *  exceptions give one line each, outermost first. Set SEMLOC_DEBUG=1 in the environment
 *  to get mrpt::exception_to_str's full text instead. */
std::string errorMessage(const std::exception& e);

/** Longest text of a value quoted in a message (characters, escapes counted as written). */
constexpr size_t kMaxShownValue = 60;

/** `value` as a message quotes it (a cell, a key, a label, an ini value): escaped and cut, so
 *  that a hostile input never reaches the terminal raw. Bytes that are not printable, and
 *  characters that print nothing (the byte-order mark U+FEFF, zero-width and bidirectional
 *  marks), are written as `\xNN` per byte; valid UTF-8 text beyond ASCII is kept; a text
 *  longer than kMaxShownValue is cut there and ends with "…". Every message of the readers
 *  quotes values through this function. */
std::string shownValue(std::string_view value);

}  // namespace semloc

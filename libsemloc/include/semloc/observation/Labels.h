/* semloc — the rule every object label follows (world files, maps, rawlogs, --label). */
#pragma once

#include <semloc/io/ErrorMessage.h>

#include <cstddef>
#include <string>

namespace semloc
{
/** Longest label [bytes] semloc reads from a file (rawlogs, map files, world files); the
 *  writers refuse a longer one, so that nothing is written that cannot be read back. */
constexpr size_t kMaxLabelLength = 65536;

/** "" if `label` is longer than kMaxLabelLength, else "label of N bytes is too long (at
 *  most 65536)": the one rule of the binary readers (rawlogs, map files). */
inline std::string labelLengthProblem(const std::string& label)
{
    if (label.size() <= kMaxLabelLength)
    {
        return {};
    }
    return "label of " + std::to_string(label.size()) + " bytes is too long (at most " +
           std::to_string(kMaxLabelLength) + ")";
}

/** "" if `label` can name an object class in a world file or a map: one word of 1 to
 *  kMaxLabelLength bytes without blanks or control characters (bytes of UTF-8 text beyond
 *  ASCII are fine); else what is wrong with it, e.g. "label 'oil rig' holds a blank or
 *  control character (a label is one word)". */
inline std::string labelProblem(const std::string& label)
{
    if (label.empty())
    {
        return "label is empty (a label is one word)";
    }
    if (std::string p = labelLengthProblem(label); !p.empty())
    {
        return p;
    }
    for (const char c : label)
    {
        const auto u = static_cast<unsigned char>(c);
        if (u <= 0x20 || u == 0x7F)
        {
            return "label '" + shownValue(label) +
                   "' holds a blank or control character (a label is one word)";
        }
    }
    return {};
}
}  // namespace semloc

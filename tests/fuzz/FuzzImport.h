/* semloc — what the fuzz_import_* targets share (docs/testing.md, "Fuzzing"): a reader of
 * semloc-import's CSV files run on the fuzzed bytes, and the checks of what it returned. */
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

namespace semloc::fuzz
{
/** The name the readers are given for the fuzzed text: every message must name it. */
inline const std::string kCsvName = "fuzz.csv";

/** Aborts, saying `what`, unless `ok`: a property of an accepted input does not hold. */
inline void require(bool ok, const char* what)
{
    if (!ok)
    {
        std::cerr << "fuzzed CSV accepted, but: " << what << "\n";
        std::abort();
    }
}

/** `read(stream, name)` on the bytes, or nothing when the reader rejected them with an
 *  exception; that exception's message must name the file, as the reader's on a file does. */
template <class READ>
auto readCsv(const uint8_t* data, size_t size, READ read)
    -> std::optional<decltype(read(std::declval<std::istream&>(), kCsvName))>
{
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try
    {
        return read(in, kCsvName);
    }
    catch (const std::exception& e)
    {
        const std::string message = e.what();
        if (message.find(kCsvName) == std::string::npos)
        {
            std::cerr << "a reader's message does not name the file:\n" << message << "\n";
            std::abort();
        }
        return std::nullopt;  // rejected with a message: what a bad file must do
    }
}

/** True for a heading wrapped into [-pi, pi]. */
inline bool wrapped(double phi)
{
    return phi >= -M_PI && phi <= M_PI;
}

/** True when every time is finite and each is after the one before. */
template <class TIMES>
bool increasing(const TIMES& t)
{
    for (size_t i = 0; i < t.size(); i++)
    {
        if (!std::isfinite(t[i]) || (i > 0 && !(t[i] > t[i - 1])))
        {
            return false;
        }
    }
    return true;
}

}  // namespace semloc::fuzz

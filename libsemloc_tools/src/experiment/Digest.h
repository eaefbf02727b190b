/* semloc — the digests of semloc-benchmark's shards and run files: 64-bit FNV-1a (private). */
#pragma once

#include <mrpt/core/format.h>

#include <cstdint>
#include <string>

namespace semloc::detail
{
/** FNV-1a's 64-bit offset basis: the hash of nothing. */
constexpr uint64_t kFnv1aBasis = 14695981039346656037ULL;

/** 64-bit FNV-1a over `bytes`, continuing from `h`. */
inline uint64_t fnv1a(const std::string& bytes, uint64_t h = kFnv1aBasis)
{
    for (const unsigned char c : bytes)
    {
        h ^= c;
        h *= 1099511628211ULL;
    }
    return h;
}

/** `h` as 16 lowercase hex digits. */
inline std::string digestText(uint64_t h)
{
    return mrpt::format("%016llx", static_cast<unsigned long long>(h));
}
}  // namespace semloc::detail

/* semloc — reading lengths and strings from MRPT archives within bounds: a corrupted length
 * in a rawlog or map file must throw, not allocate gigabytes (tests/fuzz/fuzz_deserialize). */
#pragma once

#include <mrpt/core/exceptions.h>
#include <mrpt/maps/metric_map_types.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <cstring>
#include <string>

namespace semloc::detail
{
/** Longest string accepted from an archive (labels, sensor labels, world names). The writers
 *  check labels against the observation's kMaxLabelLength, which may not exceed it (a
 *  static_assert in CObservationSemantic.cpp). */
constexpr uint32_t kMaxSerializedString = 65536;

/** Reads an element count written as uint32 and checks it against `maxCount`; `what` names
 *  the class and the elements in the message. Readers must then grow their containers as
 *  elements arrive (push_back), never resize to the count: memory follows the bytes present. */
inline uint32_t readCount(mrpt::serialization::CArchive& in, uint32_t maxCount, const char* what)
{
    const auto n = in.ReadAs<uint32_t>();
    if (n > maxCount)
    {
        THROW_EXCEPTION_FMT("%s: corrupted data: %u elements (at most %u)", what,
                            static_cast<unsigned>(n), static_cast<unsigned>(maxCount));
    }
    return n;
}

/** Reads a string as MRPT's `operator<<(CArchive&, const std::string&)` writes it (uint32
 *  length, bytes), throwing on a length beyond kMaxSerializedString or a short read. MRPT's
 *  own `operator>>` allocates whatever the length says and ignores short reads. */
inline void readString(mrpt::serialization::CArchive& in, std::string& s, const char* what)
{
    const uint32_t n = readCount(in, kMaxSerializedString, what);
    s.assign(n, '\0');
    if (n > 0 && in.ReadBuffer(s.data(), n) != n)
    {
        THROW_EXCEPTION_FMT("%s: corrupted data: string truncated", what);
    }
}

/** Reads a bool written by MRPT's `operator<<(CArchive&, bool)` (one byte, 0 or 1). MRPT's
 *  `operator>>` copies the byte into the bool as is: any other value makes the bool invalid. */
inline bool readBool(mrpt::serialization::CArchive& in, const char* what)
{
    const auto b = in.ReadAs<uint8_t>();
    if (b > 1)
    {
        THROW_EXCEPTION_FMT("%s: corrupted data: a flag byte is %u (0 or 1 expected)", what,
                            static_cast<unsigned>(b));
    }
    return b == 1;
}

/** True when the bool's byte is 0 or 1: inspects the bytes, never loads an invalid bool. */
inline bool validBoolBytes(const bool& b)
{
    unsigned char byte = 0;
    std::memcpy(&byte, &b, 1);
    return byte <= 1;
}

/** Reads MRPT's generic map parameters (three flags MRPT reads byte for byte) and checks that
 *  each flag is 0 or 1; `what` names the map class in the message. */
inline mrpt::maps::TMapGenericParams readGenericMapParams(mrpt::serialization::CArchive& in,
                                                          const char* what)
{
    mrpt::maps::TMapGenericParams p;
    in >> p;
    if (!validBoolBytes(p.enableSaveAs3DObject) || !validBoolBytes(p.enableObservationLikelihood) ||
        !validBoolBytes(p.enableObservationInsertion))
    {
        THROW_EXCEPTION_FMT("%s: corrupted data: a generic map flag is neither 0 nor 1", what);
    }
    return p;
}
}  // namespace semloc::detail

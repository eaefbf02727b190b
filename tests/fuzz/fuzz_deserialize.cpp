/* semloc — libFuzzer target: semloc's serializable classes read from bytes (docs/testing.md,
 * "Fuzzing"). Input: one byte choosing the class (CObservationSemantic, CSemanticMap,
 * CStructureMap), then the serialization version byte and the object's payload. The target
 * wraps them in a valid MRPT object header and end marker, so that every fuzzed byte reaches
 * semloc's own serializeFrom() rather than MRPT's (uninstrumented) header parsing. Any input
 * must either load or throw; a loaded object must give finite-or-handled likelihoods and
 * serialize again to bytes that load to the same bytes. */
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/structure/CStructureMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

namespace
{
/** MRPT's end-of-object marker (CArchive::WriteObject). */
constexpr uint8_t kEndOfObject = 0x88;

const std::array<const mrpt::rtti::TRuntimeClassId*, 3> kClasses = {
    CLASS_ID(semloc::CObservationSemantic), CLASS_ID(semloc::CSemanticMap),
    CLASS_ID(semloc::CStructureMap)};

/** The object's bytes as CArchive::WriteObject() lays them out (MRPT's v2 object format):
 *  0x80 | name length, the class name, then `versionAndPayload`, then the end marker. */
std::string objectBytes(const mrpt::rtti::TRuntimeClassId& cls, const uint8_t* versionAndPayload,
                        size_t size)
{
    const std::string name = cls.className;
    std::string bytes;
    bytes.push_back(static_cast<char>(0x80 | name.size()));
    bytes += name;
    bytes.append(reinterpret_cast<const char*>(versionAndPayload), size);
    bytes.push_back(static_cast<char>(kEndOfObject));
    return bytes;
}

mrpt::serialization::CSerializable::Ptr read(const std::string& bytes)
{
    mrpt::io::CMemoryStream in;
    in.assignMemoryNotOwn(bytes.data(), bytes.size());
    return mrpt::serialization::archiveFrom(in).ReadObject();
}

std::string write(const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream out;
    mrpt::serialization::archiveFrom(out).WriteObject(&o);
    return std::string(static_cast<const char*>(out.getRawBufferData()), out.getTotalBytesCount());
}

/** A fixed observation and pose for the likelihoods of a fuzzed map. */
const mrpt::poses::CPose3D kPose(10.0, 20.0, 0.0, 0.3, 0.0, 0.0);

semloc::CObservationSemantic fixedDetections()
{
    semloc::CObservationSemantic obs;
    obs.detections = {{"pillar", 5.0, 0.2, 0.9, -1}, {"wellhead", 12.0, -0.4, 0.7, -1}};
    return obs;
}

mrpt::obs::CObservation2DRangeScan fixedScan()
{
    mrpt::obs::CObservation2DRangeScan scan;
    scan.aperture = M_PI;
    scan.maxRange = 30.0f;
    scan.resizeScanAndAssign(9, 10.0f, true);
    return scan;
}

/** Uses a successfully read object the way the localizer does. */
void exercise(const mrpt::serialization::CSerializable& o)
{
    if (const auto* obs = dynamic_cast<const semloc::CObservationSemantic*>(&o))
    {
        semloc::CSemanticMap map;
        map.addObject({1, "pillar", 14.0, 21.0, 0.0, 1.0, 1});
        (void)map.computeObservationLikelihood(*obs, kPose);
        std::ostringstream text;
        obs->getDescriptionAsText(text);
    }
    else if (const auto* sm = dynamic_cast<const semloc::CSemanticMap*>(&o))
    {
        (void)sm->asString();
        (void)sm->computeObservationLikelihood(fixedDetections(), kPose);
    }
    else if (const auto* st = dynamic_cast<const semloc::CStructureMap*>(&o))
    {
        (void)st->asString();
        (void)st->computeObservationLikelihood(fixedScan(), kPose);
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
    {
        return 0;
    }
    const auto& cls = *kClasses[data[0] % kClasses.size()];
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        obj = read(objectBytes(cls, data + 1, size - 1));
    }
    catch (const std::exception&)
    {
        return 0;  // rejected with a message: what corrupted data must do
    }
    exercise(*obj);
    // What was read writes out to bytes that read back to the same bytes.
    const std::string bytes = write(*obj);
    if (write(*read(bytes)) != bytes)
    {
        std::abort();
    }
    return 0;
}

/* semloc — writes the seed corpus of fuzz_deserialize (tests/fuzz/corpus/deserialize/): each
 * file is fuzz_deserialize's input format, the class byte then the version byte and payload
 * of a serialized object (MRPT's object header and end marker stripped).
 * Usage: fuzz_write_seeds <output directory> */
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/structure/CStructureMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>

namespace
{
void writeSeed(const std::string& path, uint8_t classByte,
               const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream buf;
    mrpt::serialization::archiveFrom(buf).WriteObject(&o);
    const std::string bytes(static_cast<const char*>(buf.getRawBufferData()),
                            buf.getTotalBytesCount());
    const size_t header = 1 + std::string(o.GetRuntimeClass()->className).size();
    std::ofstream f(path, std::ios::binary);
    f.put(static_cast<char>(classByte));
    f.write(bytes.data() + header, static_cast<std::streamsize>(bytes.size() - header - 1));
    if (!f)
    {
        throw std::runtime_error("cannot write " + path);
    }
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::cerr << "usage: fuzz_write_seeds <output directory>\n";
        return 1;
    }
    try
    {
        const std::string dir = argv[1];
        const auto world =
            semloc::World::FromFile(SEMLOC_SOURCE_DIR "/maps/harbour_symmetric.yaml");

        semloc::CObservationSemantic obs;
        obs.sensorLabel = "SEMANTIC";
        obs.detections = {{"pillar", 5.0, 0.2, 0.9, 3}, {"wellhead", 12.0, -0.4, 0.7, -1}};
        writeSeed(dir + "/observation_semantic", 0, obs);
        writeSeed(dir + "/observation_semantic_empty", 0, semloc::CObservationSemantic());

        semloc::CSemanticMap sem;
        sem.loadFromWorld(world);
        writeSeed(dir + "/semantic_map", 1, sem);

        semloc::CStructureMap st;
        st.loadFromWorld(world);
        writeSeed(dir + "/structure_map", 2, st);
    }
    catch (const std::exception& e)
    {
        std::cerr << e.what() << "\n";
        return 1;
    }
    return 0;
}

/* semloc tests — the writers refuse what the readers would refuse (labels beyond
 * kMaxLabelLength), and a rawlog that cannot be written names the file and the reason. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/observation/Labels.h>
#include <semloc/plot/PngText.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace
{
const std::string kOut = std::string(SEMLOC_TEST_OUT) + "/writers";

/** `o` written to memory and read back as a new object of its class. */
template <class T>
std::shared_ptr<T> roundTrip(const T& o)
{
    mrpt::io::CMemoryStream buf;
    mrpt::serialization::archiveFrom(buf).WriteObject(&o);
    buf.Seek(0);
    return std::dynamic_pointer_cast<T>(mrpt::serialization::archiveFrom(buf).ReadObject());
}

/** The message of writing `o` to memory, "" if it was written. */
std::string writeError(const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream buf;
    try
    {
        mrpt::serialization::archiveFrom(buf).WriteObject(&o);
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}

/** The uncompressed bytes of a gz file. */
std::string gunzip(const std::string& path)
{
    mrpt::io::CFileGZInputStream in(path);
    std::string out;
    char buf[4096];
    for (size_t n; (n = in.Read(buf, sizeof(buf))) > 0;)
    {
        out.append(buf, n);
    }
    return out;
}

/** Bytes of `obj` as an archive writes it. */
size_t serializedSize(const mrpt::serialization::CSerializable& obj)
{
    mrpt::io::CMemoryStream m;
    auto a = mrpt::serialization::archiveFrom(m);
    a << obj;
    return static_cast<size_t>(m.getTotalBytesCount());
}

semloc::CObservationSemantic observation(const std::string& label)
{
    semloc::CObservationSemantic o;
    o.sensorLabel = "SEMANTIC";
    o.detections = {{"pillar", 5.0, 0.2, 0.9, 3}, {label, 7.0, -0.1, 0.8, -1}};
    return o;
}
}  // namespace

TEST(Writers, ObservationLabelsUpToTheLimitRoundTrip)
{
    const std::string label(semloc::kMaxLabelLength, 'x');
    const auto back = roundTrip(observation(label));
    ASSERT_TRUE(back);
    ASSERT_EQ(back->detections.size(), 2u);
    EXPECT_EQ(back->detections[1].label, label);
}

TEST(Writers, ObservationRefusesALabelItsReaderWouldRefuse)
{
    const std::string m = writeError(observation(std::string(1000000, 'x')));
    EXPECT_NE(m.find("CObservationSemantic: cannot write detection 1: its label of 1000000 "
                     "bytes is too long (at most 65536)"),
              std::string::npos)
        << m;
    auto o = observation("pillar");
    o.sensorLabel = std::string(semloc::kMaxLabelLength + 1, 's');
    EXPECT_NE(writeError(o).find("cannot write a sensor label of 65537 bytes"), std::string::npos);
}

TEST(Writers, SemanticMapRefusesALabelItsReaderWouldRefuse)
{
    semloc::CSemanticMap map;
    semloc::CSemanticMap::TObject ok;
    ok.id = 1;
    ok.label = std::string(semloc::kMaxLabelLength, 'a');
    map.addObject(ok);
    const auto back = roundTrip(map);
    ASSERT_TRUE(back);
    ASSERT_EQ(back->objects().size(), 1u);
    EXPECT_EQ(back->objects()[0].label, ok.label);

    semloc::CSemanticMap::TObject big;
    big.id = 7;
    big.label = std::string(1000000, 'b');
    map.addObject(big);
    const std::string m = writeError(map);
    EXPECT_NE(m.find("CSemanticMap: cannot write object id 7: its label of 1000000 bytes is too "
                     "long (at most 65536)"),
              std::string::npos)
        << m;
}

TEST(Writers, SaveRawlogWritesTheSignatureThenTheBytesMrptWrites)
{
    std::filesystem::create_directories(kOut);
    mrpt::obs::CRawlog log;
    for (int k = 0; k < 50; k++)
    {
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<semloc::CObservationSemantic>(
            observation("label" + std::to_string(k))));
        log.insert(sf);
    }
    const std::string ours = kOut + "/ours.rawlog", mrpts = kOut + "/mrpt.rawlog";
    // The signature comment comes first, as MRPT writes a comment (its timestamp: the time of
    // writing); the entries after it are MRPT's bytes.
    log.setCommentText("semloc: a dataset");
    semloc::saveRawlog(log, ours, "test");
    ASSERT_TRUE(log.saveToRawLogFile(mrpts));
    mrpt::obs::CObservationComment comment;
    comment.text = log.getCommentText();
    const size_t skip = serializedSize(comment);  // its timestamp differs: the time of writing
    const std::string a = gunzip(ours), b = gunzip(mrpts);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), skip);
    EXPECT_EQ(a.substr(skip), b.substr(skip));
    EXPECT_TRUE(semloc::RawlogReader::IsSemlocRawlog(ours));

    // A log without the signature gets it, with the tool's name, before its own comment.
    log.setCommentText("a dataset");
    semloc::saveRawlog(log, ours, "semloc-test");
    mrpt::obs::CRawlog back;
    ASSERT_TRUE(back.loadFromRawLogFile(ours));
    EXPECT_EQ(back.getCommentText(), "semloc: semloc-test\na dataset");
    EXPECT_EQ(back.size(), 50u);
    EXPECT_TRUE(semloc::RawlogReader::IsSemlocRawlog(ours));
    // MRPT's own rawlog, with or without a comment, is not semloc's.
    ASSERT_TRUE(log.saveToRawLogFile(mrpts));
    EXPECT_FALSE(semloc::RawlogReader::IsSemlocRawlog(mrpts));
    log.setCommentText("");
    ASSERT_TRUE(log.saveToRawLogFile(mrpts));
    EXPECT_FALSE(semloc::RawlogReader::IsSemlocRawlog(mrpts));
    EXPECT_FALSE(semloc::RawlogReader::IsSemlocRawlog(kOut + "/no-such.rawlog"));
}

TEST(Writers, AFullDiskNamesTheFileAndTheReason)
{
    // MRPT's CRawlog::saveToRawLogFile returned true here: its stream drops the errors of the
    // last flush on close, and a small rawlog is all in that flush.
    mrpt::obs::CRawlog log;
    mrpt::obs::CSensoryFrame sf;
    sf.insert(std::make_shared<semloc::CObservationSemantic>(observation("pillar")));
    log.insert(sf);
    try
    {
        semloc::saveRawlog(log, "/dev/full", "test");
        FAIL() << "a full disk went unnoticed";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot write '/dev/full': No space left on device"), std::string::npos)
            << m;
    }
    // A large rawlog fails in a write before the close: the same message.
    try
    {
        semloc::GzOutputFile f("/dev/full", 0);
        const std::string block(1 << 20, 'x');
        for (int i = 0; i < 4; i++)
        {
            f.Write(block.data(), block.size());
        }
        f.close();
        FAIL() << "a full disk went unnoticed";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot write '/dev/full': No space left on device"), std::string::npos)
            << m;
    }
    // A directory that does not exist.
    try
    {
        semloc::saveRawlog(log, kOut + "/no/such/dir/x.rawlog", "test");
        FAIL() << "wrote into a missing directory";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("cannot write '" + kOut +
                         "/no/such/dir/x.rawlog': No such file or "
                         "directory"),
                  std::string::npos)
            << m;
    }
}

TEST(Writers, PngTextIsAddedAndReadBack)
{
    std::filesystem::create_directories(kOut);
    // The smallest PNG: signature, IHDR (1x1 grey), IDAT, IEND (CRCs of the real chunks).
    const unsigned char png[] = {0x89, 'P', 'N', 'G',  '\r', '\n', 0x1a, '\n', 0,    0, 0, 13,
                                 'I',  'H', 'D', 'R',  0,    0,    0,    1,    0,    0, 0, 1,
                                 8,    0,   0,   0,    0,    0x3a, 0x7e, 0x9b, 0x55, 0, 0, 0,
                                 10,   'I', 'D', 'A',  'T',  0x78, 0x9c, 0x63, 0x60, 0, 0, 0,
                                 2,    0,   1,   0x48, 0xaf, 0xa4, 0x71, 0,    0,    0, 0, 'I',
                                 'E',  'N', 'D', 0xae, 0x42, 0x60, 0x82};
    const std::string path = kOut + "/tiny.png";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof(png));
    EXPECT_FALSE(semloc::isSemlocPng(path));
    semloc::addPngText(path, "Software", "semloc (test)");
    EXPECT_EQ(semloc::pngText(path, "Software").value_or(""), "semloc (test)");
    EXPECT_TRUE(semloc::isSemlocPng(path));
    EXPECT_FALSE(semloc::pngText(path, "Author").has_value());
    // Not a PNG: refused naming the file, and never taken for semloc's.
    const std::string text = kOut + "/notes.png";
    std::ofstream(text) << "my notes\n";
    EXPECT_FALSE(semloc::isSemlocPng(text));
    EXPECT_THROW(semloc::addPngText(text, "Software", "semloc"), std::exception);
}

/* semloc tests — CObservationSemantic: serialization through rawlogs, text output, validity. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "TestHelpers.h"

using semloc::CObservationSemantic;
using semloc::TSemanticDetection;

namespace
{
CObservationSemantic::Ptr makeObs(int k)
{
    auto o = CObservationSemantic::Create();
    o->sensorLabel = "SEMANTIC";
    o->timestamp = mrpt::Clock::fromDouble(1000.0 + k);
    o->sensorPose = mrpt::poses::CPose3D(0.3, -0.1, -0.5, 0.1 * k, 0, 0);
    o->maxRange_m = 15 + k;
    o->fov_rad = M_PI / 2;
    for (int i = 0; i <= k % 4; i++)
    {
        TSemanticDetection d;
        d.label = i % 2 ? "pillar" : "wellhead";
        d.range_m = 1.5 + i + 0.01 * k;
        d.bearing_rad = -0.3 + 0.2 * i;
        d.confidence = 0.5 + 0.1 * i;
        d.object_id = i == 1 ? 7 : -1;
        o->detections.push_back(d);
    }
    return o;
}

/** The number of observations the rawlog_edit ctest expects in the file below. */
constexpr int kObsInRoundTripRawlog = 12;
}  // namespace

TEST(CObservationSemantic, RoundTripThroughRawlogFile)
{
    // The file is also read by the rawlog-edit ctest (fixture semantic_rawlog).
    const std::string path = std::string(SEMLOC_TEST_OUT) + "/semantic_roundtrip.rawlog";
    mrpt::obs::CRawlog log;
    for (int k = 0; k < kObsInRoundTripRawlog; k++)
    {
        mrpt::obs::CActionCollection acts;
        mrpt::obs::CActionRobotMovement2D mv;
        mv.computeFromOdometry(mrpt::poses::CPose2D(0.5, 0, 0.01), {});
        mv.timestamp = mrpt::Clock::fromDouble(1000.0 + k);
        acts.insert(mv);
        log.insert(acts);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(makeObs(k));
        log.insert(sf);
    }
    ASSERT_TRUE(log.saveToRawLogFile(path));

    mrpt::obs::CRawlog back;
    ASSERT_TRUE(back.loadFromRawLogFile(path));
    ASSERT_EQ(back.size(), log.size());
    for (int k = 0; k < kObsInRoundTripRawlog; k++)
    {
        const auto sf = back.getAsObservations(2 * static_cast<size_t>(k) + 1);
        ASSERT_EQ(sf->size(), 1u);
        const auto o = sf->getObservationByClass<CObservationSemantic>();
        ASSERT_TRUE(o) << "entry " << 2 * k + 1 << " is not a CObservationSemantic";
        const auto ref = makeObs(k);
        EXPECT_EQ(o->sensorLabel, ref->sensorLabel);
        EXPECT_EQ(o->timestamp, ref->timestamp);
        EXPECT_NEAR((o->sensorPose.asVectorVal() - ref->sensorPose.asVectorVal()).norm(), 0, 1e-12);
        EXPECT_EQ(o->maxRange_m, ref->maxRange_m);
        EXPECT_EQ(o->fov_rad, ref->fov_rad);
        EXPECT_EQ(o->detections, ref->detections);
    }
}

TEST(CObservationSemantic, CorruptedDetectionCountIsRejected)
{
    // Serialize, then overwrite the detection count with a huge value.
    auto o = makeObs(3);
    std::vector<uint8_t> buf;
    {
        mrpt::io::CMemoryStream mem;
        auto ar = mrpt::serialization::archiveFrom(mem);
        ar << *o;
        buf.assign(static_cast<const uint8_t*>(mem.getRawBufferData()),
                   static_cast<const uint8_t*>(mem.getRawBufferData()) + mem.getTotalBytesCount());
    }
    // Find the uint32 count (4 detections for k=3) followed by the first label's length.
    bool patched = false;
    for (size_t i = 0; i + 4 <= buf.size(); i++)
    {
        uint32_t v;
        std::memcpy(&v, &buf[i], 4);
        if (v == 4u && i + 8 <= buf.size())
        {
            uint32_t next;
            std::memcpy(&next, &buf[i + 4], 4);
            if (next == 8u)  // strlen("wellhead")
            {
                const uint32_t huge = 0x7fffffff;
                std::memcpy(&buf[i], &huge, 4);
                patched = true;
                break;
            }
        }
    }
    ASSERT_TRUE(patched);
    mrpt::io::CMemoryStream in;
    in.assignMemoryNotOwn(buf.data(), buf.size());
    auto ar = mrpt::serialization::archiveFrom(in);
    CObservationSemantic back;
    EXPECT_THROW(ar >> back, std::exception);
}

TEST(CObservationSemantic, DescriptionAndExportListEveryDetection)
{
    const auto o = makeObs(3);
    std::stringstream ss;
    o->getDescriptionAsText(ss);
    const std::string s = ss.str();
    EXPECT_NE(s.find("Detections: 4"), std::string::npos) << s;
    EXPECT_NE(s.find("wellhead"), std::string::npos);
    EXPECT_NE(s.find("pillar"), std::string::npos);
    ASSERT_TRUE(o->exportTxtSupported());
    const std::string row = o->exportTxtDataRow();
    EXPECT_EQ(row.find('\n'), std::string::npos);
    std::istringstream rs(row);
    std::vector<std::string> cols;
    for (std::string c; rs >> c;)
    {
        cols.push_back(c);
    }
    ASSERT_EQ(cols.size(), 4u + 5u * 4u);
    EXPECT_EQ(cols[3], "4");
    EXPECT_EQ(cols[4], "wellhead");
    EXPECT_EQ(cols[9], "pillar");
    EXPECT_EQ(cols[13], "7");  // object id of the second detection
}

TEST(CObservationSemantic, ValidityOfDetections)
{
    CObservationSemantic o;
    o.maxRange_m = 10;
    o.fov_rad = M_PI / 2;
    auto det = [](double r, double b, double c = 1.0, const char* l = "x")
    {
        TSemanticDetection d = semloc::test::detection(l, r, b);
        d.confidence = c;
        return d;
    };
    EXPECT_TRUE(o.isValid(det(5, 0.2)));
    EXPECT_TRUE(o.isValid(det(0, 0)));
    EXPECT_TRUE(o.isValid(det(10, M_PI / 4)));
    EXPECT_TRUE(o.isValid(det(5, 2 * M_PI + 0.1)));  // wrapped
    EXPECT_FALSE(o.isValid(det(10.01, 0)));
    EXPECT_FALSE(o.isValid(det(-0.1, 0)));
    EXPECT_FALSE(o.isValid(det(std::nan(""), 0)));
    EXPECT_FALSE(o.isValid(det(5, std::numeric_limits<double>::infinity())));
    EXPECT_FALSE(o.isValid(det(5, M_PI / 4 + 0.01)));
    EXPECT_FALSE(o.isValid(det(5, 0, 1.5)));
    EXPECT_FALSE(o.isValid(det(5, 0, 1.0, "")));
}

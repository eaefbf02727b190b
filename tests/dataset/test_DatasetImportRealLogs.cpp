/* semloc tests — DatasetImport on what real logs bring: repeated times (odometry, ground
 * truth), a scan's readings a few milliseconds apart, detections no landmark explains, gaps in
 * the ground truth; each settled by its rule, counted for the summary line and warned about
 * where the result may be wrong. */
#include <gtest/gtest.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/io/ErrorMessage.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace
{
namespace fs = std::filesystem;
using semloc::DatasetImport;
using semloc::TDatasetImportStats;

std::string write(const std::string& name, const std::string& text)
{
    const fs::path d = fs::path(SEMLOC_TEST_OUT) / "dataset_import_real_logs";
    fs::create_directories(d);
    std::ofstream(d / name) << text;
    return (d / name).string();
}

bool warned(const TDatasetImportStats& s, const std::string& excerpt)
{
    for (const auto& w : s.warnings)
    {
        if (w.find(excerpt) != std::string::npos)
        {
            return true;
        }
    }
    return false;
}

TEST(DatasetImportRealLogs, RepeatedOdometryTimesKeepTheLaterReading)
{
    TDatasetImportStats s;
    // Poses: the later row of time 2 is the pose from then on.
    const auto p = DatasetImport::readOdometry(
        write("p.csv", "t,x,y,phi\n1,0,0,0\n2,0.9,0,0\n2,1,0,0\n3,2,0,0\n3,2,0,0\n"), &s);
    ASSERT_EQ(p.t, (std::vector<double>{1, 2, 3}));
    EXPECT_DOUBLE_EQ(p.pose[1].x, 1);
    EXPECT_EQ(s.odometryRepeatedTimes, 2u);
    ASSERT_EQ(s.warnings.size(), 1u);  // time 2 disagrees; time 3 repeats the same pose
    EXPECT_NE(s.warnings[0].find("p.csv': 1 of the 2 repeated times hold another pose than their "
                                 "last row (the first on line 3): the last is kept"),
              std::string::npos)
        << s.warnings[0];
    // Speeds: the earlier reading of a time is held for no time, the later one until the next.
    TDatasetImportStats v;
    const auto o =
        DatasetImport::readOdometry(write("v.csv", "t,v,w\n0,1,0\n1,5,0\n1,2,0\n2,0,0\n"), &v);
    ASSERT_EQ(o.t.size(), 3u);
    EXPECT_DOUBLE_EQ(o.pose[2].x, 3);  // 1 m in the first second, 2 m in the next
    EXPECT_EQ(v.odometryRepeatedTimes, 1u);
    EXPECT_TRUE(warned(v, "another speed than their last row"));
    // Still refused: a time going back; one distinct time only.
    std::string back;
    try
    {
        DatasetImport::readOdometry(write("b.csv", "t,x,y,phi\n1,0,0,0\n2,0,0,0\n1.5,0,0,0\n"));
    }
    catch (const std::exception& e)
    {
        back = semloc::errorMessage(e);
    }
    EXPECT_NE(back.find("b.csv:4: column 1 't': time 1.5 goes back"), std::string::npos) << back;
    EXPECT_THROW(DatasetImport::readOdometry(write("one.csv", "t,x,y,phi\n1,0,0,0\n1,1,0,0\n")),
                 std::exception);
}

TEST(DatasetImportRealLogs, ReadingsWithinTheScanWindowAreOneScan)
{
    const std::string det =
        write("d.csv",
              "t,label,range_m,bearing_rad,id\n1,buoy,3,0.1,1\n1.004,buoy,5,0,2\n"
              "1.010,rock,2,0,3\n1.011,buoy,4,0,4\n2,,,,\n3,buoy,2,0.2,1\n");
    TDatasetImportStats s;
    const auto scans = DatasetImport::readDetections(det, 0.01, &s);
    ASSERT_EQ(scans.size(), 4u);
    EXPECT_DOUBLE_EQ(scans[0].t, 1);            // timed by its first reading
    EXPECT_EQ(scans[0].detections.size(), 3u);  // 1.010 within 0.01 s of 1, 1.011 not
    EXPECT_DOUBLE_EQ(scans[1].t, 1.011);
    EXPECT_EQ(s.detectionsGrouped, 2u);
    EXPECT_TRUE(s.warnings.empty());
    EXPECT_EQ(DatasetImport::summaryCounts(s), "2 detections grouped into scans within 0.01 s");
    // Window 0: only rows of one time.
    TDatasetImportStats z;
    EXPECT_EQ(DatasetImport::readDetections(det, 0, &z).size(), 6u);
    EXPECT_EQ(z.detectionsGrouped, 0u);
    // Times since 1970 (their rounding is ~0.2 us): 10 ms apart is within 0.01 s.
    EXPECT_EQ(
        DatasetImport::readDetections(write("e.csv",
                                            "t,label,range_m,bearing_rad\n1248444189.599,a,1,0\n"
                                            "1248444189.609,a,1,0\n1248444189.8,a,1,0\n"))
            .size(),
        2u);
}

TEST(DatasetImportRealLogs, GroupingThatMayJoinTwoScansIsWarned)
{
    // One id twice in a grouped scan: two scans' readings?
    TDatasetImportStats s;
    DatasetImport::readDetections(write("r.csv",
                                        "t,label,range_m,bearing_rad,id\n1,a,3,0,5\n"
                                        "1.003,a,3.1,0,5\n2,a,3,0,5\n"),
                                  0.01, &s);
    EXPECT_TRUE(warned(s,
                       "r.csv': 1 scan grouped within --scan-window-s 0.01 s holds one id "
                       "twice (the first on line 3)"));
    // Readings 6 ms apart, a window of 10 ms: pairs, scans 12 ms apart (less than 5 windows).
    TDatasetImportStats p;
    std::string fast = "t,label,range_m,bearing_rad\n";
    for (int k = 0; k < 20; k++)
    {
        fast += std::to_string(100 + 0.006 * k) + ",a,3,0\n";
    }
    DatasetImport::readDetections(write("f.csv", fast), 0.01, &p);
    EXPECT_TRUE(warned(p, "less than 5 times --scan-window-s 0.01 s")) << p.warnings.size();
}

TEST(DatasetImportRealLogs, RepeatedGroundTruthTimesAreOnePoseTheLater)
{
    TDatasetImportStats s;
    const auto gt = DatasetImport::readGroundTruth(
        write("g.csv", "t,x,y,phi\n1,0,0,0\n2,5,0,0\n2,1,0,0\n3,2,0,0\n"), &s);
    ASSERT_EQ(gt.size(), 3u);
    EXPECT_DOUBLE_EQ(gt[1].x, 1);
    EXPECT_EQ(s.groundTruthRepeatedTimes, 1u);
    EXPECT_TRUE(warned(s, "g.csv': 1 of the 1 repeated times hold another pose"));
    EXPECT_EQ(DatasetImport::summaryCounts(s),
              "1 repeated ground-truth time (the later pose kept)");
}

/** Ground truth every 0.1 s over [0, 10] and [110, 120] (100 s removed) and steps every 0.5 s
 *  over [0, 120]. */
std::pair<std::vector<semloc::GroundTruthRow>, std::vector<semloc::ImportStep>> gappedRun()
{
    std::vector<semloc::GroundTruthRow> gt;
    for (int k = 0; k <= 1200; k++)
    {
        if (k <= 100 || k >= 1100)
        {
            gt.push_back({0.1 * k, 0.1 * k, 0, 0});
        }
    }
    std::vector<semloc::ImportStep> steps;
    for (int k = 0; k <= 240; k++)
    {
        steps.push_back({0.5 * k, k});
    }
    return {gt, steps};
}

TEST(DatasetImportRealLogs, StepsInsideAGroundTruthGapHaveNone)
{
    const auto [gt, steps] = gappedRun();
    EXPECT_DOUBLE_EQ(DatasetImport::groundTruthMaxGap(gt, 0), 1.0);  // 10 x 0.1 s
    EXPECT_DOUBLE_EQ(DatasetImport::groundTruthMaxGap(gt, 250), 250);
    TDatasetImportStats s;
    const auto rows = DatasetImport::groundTruthAtSteps(gt, steps, "gt.csv", 0, &s);
    // Steps 10.5 .. 109.5 (199) lie inside the gap: no row; 10 and 110 are at rows.
    EXPECT_EQ(rows.size(), 241u - 199u);
    EXPECT_EQ(s.stepsInGroundTruthGaps, 199u);
    EXPECT_EQ(s.groundTruthGaps, 1u);
    for (const auto& r : rows)
    {
        EXPECT_TRUE(r.t <= 10 || r.t >= 110) << r.t;
        EXPECT_NEAR(r.x, r.t, 1e-9);  // never a pose interpolated across the gap
    }
    EXPECT_TRUE(warned(s,
                       "ground truth 'gt.csv': 1 gap longer than 1 s (--gt-max-gap-s; 100 s, "
                       "from 10 to 110) holds 199 steps"));
    EXPECT_EQ(DatasetImport::summaryCounts(s), "199 steps without ground truth in 1 gap over 1 s");
    // A limit above the gap interpolates across it, as before.
    TDatasetImportStats wide;
    EXPECT_EQ(DatasetImport::groundTruthAtSteps(gt, steps, "gt.csv", 200, &wide).size(), 241u);
    EXPECT_EQ(wide.stepsInGroundTruthGaps, 0u);
}

semloc::TSemanticDetection detection(const std::string& label, int id)
{
    semloc::TSemanticDetection d;
    d.label = label;
    d.range_m = 3;
    d.object_id = id;
    return d;
}

TEST(DatasetImportRealLogs, DetectionsNoLandmarkExplainsAreKeptCountedAndNamed)
{
    std::vector<semloc::ImportedLandmark> lm(2);
    lm[0].object.id = 6;
    lm[0].object.label = "tube";
    lm[1].object.id = 7;
    lm[1].object.label = "tube";
    std::vector<semloc::DetectionScan> scans = {
        {1, {detection("tube", 6), detection("robot", 2), detection("robot", 3)}},
        {2, {detection("robot", 4), detection("robot", 5), detection("tube", 21)}},
        {3, {detection("robot", 6), detection("crate", -1), detection("tube", -1)}}};
    const std::vector<semloc::ImportStep> steps = {{1, 0}, {1.5, -1}, {2, 1}, {3, 2}};
    TDatasetImportStats s;
    DatasetImport::checkLandmarks(steps, scans, lm, s);
    EXPECT_EQ(s.detectionsUnknown, 5u);            // robot 2-5, the crate
    EXPECT_EQ(s.detectionsIdNotLandmark, 1u);      // tube 21
    EXPECT_EQ(s.detectionsLabelNotLandmarks, 1u);  // robot 6: landmark 6 is a tube
    EXPECT_TRUE(warned(s,
                       "5 detections are of no landmark (label robot, ids 2-5: 4; label crate, "
                       "no id: 1): kept; semloc-localize counts them as detections_unknown"));
    EXPECT_TRUE(warned(s,
                       "1 detection has an id no landmark has (label tube, id 21: 1): kept; "
                       "semloc-localize associates them by their label"));
    EXPECT_TRUE(warned(s,
                       "1 detection has a landmark's id and another label (label robot, id 6: "
                       "1): kept; semloc-localize associates them by their id"));
    EXPECT_EQ(DatasetImport::summaryCounts(s),
              "5 detections of no landmark (unknown to the map), 1 detection of an id no landmark "
              "has (associated by label), 1 detection labelled unlike their landmark (associated "
              "by id)");
    // Without landmarks nothing is counted.
    TDatasetImportStats none;
    DatasetImport::checkLandmarks(steps, scans, {}, none);
    EXPECT_EQ(DatasetImport::summaryCounts(none), "");
}

}  // namespace

/* semloc tests — importing a landmark dataset made by MRPT's stock simul-landmarks. */
#include <gtest/gtest.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>

using semloc::LandmarkImport;

namespace
{
/** Runs simul-landmarks once (2D square path, ids reported) and returns its rawlog path. */
std::string simulateLandmarks()
{
    static std::string rawlog;
    if (!rawlog.empty())
    {
        return rawlog;
    }
    const std::string dir = std::string(SEMLOC_TEST_OUT) + "/simul_landmarks";
    const std::string ini = dir + "/sim.ini";
    std::system(("mkdir -p '" + dir + "'").c_str());
    std::ofstream(ini) << "[Params]\nrandom_seed=123\nnSteps=80\ncircularPath=0\n"
                          "squarePathLength=20\nloadLandmarksFromFile=\nodometryNoiseXY_std=0.02\n"
                          "minSensorDistance=0\nmaxSensorDistance=6\nfieldOfView_deg=180\n"
                          "stdRange=0.02\nstdYaw_deg=0.5\nstdPitch_deg=0\n"
                          "outFile=lm.rawlog\noutDir="
                       << dir
                       << "/OUT\nshow_in_3d=false\n"
                          "[RANDOMSET_1]\nnLandmarks=40\nmin_x=-4\nmax_x=8\nmin_y=-3\nmax_y=8\n"
                          "min_z=0\nmax_z=0\n";
    const std::string cmd = "cd '" + dir + "' && '" SIMUL_LANDMARKS "' sim.ini > sim.log 2>&1";
    if (std::system(cmd.c_str()) != 0)
    {
        return {};
    }
    rawlog = dir + "/OUT/lm.rawlog";
    return rawlog;
}
}  // namespace

TEST(LandmarkImport, SimulLandmarksDatasetBecomesASemanticOne)
{
    const std::string in = simulateLandmarks();
    ASSERT_FALSE(in.empty()) << "simul-landmarks failed";
    mrpt::obs::CRawlog log;
    ASSERT_TRUE(log.loadFromRawLogFile(in));
    const auto lms = LandmarkImport::readLandmarks(in + "_ground_truth.txt", "buoy");
    const auto path = LandmarkImport::readPath(in + "_ground_truth_robot_path.txt");
    ASSERT_EQ(lms.size(), 40u);
    const size_t n = LandmarkImport::convertRawlog(log, "buoy");
    const auto times = LandmarkImport::frameTimes(log);
    ASSERT_EQ(n, times.size());
    ASSERT_GE(path.size(), times.size());

    // The converted observations must agree with the ground truth: at the true pose the
    // likelihood beats a pose 1 m away in almost every frame.
    semloc::CSemanticMap map;
    map.loadFromWorld(LandmarkImport::makeWorld(lms, path, 5.0, "lm"));
    size_t frame = 0, better = 0, informative = 0;
    for (size_t i = 0; i < log.size(); i++)
    {
        if (log.getType(i) != mrpt::obs::CRawlog::etSensoryFrame)
        {
            continue;
        }
        const auto obs =
            log.getAsObservations(i)->getObservationByClass<semloc::CObservationSemantic>();
        ASSERT_TRUE(obs);
        EXPECT_EQ(obs->sensorLabel, "SEMANTIC");
        for (const auto& d : obs->detections)
        {
            EXPECT_EQ(d.label, "buoy");
            EXPECT_GE(d.object_id, 1);
        }
        const auto& p = path[frame++];
        if (obs->detections.size() >= 2)
        {
            informative++;
            const mrpt::math::TPose2D away(p.x + 1.0, p.y, p.phi);
            better += map.computeLogLikelihood(*obs, p) > map.computeLogLikelihood(*obs, away);
        }
    }
    ASSERT_GT(informative, 20u);
    EXPECT_GE(better, informative * 95 / 100) << better << " of " << informative;

    const std::string gt = std::string(SEMLOC_TEST_OUT) + "/simul_landmarks/gt.txt";
    LandmarkImport::writeGroundTruth(times, path, gt);
    std::ifstream f(gt);
    size_t rows = 0;
    for (std::string line; std::getline(f, line);)
    {
        rows++;
    }
    EXPECT_EQ(rows, times.size());
}

TEST(LandmarkImport, MalformedFilesNameFileAndLine)
{
    const std::string bad = std::string(SEMLOC_TEST_OUT) + "/bad_landmarks.txt";
    std::ofstream(bad) << "1 2 0 5 0 0 1\n3 four 0 5 0 0 2\n";
    try
    {
        LandmarkImport::readLandmarks(bad, "x");
        FAIL() << "accepted a malformed file";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("bad_landmarks.txt' line 2"), std::string::npos) << m;
        EXPECT_NE(m.find("'four'"), std::string::npos) << m;
    }
    EXPECT_THROW(LandmarkImport::readPath("/no/such/path.txt"), std::exception);
    EXPECT_THROW(LandmarkImport::writeGroundTruth({1.0, 2.0}, {{0, 0, 0}}, bad + ".gt"),
                 std::exception);
}

TEST(LandmarkImport, OptionsAreCheckedBeforeAnyWork)
{
    auto message = [](const std::string& label, double margin)
    {
        try
        {
            LandmarkImport::checkOptions(label, margin);
        }
        catch (const std::exception& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(message("buoy", 5), "");
    EXPECT_EQ(message("buoy", semloc::kMaxWorldCoordinate_m), "");
    EXPECT_NE(message("oil rig", 5).find("--label: label 'oil rig' holds a blank"),
              std::string::npos);
    EXPECT_NE(message("", 5).find("--label: label is empty"), std::string::npos);
    EXPECT_NE(message(std::string(1000000, 'x'), 5)
                  .find("--label: label of 1000000 bytes is too long (at most 65536)"),
              std::string::npos);
    for (const double bad : {-1.0, 1e300, std::nan(""), std::numeric_limits<double>::infinity()})
    {
        EXPECT_NE(message("buoy", bad).find("--margin "), std::string::npos) << bad;
    }
    EXPECT_NE(message("buoy", 1e300).find("--margin 1e+300: must be a finite number in [0, "),
              std::string::npos);
}

TEST(LandmarkImport, MakeWorldReturnsOnlyWorldsTheLoaderReads)
{
    semloc::WorldObject lm;
    lm.id = 1;
    lm.label = "buoy";
    lm.shape = semloc::ShapeType::Point;
    lm.center = {100, 0};
    const std::vector<mrpt::math::TPose2D> path = {{0, 0, 0}, {1, 0, 0}};
    // Within the bound of world coordinates: the world loads back as it is.
    const auto w = LandmarkImport::makeWorld({lm}, path, semloc::kMaxWorldCoordinate_m - 100, "lm");
    EXPECT_EQ(semloc::World::FromText(w.toYamlText(), "lm").toYamlText(), w.toYamlText());
    // Beyond it: the margin is named.
    try
    {
        LandmarkImport::makeWorld({lm}, path, semloc::kMaxWorldCoordinate_m - 50, "lm");
        FAIL() << "made a world beyond the bound of world coordinates";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("--margin 9999950: the world's bounds (x -9999950 .. 10000050"),
                  std::string::npos)
            << m;
    }
    // A landmark beyond the bound: the bounds say so.
    lm.center = {2e7, 0};
    try
    {
        LandmarkImport::makeWorld({lm}, {}, 0, "lm");
        FAIL() << "made a world the loader refuses";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("would reach beyond"), std::string::npos) << m;
    }
    // Anything else the world loader refuses, in its words.
    lm.center = {1, 1};
    lm.label = "oil rig";
    try
    {
        LandmarkImport::makeWorld({lm}, path, 5, "lm");
        FAIL() << "made a world the loader refuses";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("the world of the landmarks and the path would not load: world file "
                         "'lm': objects[0] (id 1): key 'label': label 'oil rig' holds a blank"),
                  std::string::npos)
            << m;
    }
}

TEST(LandmarkImport, LabelsAreCheckedByEveryConversion)
{
    mrpt::obs::CRawlog log;
    EXPECT_THROW(LandmarkImport::convertRawlog(log, "oil rig"), std::exception);
    const std::string file = std::string(SEMLOC_TEST_OUT) + "/labels_landmarks.txt";
    std::ofstream(file) << "1 2 0 5 0 0 1\n";
    EXPECT_THROW(LandmarkImport::readLandmarks(file, ""), std::exception);
    EXPECT_EQ(LandmarkImport::readLandmarks(file, "buoy").size(), 1u);
}

TEST(LandmarkImport, WriteErrorsNameTheFileAndTheReason)
{
    try
    {
        LandmarkImport::writeGroundTruth({1.0}, {{0, 0, 0}},
                                         std::string(SEMLOC_TEST_OUT) + "/no/such/dir/gt.txt");
        FAIL() << "wrote into a missing directory";
    }
    catch (const std::exception& e)
    {
        const std::string m = e.what();
        EXPECT_NE(m.find("/no/such/dir/gt.txt': No such file or directory"), std::string::npos)
            << m;
    }
}

TEST(LandmarkImport, IdsAreDecimalDigits)
{
    // simul-landmarks writes ids with %i: 0x10, 1e3, 16.0 and +5, which strtod reads as
    // numbers, are refused; leading zeros are digits.
    const std::string file = std::string(SEMLOC_TEST_OUT) + "/ids_landmarks.txt";
    for (const std::string id : {"0x10", "1e3", "16.0", "+5", "-3", "2000000001", "99999999999"})
    {
        std::ofstream(file) << "1 2 0 5 0 0 1\n3 4 0 5 0 0 " << id << "\n";
        try
        {
            LandmarkImport::readLandmarks(file, "buoy");
            FAIL() << "accepted the id " << id;
        }
        catch (const std::exception& e)
        {
            const std::string m = e.what();
            EXPECT_NE(m.find("ids_landmarks.txt' line 2: last column must be a landmark id: '" +
                             id + "' is not an integer of decimal digits in [0, 2000000000]"),
                      std::string::npos)
                << m;
        }
    }
    std::ofstream(file) << "1 2 0 5 0 0 007\n3 4 0 5 0 0 2000000000\n";
    const auto lms = LandmarkImport::readLandmarks(file, "buoy");
    ASSERT_EQ(lms.size(), 2u);
    EXPECT_EQ(lms[0].id, 7);
    EXPECT_EQ(lms[1].id, 2000000000);
}

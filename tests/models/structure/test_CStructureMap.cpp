/* semloc tests — CStructureMap: the beam-model likelihood, ini, CMultiMetricMap, I/O. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/models/structure/CStructureMap.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <thread>

#include "ScanSimulation.h"
#include "TestHelpers.h"

using semloc::test::errorOf;

using mrpt::math::TPose2D;
using mrpt::obs::CObservation2DRangeScan;
using semloc::CStructureMap;
using semloc::World;
using semloc::test::simulateScan;

namespace
{
const std::string kPaper = SEMLOC_SOURCE_DIR "/maps/paper_50x50.yaml";
const std::string kHarbour = SEMLOC_SOURCE_DIR "/maps/harbour_symmetric.yaml";

CStructureMap paperMap()
{
    CStructureMap m;
    m.loadFromWorldFile(kPaper);
    return m;
}

/** Poses on the paper trajectory, looking at the structures. */
const std::vector<TPose2D> kTruePoses = {{12.5, 4.0, M_PI / 2},  {30.0, 17.0, -M_PI / 2},
                                         {40.0, 30.0, M_PI / 2}, {20.0, 43.0, M_PI / 2},
                                         {47.0, 10.0, M_PI},     {3.0, 24.0, 0.3}};

std::string iniText(const std::string& extraLikelihoodKey = "")
{
    return "[MetricMap]\n"
           "structureMap_count=1\n"
           "occupancyGrid_count=1\n"
           "[MetricMap_structureMap_00_creationOpts]\n"
           "world_file=" +
           kPaper +
           "\n"
           "cylinder_tolerance_m=0.005\n"
           "enableSaveAs3DObject=false\n"
           "[MetricMap_structureMap_00_likelihoodOpts]\n"
           "sigma_hit_m=0.4\n"
           "decimation=2\n" +
           extraLikelihoodKey +
           "[MetricMap_occupancyGrid_00_creationOpts]\n"
           "min_x=0\nmax_x=50\nmin_y=0\nmax_y=50\nresolution=0.1\n"
           "[MetricMap_occupancyGrid_00_likelihoodOpts]\n"
           "likelihoodMethod=lmLikelihoodField_Thrun\n"
           "LF_decimation=1\n";
}
}  // namespace

TEST(CStructureMap, LikelihoodPeaksAtTheTruePose)
{
    const CStructureMap map = paperMap();
    for (const auto& truth : kTruePoses)
    {
        const auto scan = simulateScan(map.rayCaster(), truth);
        const double best = map.computeLogLikelihood(scan, truth);
        ASSERT_TRUE(std::isfinite(best));
        for (const double d : {0.3, 1.0, 2.0, 5.0})
        {
            for (const auto& [dx, dy] :
                 {std::pair{d, 0.0}, std::pair{-d, 0.0}, std::pair{0.0, d}, std::pair{0.0, -d}})
            {
                const TPose2D p(truth.x + dx, truth.y + dy, truth.phi);
                EXPECT_GT(best, map.computeLogLikelihood(scan, p))
                    << "truth " << truth.asString() << " vs " << p.asString();
            }
        }
        for (const double dphi : {2.0, 5.0, 15.0, 45.0, 180.0})
        {
            for (const double sgn : {-1.0, 1.0})
            {
                const TPose2D p(truth.x, truth.y, truth.phi + sgn * dphi * M_PI / 180);
                EXPECT_GT(best, map.computeLogLikelihood(scan, p))
                    << "truth " << truth.asString() << " vs " << p.asString();
            }
        }
    }
    // The look-alike cluster: the same relative pose at the twin scores lower, but a
    // scan that sees only the cluster cannot tell them apart.
    const TPose2D atA(12.5, 4.0, M_PI / 2), atB(36.5, 30.0, M_PI / 2);
    const auto scanA = simulateScan(map.rayCaster(), atA);
    EXPECT_GT(map.computeLogLikelihood(scanA, atA), map.computeLogLikelihood(scanA, atB));
    const auto shortA = simulateScan(map.rayCaster(), atA, 60, 8.0);
    EXPECT_NEAR(map.computeLogLikelihood(shortA, atA), map.computeLogLikelihood(shortA, atB), 1e-6);
}

TEST(CStructureMap, HarbourMirrorPosesAreAmbiguous)
{
    CStructureMap map;
    map.loadFromWorldFile(kHarbour);
    const TPose2D west(22.0, 9.0, 2.0), east(60.0 - 22.0, 9.0, M_PI - 2.0);
    auto scan = simulateScan(map.rayCaster(), west);
    const double llWest = map.computeLogLikelihood(scan, west);
    // The mirror pose sees the mirrored scan: reverse the beam order.
    scan.rightToLeft = false;
    const double llEast = map.computeLogLikelihood(scan, east);
    const double llOff = map.computeLogLikelihood(scan, TPose2D(east.x + 1.0, east.y, east.phi));
    EXPECT_NEAR(llWest, llEast, 0.5) << "mirror images look the same to the sonar";
    EXPECT_GT(llEast, llOff + 5);
}

TEST(CStructureMap, LikelihoodIsFiniteOnBadBeams)
{
    const CStructureMap map = paperMap();
    const TPose2D truth = kTruePoses[0];
    auto scan = simulateScan(map.rayCaster(), truth);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    scan.setScanRange(0, nan);
    scan.setScanRange(1, -3.0f);
    scan.setScanRange(2, scan.maxRange);
    scan.setScanRange(3, 1000.0f);
    scan.setScanRange(4, std::numeric_limits<float>::infinity());
    scan.setScanRange(5, 0.0f);
    scan.setScanRangeValidity(6, false);
    for (const auto& p : {truth, TPose2D(0, 0, 0), TPose2D(-100, 300, 1), TPose2D(25, 25, 7)})
    {
        EXPECT_TRUE(std::isfinite(map.computeLogLikelihood(scan, p)));
    }
    // NaN and negative beams are skipped: the same as marking them invalid.
    auto clean = simulateScan(map.rayCaster(), truth);
    auto skipped = clean;
    skipped.setScanRange(0, nan);
    skipped.setScanRange(1, -3.0f);
    clean.setScanRangeValidity(0, false);
    clean.setScanRangeValidity(1, false);
    EXPECT_DOUBLE_EQ(map.computeLogLikelihood(skipped, truth),
                     map.computeLogLikelihood(clean, truth));
    // Readings beyond the max range are max-range readings.
    auto beyond = simulateScan(map.rayCaster(), truth);
    auto atMax = beyond;
    beyond.setScanRange(10, 1000.0f);
    atMax.setScanRange(10, atMax.maxRange);
    EXPECT_DOUBLE_EQ(map.computeLogLikelihood(beyond, truth),
                     map.computeLogLikelihood(atMax, truth));
    // All invalid, or no beams: 0 (uninformative) for every pose.
    auto none = simulateScan(map.rayCaster(), truth);
    for (size_t i = 0; i < none.getScanSize(); i++)
    {
        none.setScanRangeValidity(i, false);
    }
    EXPECT_EQ(map.computeLogLikelihood(none, truth), 0.0);
    EXPECT_EQ(map.computeLogLikelihood(CObservation2DRangeScan(), truth), 0.0);
    // A non-finite pose gets a finite, lowest score.
    const double bad = map.computeLogLikelihood(scan, TPose2D(std::nan(""), 1, 0));
    EXPECT_TRUE(std::isfinite(bad));
    EXPECT_LT(bad, map.computeLogLikelihood(scan, truth));
    // Every beam very unlikely: the per-beam floor keeps the sum finite.
    CStructureMap strict = paperMap();
    strict.likelihoodOptions.z_hit = 1;
    strict.likelihoodOptions.z_short = strict.likelihoodOptions.z_max =
        strict.likelihoodOptions.z_rand = 0;
    strict.likelihoodOptions.sigma_hit_m = 1e-3;
    const double ll = strict.computeLogLikelihood(scan, TPose2D(25, 25, 0));
    EXPECT_TRUE(std::isfinite(ll));
    EXPECT_GE(ll, 60 * std::log(strict.likelihoodOptions.min_beam_likelihood) - 1e-6);
}

TEST(CStructureMap, BeamGeometryConventions)
{
    const CStructureMap map = paperMap();
    const TPose2D truth = kTruePoses[0];
    const auto scan = simulateScan(map.rayCaster(), truth);
    // Decimation 2 == odd beams invalid.
    CStructureMap dec = paperMap();
    dec.likelihoodOptions.decimation = 2;
    auto odd = scan;
    for (size_t i = 1; i < odd.getScanSize(); i += 2)
    {
        odd.setScanRangeValidity(i, false);
    }
    EXPECT_NEAR(dec.computeLogLikelihood(scan, truth), map.computeLogLikelihood(odd, truth), 1e-9);
    // The sensor offset composes with the vehicle pose.
    auto mounted = scan;
    mounted.sensorPose = mrpt::poses::CPose3D(1.0, 0.5, 0, 0.3, 0, 0);
    const auto mountInverse = mrpt::poses::CPose2D() - mrpt::poses::CPose2D(1.0, 0.5, 0.3);
    const TPose2D vehicle = (mrpt::poses::CPose2D(truth) + mountInverse).asTPose();
    EXPECT_NEAR(map.computeLogLikelihood(mounted, vehicle), map.computeLogLikelihood(scan, truth),
                1e-6);
    // Left-to-right scans: the same ranges in reverse order.
    auto reversed = scan;
    reversed.rightToLeft = false;
    for (size_t i = 0; i < scan.getScanSize(); i++)
    {
        reversed.setScanRange(i, scan.getScanRange(scan.getScanSize() - 1 - i));
    }
    EXPECT_NEAR(map.computeLogLikelihood(reversed, truth), map.computeLogLikelihood(scan, truth),
                1e-6);
    // The CMetricMap entry point routes to computeLogLikelihood.
    EXPECT_DOUBLE_EQ(
        map.computeObservationLikelihood(scan, mrpt::poses::CPose3D(mrpt::poses::CPose2D(truth))),
        map.computeLogLikelihood(scan, truth));
    EXPECT_TRUE(map.canComputeObservationLikelihood(scan));
    EXPECT_FALSE(map.canComputeObservationLikelihood(mrpt::obs::CObservationBearingRange()));
}

TEST(CStructureMap, ThreadSafeLikelihood)
{
    const CStructureMap map = paperMap();
    const auto scan = simulateScan(map.rayCaster(), kTruePoses[1]);
    const World world = World::FromFile(kPaper);
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(3);
    std::vector<TPose2D> poses;
    std::vector<double> serial;
    for (int i = 0; i < 4000; i++)
    {
        poses.push_back(world.sampleFreePose(rng));
        serial.push_back(map.computeLogLikelihood(scan, poses.back()));
    }
    std::vector<double> out(poses.size());
    auto work = [&](size_t from, size_t to)
    {
        for (size_t i = from; i < to; i++)
        {
            out[i] = map.computeLogLikelihood(scan, poses[i]);
        }
    };
    std::thread t1(work, 0, poses.size() / 2), t2(work, poses.size() / 2, poses.size());
    t1.join();
    t2.join();
    EXPECT_EQ(out, serial);
}

TEST(CStructureMap, MultiMetricMapWithOccupancyGrid)
{
    const World world = World::FromFile(kPaper);
    const std::string png = SEMLOC_TEST_OUT "/paper_50x50_grid.png";
    ASSERT_TRUE(world.makeOccupancyGrid(0.1).saveAsBitmapFile(png));

    mrpt::config::CConfigFileMemory ini(iniText());
    mrpt::maps::TSetOfMetricMapInitializers init;
    init.loadFromConfigFile(ini, "MetricMap");
    ASSERT_EQ(init.size(), 2u);
    mrpt::maps::CMultiMetricMap mmm(init);
    auto sm = mmm.mapByClass<CStructureMap>();
    auto grid = mmm.mapByClass<mrpt::maps::COccupancyGridMap2D>();
    ASSERT_TRUE(sm);
    ASSERT_TRUE(grid);
    EXPECT_FALSE(sm->isEmpty());
    EXPECT_EQ(sm->likelihoodOptions.decimation, 2);
    EXPECT_EQ(sm->likelihoodOptions.sigma_hit_m, 0.4);
    EXPECT_FALSE(sm->genericMapParams.enableSaveAs3DObject);               // MRPT's generic key
    EXPECT_GT(sm->segments().size(), world.outlineSegments(0.01).size());  // finer tolerance
    // The grid from the image written by makeOccupancyGrid (pixel (0, 0) at the origin).
    ASSERT_TRUE(grid->loadFromBitmapFile(png, 0.1f, mrpt::math::TPoint2D(0, 0)));
    EXPECT_NEAR(grid->getXMax(), 50, 0.11);
    EXPECT_LT(grid->getPos(12.5, 10.5), 0.5);  // inside the manifold
    EXPECT_GT(grid->getPos(3.0, 4.0), 0.5);

    const TPose2D truth = kTruePoses[0];
    const auto scan = simulateScan(sm->rayCaster(), truth);
    const mrpt::poses::CPose3D at{mrpt::poses::CPose2D(truth)};
    const mrpt::poses::CPose3D off{mrpt::poses::CPose2D(truth.x + 2, truth.y + 1, truth.phi)};
    const double llS = sm->computeObservationLikelihood(scan, at);
    const double llG = grid->computeObservationLikelihood(scan, at);
    const double llM = mmm.computeObservationLikelihood(scan, at);
    EXPECT_TRUE(std::isfinite(llS));
    EXPECT_TRUE(std::isfinite(llG));
    EXPECT_NEAR(llM, llS + llG, 1e-6 * std::abs(llM));
    EXPECT_GT(llS, sm->computeObservationLikelihood(scan, off));
    EXPECT_GT(llG, grid->computeObservationLikelihood(scan, off));
}

TEST(CStructureMap, UnknownIniKeysAreRejected)
{
    for (const auto& [text, key] : {std::pair{iniText("sigma_hit=0.3\n"), std::string("sigma_hit")},
                                    std::pair{iniText("z_hits=0.3\n"), std::string("z_hits")}})
    {
        mrpt::config::CConfigFileMemory ini(text);
        mrpt::maps::TSetOfMetricMapInitializers init;
        try
        {
            init.loadFromConfigFile(ini, "MetricMap");
            FAIL() << "accepted unknown key " << key;
        }
        catch (const std::exception& e)
        {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(key + ": unknown key"), std::string::npos) << msg;
            EXPECT_NE(msg.find("structureMap_00_likelihoodOpts"), std::string::npos) << msg;
        }
    }
    mrpt::config::CConfigFileMemory bad(
        "[s]\nworld_file=x\n[s_creationOpts]\nworld_fil=nope.yaml\n");
    CStructureMap::TMapDefinition def;
    EXPECT_ANY_THROW(def.loadFromConfigFile(bad, "s"));
    // Out-of-range and all-zero weights are rejected too.
    CStructureMap::TLikelihoodOptions o;
    EXPECT_ANY_THROW(o.loadFromConfigFile(mrpt::config::CConfigFileMemory("[l]\nz_hit=2\n"), "l"));
    EXPECT_ANY_THROW(o.loadFromConfigFile(
        mrpt::config::CConfigFileMemory("[l]\nz_hit=0\nz_short=0\nz_max=0\nz_rand=0\n"), "l"));
    // Every key written by saveToConfigFile (as the apps' config.ini) reads back, to the bit
    // (MRPT's write() of a double keeps 6 decimals).
    mrpt::config::CConfigFileMemory round;
    CStructureMap::TLikelihoodOptions a;
    a.sigma_hit_m = 0.123456789012345;
    a.min_beam_likelihood = 1.2345678901234567e-13;
    a.decimation = 3;
    a.saveToConfigFile(round, "l");
    std::string text;
    round.getContent(text);
    CStructureMap::TLikelihoodOptions b;
    b.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), "l");
    EXPECT_EQ(b.sigma_hit_m, a.sigma_hit_m);
    EXPECT_EQ(b.min_beam_likelihood, a.min_beam_likelihood);
    EXPECT_EQ(b.decimation, 3);
}

TEST(CStructureMap, SerializationRoundTrip)
{
    CStructureMap map = paperMap();
    map.likelihoodOptions.sigma_hit_m = 0.45;
    map.likelihoodOptions.decimation = 3;
    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << map;
    buf.Seek(0);
    const auto obj = arch.ReadObject();
    const auto back = std::dynamic_pointer_cast<CStructureMap>(obj);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->segments().size(), map.segments().size());
    for (size_t i = 0; i < map.segments().size(); i++)
    {
        EXPECT_EQ(back->segments()[i].point1, map.segments()[i].point1);
        EXPECT_EQ(back->segments()[i].point2, map.segments()[i].point2);
    }
    EXPECT_EQ(back->likelihoodOptions.sigma_hit_m, 0.45);
    EXPECT_EQ(back->likelihoodOptions.decimation, 3);
    EXPECT_EQ(back->asString(), map.asString());
    const auto scan = simulateScan(map.rayCaster(), kTruePoses[2]);
    for (const auto& p : kTruePoses)
    {
        EXPECT_EQ(back->computeLogLikelihood(scan, p), map.computeLogLikelihood(scan, p));
    }
}

TEST(CStructureMap, CorruptedOptionsInAnArchiveAreRejected)
{
    // A map whose options the ini reader would reject, serialized as is: reading it back into
    // an existing map throws, names the option, and leaves that map as it was.
    const CStructureMap good = paperMap();
    const auto scan = simulateScan(good.rayCaster(), kTruePoses[1]);
    const double before = good.computeLogLikelihood(scan, kTruePoses[1]);
    auto corrupted = [&](auto&& spoil)
    {
        CStructureMap bad = paperMap();
        spoil(bad.likelihoodOptions);
        mrpt::io::CMemoryStream buf;
        auto arch = mrpt::serialization::archiveFrom(buf);
        arch << bad;
        buf.Seek(0);
        CStructureMap target = paperMap();
        std::string e = errorOf([&] { arch.ReadObject(&target); });
        EXPECT_EQ(target.computeLogLikelihood(scan, kTruePoses[1]), before);
        EXPECT_EQ(target.segments().size(), good.segments().size());
        return e;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::string e = corrupted([&](auto& o) { o.sigma_hit_m = nan; });
    EXPECT_NE(e.find("sigma_hit_m"), std::string::npos) << e;
    e = corrupted([](auto& o) { o.z_rand = -0.5; });
    EXPECT_NE(e.find("z_rand"), std::string::npos) << e;
    e = corrupted([](auto& o) { o.decimation = 0; });
    EXPECT_NE(e.find("decimation"), std::string::npos) << e;
    e = corrupted([](auto& o) { o.z_hit = o.z_short = o.z_max = o.z_rand = 0; });
    EXPECT_NE(e.find("all zero"), std::string::npos) << e;
}

TEST(CStructureMap, GenericMapFlagBytesOtherThanZeroOrOneAreRejected)
{
    // MRPT reads TMapGenericParams' three flags byte for byte: a corrupted one is refused,
    // and the map read into is left as it was.
    const CStructureMap good = paperMap();
    const std::string bytes = semloc::test::archiveBytes(good);
    const size_t firstFlag = semloc::test::genericMapFlagsAt(bytes);
    ASSERT_NE(firstFlag, std::string::npos);
    for (size_t i = firstFlag; i < firstFlag + 3; i++)
    {
        ASSERT_LE(static_cast<unsigned char>(bytes[i]), 1) << i;
        std::string spoiled = bytes;
        spoiled[i] = 7;
        CStructureMap target = paperMap();
        target.genericMapParams.enableSaveAs3DObject = false;
        const std::string e = semloc::test::readArchiveInto(spoiled, target);
        EXPECT_NE(e.find("CStructureMap: corrupted data"), std::string::npos) << i << ": " << e;
        EXPECT_FALSE(target.genericMapParams.enableSaveAs3DObject) << i;
        EXPECT_EQ(target.segments().size(), good.segments().size()) << i;
    }
}

TEST(CStructureMap, StaticMapInterface)
{
    CStructureMap map = paperMap();
    const size_t n = map.segments().size();
    EXPECT_FALSE(map.isEmpty());
    EXPECT_NE(map.asString().find("paper_50x50"), std::string::npos);
    // Static: inserting changes nothing.
    const auto scan = simulateScan(map.rayCaster(), kTruePoses[0]);
    EXPECT_FALSE(map.insertObservation(scan));
    EXPECT_EQ(map.segments().size(), n);
    // Text representation: a header plus one line per segment.
    const std::string prefix = SEMLOC_TEST_OUT "/structure_map";
    map.saveMetricMapRepresentationToFile(prefix);
    std::ifstream f(prefix + "_outlines.txt");
    ASSERT_TRUE(f.good());
    std::string line;
    size_t lines = 0;
    std::getline(f, line);
    EXPECT_EQ(line[0], '#');
    while (std::getline(f, line))
    {
        double x1, y1, x2, y2;
        EXPECT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf", &x1, &y1, &x2, &y2), 4);
        lines++;
    }
    EXPECT_EQ(lines, n);
    // Visualization: one CSetOfLines with every segment.
    mrpt::opengl::CSetOfObjects scene;
    map.getVisualizationInto(scene);
    ASSERT_EQ(scene.size(), 1u);
    const auto lines3d = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(*scene.begin());
    ASSERT_TRUE(lines3d);
    EXPECT_EQ(lines3d->getLineCount(), n);
    // clear() empties it.
    map.clear();
    EXPECT_TRUE(map.isEmpty());
    EXPECT_EQ(map.computeLogLikelihood(scan, kTruePoses[0]),
              map.computeLogLikelihood(scan, TPose2D(10, 10, 0)));
}

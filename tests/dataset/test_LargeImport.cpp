/* semloc tests — a landmark map of 200 000 landmarks imported by semloc-import-landmarks and
 * semloc-import within a memory budget: what the import holds beyond the tool itself (the
 * same import of two landmarks) stays within a few times the landmark file's size
 * (the landmarks held compactly, the world file's text and YAML never held whole). */
#include <gtest/gtest.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/world/World.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "LandmarkLog.h"
#include "ProcessRun.h"
#include "TestHelpers.h"

namespace fs = std::filesystem;

namespace
{
const std::string kBin = SEMLOC_BIN_DIR;
using semloc::test::readText;

/** Landmarks of the large map: about 27 bytes a row in either file. */
constexpr int kLandmarks = 200000;

/** What an import may hold beyond the tool's own resident set, per byte of the landmark file
 *  (docs/tools.md, "Large landmark maps"): about 3 is measured, 10 was the aim. */
[[maybe_unused]] constexpr double kBytesPerFileByte = 10;

int run(std::vector<std::string> args, const fs::path& log, double& maxRss_MiB)
{
    args[0] = kBin + "/" + args[0];
    return semloc::test::runMeasured(args, log, maxRss_MiB);
}

/** simul-landmarks' output, small: 3 frames seeing landmarks 1 and 2, the robot path. */
void writeLandmarkDataset(const fs::path& d)
{
    const mrpt::obs::CRawlog log = semloc::test::landmarkLog();
    ASSERT_TRUE(log.saveToRawLogFile((d / "in.rawlog").string()));
    std::ofstream(d / "path.txt") << "0 0 0 0 0 0\n0.5 0 0 0 0 0\n1 0 0 0 0 0\n";
    std::ofstream(d / "odom.csv") << "t,x,y,phi\n1,0,0,0\n2,1,0,0\n3,2,0,0\n";
    std::ofstream(d / "det.csv")
        << "t,label,range_m,bearing_rad\n1,buoy,3,0.1\n2,,,\n3,buoy,2,0.2\n";
    std::ofstream(d / "gt.csv") << "t,x,y,phi\n1,5,5,0\n2,6,5,0\n3,7,5,0\n";
}

/** `n` landmarks uniform over 4 x 4 km: `x y z id` rows (simul-landmarks' file) and
 *  `id,label,x,y` rows (semloc-import's CSV). */
void writeLandmarks(const fs::path& txt, const fs::path& csv, int n)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2000, 2000);
    std::ofstream t(txt), c(csv);
    c << "id,label,x,y\n";
    char line[128];
    for (int id = 1; id <= n; id++)
    {
        const double x = u(rng), y = u(rng);
        std::snprintf(line, sizeof line, "%.3f %.3f 0 %d\n", x, y, id);
        t << line;
        std::snprintf(line, sizeof line, "%d,buoy,%.3f,%.3f\n", id, x, y);
        c << line;
    }
}

/** Peak resident set [MiB] of importing the landmark files `txt` and `csv` (into `out`),
 *  the imported worlds checked to hold `n` objects. */
void importBoth(const fs::path& d, const fs::path& txt, const fs::path& csv, const std::string& out,
                size_t n, double& rssLandmarks, double& rssCsv)
{
    const fs::path log = d / (out + ".log");
    ASSERT_EQ(
        run({"semloc-import-landmarks", (d / "in.rawlog").string(), "--landmarks", txt.string(),
             "--path", (d / "path.txt").string(), "-o", (d / (out + "_lm.rawlog")).string()},
            log, rssLandmarks),
        0)
        << readText(log);
    ASSERT_EQ(run({"semloc-import", "-o", (d / (out + "_csv.rawlog")).string(), "--odometry",
                   (d / "odom.csv").string(), "--detections", (d / "det.csv").string(),
                   "--ground-truth", (d / "gt.csv").string(), "--landmarks", csv.string()},
                  log, rssCsv),
              0)
        << readText(log);
    for (const char* w : {"_lm_world.yaml", "_csv_world.yaml"})
    {
        EXPECT_EQ(semloc::World::FromFile((d / (out + w)).string()).objects.size(), n) << w;
    }
}
}  // namespace

TEST(LargeImport, ALandmarkMapOf200000IsImportedWithinTheMemoryBudget)
{
    const fs::path d = fs::path(SEMLOC_TEST_OUT) / "large_import";
    fs::remove_all(d);
    fs::create_directories(d);
    writeLandmarkDataset(d);
    writeLandmarks(d / "small.txt", d / "small.csv", 2);
    writeLandmarks(d / "large.txt", d / "large.csv", kLandmarks);

    double smallLm = 0, smallCsv = 0, largeLm = 0, largeCsv = 0;
    importBoth(d, d / "small.txt", d / "small.csv", "small", 2, smallLm, smallCsv);
    importBoth(d, d / "large.txt", d / "large.csv", "large", kLandmarks, largeLm, largeCsv);
    const double txtMiB = static_cast<double>(fs::file_size(d / "large.txt")) / (1 << 20);
    const double csvMiB = static_cast<double>(fs::file_size(d / "large.csv")) / (1 << 20);
    std::cout << "semloc-import-landmarks: " << txtMiB << " MiB file, peak RSS " << largeLm
              << " MiB (" << smallLm << " MiB for 2 landmarks)\n"
              << "semloc-import: " << csvMiB << " MiB file, peak RSS " << largeCsv << " MiB ("
              << smallCsv << " MiB for 2 landmarks)\n";
#ifndef SEMLOC_SANITIZED  // the sanitizers' shadow memory and quarantine count as resident
    EXPECT_LT(largeLm - smallLm, kBytesPerFileByte * txtMiB);
    EXPECT_LT(largeCsv - smallCsv, kBytesPerFileByte * csvMiB);
#endif
}

/* semloc tests — the bad inputs of docs/bad-input.md's table for semloc-import's CSV files
 * (hostile bytes, implausible times and values) and for the messages of the ini's map
 * sections. Each case builds its input in a fresh directory and returns the tool's command
 * line (test_BadInput.cpp runs it and checks the row). */
#include <semloc/io/RawlogWriter.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{
namespace
{
const std::string kDetHeader = "t,label,range_m,bearing_rad";

/** `text` gz-compressed into `path`. */
void writeGz(const fs::path& path, const std::string& text)
{
    semloc::GzOutputFile f(path.string(), 6);
    f.Write(text.data(), text.size());
    f.close();
}
}  // namespace

/** semloc-import: the bytes of the CSV files. */
Cases csvBytesCases()
{
    return {
        {"import-csv-utf8-bom",  // read past the header: the error is on line 3
         [](const fs::path& d)
         {
             return importCsv(
                 d, {{"det.csv", "\xEF\xBB\xBF" + kDetHeader + "\n1,buoy,3,0.1\n2,buoy,far,0\n"}});
         }},
        {"import-csv-cr-line-ends",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", kDetHeader + "\r1,buoy,3,0.1\r2,buoy,far,0\r"}});
         }},
        {"import-csv-line-too-long",
         [](const fs::path& d)
         {
             return importCsv(
                 d, {{"det.csv", kDetHeader + "\n1,buoy," + std::string(2 << 20, '3') + ",0.1\n"}});
         }},
        {"import-csv-binary",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", std::string(3 << 20, '\0')}});
         }},
        {"import-csv-control-bytes",
         [](const fs::path& d)
         {
             return importCsv(d, {{"det.csv", kDetHeader + "\n1,buoy,3,0.1\n2,buoy,\x1b[2J" +
                                                  std::string(1000, '9') + ",0\n"}});
         }},
    };
}

/** semloc-import: implausible times and values. */
Cases csvValueCases()
{
    return {
        {"import-csv-times-nanoseconds",
         [](const fs::path& d)
         {
             return importCsv(d, {{"odom.csv",
                                   "t,x,y,phi\n1700000000000000000,0,0,0\n"
                                   "1700000001000000000,1,0,0\n"}});
         }},
        {"import-csv-times-milliseconds",
         [](const fs::path& d)
         {
             return importCsv(
                 d, {{"odom.csv", "t,x,y,phi\n1000,0,0,0\n2000,1,0,0\n3000,2,0,0\n"},
                     {"det.csv", kDetHeader + "\n1000,buoy,3,0.1\n2000,,,\n3000,buoy,2,0.2\n"},
                     {"gt.csv", "t,x,y,phi\n1000,5,5,0\n2000,6,5,0\n3000,7,5,0\n"}});
         }},
        {"import-csv-max-step-too-short",
         [](const fs::path& d) {
             return importCsv(d, {}, {"--max-step-s", "1e-8"});
         }},
        {"import-csv-position-huge",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,x,y,phi\n1,0,0,0\n2,1e308,0,0\n3,2,0,0\n"}});
         }},
        {"import-csv-speed-huge",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,v,w\n1,1e300,0\n2,0,0\n3,0,0\n"}});
         }},
        {"import-csv-bearing-degrees",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", kDetHeader + "\n1,buoy,3,5\n3,buoy,2,90\n"}});
         }},
    };
}

/** semloc-import: what real logs bring (repeated times, a scan's readings a few milliseconds
 *  apart, detections of no landmark, gaps in the ground truth, gz-compressed files). */
Cases csvRealLogCases()
{
    return {
        {"import-csv-odometry-repeated-time",
         [](const fs::path& d) {
             return importCsv(d,
                              {{"odom.csv", "t,x,y,phi\n1,0,0,0\n2,0.9,0,0\n2,1,0,0\n3,2,0,0\n"}});
         }},
        {"import-csv-detections-ms-apart",
         [](const fs::path& d)
         {
             return importCsv(d,
                              {{"det.csv", kDetHeader + "\n1,buoy,3,0.1\n1.004,buoy,5,-0.2\n2,,,\n"
                                                        "3,buoy,2,0.2\n3.002,buoy,4,0.3\n"}});
         }},
        {"import-csv-gt-repeated-time",
         [](const fs::path& d) {
             return importCsv(d, {{"gt.csv", "t,x,y,phi\n1,5,5,0\n2,6,5,0\n2,6,5,0\n3,7,5,0\n"}});
         }},
        {"import-csv-detections-of-no-landmark",
         [](const fs::path& d)
         {
             return importCsv(
                 d, {{"det.csv", kDetHeader + ",id\n1,buoy,3,0.1,1\n1,robot,4,0,7\n2,,,,\n"
                                              "3,robot,2,0.2,7\n"}});
         }},
        {"import-csv-gt-gap",
         [](const fs::path& d) {
             return importCsv(
                 d, {{"gt.csv", "t,x,y,phi\n1,5,5,0\n1.1,5.1,5,0\n1.2,5.2,5,0\n3,7,5,0\n"}});
         }},
        {"import-csv-gz",
         [](const fs::path& d)
         {
             auto a = importCsv(d, {});
             for (const char* f : {"odom.csv", "det.csv", "gt.csv", "lm.csv"})
             {
                 writeGz(d / (std::string(f) + ".gz"), readText(d / f));
                 fs::remove(d / f);
                 std::replace(a.begin(), a.end(), std::string(f), std::string(f) + ".gz");
             }
             return a;
         }},
        {"import-csv-gz-truncated",
         [](const fs::path& d)
         {
             std::string odom = "t,x,y,phi\n";
             for (int k = 0; k < 20000; k++)
             {
                 odom += std::to_string(1 + k * 1e-4) + "," + std::to_string(k * 1e-4) + ",0,0\n";
             }
             auto a = importCsv(d, {});
             writeGz(d / "odom.csv.gz", odom);
             const std::string gz = readText(d / "odom.csv.gz");
             writeText(d / "odom.csv.gz", gz.substr(0, gz.size() / 2));
             std::replace(a.begin(), a.end(), std::string("odom.csv"), std::string("odom.csv.gz"));
             return a;
         }},
    };
}

/** semloc-localize: the messages of the map sections and of a map file not found. */
Cases iniMessageCases()
{
    return {
        {"ini-map-value-names-the-file",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"sigma_range_m", "-1"}});
         }},
        {"ini-cr-line-ends",  // as MRPT reads it
         [](const fs::path& d)
         {
             auto a = localizeGood(d, "", {{"convergence_min_steps", "9"}});
             std::string text = readText(d / "loc.ini");
             std::replace(text.begin(), text.end(), '\n', '\r');
             writeText(d / "loc.ini", text);
             return a;
         }},
        {"ini-symlinked-map-missing",
         [](const fs::path& d)
         {
             fs::create_directories(d / "cfg");
             fs::create_directories(d / "run");
             writeIni(d / "cfg", "", {{"map_file", "../maps/nope.yaml"}});
             fs::create_symlink("../cfg/loc.ini", d / "run" / "loc.ini");
             saveGz(simulate().rawlog, d / "data.rawlog");
             return localize(d, d / "run" / "loc.ini", d / "data.rawlog");
         }},
    };
}

}  // namespace semloc::test::bad_input

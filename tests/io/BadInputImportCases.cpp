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

/** `text` as `file`, given to semloc-import with `option`. */
std::vector<std::string> importWith(const fs::path& d, const std::string& option,
                                    const std::string& file, const std::string& text)
{
    return importCsv(d, {{file, text}}, {option, file});
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

/** semloc-import: an AUV's odometry and detections (the DVL's velocities, several sensors). */
Cases csvAuvDetectionCases()
{
    return {
        {"import-csv-dvl-vx-without-vy",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,vx,w\n1,1,0\n2,1,0\n3,1,0\n"}});
         }},
        {"import-csv-dvl-mixed-forms",
         [](const fs::path& d) {
             return importCsv(d, {{"odom.csv", "t,v,vx,vy,w\n1,1,1,0,0\n2,1,1,0,0\n3,1,1,0,0\n"}});
         }},
        {"import-csv-side-with-bearing",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", kDetHeader + ",side\n1,buoy,3,0.1,port\n"}});
         }},
        {"import-csv-side-unknown",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", kDetHeader + ",side\n1,buoy,3,,aft\n"}});
         }},
        {"import-csv-sensor-label-blank",
         [](const fs::path& d) {
             return importCsv(d, {{"det.csv", kDetHeader + ",sensor\n1,buoy,3,0.1,side scan\n"}});
         }},
    };
}

/** semloc-import: an AUV's depth, heading and fixes files, the per-sensor options and a whole
 *  AUV log. */
Cases csvAuvReadingCases()
{
    const std::string auvOdom = "t,vx,vy,w\n1,1,0.2,0\n2,1,0.2,0.1\n3,1,0,0\n";
    const std::string auvDet =
        "t,sensor,label,range_m,bearing_rad,side\n1,sidescan,buoy,3,,port\n"
        "1.004,camera,buoy,,0.1,\n2,sidescan,,,,\n3,sidescan,buoy,2,,starboard\n";
    return {
        {"import-csv-depth-not-a-number", [](const fs::path& d)
         { return importWith(d, "--depth", "depth.csv", "t,depth_m\n1,deep\n"); }},
        {"import-csv-altitude-negative", [](const fs::path& d)
         { return importWith(d, "--depth", "depth.csv", "t,depth_m,altitude_m\n1,25,-0.5\n"); }},
        {"import-csv-heading-column-missing", [](const fs::path& d)
         { return importWith(d, "--heading", "heading.csv", "t,heading_deg\n1,90\n"); }},
        {"import-csv-readings-time-back",
         [](const fs::path& d) {
             return importWith(d, "--heading", "heading.csv", "t,heading_rad\n1,0\n3,0.1\n2,0.2\n");
         }},
        {"import-csv-fix-sigma-not-positive", [](const fs::path& d)
         { return importWith(d, "--fixes", "fixes.csv", "t,x,y,sigma_m\n1,5,5,0\n"); }},
        {"import-csv-fix-both-sigma-forms",
         [](const fs::path& d)
         {
             return importWith(d, "--fixes", "fixes.csv",
                               "t,x,y,sigma_m,sigma_x_m,sigma_y_m\n1,5,5,1,1,1\n");
         }},
        {"import-csv-fixes-without-sigma",
         [](const fs::path& d) { return importWith(d, "--fixes", "fixes.csv", "t,x,y\n2,6,5\n"); }},
        {"import-csv-max-range-named-malformed",
         [](const fs::path& d) {
             return importCsv(d, {}, {"--max-range-m", "20", "--max-range-m", "sonar="});
         }},
        {"import-csv-sensor-pose-named-malformed",
         [](const fs::path& d) {
             return importCsv(d, {}, {"--sensor-pose", "sonar=1,2"});
         }},
        {"import-csv-sensor-name-unused",
         [](const fs::path& d) {
             return importCsv(d, {}, {"--max-range-m", "sonar=30"});
         }},
        {"import-csv-readings-superseded",
         [](const fs::path& d)
         {
             return importWith(d, "--depth", "depth.csv",
                               "t,depth_m\n0.9,20\n1,21\n1.2,21\n1.4,22\n1.6,22\n2,23\n2.2,23\n"
                               "3,24\n3.5,25\n");
         }},
        {"import-csv-auv-log",
         [=](const fs::path& d)
         {
             return importCsv(
                 d,
                 {{"odom.csv", auvOdom},
                  {"det.csv", auvDet},
                  {"depth.csv", "t,depth_m,altitude_m\n0.5,25,5\n1.5,25.2,\n2.9,25.1,4.8\n"},
                  {"heading.csv", "t,heading_rad\n1,0\n2,0.1\n"},
                  {"fixes.csv", "t,x,y,sigma_m\n2.5,6,5,2\n"}},
                 {"--depth", "depth.csv", "--heading", "heading.csv", "--fixes", "fixes.csv",
                  "--fov-deg", "sidescan=360", "--max-range-m", "camera=8", "--sensor-pose",
                  "camera=0.3,0,0,-0.2"});
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

/* semloc tests — the bad inputs of docs/bad-input.md's table that a hostile user tries: special
 * files where a file is read, benchmark shards and merges, calibration, large maps. Each case
 * writes its input in a fresh directory and returns the tool's command line (test_BadInput.cpp
 * runs it and checks the row). */
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{

namespace
{
/** A FIFO at `p` (nothing ever writes it: a reader that opened it would wait forever). */
fs::path fifo(const fs::path& p)
{
    if (::mkfifo(p.c_str(), 0600) != 0)
    {
        throw std::runtime_error("mkfifo " + p.string() + ": " + std::strerror(errno));
    }
    return p;
}

/** `argv` with the argument after `option` replaced by `value`. */
std::vector<std::string> with(std::vector<std::string> argv, const std::string& option,
                              const std::string& value)
{
    const auto at = std::find(argv.begin(), argv.end(), option);
    if (at == argv.end() || at + 1 == argv.end())
    {
        throw std::runtime_error("no option " + option);
    }
    *(at + 1) = value;
    return argv;
}
/** Special files (devices, FIFOs), oversized files, link loops and directories as an ini. */
Cases iniSpecialFileCases()
{
    return {
        {"ini-device",
         [](const fs::path& d) { return localize(d, "/dev/zero", d / "data.rawlog"); }},
        {"ini-fifo",
         [](const fs::path& d) { return localize(d, fifo(d / "loc.ini"), d / "data.rawlog"); }},
        {"ini-too-large",
         [](const fs::path& d)
         {
             writeText(d / "loc.ini", "");
             fs::resize_file(d / "loc.ini", 17u << 20);  // sparse: no disk used
             return localize(d, d / "loc.ini", d / "data.rawlog");
         }},
        {"ini-symlink-loop",  // beside the case's directory, whose listing would fail
         [](const fs::path& d)
         {
             const fs::path out = d.parent_path();
             fs::create_symlink("b.ini", out / "a.ini");
             fs::create_symlink("a.ini", out / "b.ini");
             return localize(d, out / "a.ini", d / "data.rawlog");
         }},
        {"ini-base-directory",
         [](const fs::path& d)
         {
             fs::create_directory(d / "adir");
             writeText(d / "loc.ini", "base = adir\n");
             return localize(d, d / "loc.ini", d / "data.rawlog");
         }},
    };
}

/** The same for rawlogs, ground truth, worlds and the other tools; outputs over a base. */
Cases dataSpecialFileCases()
{
    return {
        {"rawlog-device", [](const fs::path& d) { return localize(d, writeIni(d), "/dev/zero"); }},
        {"rawlog-null", [](const fs::path& d) { return localize(d, writeIni(d), "/dev/null"); }},
        {"rawlog-fifo",
         [](const fs::path& d) { return localize(d, writeIni(d), fifo(d / "data.rawlog")); }},
        {"gt-device",
         [](const fs::path& d) {
             return localizeGood(d, "", {{"ground_truth_path_file", "/dev/zero"}});
         }},
        {"benchmark-ini-device",
         [](const fs::path&) {
             return std::vector<std::string>{"semloc-benchmark", "/dev/zero"};
         }},
        {"simulate-ini-device",
         [](const fs::path&) {
             return std::vector<std::string>{"semloc-simulate", "/dev/zero"};
         }},
        {"world-device",
         [](const fs::path& d)
         {
             return std::vector<std::string>{"semloc-plot-world", "/dev/zero", "-o",
                                             (d / "w.png").string()};
         }},
        {"calibrate-base-device", [](const fs::path& d)
         { return with(calibrate(d, 100, "semantic", "out.ini"), "--base", "/dev/zero"); }},
        {"calibrate-rawlog-device",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "out.ini");
             a[1] = "/dev/zero";
             return a;
         }},
        {"import-landmarks-device",
         [](const fs::path& d)
         {
             auto a = importLandmarks(d, {});
             a[1] = "/dev/zero";
             return a;
         }},
        {"simulate-out-replaces-base",
         [](const fs::path& d)
         {
             writeText(d / "d5.ini", "// semloc-simulate: \n[Simulation]\nworld_file = " + kSrc +
                                         "/maps/paper_50x50.yaml\n");
             writeText(d / "over.ini", "base = d5.ini\n[Simulation]\nseed = 3\n");
             return std::vector<std::string>{"semloc-simulate", (d / "over.ini").string(), "-o",
                                             (d / "d5.rawlog").string()};
         }},
        {"calibrate-out-replaces-base",
         [](const fs::path& d)
         {
             auto a = calibrate(d, 100, "semantic", "cal.ini");
             writeText(d / "cal.ini", "// semloc-calibrate: \n" + readText(d / "base.ini"));
             writeText(d / "base2.ini", "base = cal.ini\n");
             return with(a, "--base", (d / "base2.ini").string());
         }},
    };
}

}  // namespace

/** Special files, oversized files, link loops, directories; outputs over a base. */
Cases specialFileCases()
{
    Cases all = iniSpecialFileCases();
    const Cases more = dataSpecialFileCases();
    all.insert(more.begin(), more.end());
    return all;
}

/** Benchmark sweeps, shards and merges. */
Cases benchmarkSafetyCases()
{
    return {};
}

/** semloc-calibrate. */
Cases calibrateSafetyCases()
{
    return {};
}

/** Large maps and landmark imports. */
Cases largeMapCases()
{
    return {};
}

}  // namespace semloc::test::bad_input

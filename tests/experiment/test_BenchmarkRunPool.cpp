/* semloc tests — Benchmark's run files: what a child process hands back to the parent, sealed
 * by the digests of its benchmark and of its content. */
#include <gtest/gtest.h>
#include <semloc/io/ErrorMessage.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "experiment/BenchmarkRunPool.h"
#include "experiment/Digest.h"

namespace
{
using semloc::Benchmark;

/** The bits of a double: the run file must give back the very same values. */
uint64_t bits(double v)
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

const std::string kInputs = "00cba9e3f5b16f80";

std::string writeTemp(const std::string& name, const std::string& text)
{
    std::string path = std::string(SEMLOC_TEST_OUT) + "/" + name;
    std::ofstream(path) << text;
    return path;
}

/** The error of reading `text` as the run file of `run` with `series`. */
std::string errorOf(const std::string& text, int run = 1,
                    const semloc::detail::RunSeries& series = {{"semantic", "route"}})
{
    try
    {
        (void)semloc::detail::readRunFile(writeTemp("run_corrupt.txt", text), run, kInputs, series);
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);
    }
    return {};
}

std::vector<std::string> splitLines(const std::string& text)
{
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
    {
        lines.push_back(l);
    }
    return lines;
}

/** The lines but the last (the content digest) with a content digest of their own. */
std::string sealed(const std::vector<std::string>& lines)
{
    std::string body;
    for (size_t i = 0; i + 1 < lines.size(); i++)
    {
        body += lines[i] + "\n";
    }
    return body + "content " + semloc::detail::digestText(semloc::detail::fnv1a(body)) + "\n";
}
}  // namespace

TEST(BenchmarkRunPool, RunFileGivesBackEveryValueBitForBit)
{
    std::vector<Benchmark::TRunResult> in(2);
    in[0].variant = "semantic";
    in[0].particles = 2000;
    in[0].threads = 3;
    in[0].wallTime_s = 0.1 + 0.2;
    in[0].reinitializations = 4;
    in[0].control = "active";
    in[0].decisions = 5;
    in[0].decisionWall_s = 1.0 / 3.0;
    in[0].decisionFilterSteps = 2.0 / 7.0 + 40;
    in[0].maxDecisionFilterSteps = 1e-7 / 3;
    in[0].stuckDecisions = 2;
    for (size_t k = 0; k < 3; k++)
    {
        semloc::TStepRecord s;
        s.step = k;
        s.t = 1700000000.0 + 0.1 * static_cast<double>(k);
        if (k != 1)
        {
            s.gt = mrpt::math::TPose2D(1.0 / 3.0, -2.5e-300, 3.14159 * static_cast<double>(k));
        }
        s.est = mrpt::math::TPose2D(std::sqrt(2.0), 1e300, -1.0 / 7.0);
        s.var_xy = 0.123456789012345678;
        s.ess = 0.5 / 3.0;
        s.n_particles = 2000 - k;
        s.update_us = 1234.5678;
        s.var_x = 0.1 / 3.0;
        s.var_y = 1e-310;  // subnormal
        s.var_phi = 2.0 / 7.0;
        s.cov_xy = -0.1 / 7.0;
        s.cov_xphi = -1.0 / 11.0;
        s.cov_yphi = 5e-17 * static_cast<double>(k);
        in[0].records.push_back(s);
    }
    in[0].detectorBound = {{1.0 / 3.0, 0.1 + 0.2}, {1e-300, 2.0 / 7.0}};
    in[1].variant = "grid_lf";  // no step at all
    const std::string path =
        writeTemp("run_roundtrip.txt", semloc::detail::runFileText(in, 7, kInputs));

    const auto out = semloc::detail::readRunFile(path, 7, kInputs,
                                                 {{"semantic", "active"}, {"grid_lf", "route"}});
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].run, 7);
    EXPECT_EQ(out[0].seed, 7u);
    EXPECT_EQ(out[0].variant, "semantic");
    EXPECT_EQ(out[0].particles, 2000u);
    EXPECT_EQ(out[0].threads, 3u);
    EXPECT_EQ(bits(out[0].wallTime_s), bits(in[0].wallTime_s));
    EXPECT_EQ(out[0].reinitializations, 4u);
    EXPECT_EQ(out[0].control, "active");
    EXPECT_EQ(out[0].decisions, 5u);
    EXPECT_EQ(bits(out[0].decisionWall_s), bits(in[0].decisionWall_s));
    EXPECT_EQ(bits(out[0].decisionFilterSteps), bits(in[0].decisionFilterSteps));
    EXPECT_EQ(bits(out[0].maxDecisionFilterSteps), bits(in[0].maxDecisionFilterSteps));
    EXPECT_EQ(out[0].stuckDecisions, 2u);
    ASSERT_EQ(out[0].records.size(), 3u);
    for (size_t k = 0; k < 3; k++)
    {
        const auto &a = in[0].records[k], &b = out[0].records[k];
        EXPECT_EQ(b.step, a.step);
        EXPECT_EQ(bits(b.t), bits(a.t));
        ASSERT_EQ(b.gt.has_value(), a.gt.has_value());
        if (a.gt)
        {
            EXPECT_EQ(bits(b.gt->x), bits(a.gt->x));
            EXPECT_EQ(bits(b.gt->y), bits(a.gt->y));
            EXPECT_EQ(bits(b.gt->phi), bits(a.gt->phi));
        }
        EXPECT_EQ(bits(b.est.x), bits(a.est.x));
        EXPECT_EQ(bits(b.est.y), bits(a.est.y));
        EXPECT_EQ(bits(b.est.phi), bits(a.est.phi));
        EXPECT_EQ(bits(b.var_xy), bits(a.var_xy));
        EXPECT_EQ(bits(b.ess), bits(a.ess));
        EXPECT_EQ(b.n_particles, a.n_particles);
        EXPECT_EQ(bits(b.update_us), bits(a.update_us));
        EXPECT_EQ(bits(b.var_x), bits(a.var_x));
        EXPECT_EQ(bits(b.var_y), bits(a.var_y));
        EXPECT_EQ(bits(b.var_phi), bits(a.var_phi));
        EXPECT_EQ(bits(b.cov_xy), bits(a.cov_xy));
        EXPECT_EQ(bits(b.cov_xphi), bits(a.cov_xphi));
        EXPECT_EQ(bits(b.cov_yphi), bits(a.cov_yphi));
        EXPECT_EQ(bits(b.nees()), bits(a.nees()));
    }
    ASSERT_EQ(out[0].detectorBound.size(), 2u);
    for (size_t k = 0; k < 2; k++)
    {
        EXPECT_EQ(bits(out[0].detectorBound[k].rms_xy_m), bits(in[0].detectorBound[k].rms_xy_m));
        EXPECT_EQ(bits(out[0].detectorBound[k].mean_err_xy_m),
                  bits(in[0].detectorBound[k].mean_err_xy_m));
    }
    EXPECT_EQ(out[1].variant, "grid_lf");
    EXPECT_TRUE(out[1].records.empty());
    EXPECT_TRUE(out[1].detectorBound.empty());
}

TEST(BenchmarkRunPool, CorruptRunFileIsAnErrorNamingItsLine)
{
    Benchmark::TRunResult r;
    r.variant = "semantic";
    r.records.resize(2);
    r.detectorBound.resize(3, {0.25, 0.125});
    const std::string text = semloc::detail::runFileText({r}, 1, kInputs);
    EXPECT_NE(
        errorOf("X" + text).find("run_corrupt.txt' line 1: not a run file of semloc-benchmark"),
        std::string::npos);
    // Cut in the middle of its steps, of its detector bound.
    for (const size_t cut : {size_t(60), size_t(8)})
    {
        EXPECT_NE(errorOf(text.substr(0, text.size() - cut)).find("the file was cut short"),
                  std::string::npos);
    }
    // Lines that do not read, sealed again as a forger would: named by their line.
    const auto lines = splitLines(text);
    auto bad = lines;
    bad[4] = "0 x" + bad[4].substr(bad[4].find(' ', 2));  // the first step's time
    EXPECT_NE(errorOf(sealed(bad)).find("run_corrupt.txt' line 5: 'x' is not a number"),
              std::string::npos)
        << errorOf(sealed(bad));
    bad = lines;
    bad[3] = "V semantic route 0 1 0 0 0 0 0 0 0 1000";  // more steps than lines
    EXPECT_NE(errorOf(sealed(bad)).find("line 4: 1000 steps, but the file ends before them"),
              std::string::npos);
    bad = lines;
    bad[6] += " 1";
    EXPECT_NE(errorOf(sealed(bad)).find("line 7: 9 fields where this B line has 8"),
              std::string::npos)
        << errorOf(sealed(bad));
}

TEST(BenchmarkRunPool, RunFileOfAnotherRunBenchmarkOrSeriesOrEditedIsRefused)
{
    Benchmark::TRunResult r;
    r.variant = "semantic";
    r.records.resize(2);
    const std::string text = semloc::detail::runFileText({r}, 2, kInputs);
    EXPECT_NO_THROW(semloc::detail::readRunFile(writeTemp("run_ok.txt", text), 2, kInputs,
                                                {{"semantic", "route"}}));
    // A figure edited by hand: the content digest of the last line (line 8) no longer matches.
    std::string edited = text;
    edited[edited.find("\n0 0 0") + 3] = '1';
    EXPECT_NE(errorOf(edited, 2).find("line 8: the file was changed after its run wrote it"),
              std::string::npos)
        << errorOf(edited, 2);
    EXPECT_NE(errorOf(text, 1).find("line 2: the results of another run than run 1 ('run 2'"),
              std::string::npos);
    EXPECT_NE(errorOf(semloc::detail::runFileText({r}, 2, "0123456789abcdef"), 2)
                  .find("line 3: the results of another benchmark ('inputs 0123456789abcdef', "
                        "this one's inputs digest is " +
                        kInputs),
              std::string::npos);
    EXPECT_NE(errorOf(text, 2, {{"geometric", "route"}})
                  .find("line 4: the results of variant 'semantic' (control route), not a series"),
              std::string::npos);
    EXPECT_NE(errorOf(text, 2, {{"semantic", "route"}, {"semantic", "active"}})
                  .find("line 8: the file ends after 1 of the 2 results of a run"),
              std::string::npos);
}

TEST(BenchmarkRunPool, RunFileThatIsNotARegularFileIsRefusedInOneLine)
{
    const std::string dir = std::string(SEMLOC_TEST_OUT) + "/run_special";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto error = [](const std::string& path, uint64_t max = semloc::detail::kMaxRunFileBytes)
    {
        try
        {
            (void)semloc::detail::readBoundedFile(path, max, "run file");
        }
        catch (const std::exception& e)
        {
            return semloc::errorMessage(e);
        }
        return std::string();
    };
    std::filesystem::create_symlink("/dev/zero", dir + "/zero.txt");
    EXPECT_EQ(error(dir + "/zero.txt"), "run file '" + dir +
                                            "/zero.txt' is a symbolic link, not a regular file: "
                                            "semloc-benchmark reads only the files it wrote");
    ASSERT_EQ(::mkfifo((dir + "/fifo.txt").c_str(), 0600), 0);
    EXPECT_NE(error(dir + "/fifo.txt").find("fifo.txt' is a FIFO (a pipe), not a regular file"),
              std::string::npos);
    EXPECT_NE(error(dir).find("run_special' is a directory, not a file"), std::string::npos);
    EXPECT_EQ(error(dir + "/none.txt"), "run file '" + dir + "/none.txt' does not exist");
    std::ofstream(dir + "/big.txt") << "0123456789a";
    EXPECT_NE(error(dir + "/big.txt", 10)
                  .find("big.txt' holds 11 bytes, more than the 10 bytes a run file may hold"),
              std::string::npos);
    EXPECT_EQ(error(dir + "/big.txt", 11), "");
}

/* semloc tests — Benchmark's run files: what a child process hands back to the parent. */
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "experiment/BenchmarkRunPool.h"

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

std::string writeTemp(const std::string& name, const std::string& text)
{
    std::string path = std::string(SEMLOC_TEST_OUT) + "/" + name;
    std::ofstream(path) << text;
    return path;
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
    const std::string path = writeTemp("run_roundtrip.txt", semloc::detail::runFileText(in));

    const auto out = semloc::detail::readRunFile(path, 7);
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

TEST(BenchmarkRunPool, CorruptRunFileIsAnError)
{
    const std::string text = semloc::detail::runFileText({Benchmark::TRunResult()});
    EXPECT_THROW(semloc::detail::readRunFile(writeTemp("run_bad_tag.txt", "X" + text), 1),
                 std::exception);
    // A run file cut in the middle of its steps.
    Benchmark::TRunResult r;
    r.variant = "semantic";
    r.records.resize(2);
    const std::string full = semloc::detail::runFileText({r});
    EXPECT_THROW(
        semloc::detail::readRunFile(writeTemp("run_cut.txt", full.substr(0, full.size() - 12)), 1),
        std::exception);
    // Cut in the middle of its detector bound.
    r.detectorBound.resize(3, {0.25, 0.125});
    const std::string withBound = semloc::detail::runFileText({r});
    EXPECT_THROW(semloc::detail::readRunFile(
                     writeTemp("run_cut_bound.txt", withBound.substr(0, withBound.size() - 8)), 1),
                 std::exception);
}

/* semloc tests — a run you can see: semloc-localize's particles.csv (the saved steps, each
 * step's weights summing to one) and RunPlot (semloc-plot-run): the run read back, run.png,
 * error.png and an animated run.gif drawn, the clouds chosen, bad files named. */
#include <gtest/gtest.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/experiment/RunPlot.h>
#include <semloc/simulator/Simulator.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "TestHelpers.h"

namespace fs = std::filesystem;
using semloc::LocalizationExperiment;
using semloc::RunPlot;
using semloc::test::errorOf;
using semloc::test::readText;

namespace
{
const fs::path kOut = fs::path(SEMLOC_TEST_OUT) / "runplot";

/** Images of GIF89a: its graphic control extensions (one per frame gnuplot writes). */
size_t gifFrames(const fs::path& gif)
{
    const std::string d = readText(gif);
    EXPECT_EQ(d.substr(0, 6), "GIF89a");
    size_t n = 0;
    for (size_t p = d.find("\x21\xf9\x04"); p != std::string::npos;
         p = d.find("\x21\xf9\x04", p + 1))
    {
        n++;
    }
    return n;
}

/** The cells of a CSV line. */
std::vector<std::string> cellsOf(const std::string& line)
{
    std::vector<std::string> cells(1);
    for (const char c : line)
    {
        if (c == ',')
        {
            cells.emplace_back();
        }
        else
        {
            cells.back() += c;
        }
    }
    return cells;
}

bool isPng(const fs::path& p)
{
    return fs::exists(p) && readText(p).substr(1, 3) == "PNG";
}

class RunPlotTest : public ::testing::Test
{
protected:
    /** A run of config/localize/semantic.ini (300 particles, particles of every 50th step) on the
     * paper dataset; with `save` 0 no particles.csv. */
    static fs::path localize(const std::string& name, int save, int particles = 300)
    {
        LocalizationExperiment::TOverrides ov;
        ov.rawlog_file = rawlog;
        ov.logOutput_dir = (kOut / name).string();
        ov.particles_count = particles;
        ov.particles_save_every = save;
        LocalizationExperiment::FromConfigFile(SEMLOC_SOURCE_DIR "/config/localize/semantic.ini",
                                               ov)
            .run();
        return kOut / name;
    }

    static void SetUpTestSuite()
    {
        fs::create_directories(kOut);
        rawlog = (kOut / ("paper_" + std::to_string(::getpid()) + ".rawlog")).string();
        const semloc::Simulator sim(semloc::TSimulatorOptions::FromConfigFile(
            SEMLOC_SOURCE_DIR "/config/simulate/simulate.ini"));
        sim.writeDataset(sim.run(), rawlog);
    }
    static std::string rawlog;
};
std::string RunPlotTest::rawlog;

TEST_F(RunPlotTest, ParticlesCsvHoldsEveryNthStepAndTheLastWithNormalizedWeights)
{
    const auto dir = localize("particles_" + std::to_string(::getpid()), 50);
    std::istringstream in(readText(dir / "particles.csv"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "step,t,x,y,phi,weight");
    std::map<size_t, size_t> rows;
    std::map<size_t, double> sums;
    while (std::getline(in, line))
    {
        std::istringstream row(line);
        std::string cell;
        std::vector<double> v;
        while (std::getline(row, cell, ','))
        {
            v.push_back(std::stod(cell));
        }
        ASSERT_EQ(v.size(), 6u) << line;
        rows[static_cast<size_t>(v[0])]++;
        sums[static_cast<size_t>(v[0])] += v[5];
    }
    const auto plot = RunPlot::FromDirectory(dir.string());
    const auto& records = plot.records();
    ASSERT_EQ(records.size(), 431u);
    std::vector<size_t> steps;
    for (const auto& [s, n] : rows)
    {
        steps.push_back(s);
        EXPECT_EQ(n, records[s].n_particles) << "step " << s;
        EXPECT_NEAR(sums[s], 1.0, 1e-9) << "step " << s;
    }
    EXPECT_EQ(steps, (std::vector<size_t>{0, 50, 100, 150, 200, 250, 300, 350, 400, 430}));
    ASSERT_EQ(plot.clouds().size(), steps.size());
    EXPECT_EQ(plot.clouds().back().points.size(), records.back().n_particles);

    // Without the option: no particles.csv.
    EXPECT_FALSE(
        fs::exists(localize("noparticles_" + std::to_string(::getpid()), 0) / "particles.csv"));
}

TEST_F(RunPlotTest, DrawsTheRunTheErrorAndAnAnimatedGif)
{
    const std::string tag = std::to_string(::getpid());
    const auto dir = localize("drawn_" + tag, 50);
    const auto plot = RunPlot::FromDirectory(dir.string());
    ASSERT_TRUE(plot.convergenceStep().has_value());
    EXPECT_EQ(plot.world().objects.size(), 24u);  // the run's map_file, the paper world
    const auto figs = kOut / ("figs_" + tag);
    RunPlot::TOptions o;
    o.cloudSteps = {0, 200, 430};
    plot.save(figs.string(), o);
    EXPECT_TRUE(isPng(figs / "run.png"));
    EXPECT_TRUE(isPng(figs / "error.png"));
    EXPECT_EQ(gifFrames(figs / "run.gif"), 10u);  // one frame per saved step
    const std::string script = readText(figs / "run.gp");
    EXPECT_NE(script.find("'particles, step 200'"), std::string::npos);
    EXPECT_NE(script.find("lc palette"), std::string::npos);  // the estimate coloured by error
    EXPECT_TRUE(fs::exists(figs / "clouds.dat"));

    // At most maxGifFrames frames, taken evenly; replacing a previous output is allowed.
    o.maxGifFrames = 4;
    plot.save(figs.string(), o);
    EXPECT_EQ(gifFrames(figs / "run.gif"), 4u);

    // A step without particles, and the run's own directory as output, are refused.
    o.cloudSteps = {7};
    EXPECT_NE(errorOf([&] { plot.save((kOut / ("bad_" + tag)).string(), o); })
                  .find("step 7 has no particles in particles.csv (saved: 0, 50, 100 ... 430)"),
              std::string::npos);
    EXPECT_FALSE(fs::exists(kOut / ("bad_" + tag)));
    o.cloudSteps.clear();
    const std::string before = readText(dir / "steps.csv");
    EXPECT_NE(errorOf([&] { plot.save(dir.string(), o); }), "");
    EXPECT_EQ(readText(dir / "steps.csv"), before);
}

// One particle: no spread at any step (zero on error.png's log axis); every figure is drawn.
TEST_F(RunPlotTest, OneParticleRunIsDrawnWhole)
{
    const std::string tag = std::to_string(::getpid());
    const auto run = localize("one_particle_" + tag, 50, 1);
    const auto plot = RunPlot::FromDirectory(run.string());
    for (const auto& r : plot.records())
    {
        ASSERT_EQ(r.var_xy, 0.0);
    }
    const fs::path figs = kOut / ("one_particle_figs_" + tag);
    RunPlot::TOptions o;
    o.maxGifFrames = 3;
    const auto warnings = plot.save(figs.string(), o);
    for (const auto& w : warnings)
    {
        ADD_FAILURE() << w.text();
    }
    EXPECT_TRUE(isPng(figs / "run.png"));
    EXPECT_TRUE(isPng(figs / "error.png"));
    EXPECT_EQ(gifFrames(figs / "run.gif"), 3u);
}

TEST_F(RunPlotTest, WithoutParticlesTheRunAndErrorAreDrawnAndCloudsAskForThem)
{
    const std::string tag = std::to_string(::getpid());
    const auto dir = localize("plain_" + tag, 0);
    const auto plot = RunPlot::FromDirectory(dir.string());
    EXPECT_TRUE(plot.clouds().empty());
    RunPlot::TOptions o;
    plot.save((kOut / ("plainfigs_" + tag)).string(), o);
    EXPECT_TRUE(isPng(kOut / ("plainfigs_" + tag) / "run.png"));
    EXPECT_TRUE(isPng(kOut / ("plainfigs_" + tag) / "error.png"));
    EXPECT_FALSE(fs::exists(kOut / ("plainfigs_" + tag) / "run.gif"));
    o.cloudSteps = {0};
    EXPECT_NE(errorOf([&] { plot.save((kOut / ("plainbad_" + tag)).string(), o); })
                  .find("the run has no particles.csv (semloc-localize --save-particles N)"),
              std::string::npos);
}

TEST_F(RunPlotTest, StepsCsvEndsWithTheNeesAndThePoseCovarianceReadBackExactly)
{
    // steps.csv's last columns: each step's NEES and the pose covariance it is made of. The
    // run read back has the same covariance, so its records' NEES is the column's to the bit;
    // a steps.csv written without those columns is still read (covariance 0).
    const std::string tag = std::to_string(::getpid());
    const auto dir = localize("nees_" + tag, 0);
    std::istringstream in(readText(dir / "steps.csv"));
    std::string line;
    std::getline(in, line);
    const auto header = cellsOf(line);
    ASSERT_EQ(header.size(), 21u);
    EXPECT_EQ(header[13], "update_us") << "the columns before keep their places";
    EXPECT_EQ(std::vector<std::string>(header.begin() + 14, header.end()),
              (std::vector<std::string>{"nees", "var_x", "var_y", "var_phi", "cov_xy", "cov_xphi",
                                        "cov_yphi"}));
    const auto plot = RunPlot::FromDirectory(dir.string());
    size_t inside = 0;
    std::vector<double> all, wellConditioned;
    std::string old = line.substr(0, line.find(",nees")) + "\n";
    for (const auto& r : plot.records())
    {
        ASSERT_TRUE(std::getline(in, line));
        const auto cells = cellsOf(line);
        ASSERT_EQ(cells.size(), 21u) << line;
        const double nees = std::stod(cells[14]);
        ASSERT_EQ(r.nees(), nees) << "step " << r.step;
        ASSERT_TRUE(std::isfinite(nees)) << "step " << r.step;
        ASSERT_EQ(r.var_x + r.var_y, r.var_xy) << "step " << r.step;
        ASSERT_GE(r.var_phi, 0.0) << "step " << r.step;
        inside += nees <= semloc::RunMetrics::kNeesChi2_95 ? 1 : 0;
        all.push_back(nees);
        if (r.neesWellConditioned())
        {
            wellConditioned.push_back(nees);
        }
        for (size_t k = 0; k < 14; k++)
        {
            old += cells[k] + (k < 13 ? "," : "\n");
        }
    }
    const std::string summary = readText(dir / "summary.yaml");
    const auto value = [&](const std::string& key)
    {
        const size_t at = summary.find("\n" + key + ": ");
        EXPECT_NE(at, std::string::npos) << key;
        return std::stod(summary.substr(at + key.size() + 3));
    };
    const double n = static_cast<double>(plot.records().size());
    EXPECT_EQ(summary.find("\nnees_mean:"), std::string::npos) << "a mean of every step";
    std::sort(all.begin(), all.end());
    const double median = 0.5 * (all[(all.size() - 1) / 2] + all[all.size() / 2]);
    EXPECT_NEAR(value("nees_median"), median, 1e-9 * median);
    EXPECT_DOUBLE_EQ(value("nees_inside_share"), static_cast<double>(inside) / n);
    EXPECT_GT(inside, 0u);
    ASSERT_FALSE(wellConditioned.empty());
    double wcSum = 0;
    for (const double v : wellConditioned)
    {
        wcSum += v;
    }
    const double wcMean = wcSum / static_cast<double>(wellConditioned.size());
    EXPECT_NEAR(value("nees_mean_well_conditioned"), wcMean, 1e-9 * wcMean);
    EXPECT_DOUBLE_EQ(value("nees_well_conditioned_share"),
                     static_cast<double>(wellConditioned.size()) / n);

    // The steps.csv of a run written before these columns.
    const auto before = kOut / ("nees_before_" + tag);
    fs::remove_all(before);
    fs::copy(dir, before);
    std::ofstream(before / "steps.csv", std::ios::trunc) << old;
    const auto read = RunPlot::FromDirectory(before.string());
    ASSERT_EQ(read.records().size(), plot.records().size());
    EXPECT_EQ(read.records().back().est.x, plot.records().back().est.x);
    EXPECT_EQ(read.records().back().var_x, 0.0);
}

TEST_F(RunPlotTest, BadRunFilesAreNamedWithTheirLine)
{
    const std::string tag = std::to_string(::getpid());
    const auto dir = localize("badfiles_" + tag, 100);
    const auto copy = kOut / ("badcopy_" + tag);
    fs::remove_all(copy);
    fs::copy(dir, copy);
    const auto p = (copy / "particles.csv").string();
    std::string text = readText(p);
    const size_t third = text.find('\n', text.find('\n') + 1) + 1;  // the second data row
    text.insert(text.find(',', text.find(',', third) + 1) + 1, "x");
    std::ofstream(p, std::ios::trunc) << text;
    EXPECT_NE(errorOf([&] { RunPlot::FromDirectory(copy.string()); })
                  .find("particles.csv:3: column 3 'x': not a finite number"),
              std::string::npos);
    fs::remove(p);
    std::ofstream(copy / "steps.csv", std::ios::app) << "431,1,2\n";
    EXPECT_NE(errorOf([&] { RunPlot::FromDirectory(copy.string()); }).find("steps.csv:433"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { RunPlot::FromDirectory((kOut / "none").string()); })
                  .find("is not a directory (a semloc-localize output)"),
              std::string::npos);

    // A map that is not a world file: the view spans the paths, no objects.
    const auto plain = kOut / ("gridmap_" + tag);
    fs::remove_all(plain);
    fs::copy(dir, plain);
    fs::remove(plain / "particles.csv");
    std::string ini = readText(plain / "config.ini");
    const size_t k = ini.find("map_file");
    ini.replace(k, ini.find('\n', k) - k, "map_file = /nowhere/map.gridmap");
    std::ofstream(plain / "config.ini", std::ios::trunc) << ini;
    const auto plot = RunPlot::FromDirectory(plain.string());
    EXPECT_TRUE(plot.world().objects.empty());
    const auto& b = plot.world().bounds;
    for (const auto& r : plot.records())
    {
        ASSERT_TRUE(r.gt.has_value());
        EXPECT_TRUE(r.gt->x > b.x_min && r.gt->x < b.x_max && r.gt->y > b.y_min &&
                    r.gt->y < b.y_max)
            << "step " << r.step << " outside the view";
    }
    EXPECT_LT(plot.world().bounds.x_min, 3.0);
    EXPECT_GT(plot.world().bounds.x_max, 47.0);
}

}  // namespace
